"""Tests of planners.plot_style: the style cycle, the legend below, phase shading."""

from __future__ import annotations

import pytest

from optraj.errors import InvalidInputError
from optraj.planners import plot_style

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")


def test_no_two_of_the_first_styles_look_alike_and_widths_shrink():
    styles = [plot_style.line_style(k) for k in range(12)]
    looks = {(s.color, str(s.linestyle), s.marker) for s in styles}
    assert len(looks) == 12
    widths = [s.linewidth for s in styles]
    assert widths == sorted(widths, reverse=True) and widths[0] > widths[1]
    assert min(widths) >= plot_style.THINNEST
    named = plot_style.line_styles(["a", "b"])
    assert named["a"] == styles[0] and named["b"] == styles[1]


def test_markers_are_spread_in_time_when_the_point_count_is_given():
    kwargs = plot_style.line_style(1).kwargs(900)
    step = 900 // plot_style.MARKERS_PER_CURVE
    assert kwargs["markevery"].step == step
    assert 0 < kwargs["markevery"].start < step  # shifted from the first style's markers
    assert plot_style.line_style(0).kwargs(900)["markevery"].start == 0


def test_legend_below_keeps_each_label_once_and_leaves_the_axes_free():
    plt = plot_style.pyplot()
    figure, axes = plt.subplots(2, 1, layout="constrained")
    for ax in axes:
        ax.plot([0, 1], [0, 1], label="a")
        ax.plot([0, 1], [1, 0], label="_hidden")
    handles, labels = [], []
    for ax in axes:
        h, lab = ax.get_legend_handles_labels()
        handles += h
        labels += lab
    legend = plot_style.legend_below(figure, handles, labels)
    assert [t.get_text() for t in legend.get_texts()] == ["a"]
    figure.canvas.draw()
    assert legend.get_window_extent().y1 <= axes[-1].get_window_extent().y0
    assert plot_style.legend_below(figure, [], []) is None
    plt.close(figure)


def test_shade_phase_uses_the_curve_colour_and_one_bar_row_per_curve():
    plt = plot_style.pyplot()
    figure, ax = plt.subplots()
    style = plot_style.line_style(3)
    plot_style.shade_phase(ax, 0.2, 0.4, style, row=1)
    band, bar = ax.patches
    assert matplotlib.colors.same_color(band.get_facecolor()[:3], style.color)
    assert bar.get_y() == pytest.approx(0.035) and bar.get_height() == pytest.approx(0.035)
    plt.close(figure)


def test_a_bad_index_is_refused():
    with pytest.raises(InvalidInputError, match="index must be an integer >= 0, got -1"):
        plot_style.line_style(-1)
