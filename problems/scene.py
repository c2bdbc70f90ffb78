"""A scene: the solids around a robot, the ones it carries, and the pairs that may touch.

A :class:`Scene` holds named solids (:mod:`problems.scene_shapes`), objects attached to a
robot frame between two times (:class:`Attachment`: a held block moves with the gripper and
stays where it is released), the pairs allowed to touch (:class:`AllowedPair`: the cue tip and
the ball, the gripper and the block it grasps; the robot's adjacent links are allowed by
:mod:`robots.collision` itself) and the clearance every other pair must keep (``margin``).

Example::

    scene = Scene(
        objects=(Plane("floor", point=(0, 0, -0.914)), Sphere("ball", 0.0286, translation(p))),
        allowed=(AllowedPair("tool/tip", "ball"),),
        margin=0.01,
    )
"""

from __future__ import annotations

import fnmatch
from dataclasses import dataclass

from optraj.errors import InvalidInputError, UnknownNameError
from optraj.problems.scene_shapes import Box, Cylinder, Plane, Shape, Sphere
from optraj.validation import as_number

__all__ = ["AllowedPair", "Attachment", "Scene"]

_SHAPES = (Box, Sphere, Cylinder, Plane)


def _text(value: object, what: str) -> str:
    if not isinstance(value, str) or not value:
        raise InvalidInputError(f"{what} must be a non-empty str, got {value!r}", name=what)
    return value


def _when(value: object, what: str) -> float | str:
    """A time [s] (finite, >= 0) or a phase name."""
    if isinstance(value, str):
        return _text(value, what)
    return as_number(value, what, "s", minimum=0.0)


@dataclass(frozen=True)
class Attachment:
    """An object that moves with a robot frame from ``start`` to ``end``.

    Until ``start`` the object is where the scene puts it; from ``start`` it keeps the offset
    from ``frame`` that it has then; after ``end`` it stays where the frame left it.

    Attributes:
        object: Name of one of the scene's objects.
        frame: Name of a frame of the robot (e.g. ``"tcp"``).
        start: When it is taken: a time [s] or a phase name (the phase's start).
        end: When it is released: a time [s] or a phase name (the phase's end).
    """

    object: str
    frame: str
    start: float | str
    end: float | str

    def __post_init__(self) -> None:
        object.__setattr__(self, "object", _text(self.object, "Attachment.object"))
        object.__setattr__(self, "frame", _text(self.frame, "Attachment.frame"))
        object.__setattr__(self, "start", _when(self.start, "Attachment.start"))
        object.__setattr__(self, "end", _when(self.end, "Attachment.end"))


@dataclass(frozen=True)
class AllowedPair:
    """Two names (shell patterns, e.g. ``"tool/*"``) whose shapes may touch.

    Attributes:
        first: Pattern of a robot shape's or an object's name.
        second: The other pattern; the pair matches either way round.
        phases: Phase names during which the pair may touch (each phase's closed time span);
            empty: always. A check without times (one configuration) allows every pair that
            may touch at some time.
    """

    first: str
    second: str
    phases: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "first", _text(self.first, "AllowedPair.first"))
        object.__setattr__(self, "second", _text(self.second, "AllowedPair.second"))
        if isinstance(self.phases, str):
            raise InvalidInputError(
                f"AllowedPair.phases must be a tuple of phase names, got {self.phases!r}",
                name="phases",
            )
        phases = tuple(_text(p, "AllowedPair.phases") for p in self.phases)
        object.__setattr__(self, "phases", phases)

    def matches(self, a: str, b: str) -> bool:
        """Whether the shapes named ``a`` and ``b`` are this pair (either way round)."""

        def match(x: str, y: str) -> bool:
            return fnmatch.fnmatchcase(x, self.first) and fnmatch.fnmatchcase(y, self.second)

        return match(a, b) or match(b, a)


@dataclass(frozen=True, eq=False)
class Scene:
    """The solids around a robot, what it carries, and what may touch.

    Attributes:
        objects: The solids (:class:`Box`, :class:`Sphere`, :class:`Cylinder`,
            :class:`Plane`), names unique.
        attachments: Objects carried by a robot frame between two times.
        allowed: Pairs that may touch (:class:`AllowedPair`, or ``(first, second)``).
        margin: The clearance every other pair must keep [m], >= 0.
    """

    objects: tuple[Shape, ...]
    attachments: tuple[Attachment, ...] = ()
    allowed: tuple[AllowedPair, ...] = ()
    margin: float = 0.0

    def __post_init__(self) -> None:
        objects = tuple(self.objects)
        names: set[str] = set()
        for item in objects:
            if not isinstance(item, _SHAPES):
                raise InvalidInputError(
                    "scene objects must be Box, Sphere, Cylinder or Plane, got "
                    f"{type(item).__name__}",
                    name="objects",
                )
            if item.name in names:
                raise InvalidInputError(
                    f"scene object name {item.name!r} is used twice", name="objects"
                )
            names.add(item.name)
        attachments = tuple(self.attachments)
        for attachment in attachments:
            if not isinstance(attachment, Attachment):
                raise InvalidInputError(
                    f"attachments must be Attachment, got {type(attachment).__name__}",
                    name="attachments",
                )
            if attachment.object not in names:
                raise UnknownNameError("scene object", attachment.object, sorted(names))
        allowed = tuple(
            item if isinstance(item, AllowedPair) else AllowedPair(*item) for item in self.allowed
        )
        object.__setattr__(self, "objects", objects)
        object.__setattr__(self, "attachments", attachments)
        object.__setattr__(self, "allowed", allowed)
        object.__setattr__(self, "margin", as_number(self.margin, "margin", "m", minimum=0.0))

    @property
    def names(self) -> tuple[str, ...]:
        """The objects' names, in order."""
        return tuple(item.name for item in self.objects)

    def object(self, name: str) -> Shape:
        """The object called ``name``.

        Raises:
            UnknownNameError: No such object; lists the objects.
        """
        for item in self.objects:
            if item.name == name:
                return item
        raise UnknownNameError("scene object", name, self.names)

    def always_allowed(self, a: str, b: str) -> bool:
        """Whether ``a`` and ``b`` may touch at every time."""
        return any(p.matches(a, b) for p in self.allowed if not p.phases)

    def sometimes_allowed(self, a: str, b: str) -> tuple[str, ...] | None:
        """The phases during which ``a`` and ``b`` may touch, if only during some; else None."""
        phases = [ph for p in self.allowed if p.phases and p.matches(a, b) for ph in p.phases]
        return tuple(phases) if phases else None
