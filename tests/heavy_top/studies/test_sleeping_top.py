"""The sleeping-top study from its file: Dataset, figure and summary against linear theory."""

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from stability.heavy_top.figures import sleeping_top_figure
from stability.study import run_study

from ...helpers import assert_cf_compliant, assert_declared, assert_readable, quick_study

ROOT = Path(__file__).resolve().parents[3]
STUDY = ROOT / "studies" / "sleeping_top.toml"


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    return quick_study(tmp_path_factory, "sleeping_top")


def test_measured_rates_meet_the_claim_and_every_cell_is_on_its_side(quick):
    summary, out = quick
    v = summary.values
    assert v["counted"] >= 4 and v["max_relative_error"] < v["claim"] == 1e-3
    assert v["wrong_side"] == 0
    with xr.open_dataset(out / "sleeping_top.nc") as ds:
        assert float(ds.attrs["critical_spin"]) == pytest.approx(v["critical_spins"][0])
        unstable = ds.growth_rate_analytic.values > 0
        assert unstable.any() and (~unstable).any()
        for name, var in ds.data_vars.items():
            assert var.attrs.get("units") and var.attrs.get("long_name"), name


def test_files_and_a_figure_with_units_on_every_axis(quick):
    summary, out = quick
    assert sorted(p.name for p in summary.files) == ["config.toml", "sleeping_top.nc",
                                                      "sleeping_top.png"]
    with xr.open_dataset(out / "sleeping_top.nc") as ds:
        assert_readable(sleeping_top_figure(ds, claim=1e-3))


def test_dataset_follows_cf(quick):
    assert_cf_compliant(quick[1] / "sleeping_top.nc")


def test_dataset_is_as_the_register_declares(quick):
    assert_declared(quick[1] / "sleeping_top.nc", "sleeping_top")


def test_set_changes_the_top_and_moves_the_threshold(tmp_path):
    """The body's numbers are keys: a longer l raises the critical spin as sqrt(A M g l) / C."""
    base = run_study(STUDY, tmp_path / "a", quick=True, progress=False,
                     overrides=[("output.figures", "false"), ("spins.count", "3")])
    longer = run_study(STUDY, tmp_path / "b", quick=True, progress=False,
                       overrides=[("output.figures", "false"), ("spins.count", "3"),
                                  ("top.lengths", "[0.08]")])
    m, r2 = 0.1, 2.25e-5
    ratio = np.sqrt((r2 + m * 0.08**2) * 0.08 / ((r2 + m * 0.04**2) * 0.04))
    assert longer.values["critical_spins"][0] / base.values["critical_spins"][0] == \
        pytest.approx(ratio, rel=1e-12)


def test_the_summary_says_in_words_what_it_has_no_number_for(quick):
    """Quick mode fits no cell near the threshold: the summary says so, not "nan"."""
    summary, _ = quick
    assert "nan" not in summary.table()
    assert "nearer the threshold: no fitted cell below 0.1 x its zero-spin rate" in (
        summary.table())
