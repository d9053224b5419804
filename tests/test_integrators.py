"""Every registered method: measured order against a reference, and its declared invariants.

Thresholds in one table per property, one row per method (``INVARIANT_BOUNDS``).
"""

import math

import numpy as np
from numba import njit
import pytest

import stability
from stability.free_body.propagate import propagate
from stability.integrators.composition import KAHAN_LI6, KAHAN_LI8, SUZUKI4

from .helpers import reference_omega

W0 = np.array([0.3, 1.0, 0.9])
T_ORDER = 32.0
#: Errors used for the slope fit: above round-off (the exact reference is good to ~1e-15) and
#: below the pre-asymptotic range (lp8 still shows slopes of 6 at errors of ~3e-8 here).
ORDER_WINDOW = (1e-12, 1e-8)
#: Step sizes tried: T / n for n growing by 2^(1/4), until 4 errors fall in the window.
MAX_STEPS = 4_000_000

FINITE_ORDER = [name for name, spec in stability.METHODS.items() if not spec.is_exact]
EXACT = [name for name, spec in stability.METHODS.items() if spec.is_exact]


def final_error(body, method, h, w_ref, t_end=T_ORDER):
    ds = stability.integrate(body, W0, t_end, h, method, save_every=round(t_end / h))
    return np.max(np.abs(ds.w.values[-1] - w_ref))


@pytest.mark.parametrize("name", FINITE_ORDER)
def test_measured_order_matches_declared(name, body123):
    """Slope of log(error) against log(h), fitted in the asymptotic window, within 0.1."""
    spec = stability.METHODS[name]
    w_ref = reference_omega(body123, W0, T_ORDER)
    hs, errors = [], []
    k = 0
    while len(hs) < 4:
        n = round(T_ORDER * 2.0 ** (k / 4))
        assert n <= MAX_STEPS, f"{name}: no asymptotic range found, errors {errors}"
        h = T_ORDER / n
        err = final_error(body123, name, h, w_ref)
        k += 4 if err > 100 * ORDER_WINDOW[1] else 1  # double n while far above the window
        if err < ORDER_WINDOW[0]:
            break
        if err < ORDER_WINDOW[1]:
            hs.append(h)
            errors.append(err)
        elif hs:
            # Jumped back above the window: not yet asymptotic, start the fit afresh.
            hs, errors = [], []
    assert len(hs) >= 3, f"{name}: too few step sizes in the asymptotic window: {errors}"
    slope = np.polyfit(np.log(hs), np.log(errors), 1)[0]
    assert abs(slope - spec.order) < 0.1, f"{name}: measured order {slope:.3f}, declared {spec.order}"


@pytest.mark.parametrize("name", EXACT)
def test_exact_methods_have_no_step_size_error(name, body123):
    w_ref = reference_omega(body123, W0, 8.0)
    for h in (2.0, 0.5, 0.1):
        assert final_error(body123, name, h, w_ref, t_end=8.0) < 1e-12


def invariants(moments, m):
    """Relative |m| and energy of states m (..., 3) against the first one."""
    L = np.linalg.norm(m, axis=-1)
    E = 0.5 * np.sum(m * m / moments, axis=-1)
    return np.abs(L / L[0] - 1.0), E / E[0] - 1.0


CASIMIR = [name for name, spec in stability.METHODS.items() if spec.preserves_casimir]


