"""The stability map: the grid of shapes, a small map within the accuracy bar, its edges."""

import math
import re
import tomllib

import numpy as np
import pytest

import stability
from stability.util.conventions import REGIME_ALGEBRAIC, REGIME_NEUTRAL
from stability.free_body.stability_map import figures as figures
from stability.free_body.stability_map.shapes import EDGE_EQUAL_12, EDGE_EQUAL_23
from stability.study import ConfigError, load_study, run_study

from ...helpers import assert_cf_compliant, assert_declared, assert_readable

STUDY_FILE = "studies/stability_map.toml"


def test_study_file_errors_name_the_key():
    with pytest.raises(ConfigError, match=r"\[integration\] h must give one step per method"):
        load_study(STUDY_FILE, overrides=[("integration.h", "[0.1]")])
    with pytest.raises(ConfigError, match=r"\[flips\] shapes pair \(0.2, 0.3\)"):
        load_study(STUDY_FILE, overrides=[("flips.shapes", "[0.2, 0.3]")])
    with pytest.raises(ConfigError, match=r"\[analysis\] window_high"):
        load_study(STUDY_FILE, overrides=[("ensemble.epsilon", "1e-4"),
                                          ("analysis.window_low", "300.0")])


@pytest.fixture(scope="module")
def small_map(tmp_path_factory):
    """A 9-shape map (divisions 3: interior, every edge and the sphere) with rk4 and exact."""
    out = tmp_path_factory.mktemp("map")
    summary = run_study(
        STUDY_FILE, out, quick=True, progress=False,
        overrides=[
            ("grid.divisions", "3"), ("ensemble.members", "16"),
            ("integration.methods", '["rk4", "exact"]'), ("integration.h", "[0.1, 0.1]"),
            ("integration.bias_stride", "3"), ("flips.shapes", "[0.25, 0.75]"),
            ("flips.epsilons", "[1e-2, 1e-4, 1e-6]"), ("edges.t_end", "60.0"),
            ("ftle.run", "true"), ("ftle.divisions", "4"),
            ("output.formats", '["png"]'),
        ],
    )
    return summary, stability.load(out / "stability_map.nc")


def test_small_map_meets_the_accuracy_bar(small_map):
    summary, ds = small_map
    norm = ds.omega_squared_normalised.values
    bar = np.abs(norm) > 1e-3
    # Omega^2 = 0 exactly where the spin axis's moment equals another one (the equal-moment
    # edges): every other (shape, axis) of this grid is under the bar.
    moments = np.stack([ds.I1.values, ds.I2.values, ds.I3.values], axis=1)
    equal = np.array([[np.sum(I == I[a]) > 1 for a in range(3)] for I in moments])
    np.testing.assert_array_equal(bar, ~equal)
    assert bar.sum() == 14
    rel = ds.relative_error.values[:, bar]
    assert np.all(np.isfinite(rel))
    assert np.max(np.abs(rel)) < 1e-3
    assert np.all(ds.sign_agrees.values == 1)
    assert summary.values["all_passed"]
    # Measured sign follows the analytic one wherever a rate was measured.
    measured = ds.omega_squared_measured.values
    ok = np.isfinite(measured)
    assert np.all(np.sign(measured[ok]) == np.sign(np.broadcast_to(norm, measured.shape)[ok]))
    # The bias check ran at h/2 on every third shape, and rk4's bias there is tiny.
    bias = ds.step_bias.sel(integrator="rk4").values
    assert np.isfinite(bias[::3][bar[::3]]).all()
    assert np.nanmax(np.abs(bias)) < 1e-4


def test_small_map_classifies_the_edges_instead_of_fitting(small_map):
    _, ds = small_map
    zero = ds.omega_squared.values == 0.0
    sphere = ds.edge.values == (EDGE_EQUAL_12 | EDGE_EQUAL_23)
    regime = ds.regime.values
    assert np.all(regime[:, sphere, :] == REGIME_NEUTRAL)
    drift = zero & ~sphere[:, None]
    assert drift.sum() == 10  # five equal-moment shapes besides the sphere, two axes each
    assert np.all(regime[:, drift] == REGIME_ALGEBRAIC)
    assert np.all(np.isnan(ds.omega_squared_measured.values[:, zero]))
    assert np.all(ds.n_flips_mean.values[:, zero] == 0)
    # Flips happen exactly on the unstable axes, and match the exact 2K/nu.
    unstable = ds.omega_squared.values < 0
    assert np.all(ds.n_flips_mean.values[:, unstable] >= 2)
    assert np.all(ds.n_flips_mean.values[:, ~unstable] == 0)
    assert np.nanmax(np.abs(ds.flip_interval_relative_error.values[:, unstable])) < 1e-3


