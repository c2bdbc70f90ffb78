"""Tests of sweeps.plot: heat maps per heading, colours at the right cells, typed errors."""

import sys

import numpy as np
import pytest
from sweeps_support import HEADINGS, SMALL, XS, YS, grid_rows, made_up_value, random_rows

from optraj import sweeps
from optraj.errors import InvalidInputError, MissingDependencyError
from optraj.sweeps import plot_max_speed, plot_motion_time

matplotlib = pytest.importorskip("matplotlib")  # the examples extra, which make test installs
matplotlib.use("Agg")


def _rows():
    """The made-up grid with one max_speed per ball position."""
    return grid_rows(max_speed_per_position=True)


def _panels(figure):
    return [ax for ax in figure.axes if ax.get_title().startswith("heading")]


def test_max_speed_map_has_a_panel_per_heading_and_the_values_at_their_cells():
    figure = plot_max_speed(_rows())
    panels = _panels(figure)
    assert [ax.get_title() for ax in panels] == ["heading 0 deg", "heading 45 deg"]
    for ax, heading in zip(panels, HEADINGS, strict=True):
        (mesh,) = [c for c in ax.collections if isinstance(c, matplotlib.collections.QuadMesh)]
        colours = np.ma.asarray(mesh.get_array()).reshape(len(YS), len(XS))
        for i, x in enumerate(XS):
            for j, y in enumerate(YS):
                if x == 0.9:
                    assert colours.mask[j, i]  # no value: drawn over the hatched grey
                else:
                    assert colours[j, i] == made_up_value(x, y, heading, 0.9)
        assert any(p.get_hatch() for p in ax.patches)
        assert ax.get_xlabel() == "ball x [m]" and ax.get_ylabel() == "ball y [m]"
        (base,) = ax.lines
        assert base.get_xydata().tolist() == [[0.0, 0.0]]  # the robot base, marked
    assert any(ax.get_ylabel() == "max speed [m/s]" for ax in figure.axes)  # the colour bar
    assert "no max_speed" in figure.legends[0].get_texts()[0].get_text()


def test_a_real_sweep_is_drawn_with_its_motion_times():
    rows = sweeps.run(SMALL, planner="cubic", workers=0, progress=False)
    (panel,) = _panels(plot_motion_time(rows, speed=0.3))
    colours = np.ma.asarray(panel.collections[-1].get_array()).reshape(2, 2)
    for row in rows:
        if row["speed"] == 0.3:
            i, j = [0.7, 0.8].index(row["ball_x"]), [0.0, 0.2].index(row["ball_y"])
            assert colours[j, i] == row["motion_time"]


def test_motion_time_map_shows_the_chosen_speed():
    figure = plot_motion_time(_rows(), speed=0.3, headings=[45.0])
    (panel,) = _panels(figure)
    mesh = panel.collections[0]
    colours = np.ma.asarray(mesh.get_array()).reshape(len(YS), len(XS))
    assert colours[1, 2] == made_up_value(0.9, 0.1, 45.0, 0.3)
    assert not np.ma.getmaskarray(colours).any() and not panel.patches  # every cell planned
    assert any(ax.get_ylabel() == "motion time [s]" for ax in figure.axes)
    assert "0.3 m/s" in figure.get_suptitle()
    refused = plot_motion_time(_rows(), speed=0.9)
    assert all(np.ma.getmaskarray(ax.collections[0].get_array()).all() for ax in _panels(refused))


def test_a_random_set_is_drawn_as_points():
    rows = random_rows(12, seed=2, refused_every=4)
    (panel,) = [ax for ax in plot_motion_time(rows).axes if ax.get_title() == "every heading"]
    drawn, missed = panel.collections
    assert sorted(drawn.get_array().tolist()) == [float(i) for i in range(12) if i % 4]
    assert len(missed.get_offsets()) == 3


@pytest.mark.parametrize(
    ("call", "words"),
    [
        (lambda: plot_max_speed([]), "at least one sweep row, got none"),
        (
            lambda: plot_max_speed(_rows(), headings=[90.0]),
            "heading 90 deg is not in the rows",
        ),
        (
            lambda: plot_motion_time(_rows(), speed=0.5),
            "speed 0.5 m/s is not in the rows",
        ),
        (
            lambda: plot_motion_time(_rows()),
            "several speeds (0.3, 0.9 m/s)",
        ),
    ],
)
def test_bad_input_raises_typed_errors_naming_themade_up_value(call, words):
    with pytest.raises(InvalidInputError) as info:
        call()
    assert words in str(info.value)


def test_without_matplotlib_the_error_names_the_package_and_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib now fails
    with pytest.raises(MissingDependencyError, match=r"optraj\[examples\]") as info:
        plot_max_speed(_rows())
    assert info.value.package == "matplotlib"
