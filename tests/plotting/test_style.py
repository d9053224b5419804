"""The figures' style and checks (stability.plotting.style): units shown as people read them,
figures drawn in the package's style, written whole in each format asked for, and the two
checks every study's figures pass (every axis labelled with its unit, no legend over data)
finding what they are there to find."""

import matplotlib as mpl
import numpy as np
import pytest

from stability.plotting.style import (
    covered_data, label, missing_units, new_figure, place_legend, pretty_unit, save, styled,
)


def test_units_are_shown_as_people_read_them():
    assert pretty_unit("rad s-1") == "rad/s" and pretty_unit("kg m2 s-1") == "kg m²/s"
    assert pretty_unit("1") == "dimensionless" and pretty_unit("J") == "J"
    assert label("growth rate", "s-1") == "growth rate (1/s)"


def test_a_styled_figure_is_drawn_in_the_style_and_leaves_the_callers_untouched():
    before = mpl.rcParams["axes.grid"]

    @styled
    def figure():
        fig = new_figure(4.0, 3.0)
        ax = fig.subplots()
        ax.plot([0, 1], [0, 1])
        return fig, mpl.rcParams["axes.grid"], mpl.rcParams["font.size"]

    fig, grid, size = figure()
    assert grid is True and size == 10 and mpl.rcParams["axes.grid"] == before
    assert fig.get_layout_engine() is not None  # constrained layout


def test_a_figure_is_saved_whole_in_each_format(tmp_path):
    fig = new_figure(3.0, 2.0)
    fig.subplots().plot([0, 1], [1, 0])
    paths = save(fig, tmp_path, "line", formats=("png", "pdf", "svg"))
    assert [p.name for p in paths] == ["line.png", "line.pdf", "line.svg"]
    assert paths[0].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert paths[1].read_bytes()[:4] == b"%PDF"
    assert not list(tmp_path.glob(".*.part"))
    with pytest.raises(ValueError, match="figure format must be one of png, pdf, svg"):
        save(fig, tmp_path, "line", formats=("jpg",))


def test_the_unit_check_names_each_axis_without_its_unit():
    fig = new_figure()
    left, right = fig.subplots(1, 2)
    left.set_xlabel(label("time", "s"))
    left.set_ylabel("w2")  # no unit
    right.set_xlabel(label("spin", "rad s-1"))
    right.set_ylabel(label("count", "1"))
    found = missing_units(fig)
    assert len(found) == 1 and "w2" in found[0]


def test_a_legend_is_placed_clear_of_the_data_and_one_over_it_is_found():
    fig = new_figure(4.0, 3.0)
    ax = fig.subplots()
    t = np.linspace(0.0, 1.0, 50)
    ax.plot(t, t, label="rising")
    ax.plot(t, 1.0 - t, label="falling")  # an X: the corners upper left and right are taken
    place_legend(ax)
    assert covered_data(fig) == []
    ax.legend(loc="center")  # over the crossing
    assert len(covered_data(fig)) == 1
