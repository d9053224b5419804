"""The speed-against-error study: its quick mode end to end, and the pieces it is built from."""

import numpy as np
import pytest
import xarray as xr

import stability
from stability.free_body.work_precision.figures import (
    invariant_drift_figure, work_precision_figure,
)
from stability.free_body.work_precision import measure as wp
from stability.free_body.work_precision.drift import drift_kind
from stability.free_body.accuracy import METRICS
from stability.study import ConfigError, load_study, run_study

from ...helpers import assert_cf_compliant, assert_declared, assert_readable

STUDY_FILE = "studies/work_precision.toml"


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    """The study file in quick mode, run once for the module: (summary, Dataset, folder)."""
    out = tmp_path_factory.mktemp("work_precision")
    summary = run_study(STUDY_FILE, out, quick=True, progress=False)
    ds = xr.open_dataset(out / "work_precision.nc", decode_timedelta=False).load()
    return summary, ds, out


def test_quick_study_writes_dataset_figures_and_table(quick):
    summary, ds, out = quick
    for name in ("work_precision.nc", "work_precision.md", "config.toml",
                 "work_precision.png", "work_precision.pdf",
                 "invariant_drift.png", "invariant_drift.pdf"):
        assert (out / name).is_file(), name
    assert list(ds.method.values) == list(stability.METHODS) + [wp.ADAPTIVE, wp.SCIPY]
    assert list(ds.workload.values) == list(wp.WORKLOADS)
    assert list(ds.metric.values) == list(METRICS)
    for name, var in {**ds.data_vars, **ds.coords}.items():
        if name in ("workload", "method", "sweep", "metric"):
            continue
        assert var.attrs.get("units") is not None and var.attrs.get("long_name"), name
    assert "config_toml" in ds.attrs and ds.attrs["study"] == "work_precision"
    assert (out / "work_precision.md").read_text() == wp.markdown_report(ds)
    assert summary.values["wall_time"] > 0


def test_dataset_follows_cf(quick):
    assert_cf_compliant(quick[2] / "work_precision.nc")


def test_dataset_is_as_the_register_declares(quick):
    assert_declared(quick[2] / "work_precision.nc", "work_precision")


def test_every_method_ran_both_workloads_without_failures(quick):
    _, ds, _ = quick
    for method in stability.METHODS:
        for workload in wp.WORKLOADS:
            sel = ds.sel({"workload": workload, "method": method})
            ran = np.isfinite(sel.wall_time.values)
            assert ran.any(), f"{method} did not run on {workload}"
            assert np.all(sel.failed.values[ran] == 0)
            assert np.all(sel.evaluations.values[ran] == stability.METHODS[method].evaluations
                          * sel.steps.values[ran])


def test_errors_shrink_at_the_declared_order(quick):
    """On the stable ensemble, the max error over the sweep falls like h^p: the fitted slope
    over the points above round-off is within 0.3 of the declared order."""
    _, ds, _ = quick
    fitted = 0
    for method, spec in stability.METHODS.items():
        if spec.is_exact:
            continue
        sel = ds.sel({"workload": "stable", "method": method})
        h = sel.h.values
        err = sel.w_error.sel(metric="max").values
        keep = np.isfinite(err) & (err > 1e-11) & (err < 1e-2)
        if np.count_nonzero(keep) < 3:
            continue
        slope = np.polyfit(np.log(h[keep]), np.log(err[keep]), 1)[0]
        assert abs(slope - spec.order) < 0.3, f"{method}: slope {slope:.2f}"
        fitted += 1
    assert fitted >= 2


def test_scipy_runs_on_the_same_ensembles(quick):
    """DOP853 ran every tolerance: tighter rtol, more evaluations and a smaller error."""
    _, ds, _ = quick
    for workload in wp.WORKLOADS:
        sel = ds.sel({"workload": workload, "method": wp.SCIPY})
        ran = np.isfinite(sel.rtol.values)
        rtol = sel.rtol.values[ran]
        assert np.all(np.diff(rtol) < 0)
        assert np.all(np.diff(sel.evaluations.values[ran]) > 0)
        err = sel.w_error.sel(metric="median").values[ran]
        assert err[-1] < err[0]


def test_the_adaptive_method_runs_its_tolerances_with_error_following_rtol(quick):
    """dopri5 ran each (rtol, atol) of the quick file on both workloads without failures: six
    evaluations per step tried (plus two for the first step), the median error within a
    small multiple of rtol and falling with it (tennis: 3.9e-6 and 1.2e-9 at rtol 1e-6 and
    1e-9; stable: 3.6e-7 and 3.3e-10)."""
    _, ds, _ = quick
    assert float(ds.order.sel({"method": wp.ADAPTIVE})) == 5.0
    for workload in wp.WORKLOADS:
        sel = ds.sel({"workload": workload, "method": wp.ADAPTIVE})
        ran = np.isfinite(sel.rtol.values)
        rtol = sel.rtol.values[ran]
        assert rtol.tolist() == [1e-6, 1e-9] and np.all(sel.failed.values[ran] == 0)
        assert np.allclose(sel.evaluations.values[ran], 6 * sel.steps.values[ran] + 2)
        err = sel.w_error.sel(metric="median").values[ran]
        assert np.all(err < 10 * rtol) and err[1] < err[0] / 100


