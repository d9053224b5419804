"""The rigid Earth's free wobble: published moments, Euler's period, the cones, the study."""

import math
from pathlib import Path

import pytest
import xarray as xr

import stability
from stability.earth.model import (
    ARCSEC, DYNAMICAL_ELLIPTICITY, SIDEREAL_DAY, earth, earth_moments, euler_period,
    oblate_euler_period,
)
from stability.earth.figures import wobble_cones_figure
from stability.study import run_study
from stability.earth.wobble import measure_free_wobble

from ..helpers import assert_cf_compliant, assert_declared, assert_readable

ROOT = Path(__file__).resolve().parents[2]
SPIN = 2.0 * math.pi / SIDEREAL_DAY


def test_moments_reproduce_the_published_ratios():
    A, B, C = earth_moments()
    assert (C - 0.5 * (A + B)) / C == pytest.approx(DYNAMICAL_ELLIPTICITY, rel=1e-12)
    assert C / (5.9722e24 * 6378136.6**2) == pytest.approx(0.3307, rel=1e-12)
    # Literature notes 5.1: A / (C - A) = 304.46 sidereal days = 303.6 solar days.
    assert oblate_euler_period((A, B, C), SPIN) / SIDEREAL_DAY == pytest.approx(304.46, abs=0.01)
    assert oblate_euler_period((A, B, C), SPIN) / 86400 == pytest.approx(303.6, abs=0.05)


@pytest.fixture(scope="module")
def wobble():
    return measure_free_wobble(earth(), SPIN, 0.3 * ARCSEC, members=6, periods=2.0,
                               options=stability.RunOptions(progress=False))


def test_measured_period_is_eulers_to_1e_9(wobble):
    assert abs(float(wobble.relative_error)) < 1e-9
    assert float(wobble.wobble_period_euler) == pytest.approx(
        euler_period(earth().moments, SPIN) / 86400, rel=1e-15)
    assert 300 < float(wobble.wobble_period_measured) < 310
    assert "not rigid" in wobble.attrs["chandler_note"]
    assert wobble.attrs["chandler_period_days"] == 433.0


def test_cones_have_the_angles_of_the_theory(wobble):
    """The rotation axis stays 0.3 arcsec from the figure axis (the body cone, to the
    triaxial wobble's small ellipticity) and H times that from L (the space cone); the figure
    axis is (1 - H) times 0.3 arcsec from L."""
    body = wobble.body_cone_angle.values
    assert abs(body - 0.3).max() < 1e-3 * 0.3 * 20  # (B - A) / (C - A) ~ 0.7 % ellipticity
    ratio = float(wobble.space_cone_angle.mean()) / float(wobble.body_cone_angle.mean())
    assert ratio == pytest.approx(DYNAMICAL_ELLIPTICITY, rel=0.01)
    assert_readable(wobble_cones_figure(wobble))


def test_study_runs_from_its_file(tmp_path):
    summary = run_study(ROOT / "studies" / "earth_wobble.toml", tmp_path, quick=True,
                        progress=False, overrides=[("output.formats", "['png']")])
    assert abs(summary.values["relative_error"]) < 1e-9
    with xr.open_dataset(tmp_path / "earth_wobble.nc") as ds:
        for name, var in ds.data_vars.items():
            assert var.attrs.get("units") and var.attrs.get("long_name"), name
    assert (tmp_path / "earth_wobble.png").exists()
    assert_cf_compliant(tmp_path / "earth_wobble.nc")
    assert_declared(tmp_path / "earth_wobble.nc", "earth_wobble")
