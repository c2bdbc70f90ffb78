"""Scenes: unique names, attachments to known objects, allowed pairs by pattern and phase."""

from __future__ import annotations

import pytest

from optraj.errors import InvalidInputError, UnknownNameError
from optraj.problems import AllowedPair, Attachment, Box, Plane, Scene, Sphere


def _objects():
    return (Box("block_0", (0.01, 0.01, 0.015)), Plane("floor", (0, 0, -1)))


def test_a_scene_keeps_its_objects_attachments_and_margin():
    held = Attachment("block_0", "tcp", "grasp_0", "release_0")
    scene = Scene(_objects(), (held,), (("tool/tip", "ball"),), margin=0.02)
    assert scene.names == ("block_0", "floor")
    assert scene.object("floor").name == "floor"
    assert scene.allowed == (AllowedPair("tool/tip", "ball"),)
    assert scene.margin == 0.02 and scene.attachments == (held,)


def test_allowed_pairs_match_by_pattern_either_way_and_by_phase():
    scene = Scene(
        _objects(),
        allowed=(AllowedPair("tool/tip", "ball"), AllowedPair("tool/*", "block_0", ("grasp_0",))),
    )
    assert scene.always_allowed("ball", "tool/tip")
    assert not scene.always_allowed("tool/cue", "ball")
    assert not scene.always_allowed("tool/palm", "block_0")
    assert scene.sometimes_allowed("block_0", "tool/finger_left") == ("grasp_0",)
    assert scene.sometimes_allowed("link_3", "block_0") is None


@pytest.mark.parametrize(
    ("build", "error", "match"),
    [
        (lambda: Scene((Sphere("a", 0.1), Sphere("a", 0.2))), InvalidInputError, "twice"),
        (lambda: Scene(("table",)), InvalidInputError, "Box, Sphere"),
        (lambda: Scene(_objects(), margin=-0.01), InvalidInputError, "margin"),
        (
            lambda: Scene(_objects(), (Attachment("block_9", "tcp", 0.0, 1.0),)),
            UnknownNameError,
            "block_9",
        ),
        (lambda: Attachment("block_0", "tcp", -1.0, 1.0), InvalidInputError, "start"),
        (lambda: AllowedPair("a", "b", "grasp_0"), InvalidInputError, "phases"),
        (lambda: AllowedPair("", "b"), InvalidInputError, "first"),
    ],
)
def test_bad_scenes_are_refused(build, error, match):
    with pytest.raises(error, match=match):
        build()


def test_an_unknown_object_lists_the_known_ones():
    with pytest.raises(UnknownNameError, match="floor"):
        Scene(_objects()).object("flor")
