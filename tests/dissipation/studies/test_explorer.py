"""The Explorer study (stability.dissipation.studies.explorer): quick run, its Dataset (CF,
units), figures, summary and bad input."""

import tomllib
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from stability.dissipation import model
from stability.dissipation.figures import end_state_figure, flat_time_figure, nutation_figure

from ...helpers import (
    assert_cf_compliant, assert_declared, assert_readable, bad_study_line, quick_study,
)

ROOT = Path(__file__).resolve().parents[3]


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    return quick_study(tmp_path_factory, "explorer")


def test_study_meets_its_claims(quick):
    summary, _ = quick
    v = summary.values
    assert v["members"] == 6 and v["members_fitted"] >= 3
    assert v["max_growth_rate_error"] <= v["claim"] == 1e-3
    assert v["max_decay_rate_error"] <= v["claim"] and v["members_fitted_decay"] == 6
    assert v["members_major_axis"] == 6 and v["members_failed"] == 0
    assert v["max_angular_momentum_drift"] <= v["drift_claim"] == 1e-12
    assert v["max_energy_rise"] == 0.0 and v["max_end_energy_error"] < 1e-5
    assert v["energy_lost_error_smallest_angle"] < 1e-6  # sin^2(0.02 degrees) = 1.2e-7
    assert v["c_linear_optimum"] == pytest.approx(v["c_energy_sink_optimum"], rel=2e-2)
    linear, sink = v["growth_rate_at_c_star"]
    assert sink == pytest.approx(linear, rel=2e-2)
    assert v["whip_max_growth_rate_error"] <= 1e-3 and v["whip_members_major_axis"] == 1
    assert "growth rate vs linear eigenvalue" in summary.table()


def test_quick_summary_says_the_physics_changed(quick):
    """The quick run's heavier sphere and whips are printed with the values they replace."""
    text = " ".join(quick[0].table().split())
    assert "damper.inertia = 0.001 (the file: 0.0001)" in text
    assert "whips.mass = 0.4 (the file: 0.02)" in text
    assert "the physics changes too" in text


def test_dataset_has_units_everywhere_and_records_its_study(quick):
    summary, out = quick
    assert sorted(p.name for p in summary.files) == [
        "config.toml", "explorer.nc", "explorer_end_state.png", "explorer_flat_time.png",
        "explorer_nutation.png"]
    with xr.open_dataset(out / "explorer.nc") as ds:
        for name, var in {**ds.data_vars, **ds.coords}.items():
            assert var.attrs.get("units") and var.attrs.get("long_name"), name
        assert list(ds.damping.values) == [0.3, 1.0, 3.0]
        assert list(ds.angle.values) == [0.02, 1.0]
        assert ds.theta.dims == ("damping", "angle", "sample")
        assert ds.attrs["study"] == "explorer" and "NSSDC" in ds.attrs["body_sources"]
        assert tomllib.loads(ds.attrs["config_toml"]) == tomllib.loads(
            (out / "config.toml").read_text())
        # The flat spin is reached sooner near the optimum than either side of it.
        flat = ds.flat_time.values
        assert np.all(flat[1] < flat[0]) and np.all(flat[1] < flat[2])


def test_dataset_follows_cf(quick):
    assert_cf_compliant(quick[1] / "explorer.nc")
    assert_declared(quick[1] / "explorer.nc", "explorer")


def test_figures_carry_units_and_clear_legends(quick):
    with xr.open_dataset(quick[1] / "explorer.nc") as ds:
        ds = ds.load()
    for figure in (nutation_figure(ds), flat_time_figure(ds), end_state_figure(ds, claim=1e-3)):
        assert_readable(figure)




@pytest.mark.parametrize("text, fragment", [
    ("[start]\nangles = [1.0, 85.0]\n", "[start] angles must be below [analysis] flat_angle"),
    ("[whips]\nangles = []\n", "[whips] angles must list at least one angle"),
    ("[damper]\ndampings = []\n", "[damper] dampings must list at least one damping"),
    ("[damper]\ndampings = [1.0, -2.0]\n", "[damper] dampings must be a list of numbers"),
    ("[damper]\ninertia = 0.0\n", "[damper] inertia must be a number > 0"),
    ("[body]\nlength = 0.1\n", "[body] length must exceed sqrt(3)/2 times the diameter"),
    ("[integration]\nmethod = \"lp8\"\n", "[integration] method must be one of"),
    ("[integration]\nstep_angle = 3.0\n", "[integration] step_angle must be a number > 0"),
    ("[analysis]\nflat_angle = 90.0\n", "[analysis] flat_angle must be a number > 0"),
    ("[run]\nscheduler = \"somewhere\"\n", "[run] scheduler must be ''"),
    ("[body]\nmoments = [120.0, 135.0, 150.0]\nlength = 2.0\n",
     "[body] give only one of moments, length"),
    ("[body]\nmoments = [120.0, 135.0, 150.0]\naxis = 3\n",
     "[body] moments are refused: the spin axis's moment 150 kg m2 must be the smallest"),
    ("[body]\nmoments = [120.0, 135.0, 300.0]\n", "violate the triangle inequality"),
    ("[body]\naxis = 2\n", "[body] axis is for a body given by moments"),
    ("[body]\nmoments = [120.0, 135.0, 150.0]\nrate = 2.0\n[damper]\ninertia = 1.0\n",
     "[integration] step_angle makes h times the damper's fastest relaxation rate"),
    ("[integration]\nsamples = 10000000000000\n", "TiB in memory"),
])
def test_bad_study_files_are_one_line_and_run_nothing(tmp_path, capsys, text, fragment):
    line = bad_study_line(tmp_path, capsys, "explorer", text)
    assert fragment in line, line


def test_measured_moments_turn_over_as_their_eigenvalues_say(tmp_path):
    """studies/spinner.toml: measured moments (120, 135, 150 kg m2) spun at 2 rad/s about the
    least, a damper; the fitted rates meet the eigenvalues (fitted to the angle the rigid motion
    keeps: the angle itself swings on unequal moments) and every member ends in the flat spin."""
    from stability.study import run_study

    summary = run_study(ROOT / "studies" / "spinner.toml", tmp_path, progress=False, overrides=[
        ("damper.dampings", "[1.0]"), ("start.angles", "[0.02, 1.0]"),
        ("integration.samples", "600"), ("output.formats", "['png']")])
    v = summary.values
    assert v["members_fitted"] == 1 and v["max_growth_rate_error"] <= v["claim"]
    assert v["max_decay_rate_error"] <= v["claim"] and v["members_major_axis"] == 2
    with xr.open_dataset(tmp_path / "explorer.nc") as ds:
        assert list(ds.attrs["moments"]) == [120.0, 135.0, 150.0] and ds.attrs["spin"] == 2.0
        assert "length" not in ds.attrs and ds.attrs["body"].startswith("satellite")
        linear = model.nutation_growth_rate(ds.attrs["moments"], 1.0, float(ds.c[0]), 2.0)
        assert float(ds.growth_rate_linear[0, 0]) == pytest.approx(linear, rel=1e-3)
        assert ds.attrs["c_linear_optimum"] == pytest.approx(model.best_damping(
            ds.attrs["moments"], 1.0, 2.0))
