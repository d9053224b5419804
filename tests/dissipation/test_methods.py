"""The damped bodies' methods: measured orders against DOP853, |H| kept to round-off by the
splittings, the energy falling step by step (the rates the damped runs measure:
``tests/dissipation/test_measure.py``)."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from stability.dissipation import model
from stability.dissipation.scene import (SPHERE_DAMPER, WHIP_DAMPER, sphere_energy,
                                         sphere_moments, sphere_momentum, sphere_rigid_state)
from stability.engine import propagate_groups

TRIAXIAL = np.array([1.0, 2.0, 3.0, 0.2, 0.1])
WHIP_BODY = np.array([1.0, 2.0, 3.0, 0.05, 0.5, 3.0, 0.2])
EXPLORER = model.EXPLORER_1


def reference(scene, values, x0, t_end):
    """The state at ``t_end`` by SciPy's DOP853 at rtol 1e-13 on the kernel's right-hand side."""
    spec = scene.method("rk4")
    p = spec.params(values, 0.0)
    rhs = spec.step.py_func.__globals__[{"sphere_damper": "sphere_rhs",
                                         "whip_damper": "whip_rhs"}[scene.name]]
    done = solve_ivp(lambda t, x: rhs(*x, p), (0.0, t_end), x0, method="DOP853", rtol=1e-13,
                     atol=1e-15)
    return done.y[:, -1]


ORDERS = [(SPHERE_DAMPER, TRIAXIAL, "rk4", 4, 0.1), (SPHERE_DAMPER, TRIAXIAL, "lp2", 2, 0.1),
          (SPHERE_DAMPER, TRIAXIAL, "lp4", 4, 0.1), (SPHERE_DAMPER, TRIAXIAL, "dmv", 2, 0.1),
          (WHIP_DAMPER, WHIP_BODY, "rk4", 4, 0.025)]


@pytest.mark.parametrize("scene, values, method, order, h0", ORDERS,
                         ids=[f"{s.name}-{m}" for s, _, m, _, _ in ORDERS])
def test_measured_order_against_dop853(scene, values, method, order, h0):
    """Errors after 2 s at h = h0, h0 / 2, h0 / 4 from a start off every axis: slopes within
    0.2 of the declared order."""
    x0, _ = scene.example(1, seed=2)
    x0 = x0[0] + 0.3 * np.linspace(0.2, 1.0, x0.shape[1])
    exact = reference(scene, values, x0, 2.0)
    spec = scene.method(method)
    errors = []
    for h in (h0, h0 / 2, h0 / 4):
        run = propagate_groups(scene, spec, x0[None], spec.params(values, h)[None], [1], h,
                               round(2.0 / h), progress=False)
        errors.append(np.abs(run.x_final[0] - exact).max())
    slopes = np.log2(np.array(errors[:-1]) / errors[1:])
    assert np.all(np.abs(slopes - order) < 0.2), (errors, slopes)


@pytest.fixture(scope="module")
def transition():
    """A triaxial body through its whole turn from near the minor axis to the major one, every
    step kept, by each method of scene sphere_damper."""
    h, steps = 0.02, 40000
    w = model.tilted_rotation(sphere_moments(TRIAXIAL), 1.0, [0.01], [0.3])
    x0 = sphere_rigid_state(TRIAXIAL, w)
    out = {}
    for method in SPHERE_DAMPER.methods:
        spec = SPHERE_DAMPER.method(method)
        run = propagate_groups(SPHERE_DAMPER, spec, x0, spec.params(TRIAXIAL, h)[None], [1], h,
                               steps, save_every=1, progress=False)
        out[method] = np.concatenate([x0[:, None], run.saved], axis=1)[0]
    return out


def test_the_splittings_keep_h_to_round_off_through_the_whole_turn(transition):
    for method, x in transition.items():
        H = np.linalg.norm(sphere_momentum(x), axis=1)
        drift = np.abs(H / H[0] - 1.0).max()
        theta = np.degrees(np.arccos(np.clip(sphere_momentum(x)[:, 0] / H, -1, 1)))
        assert theta[0] < 1.0 and abs(theta[-1] - 90.0) < 1.0, method  # the whole turn
        if method == "rk4":  # RK4 does not keep |H|: its error, measured
            assert 1e-11 < drift < 1e-6, drift
        else:
            assert drift <= 1e-12, (method, drift)


def test_dmv_lowers_the_energy_every_step_on_any_body(transition):
    """DMV keeps the shell's energy, the exact relaxation lowers it: no step raises E beyond
    round-off (a few ulps of E), through the whole turn."""
    E = sphere_energy(transition["dmv"], TRIAXIAL)
    assert E[-1] < 0.7 * E[0]
    assert np.max(np.diff(E) / E[:-1]) <= 4e-16


def test_lp2_lowers_the_energy_every_step_on_an_axisymmetric_body():
    values = np.array([*EXPLORER.moments, 1e-2, 6e-3])
    w = model.tilted_rotation(values[:3] + values[3], EXPLORER.spin, [0.02], [1.0])
    x0 = sphere_rigid_state(values, w)
    spec = SPHERE_DAMPER.method("lp2")
    h = 0.5 / EXPLORER.spin
    run = propagate_groups(SPHERE_DAMPER, spec, x0, spec.params(values, h)[None], [1], h,
                           30000, save_every=1, progress=False)
    E = sphere_energy(np.concatenate([x0, run.saved[0]]), values)
    assert E[-1] < 0.1 * E[0]  # through the turn
    assert np.max(np.diff(E) / E[:-1]) <= 4e-16

