"""Every registered method: measured order against a reference, and its declared invariants
(what each :class:`~stability.integrators.spec.MethodSpec` says of its method).

Thresholds in one table per property, one row per method (``INVARIANT_BOUNDS``).
"""

import numpy as np
import pytest

import stability
from stability.free_body.propagate import propagate

from ..helpers import invariants, reference_omega

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


def test_registry_names_one_order_each():
    for name, spec in stability.METHODS.items():
        assert spec.name == name
        assert spec.order >= 1
        assert spec.reference


def test_unknown_method_lists_known_ones(body123):
    with pytest.raises(ValueError, match="unknown method 'rk5'.*rk4.*lp2"):
        stability.integrate(body123, W0, 1.0, 0.1, method="rk5")

