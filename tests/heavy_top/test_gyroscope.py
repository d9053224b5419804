"""The gyroscope: periodic-signal measurement, released tops against the exact motion, the study."""

import tomllib
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import stability
from stability.heavy_top import exact as exact_top
from stability.heavy_top.figures import gyroscope_paths_figure, gyroscope_rates_figure
from stability.heavy_top.measure import measure_gyroscopes
from stability.analysis.periodic import extrema, level_crossings, mean_period, weighted_mean
from stability.study import run_study
from stability.heavy_top.model import (
    HeavyTop, gyroscopic_nutation_amplitude, gyroscopic_nutation_frequency,
    gyroscopic_precession_rate, tilted_starts,
)

from ..helpers import assert_cf_compliant, assert_declared, assert_readable, quick_study

ROOT = Path(__file__).resolve().parents[2]
STUDY = ROOT / "studies" / "gyroscope.toml"
#: The literature's worked example (notes 5.3): a 0.1 kg disk of radius 3 cm, 4 cm from the pivot.
DISK = HeavyTop.disk(0.1, 0.03, 0.04)


# ---------------------------------------------------------------------------------------------
# Measuring periodic signals


def _signal(t, w=2.7):
    """x = cos(w t) + 0.3 cos(2 w t) and its derivative: minima -0.7167 at cos(wt) = -5/6."""
    return (np.cos(w * t) + 0.3 * np.cos(2 * w * t),
            -w * np.sin(w * t) - 0.6 * w * np.sin(2 * w * t))


def test_hermite_crossings_and_turning_points_converge_at_fourth_order():
    """Period, crossing levels and minima of a two-harmonic signal sampled 16, 32 and 64 times
    a period (not a whole number of samples a period): errors fall by more than 2^3 per halving
(fourth order, ~16 asymptotically) and reach 1e-6."""
    w = 2.7
    lowest = 0.6 * (5 / 6) ** 2 - 5 / 6 - 0.3  # x = 0.6 c^2 + c - 0.3, min at c = cos(w t) = -5/6
    errors = []
    for per_period in (16, 32, 64):
        t = np.arange(0.0, 20 * 2 * np.pi / w, 2 * np.pi / w / (per_period + 0.37)) + 0.123
        x, dx = _signal(t, w)
        up = level_crossings(t, x, dx, 0.1)
        down = level_crossings(t, x, dx, 0.1, direction=-1)
        _, lows = extrema(t, x, dx, "min")
        assert up.size == down.size == 20 and lows.size == 40  # two minima a period
        assert np.all(_signal(up, w)[1] > 0) and np.all(_signal(down, w)[1] < 0)
        errors.append([abs(mean_period(up) * w / (2 * np.pi) - 1.0),
                       np.abs(_signal(np.concatenate([up, down]), w)[0] - 0.1).max(),
                       np.abs(lows - lowest).max()])
    errors = np.array(errors)
    assert np.all(errors[:-1] / errors[1:] > 2**3), errors
    assert errors[-1].max() < 1e-6


def test_weighted_mean_converges_faster_than_the_plain_mean():
    """Over 40 periods the bump-weighted mean of a periodic signal is right to 1e-11 where the
    plain mean over a window of 40.5 periods is off by ~1e-3."""
    w = 2.7
    t = np.linspace(0.0, 40.5 * 2 * np.pi / w, 40 * 32)
    f = 1.5 + np.cos(w * t) ** 3 + 0.2 * np.sin(3 * w * t) + 0.5 / (1.2 + np.cos(w * t))
    exact = 1.5 + 0.5 / np.sqrt(1.2**2 - 1.0)
    assert abs(weighted_mean(f) - exact) < 1e-11
    assert abs(f.mean() - exact) > 1e-4


def test_extrema_refuses_an_unknown_kind():
    with pytest.raises(ValueError, match="kind must be 'min' or 'max'"):
        extrema([0.0, 1.0], [0.0, 1.0], [1.0, 1.0], "peak")


# ---------------------------------------------------------------------------------------------
# Releases


def test_tilted_starts_set_the_euler_angle_rates():
    """phi' = (w1 g1 + w2 g2) / (g1^2 + g2^2), theta' = -u' / sin(theta), w3 = spin."""
    x = tilted_starts(300.0, 0.7, 5, top=DISK, seed=3, tilt_rate=0.4,
                      precession_rate=np.linspace(-2.0, 2.0, 5))
    A, B, C = DISK.pivot_moments
    w = x[:, :3] / [A, B, C]
    g = x[:, 3:]
    assert np.allclose(np.linalg.norm(g, axis=1), 1.0, atol=1e-15)
    assert np.allclose(w[:, 2], 300.0, rtol=1e-15)
    phi_rate = (w[:, 0] * g[:, 0] + w[:, 1] * g[:, 1]) / (g[:, 0] ** 2 + g[:, 1] ** 2)
    assert np.allclose(phi_rate, np.linspace(-2.0, 2.0, 5), atol=1e-12)
    u_rate = np.cross(g, w)[:, 2]
    assert np.allclose(-u_rate / np.sin(0.7), 0.4, atol=1e-12)


