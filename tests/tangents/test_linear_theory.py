"""Tangents of the heavy top and the gyrostat against the linear theory each family computes.

- Sleeping top (pivot moments A = 0.55, C = 0.5 kg m2, M g l = 4.90 N m: critical spin
  w_c = 6.57 rad s-1). The Jacobian at the sleeping state has the eigenvalues of Goldstein's
  ``A xi'' - i C w3 xi' - M g l xi = 0`` seen from the spinning body: real parts
  +-``sleeping_growth_rate``, imaginary parts ``w3 - f`` with ``f`` the family's
  ``sleeping_frequencies`` above w_c (to 1e-12, round-off of the products).
- Below w_c (w3 = 3 rad s-1, lambda = 2.656 s-1) a start tilted by 1e-12 rad stays linear
  (tilt < 1e-5) to t = 6 s; the leading tangent's window and instantaneous rates meet lambda
  within 1e-8 relative on [4, 6] s: the decaying mode is down by e^(-2 lambda t) < 1e-9 there
  (the rotational symmetry makes each mode's |v| constant, no oscillation), the amplitude's
  correction O(tilt^2) < 1e-10, RK4's error on the rate (h |s|)^4 / 120 ~ 1e-11.
- Above w_c (w3 = 12 rad s-1) the transverse modes are purely imaginary: v(t) = E D(t) E^-1 v0
  with D unitary, so log|v(t)| <= log cond(E) (0.68, E the eigenvectors of the transverse
  block) for the 100 slow periods run, RK4's |R(i y)| < 1 only lowering it; the FTLE is then
  below log cond(E) / T (1e-3 s-1 here) and tends to 0.
- Gyrostat (the dual-spin family's body: A_t = 1, Jr = 0.25, a damper J = 0.05 at c* in the
  rotor, whose nutation grows, or on the platform, where it decays; the map's cell A3 / A_t =
  0.6, Omega = 2 rad s-1), started on its steady spin: the tangent across
  e3 grows at the real part of the leading eigenvalue :func:`stability.dissipation.model_gyrostat
  .linear_map` gives, measured over a whole nutation period 2 pi / Im(lambda) (the oscillation of
  |v| cancels) after 8 periods (the next mode, > 1 s-1 slower, is down by e^-300): within
  1e-8 relative (RK4's error on it, ~1e-9 at h = P / 512).
"""

import numpy as np
import pytest

from stability.dissipation.model_gyrostat import (DualSpinBody, axisymmetric_eigenvalues,
                                                  linear_map, steady_spin)
from stability.engine.tangent import tangent_scene
from stability.heavy_top.model import (HeavyTop, critical_spin, sleeping_frequencies,
                                       sleeping_growth_rate, tilted_starts)
from stability.registry import SCENES
from stability.tangents.ftle import run_tangents

HEAVY_TOP = SCENES["heavy_top"]
GYROSTAT = SCENES["gyrostat"]
TOP = HeavyTop(1.0, 0.5, (0.3, 0.3, 0.5))
#: The tilt's direction across the spin axis, g1: a transverse tangent (the axial m3, g3 are
#: neutral and decoupled at the sleeping state).
ACROSS = np.eye(6)[:, 3:4]
TRANSVERSE = [0, 1, 3, 4]  # m1, m2, g1, g2


def transverse_block(spin):
    """The Jacobian across the spin axis at the sleeping state, from the scene's own tangent
    kernels (``jvp_at``)."""
    kernels = tangent_scene(HEAVY_TOP).methods["rk4"].step.py_func.__globals__
    row = HEAVY_TOP.linearisation.params(TOP.parameters, 0.01)
    x = tilted_starts(spin, 0.0, 1, top=TOP)[0]
    jacobian = np.column_stack([kernels["jvp_at"](x, e, row) for e in np.eye(6)])
    return jacobian[np.ix_(TRANSVERSE, TRANSVERSE)]


@pytest.mark.parametrize("spin", [3.0, 12.0])
def test_the_sleeping_tops_jacobian_has_the_familys_rates_and_frequencies(spin):
    lam = np.linalg.eigvals(transverse_block(spin))
    rate = float(sleeping_growth_rate(TOP, spin))
    assert np.allclose(np.sort(lam.real), [-rate, -rate, rate, rate], rtol=0, atol=1e-12 * spin)
    if spin > critical_spin(TOP):
        expected = spin - np.array(sleeping_frequencies(TOP, spin))
        assert np.allclose(np.sort(np.abs(lam.imag)), np.sort(np.repeat(np.abs(expected), 2)),
                           rtol=1e-12)


def test_below_the_critical_spin_the_tangent_grows_at_the_sleeping_growth_rate():
    spin = 3.0
    assert spin < critical_spin(TOP)
    rate = float(sleeping_growth_rate(TOP, spin))
    x0 = tilted_starts(spin, 1e-12, 1, top=TOP)
    ds = run_tangents(HEAVY_TOP, x0, TOP.parameters, h=0.002, every=50, windows=60,
                      tangents=ACROSS)
    late = ds.sel(time=slice(4.0, 6.0))
    assert late.time.size == 21
    assert np.max(np.abs(late.window_rate.values / rate - 1.0)) < 1e-8
    assert np.max(np.abs(late.growth_rate.values / rate - 1.0)) < 1e-8


def test_above_the_critical_spin_the_tangent_stays_bounded_and_the_ftle_tends_to_zero():
    spin = 12.0
    assert spin > critical_spin(TOP)
    _, vectors = np.linalg.eig(transverse_block(spin))
    bound = np.log(np.linalg.cond(vectors))
    slow = float(sleeping_frequencies(TOP, spin)[0])
    turn = 2.0 * np.pi / (spin - slow)  # the faster turn of the tilt, seen from the body
    x0 = tilted_starts(spin, 1e-12, 1, top=TOP)
    ds = run_tangents(HEAVY_TOP, x0, TOP.parameters, h=turn / 64, every=640, windows=125,
                      tangents=ACROSS)
    assert ds.time.values[-1] > 99.0 * 2.0 * np.pi / slow  # 100 slow precessions
    growth = ds.ftle_running.values[0] * ds.time.values
    assert np.all(growth <= bound + 1e-9)
    assert 0.0 <= bound / ds.time.values[-1] < 1e-3
    assert abs(float(ds.ftle.values[0])) <= bound / ds.time.values[-1] + 1e-12


@pytest.mark.parametrize("placement", ["rotor", "platform"])
def test_the_gyrostats_late_rate_is_the_real_part_of_its_leading_eigenvalue(placement):
    body = DualSpinBody(1.0, 0.25, 0.05, 1.0, 1.0, 1.0)
    ratio, speed = 0.6, 2.0
    values = body.values(placement, ratio, speed)
    linear, _ = linear_map(body, placement, [ratio], [speed])
    rate = float(linear[0, 0])
    lam = axisymmetric_eigenvalues(values, body.platform_spin, speed)
    assert lam[0].real == pytest.approx(rate, rel=1e-12)
    assert lam[0].real - lam[2].real > 1.0  # the gap the late window relies on
    period = 2.0 * np.pi / abs(lam[0].imag)
    x0 = steady_spin(values, body.platform_spin, speed)[None]
    ds = run_tangents(GYROSTAT, x0, values, h=period / 512, every=64, windows=72,
                      tangents=np.eye(10)[:, 0:1])
    last = ds.window_rate.values[0, -8:].mean()  # the last period, 8 windows of P / 8
    assert abs(last / rate - 1.0) < 1e-8