def test_edge_series_drift_linearly_with_the_distinct_component_fixed(small_map):
    _, ds = small_map
    for c, name in enumerate(ds.edge_case.values):
        assert float(ds.edge_distinct_change[c]) == 0.0
        assert int(ds.edge_flips[c]) == 0
        predicted = float(ds.edge_slope_predicted[c])
        if name == "sphere":
            assert predicted == 0.0 and int(ds.edge_regime[c]) == REGIME_NEUTRAL
            continue
        assert float(ds.edge_slope_measured[c]) == pytest.approx(predicted, rel=1e-3)
        assert int(ds.edge_regime[c]) == REGIME_ALGEBRAIC
        assert float(ds.edge_linear_residual[c]) < 0.1 * float(ds.edge_exponential_residual[c])


def test_flip_sweep_follows_the_exact_interval_and_the_log_law(small_map):
    _, ds = small_map
    exact = ds.sweep_flip_interval_exact.values[0]
    measured = ds.sweep_flip_interval.sel(integrator="rk4").values[0]
    np.testing.assert_allclose(measured, exact, rtol=1e-4)
    # Epsilon falls by 100 per point: each adds (2 / lambda) ln 100 to the asymptote
    # (2 / lambda) ln(4 / k'), since k' is proportional to epsilon up to O(epsilon^2).
    lam = float(ds.sweep_growth_rate[0])
    steps = np.diff(ds.sweep_flip_interval_asymptote.values[0])
    np.testing.assert_allclose(steps, 2 / lam * math.log(100.0), rtol=1e-4)
    np.testing.assert_allclose(exact, ds.sweep_flip_interval_asymptote.values[0], rtol=2e-3)


def test_dataset_is_labelled_and_figures_carry_units(small_map):
    summary, ds = small_map
    for name, var in ds.data_vars.items():
        assert "long_name" in var.attrs and "units" in var.attrs, name
    for name in ("I1", "I2", "I3", "h", "level", "epsilon", "edge_time"):
        assert ds[name].attrs["units"], name
    assert np.all(ds.status.values == 0) and np.all(ds.members_failed.values == 0)
    assert {"shape", "axis", "integrator"} <= set(ds.dims)
    assert {"I1", "I2", "I3"} <= set(ds.coords)
    for make in (figures.map_figure, figures.scatter_figure, figures.flip_interval_figure,
                 figures.edges_figure):
        assert_readable(make(ds))
    names = {p.name for p in summary.files}
    assert {"fig1_map.png", "fig4_edges.png", "stability_map.nc", "config.toml"} <= names
    rows = dict((r[0], r[1]) for r in summary.rows)
    assert any("peak memory" in key for key in rows)
    # Provenance as every study writes it: the kind, the configuration, a dated history line.
    assert ds.attrs["study"] == "stability_map"
    assert tomllib.loads(ds.attrs["config_toml"]) == tomllib.loads(
        (summary.out_dir / "config.toml").read_text())
    assert re.fullmatch(r"\d{4}-\d\d-\d\dT[\d:]+Z: stability run \(stability_map\)",
                        ds.attrs["history"])


def test_the_edges_figure_says_in_words_when_a_misfit_was_not_fitted(small_map):
    """The neutral sphere's amplitude never leaves its start: no misfit, said in words."""
    from stability.free_body.stability_map.figures import edges_figure

    _, ds = small_map
    texts = [t.get_text() for ax in edges_figure(ds).axes for t in ax.texts]
    assert texts and not any("nan" in text for text in texts)
    assert any("not fitted" in text for text in texts)


def test_the_maps_ftle_is_the_ftle_maps_and_within_the_linear_bound(small_map):
    """``[ftle] run``: the study's FTLE part is :func:`ftle_map`'s, bitwise, every real cell's
    FTLE lies in [sigma, sigma + log((1 + rho) / 2) / T], and figure 5 is drawn."""
    from stability.free_body.stability_map.ftle_map import ftle_map
    from stability.free_body.stability_map.study import ftle_part

    summary, ds = small_map
    part = ftle_part(ds)
    direct = ftle_map(4, axis=2, spin=1.0, horizon=10.0, epsilon=1e-8, members=2, windows=10,
                      seed=1)
    for name in direct.variables:
        assert np.array_equal(part[name].values, direct[name].values, equal_nan=True), name
    assert summary.values["ftle_cells_within"] == summary.values["ftle_cells"] > 0
    assert "fig5_ftle_map.png" in {p.name for p in summary.files}
    assert_readable(figures.ftle_map_figure(part))


def test_dataset_follows_cf(small_map):
    assert_cf_compliant(small_map[0].out_dir / "stability_map.nc")


def test_dataset_is_as_the_register_declares(small_map):
    assert_declared(small_map[0].out_dir / "stability_map.nc", "stability_map")