def test_the_worked_example_of_the_notes():
    """Disk top at w3 = 314 rad/s released at rest horizontally (the notes: W = 2.78 rad/s,
    w_n = 77.5 rad/s, 4.1 degrees), against references written out here.

    Released at rest at u = cos(theta) = 0, the energy and p_phi give
    u'^2 = f(u) = beta u (u - u2)(u - u3) with beta = 2 M g l / A, a = C w3 / A and u2, u3 the
    roots of beta u^2 - a^2 u - beta (Goldstein, section 5.7): u2 is the lowest point, the
    period is twice the integral of du / sqrt(f) from u2 to 0 and phi' = -a u / (1 - u^2),
    integrated by quadrature with the 1 / sqrt end-point weights. The fast-top values are
    M g l / (C w3), C w3 / A and 2 A M g l / (C w3)^2.
    """
    from scipy.integrate import quad

    w3 = 314.0
    x0 = tilted_starts(w3, np.pi / 2, 1, top=DISK)
    A, _, C = DISK.pivot_moments
    mgl = DISK.mgl
    a, beta = C * w3 / A, 2.0 * mgl / A
    u2, u3 = sorted(np.roots([beta, -a * a, -beta]).real)
    weight = {"weight": "alg", "wvar": (-0.5, -0.5), "epsabs": 0.0, "epsrel": 1e-13}

    def half_period_integral(g):  # integral of g(u) du / sqrt(f(u)) from u2 to 0
        return quad(lambda u: g(u) / np.sqrt(beta * (u3 - u)), u2, 0.0, **weight)[0]

    period = 2.0 * half_period_integral(lambda u: 1.0)
    precession = 2.0 * half_period_integral(lambda u: -a * u / (1.0 - u * u)) / period
    amplitude = np.degrees(np.arccos(u2) - np.pi / 2)
    assert exact_top.mean_precession_rate(x0, A, C, mgl)[0] == pytest.approx(precession,
                                                                              rel=1e-10)
    assert exact_top.nutation_period(x0, A, C, mgl)[0] == pytest.approx(period, rel=1e-10)
    u1_code, u2_code, _ = exact_top.nutation_roots(x0, A, C, mgl)
    assert np.degrees(np.arccos(u1_code) - np.arccos(u2_code))[0] == pytest.approx(
        amplitude, rel=1e-10)
    assert gyroscopic_precession_rate(DISK, w3) == pytest.approx(mgl / (C * w3), rel=1e-14)
    assert gyroscopic_nutation_frequency(DISK, w3) == pytest.approx(a, rel=1e-14)
    assert gyroscopic_nutation_amplitude(DISK, w3, np.pi / 2) == pytest.approx(
        2.0 * A * mgl / (C * w3) ** 2, rel=1e-14)
    # the notes' figures, at the notes' precision
    assert precession == pytest.approx(2.78, abs=0.015)
    assert 2.0 * np.pi / period == pytest.approx(77.5, abs=0.25)
    assert amplitude == pytest.approx(4.1, abs=0.05)


@pytest.fixture(scope="module")
def grid():
    spins = np.array([150.0, 400.0, 1200.0])
    return measure_gyroscopes(DISK, spins, np.radians([35.0, 90.0]), (-1.0, 0.0, 0.5),
                              options=stability.RunOptions(progress=False))


def test_runs_measure_precession_and_nutation_to_the_exact_motion(grid):
    """lp4 at step angle 0.02: rates within 2e-9, amplitude within 5e-7 of the exact values."""
    assert int((grid.status != 0).sum()) == 0
    assert float(np.abs(grid.precession_rate_error).max()) < 2e-9
    assert float(np.abs(grid.nutation_frequency_error).max()) < 2e-9
    assert float(np.abs(grid.nutation_amplitude_error).max()) < 5e-7
    paths = grid.path_theta - grid.path_theta_exact
    assert float(np.abs(paths).max()) < 1e-10
    assert float(np.abs(grid.path_phi - grid.path_phi_exact).max()) < 1e-3  # trapezoid phi


def test_fast_top_values_are_approached_as_one_over_spin_squared(grid):
    """exact / fast-top - 1 falls at least as w3^-2 (the next term of each expansion; w3^-4 for
    the precession at 90 degrees, where the term in cos(theta) vanishes): from 400 to 1200 rad/s
    it shrinks by (1/3)^2 or more (15% slack), to below 1e-2, for a top released at rest."""
    at_rest = grid.sel(release=0.0)
    for exact, fast in ((at_rest.precession_rate_exact, grid.precession_rate_gyroscopic),
                        (at_rest.nutation_frequency_exact, grid.nutation_frequency_gyroscopic),
                        (at_rest.nutation_amplitude_exact, at_rest.nutation_amplitude_gyroscopic)):
        offset = np.abs(exact / fast - 1.0)
        ratio = offset.sel(spin=1200.0) / offset.sel(spin=400.0)
        assert np.all(ratio < 1.15 * (400.0 / 1200.0) ** 2), ratio.values
        assert float(offset.sel(spin=1200.0).max()) < 1e-2


def test_paths_loop_cusp_and_wave(grid):
    """phi' changes sign on a looping path, stays >= 0 with a zero at the cusps, and > 0 on
    the wavy one; the cusped path starts at its highest point."""
    dphi = np.diff(grid.path_phi_exact.values, axis=1)
    loops, cusps, waves = dphi
    assert loops.min() < 0 < loops.max()
    assert cusps.min() >= -1e-12 and waves.min() > 0
    theta = grid.path_theta_exact.sel(release=0.0).values
    assert theta[0] == pytest.approx(theta.min(), abs=1e-12)


# ---------------------------------------------------------------------------------------------
# The study


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
