"""The heavy top's methods (stability.heavy_top.methods): their orders against DOP853 and the
exact solution, and the invariants the splittings keep."""


import numpy as np
import pytest
from scipy.integrate import solve_ivp

from stability.engine import propagate_groups
from stability.heavy_top.methods import METHODS
from stability.heavy_top.model import HeavyTop, tilted_starts
from stability.registry import SCENES

SCENE = SCENES["heavy_top"]
#: An asymmetric top with its centre of mass off every principal axis: nothing cancels.
TOP = np.array([1.0, 1.3, 0.9, 0.3, -0.2, 2.0])


def rhs(t, y, top):
    """Equations of motion written out here, independently of the package's kernels."""
    I, c = top[:3], top[3:]
    m, g = y[:3], y[3:]
    w = m / I
    return np.concatenate([np.cross(m, w) + np.cross(g, c), np.cross(g, w)])


def reference(x0, top, t):
    """DOP853 at a tolerance far below the errors measured."""
    return np.array([solve_ivp(rhs, (0.0, t), x, method="DOP853", rtol=1e-13, atol=1e-14,
                               args=(top,)).y[:, -1] for x in x0])


def run(name, x0, top, h, steps, **kwargs):
    spec = SCENE.method(name)
    return propagate_groups(SCENE, spec, x0, spec.params(top, h)[None, :], [len(x0)], h, steps,
                            progress=False, **kwargs)


@pytest.mark.parametrize("name", list(METHODS))
def test_measured_order_matches_the_declared_one(name):
    """Error at t = 2 s against DOP853 for h and h/2 ... : the slope is the declared order."""
    x0 = SCENE.example(4, seed=3)[0]
    t = 2.0
    ref = reference(x0, TOP, t)
    spec = METHODS[name]
    hs = [0.02, 0.01, 0.005] if spec.order == 4 else [0.01, 0.005, 0.0025]
    errors = [np.abs(run(name, x0, TOP, h, round(t / h)).x_final - ref).max() for h in hs]
    slopes = np.diff(np.log(errors)) / np.diff(np.log(hs))
    assert np.all(np.abs(slopes - spec.order) < 0.15), (errors, slopes)
    assert errors[-1] < (1e-5 if spec.order == 2 else 1e-6)


@pytest.mark.parametrize("name", ["lp2", "lp4"])
def test_splittings_keep_the_casimirs_to_round_off_and_bound_the_energy(name):
    """|g| = 1 and g . m to 1e-13 over 20,000 steps; the energy error does not grow: its
    largest value over the second half of the run is no larger than over the first half."""
    x0 = SCENE.example(8, seed=4)[0]
    h, steps = 0.02, 20_000
    r = run(name, x0, TOP, h, steps, save_every=100)
    inv = SCENE.invariants
    states = r.saved.reshape(-1, 6)
    assert np.abs(inv["vertical_norm"](states, TOP) - 1.0).max() < 1e-13
    lz0 = np.repeat(inv["vertical_momentum"](x0, TOP), r.saved.shape[1])
    assert np.abs(inv["vertical_momentum"](states, TOP) - lz0).max() < 1e-12
    e0 = inv["energy"](x0, TOP)[:, None]
    de = np.abs(inv["energy"](states, TOP).reshape(r.saved.shape[:2]) - e0)
    half = de.shape[1] // 2
    assert de[:, half:].max() <= 1.5 * de[:, :half].max()
    assert de.max() < (1e-2 if name == "lp2" else 1e-5)


def test_rk4_lets_the_casimirs_drift_which_the_splittings_do_not():
    """The contrast that makes the splittings worth their cost, at a coarse step."""
    x0 = SCENE.example(8, seed=4)[0]
    r = run("rk4", x0, TOP, 0.05, 20_000)
    drift = np.abs(SCENE.invariants["vertical_norm"](r.x_final, TOP) - 1.0).max()
    assert drift > 1e-9


def test_kick_and_free_parts_are_exact_for_a_symmetric_top_without_gravity():
    """With c = 0 and I1 = I2 the splitting is the exact free flow: any h gives one answer."""
    top = np.array([2.0, 2.0, 0.7, 0.0, 0.0, 0.0])
    x0 = SCENE.example(4, seed=5)[0]
    coarse = run("lp2", x0, top, 0.5, 8).x_final
    fine = run("lp2", x0, top, 0.01, 400).x_final
    assert np.abs(coarse - fine).max() < 1e-12


@pytest.mark.parametrize("name", list(METHODS))
def test_symmetric_top_tilt_converges_to_the_exact_solution_at_the_declared_order(name):
    """cos(theta) = g3 of a released gyroscope against the exact Jacobi-sn solution
    (stability.heavy_top.exact) over several nutation periods: the error's slope is the order."""
    from stability.heavy_top.exact import cos_theta, nutation_period

    top = HeavyTop.disk(0.1, 0.03, 0.04, gravity=9.81)
    A, _, C = top.pivot_moments
    x0 = tilted_starts(60.0, np.radians([30.0, 60.0, 80.0]), 3, top=top, seed=2)
    t = 4.0 * float(np.max(nutation_period(x0, A, C, top.mgl)))
    exact = cos_theta(t, x0, A, C, top.mgl)
    spec = METHODS[name]
    hs = [2e-3, 1e-3, 5e-4] if spec.order == 4 else [5e-4, 2.5e-4, 1.25e-4]
    errors = []
    for h in hs:
        steps = int(round(t / h))
        hh = t / steps
        r = propagate_groups(SCENE, spec, x0, spec.params(top.parameters, hh)[None, :], [3], hh,
                             steps, progress=False)
        errors.append(np.abs(r.x_final[:, 5] - exact).max())
    slopes = np.diff(np.log(errors)) / np.diff(np.log(hs))
    assert np.all(np.abs(slopes - spec.order) < 0.2), (errors, slopes)

