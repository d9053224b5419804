"""Figures of the tennis-racket study: they build, every axis carries a unit, they show what
they claim (numerical samples on the exact curve, the analytic slope); the figure styles."""

import numpy as np
import pytest
from matplotlib.figure import Figure

import stability
from stability.core.axes import intermediate_axis
from stability.free_body.tennis_racket.measure import analyse_ensemble
from stability.free_body.tennis_racket import figures as tennis
from stability.plotting.style import (
    covered_data, label, missing_units, new_figure, place_legend, save,
)

from ...helpers import assert_readable

SPIN, EPSILON = 10.0, 1e-4


@pytest.fixture(scope="module")
def analysed():
    """A small tennis-racket ensemble over two flip intervals, analysed as the study does."""
    body = stability.RigidBody.preset("tennis_racket")
    axis = int(intermediate_axis(body))
    ds = stability.run_ensemble(
        body, axis, SPIN, EPSILON, 96, h=2e-3, t_end=5.0, seed=3, method="rk4",
        keep=stability.Keep(save_every=25), options=stability.RunOptions(progress=False),
    )
    ds = analyse_ensemble(ds, body, axis, SPIN, EPSILON, low_factor=10.0, high_fraction=0.03)
    return ds, body, axis


FIGURES = [tennis.flips_figure, tennis.polhode_figure, tennis.growth_figure,
           tennis.flip_interval_figure]


@pytest.mark.parametrize("make", FIGURES, ids=lambda f: f.__name__)
def test_figure_builds_with_units_and_a_legend(make, analysed, tmp_path):
    fig = make(*analysed)
    assert isinstance(fig, Figure)
    assert_readable(fig)
    assert fig.legends or any(ax.get_legend() is not None for ax in fig.axes)
    png, pdf = save(fig, tmp_path, "figure", ("png", "pdf"))
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert pdf.read_bytes()[:5] == b"%PDF-"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["figure.pdf", "figure.png"]


def test_save_lays_out_once_and_gives_the_layout_engine_back(analysed, tmp_path):
    """PNG and PDF share the positions the first drawing settled, and the figure keeps its
    constrained layout afterwards (a second save lays it out again)."""
    fig = tennis.growth_figure(*analysed)
    engine = fig.get_layout_engine()
    save(fig, tmp_path, "a", ("png", "pdf"))
    position = fig.axes[0].get_position().bounds
    assert fig.get_layout_engine() is engine
    fig.set_size_inches(5.0, 6.0)
    save(fig, tmp_path, "b", ("png",))
    assert fig.axes[0].get_position().bounds != position  # laid out again for the new size
    with pytest.raises(ValueError, match="figure format must be one of png, pdf, svg"):
        save(fig, tmp_path, "c", ("png", "jpeg"))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.pdf", "a.png", "b.png"]


def test_missing_units_finds_a_bare_label():
    fig = Figure()
    ax = fig.subplots()
    ax.plot([0, 1], [0, 1])
    ax.set_xlabel(label("time", "s"))
    ax.set_ylabel("amplitude")
    assert missing_units(fig) == ["axes 0: y label 'amplitude' has no unit"]
    assert label("w1", "rad s-1") == "w1 (rad/s)"


def test_flips_figure_shows_numerical_samples_on_the_exact_curve(analysed):
    ds, body, axis = analysed
    member = tennis.typical_member(ds)
    fig = tennis.flips_figure(ds, body, axis, member=member)
    t = ds.time.values
    exact = stability.exact_omega(body, ds.w0.values[member], t)
    for i, ax in enumerate(fig.axes):
        markers = [line for line in ax.lines if line.get_marker() == "o"]
        assert len(markers) == 1
        x, y = markers[0].get_data()
        np.testing.assert_array_equal(x, t)
        # rk4 at h = 2 ms over two flips: agreement to about 1e-6 of the spin.
        np.testing.assert_allclose(y, exact[:, i], rtol=0, atol=1e-5 * SPIN)
    # The member flipped: its spin-axis component changed sign at least twice.
    assert np.count_nonzero(np.diff(np.signbit(exact[:, axis - 1]))) >= 2


def test_growth_figure_draws_the_analytic_slope(analysed):
    ds, body, axis = analysed
    fig = tennis.growth_figure(ds, body, axis)
    (ax,) = fig.axes
    analytic = [line for line in ax.lines if line.get_label().startswith("analytic slope")]
    assert len(analytic) == 1
    t, y = analytic[0].get_data()
    slope = np.diff(np.log(y)) / np.diff(t)
    np.testing.assert_allclose(slope, ds.attrs["growth_rate_analytic"], rtol=1e-9)
    assert ax.get_yscale() == "log"


def test_work_precision_styles_are_keyed_by_registered_families():
    """Every family style names a family of the registry, so none is silently unused."""
    from stability.free_body.work_precision import figures as work_precision

    families = {spec.family for spec in stability.METHODS.values()}
    assert set(work_precision._FAMILY_STYLE) <= families


def test_covered_data_finds_a_legend_over_the_lines_and_place_legend_clears_it():
    fig = new_figure()
    ax = fig.subplots()
    x = np.linspace(0.0, 1.0, 3)  # three vertices a line: the segments between them count too
    for k in range(8):
        ax.plot(x, np.full_like(x, float(k)), label=f"line {k}")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.legend(loc="center")
    problems = covered_data(fig)
    assert len(problems) == 1 and problems[0].startswith("axes 0: the legend covers ")
    place_legend(ax)  # no clear place inside: beside the axes
    assert covered_data(fig) == []
    ax.plot([0.0, 1.0], [40.0, 40.0], label="apart")  # room between the lines
    # placed again: the legend beside the axes is replaced by one in the room inside
    place_legend(ax)
    assert covered_data(fig) == []
    inside, legend = ax.get_window_extent(), ax.get_legend().get_window_extent()
    assert inside.x0 <= legend.x0 and legend.x1 <= inside.x1  # in the room left inside


def test_the_flip_interval_panels_have_an_axis_in_epsilon_that_gives_their_k_prime(analysed):
    """Beside ln(4/k') alone: a top axis in the nudge epsilon; a member nudged along the axis
    it names sits at the run's epsilon, every other member at or below it."""
    from stability.free_body.measure import complementary_moduli

    ds, body, axis = analysed
    fig = tennis.flip_interval_figure(ds, body, axis)
    middle, right = fig.axes[1], fig.axes[2]
    tops = [child for ax in (middle, right) for child in ax.child_axes]
    assert len(tops) == 2
    to_epsilon, to_x, b = tennis.nudge_for_modulus(body, axis)
    for top in tops:
        assert top.get_xscale() == "log"
        assert f"ε along axis {b} giving k′ (run: 0.0001)" in top.get_xlabel()
        assert "(dimensionless)" in top.get_xlabel()
    w0 = np.zeros((1, 3))
    w0[0, axis - 1], w0[0, b - 1] = SPIN, EPSILON * SPIN
    x = np.log(4.0 / complementary_moduli(body, w0))
    assert to_epsilon(x)[0] == pytest.approx(EPSILON, rel=1e-3)
    assert to_x(EPSILON) == pytest.approx(x[0], rel=1e-4)
    members = np.log(4.0 / ds.complementary_modulus.values)
    assert np.all(to_epsilon(members) <= EPSILON * (1 + 1e-3))
