"""The dual-spin study: quick run, its Dataset (CF, units, declared), figures, summary and bad
input."""

import tomllib

import numpy as np
import pytest
import xarray as xr

from stability.dissipation.figures import dual_spin_map_figure, dual_spin_rate_figure

from ...helpers import (
    assert_cf_compliant, assert_declared, assert_readable, bad_study_line, quick_study,
)


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    return quick_study(tmp_path_factory, "dual_spin")


def test_study_meets_its_claims(quick):
    summary, _ = quick
    v = summary.values
    assert v["cells"] == 108 and v["members"] == 108 and v["members_failed"] == 0
    assert v["members_fitted"] >= 100
    assert v["max_rate_error"] <= v["claim"] == 1e-3
    assert v["measured_vs_linear"] == v["cells"]
    # One damper: the criterion's sign is exact. One on each, the platform's at c* and the
    # rotor's at 0.3 c*: wrong in a cell or two along the boundary.
    per = v["placements"]
    assert per["platform"]["sink_vs_linear"] == per["rotor"]["sink_vs_linear"] == 36
    assert 33 <= per["both"]["sink_vs_linear"] < 36
    assert v["max_angular_momentum_drift"] < 1e-10 and v["max_energy_rise"] < 1e-15
    table = summary.table()
    assert "cells where the energy-sink criterion agrees with the eigenvalues" in table
    assert "measured = eigenvalue" in table


def test_the_maps_show_dual_spin_stabilisation(quick):
    """A minor-axis body (A3 / A_t = 0.5): with the damper on the platform the nutation grows
    with the rotor slow and decays with it fast; with the damper in the rotor the reverse."""
    with xr.open_dataset(quick[1] / "dual_spin.nc") as ds:
        minor = ds.sel(ratio=0.5)
        platform = minor.verdict_measured.sel(placement="platform").values
        rotor = minor.verdict_measured.sel(placement="rotor").values
        speed = minor.speed.values
    assert np.all(platform[speed > 2.0] == 1) and np.all(platform[speed < 2.0] == 0)
    assert np.all(rotor[speed > -0.67] == 0) and np.all(rotor[speed < -0.67] == 1)


def test_dataset_has_units_everywhere_and_records_its_study(quick):
    summary, out = quick
    assert sorted(p.name for p in summary.files) == [
        "config.toml", "dual_spin.nc", "dual_spin_map.png", "dual_spin_rates.png"]
    with xr.open_dataset(out / "dual_spin.nc") as ds:
        for name, var in {**ds.data_vars, **ds.coords}.items():
            assert var.attrs.get("units") and var.attrs.get("long_name"), name
        assert list(ds.placement.values) == ["platform", "rotor", "both"]
        assert ds.ratio.size == ds.speed.size == 6 and list(ds.start.values) == [0.001]
        assert ds.rate_measured.dims == ("placement", "ratio", "speed", "start")
        assert ds.attrs["study"] == "dual_spin"
        assert tomllib.loads(ds.attrs["config_toml"]) == tomllib.loads(
            (out / "config.toml").read_text())
        # Each damper at its multiple of c* = J h / A_t in every cell.
        star = 5.0 * ds.axial_momentum / 100.0
        assert np.allclose(ds.c_platform.sel(placement="platform"), 1.0 * star)
        assert np.allclose(ds.c_rotor.sel(placement="both"), 0.3 * star)
        assert float(ds.c_rotor.sel(placement="platform").max()) == 0.0


def test_dataset_follows_cf(quick):
    assert_cf_compliant(quick[1] / "dual_spin.nc")
    assert_declared(quick[1] / "dual_spin.nc", "dual_spin")


def test_figures_carry_units_and_clear_legends(quick):
    with xr.open_dataset(quick[1] / "dual_spin.nc") as ds:
        ds = ds.load()
    for figure in (dual_spin_map_figure(ds), dual_spin_rate_figure(ds, claim=1e-3)):
        assert_readable(figure)




@pytest.mark.parametrize("text, fragment", [
    ("[map]\nratio_max = 0.4\n", "[map] ratio_max must exceed ratio_min = 0.5"),
    ("[map]\nratio_min = 0.2\n", "[map] ratio_min times [body] transverse must exceed"),
    ("[map]\nspeed_min = -3.0\n", "[map] speed_min must keep the axial momentum"),
    ("[map]\nratios = 1\n", "[map] ratios must be an integer >= 2"),
    ("[dampers]\nplacements = []\n", "[dampers] placements must list at least one"),
    ("[dampers]\nplacements = [\"rotor\", \"rotor\"]\n", "[dampers] placements must list"),
    ("[dampers]\nplacements = [\"wheel\"]\n", "[dampers] placements must be a list of values"),
    ("[dampers]\nplatform = 0.0\n", "[dampers] platform must be a number > 0"),
    ("[start]\nangles = [0.001, 0.1]\n", "[start] angles must be below [analysis] fit_top"),
    ("[start]\nangles = []\n", "[start] angles must list at least one angle"),
    ("[body]\nrotor = -1.0\n", "[body] rotor must be a number > 0"),
    ("[integration]\nstep_angle = 2.0\n", "[integration] step_angle must be a number > 0"),
    ("[run]\nscheduler = \"somewhere\"\n", "[run] scheduler must be ''"),
    ("[integration]\nsamples = 10000000000000\n", "TiB in memory"),
])
def test_bad_study_files_are_one_line_and_run_nothing(tmp_path, capsys, text, fragment):
    line = bad_study_line(tmp_path, capsys, "dual_spin", text)
    assert fragment in line, line