@pytest.mark.parametrize("name", CASIMIR)
def test_casimir_to_round_off(name):
    """|L| kept to <= 1e-13 relative: over 1e6 steps (h = 0.01, t = 1e4) for lp2 and lp4,
    over 1e5 steps for the costlier methods."""
    n_steps = 1_000_000 if name in ("lp2", "lp4") else 100_000
    moments = np.array([1.0, 2.0, 3.0])
    m0 = (moments * W0)[None, :]
    run = propagate(name, moments, m0, 0.01, n_steps, save_every=n_steps // 100)
    dL, _ = invariants(moments, np.concatenate([m0, run.saved[0]]))
    assert dL.max() <= 1e-13


def test_lp2_energy_error_is_bounded():
    """Poisson map: the energy error oscillates at O(h^2) with no secular growth."""
    moments = np.array([1.0, 2.0, 3.0])
    m0 = (moments * W0)[None, :]
    run = propagate("lp2", moments, m0, 0.1, 200_000, save_every=100)  # t = 2e4
    _, dE = invariants(moments, np.concatenate([m0, run.saved[0]]))
    early = np.abs(dE[: dE.size // 100]).max()  # t <= 200
    late = np.abs(dE[dE.size // 2 :]).max()  # 1e4 <= t <= 2e4
    assert 1e-6 < early < 1e-3  # O(h^2) at h = 0.1
    assert late < 2.0 * early


def test_rk4_energy_drifts_linearly_and_dissipatively():
    """RK4's energy error grows linearly in t (literature notes 4.1: -5.45e-6 at t = 100)."""
    moments = np.array([1.0, 2.0, 3.0])
    m0 = (moments * W0)[None, :]
    run = propagate("rk4", moments, m0, 0.1, 10_000, save_every=1000)  # t = 100, ..., 1000
    _, dE = invariants(moments, np.concatenate([m0, run.saved[0]]))
    assert dE[1] < 0 and dE[10] < 0
    assert dE[10] / dE[1] == pytest.approx(10.0, rel=0.05)
    assert dE[1] == pytest.approx(-5.45e-6, rel=0.02)


@pytest.mark.parametrize(
    "weights, order", [(SUZUKI4, 4), (KAHAN_LI6, 6), (KAHAN_LI8, 8)], ids=["lp4", "lp6", "lp8"]
)
def test_composition_weights_are_consistent(weights, order):
    """Palindromic, sum to 1, and sum g^k = 0 for the odd k in 3 .. order - 1."""
    g = np.array(weights)
    np.testing.assert_array_equal(g, g[::-1])
    assert math.fsum(g) == pytest.approx(1.0, abs=1e-15)
    for k in range(3, order, 2):
        assert abs(np.sum(g**k)) < 1e-14, f"sum g^{k} = {np.sum(g**k)}"


def test_registry_names_one_order_each():
    for name, spec in stability.METHODS.items():
        assert spec.name == name
        assert spec.order >= 1
        assert spec.reference


def test_unknown_method_lists_known_ones(body123):
    with pytest.raises(ValueError, match="unknown method 'rk5'.*rk4.*lp2"):
        stability.integrate(body123, W0, 1.0, 0.1, method="rk5")


@njit(cache=True)
def _plain_rk4(w0, moments, h, n_steps):
    """RK4 with the ordinary update w += dw (no compensation): the baseline for the test below."""
    I1, I2, I3 = moments[0], moments[1], moments[2]
    a1, a2, a3 = (I2 - I3) / I1, (I3 - I1) / I2, (I1 - I2) / I3
    out = np.empty_like(w0)
    for j in range(w0.shape[0]):
        x1, x2, x3 = w0[j, 0], w0[j, 1], w0[j, 2]
        for _ in range(n_steps):
            k11, k12, k13 = a1 * x2 * x3, a2 * x3 * x1, a3 * x1 * x2
            y1, y2, y3 = x1 + 0.5 * h * k11, x2 + 0.5 * h * k12, x3 + 0.5 * h * k13
            k21, k22, k23 = a1 * y2 * y3, a2 * y3 * y1, a3 * y1 * y2
            y1, y2, y3 = x1 + 0.5 * h * k21, x2 + 0.5 * h * k22, x3 + 0.5 * h * k23
            k31, k32, k33 = a1 * y2 * y3, a2 * y3 * y1, a3 * y1 * y2
            y1, y2, y3 = x1 + h * k31, x2 + h * k32, x3 + h * k33
            k41, k42, k43 = a1 * y2 * y3, a2 * y3 * y1, a3 * y1 * y2
            x1 += h / 6.0 * (k11 + 2.0 * (k21 + k31) + k41)
            x2 += h / 6.0 * (k12 + 2.0 * (k22 + k32) + k42)
            x3 += h / 6.0 * (k13 + 2.0 * (k23 + k33) + k43)
        out[j, 0], out[j, 1], out[j, 2] = x1, x2, x3
    return out


def test_compensated_update_keeps_improving_where_plain_rk4_stalls(body123):
    """I = (1, 2, 3), starts near (1e-3, 1, 0), T = 100: the p99 error over an ensemble.

    Measured: plain RK4 stalls near 2e-8 from h = 0.01 on (round-off of w += dw accumulates
    over 1e4-1e5 steps and is amplified near the saddle); the compensated update keeps
    improving, 5.6e-10 at h = 0.01 down to ~3e-11 at h = 0.00125.
    """
    rng = np.random.default_rng(1)
    n = 200
    w0 = np.array([1e-3, 1.0, 0.0]) + np.column_stack(
        [1e-4 * rng.standard_normal(n), np.zeros(n), 1e-4 * rng.standard_normal(n)]
    )
    moments = body123.moments
    exact = np.array([stability.exact_omega(body123, w, np.array([100.0]))[0] for w in w0])
    plain, compensated = [], []
    for h in (0.01, 0.005, 0.0025, 0.00125):
        steps = round(100.0 / h)
        w_plain = _plain_rk4(w0, moments, h, steps)
        w_comp = propagate("rk4", moments, w0 * moments, h, steps, progress=False).m_final / moments
        plain.append(np.percentile(np.abs(w_plain - exact).max(axis=1), 99))
        compensated.append(np.percentile(np.abs(w_comp - exact).max(axis=1), 99))
    assert plain[-1] > 1e-8 and plain[-1] > 0.5 * plain[0]  # no gain from smaller steps
    assert all(later < 0.8 * earlier for earlier, later in zip(compensated, compensated[1:]))
    assert compensated[-1] < 1e-10
