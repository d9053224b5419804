"""The gyroscope study (stability.heavy_top.studies.gyroscope): its claim, its Dataset, its
figures and the top a file sets."""

import tomllib
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from stability.heavy_top.figures import gyroscope_paths_figure, gyroscope_rates_figure
from stability.study import run_study

from ...helpers import assert_cf_compliant, assert_declared, assert_readable, quick_study

ROOT = Path(__file__).resolve().parents[3]
STUDY = ROOT / "studies" / "gyroscope.toml"


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    return quick_study(tmp_path_factory, "gyroscope", threads=1)


def test_study_meets_its_claim_with_units_everywhere(quick):
    summary, out = quick
    v = summary.values
    for name in ("precession_rate", "nutation_frequency", "nutation_amplitude"):
        assert v[f"max_relative_error_{name}"] < v["claim"] == 1e-6
    assert v["members_failed"] == 0
    assert sorted(p.name for p in summary.files) == [
        "config.toml", "gyroscope.nc", "gyroscope_paths.png", "gyroscope_rates.png"]
    with xr.open_dataset(out / "gyroscope.nc") as ds:
        for name, var in {**ds.data_vars, **ds.coords}.items():
            assert var.attrs.get("units") and var.attrs.get("long_name"), name
        assert list(ds.tilt.values) == [60.0] and ds.sizes["spin"] == 4
        # The Dataset records its study, its configuration and the threads it ran on.
        assert ds.attrs["study"] == "gyroscope" and ds.attrs["numba_num_threads"] == 1
        assert tomllib.loads(ds.attrs["config_toml"]) == tomllib.loads(
            (out / "config.toml").read_text())
        assert_readable(gyroscope_paths_figure(ds))
        assert_readable(gyroscope_rates_figure(ds, claim=1e-6))


def test_study_dataset_follows_cf(quick):
    assert_cf_compliant(quick[1] / "gyroscope.nc")


def test_study_dataset_is_as_the_register_declares(quick):
    assert_declared(quick[1] / "gyroscope.nc", "gyroscope")


def test_set_changes_the_top(tmp_path):
    """The body is a key: doubling l doubles M g l and so the fast-top precession rate."""
    runs = [run_study(STUDY, tmp_path / name, quick=True, progress=False,
                      overrides=[("output.figures", "false"), ("spins.count", "2"),
                                 ("top.length", length)])
            for name, length in (("a", "0.04"), ("b", "0.08"))]
    rates = []
    for name in ("a", "b"):
        with xr.open_dataset(tmp_path / name / "gyroscope.nc") as ds:
            rates.append(ds.precession_rate_gyroscopic.values)
    assert np.allclose(rates[1] / rates[0], 2.0, rtol=1e-12)
    assert all(r.values["max_relative_error_precession_rate"] < 1e-6 for r in runs)