def test_long_horizon_tells_bounded_from_drifting_errors(quick):
    """Energy error over the long run: round-off only for methods that keep the energy, bounded
    for the other Poisson maps, a linear drift (slope ~1) for the rest."""
    _, ds, _ = quick
    for method, spec in stability.METHODS.items():
        energy = np.abs(ds.drift_energy.sel({"method": method}).values)
        slope = float(ds.drift_slope.sel({"method": method}))
        if spec.preserves_energy or spec.is_exact:
            assert energy.max() < 1e-12, f"{method}: energy error {energy.max():.1e}"
        elif spec.poisson:
            assert drift_kind(slope) == "bounded", f"{method}: slope {slope:.2f}"
        else:
            assert slope == pytest.approx(1.0, abs=0.1), f"{method}: slope {slope:.2f}"
        if spec.preserves_casimir or spec.is_exact:
            momentum = np.abs(ds.drift_momentum.sel({"method": method}).values)
            assert momentum.max() < 1e-13, f"{method}: |L| error {momentum.max():.1e}"


def test_attitude_errors_for_the_methods_that_carry_it(quick):
    """Every method that carries the attitude has attitude errors at every step size, falling
    from the coarsest to the finest step; the others have none. The DOP853 reference is
    checked on its w part against the exact solution."""
    from stability.free_body.attitude import attitude_methods

    _, ds, _ = quick
    carriers = attitude_methods()
    assert float(ds.attitude_reference_error.sel(metric="p99").max()) < 1e-10
    for method in ds.method.values:
        sel = ds.sel({"workload": "stable", "method": method})
        ran = np.isfinite(sel.wall_time.values)
        error = sel.attitude_error.sel(metric="max").values[ran]
        if method in carriers:
            assert np.all(np.isfinite(error)) and np.all(error >= 0), method
            if error.size > 1:
                assert error[-1] < error[0], f"{method}: {error}"
        else:
            assert np.all(np.isnan(error)), method


def test_conditioning_floor_is_measured(quick):
    """One rounding of each start moves the exact w(T) of the tennis ensemble by more than that
    of the stable ensemble: the tennis floor is the one the max error runs into."""
    _, ds, _ = quick
    floor = ds.floor
    assert np.all(np.isfinite(floor.values)) and np.all(floor.values > 0)
    assert float(floor.sel(workload="tennis", metric="max")) > float(
        floor.sel(workload="stable", metric="max"))


def test_markdown_table_names_a_winner_per_accuracy(quick):
    summary, ds, out = quick
    text = (out / "work_precision.md").read_text()
    table = wp.winner_table(ds, "stable")
    assert table in text
    rows = table.splitlines()[2:]
    assert len(rows) == len(wp.TARGETS)
    for target, row in zip(wp.TARGETS, rows):
        cells = [c.strip() for c in row.strip("|").split("|")]
        times = {m: wp.time_to_reach(ds, "stable", m, target) for m in ds.method.values}
        reached = {m: t for m, t in times.items() if np.isfinite(t)}
        if reached:
            assert cells[1] == f"**{min(reached, key=reached.get)}**"
        else:
            assert cells[1] == "none"


def test_figures_label_every_axis_with_units(quick):
    _, ds, _ = quick
    for fig in (work_precision_figure(ds), invariant_drift_figure(ds)):
        assert_readable(fig)


@pytest.mark.parametrize(
    "override, message",
    [
        (("sweep.h_min", "1.0"), r"\[sweep\] h_min must be <= h_max"),
        (("body.moments", "[1.0, 1.0, 1.5]"), r"\[body\] moments must be three distinct"),
        (("sweep.methods", '["rk5"]'), r"\[sweep\] methods must be a list of values from"),
        (("long.samples", "10000000"), r"\[long\] samples must be <= steps"),
        (("adaptive.atols", "[1e-9]"), r"\[adaptive\] atols must give one atol per rtol"),
        (("adaptive.rtols", "[0.0]"), r"\[adaptive\] rtols"),
        (("tennis.membres", "5"), r"unknown key 'membres' \(did you mean 'members'\?\)"),
    ],
)
def test_bad_study_files_get_one_line_naming_the_key(override, message):
    with pytest.raises(ConfigError, match=message):
        load_study(STUDY_FILE, overrides=[override])


def test_default_study_file_is_valid_and_covers_the_registry():
    kind, config, _ = load_study(STUDY_FILE)
    assert kind.name == "work_precision"
    assert config["sweep"]["methods"] == []  # every registered method
    assert config["tennis"]["members"] == 10_000
    assert config["long"]["steps"] >= 1_000_000
