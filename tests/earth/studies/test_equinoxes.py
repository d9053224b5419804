"""The equinoxes study (stability.earth.studies.equinoxes): its Dataset, the published values and
its quick mode."""

import numpy as np
import pytest
import xarray as xr

from stability.earth.figures import equinoxes_figure
from stability.earth.scene import figure_axes

from ...helpers import assert_cf_compliant, assert_declared, assert_readable, quick_study


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    return quick_study(tmp_path_factory, "equinoxes")


def test_dataset_follows_cf(quick):
    assert_cf_compliant(quick[1] / "equinoxes.nc")


def test_dataset_is_as_the_register_declares(quick):
    assert_declared(quick[1] / "equinoxes.nc", "equinoxes")


def test_study_meets_the_published_values_and_the_formula(quick):
    """40 years, two members: precession within 1% of IAU 2006 (measured -0.16%) and 1e-4 of
    the averaged formula; Sun + Moon = both to 1e-4; nutation within 1% of IAU 1980; the
    averaged model within 1e-4 of the full one; the step error far below."""
    summary, out = quick
    v = summary.values
    assert abs(v["relative_to_published"]) < v["claim"] == 0.01
    assert abs(v["relative_to_formula"]) < 1e-4
    assert v["sun"] + v["moon"] == pytest.approx(v["precession_rate"], rel=1e-4)
    assert abs(v["nutation_longitude_relative"]) < 0.01
    assert abs(v["nutation_obliquity_relative"]) < 0.01
    assert v["averaged_rate"] == pytest.approx(v["precession_rate"], rel=1e-4)
    assert v["step_error"] < 1e-5
    with xr.open_dataset(out / "equinoxes.nc") as ds:
        for name, var in {**ds.data_vars, **ds.coords}.items():
            assert var.attrs.get("units") and var.attrs.get("long_name"), name
        assert_readable(equinoxes_figure(ds))
        k = figure_axes(np.zeros((1, 8)) + [0, 0, 1, 1, 0, 0, 0, 0])
        assert np.allclose(k, [[0.0, 0.0, 1.0]])


def test_quick_mode_says_it_ran_no_full_turn_and_draws_no_empty_panel(quick):
    from stability.earth.figures import equinoxes_figure

    summary, out = quick
    assert "nan" not in summary.table() and "cycle_years = 0" in summary.table()
    with xr.open_dataset(out / "equinoxes.nc") as ds:
        assert len(equinoxes_figure(ds).axes) == 2  # no third, empty, panel
