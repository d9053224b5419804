"""The heavy top: its methods' orders, invariants and the sleeping top's linear theory."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import stability
from stability.engine import propagate_groups
from stability.heavy_top.measure import measure_sleeping_tops
from stability.heavy_top.methods import METHODS
from stability.heavy_top.model import (
    HeavyTop, critical_spin, sleeping_frequencies, sleeping_growth_rate, tilted_starts,
)
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


def test_scene_is_registered_with_its_three_methods():
    assert set(SCENE.methods) == {"rk4", "lp2", "lp4"}
    assert SCENE.width == 6 and SCENE.components[3:] == ("g1", "g2", "g3")


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


def test_tilted_starts_have_the_asked_tilt_spin_and_tilt_rate():
    top = HeavyTop.disk(0.1, 0.03, 0.04)
    x = tilted_starts(300.0, 0.2, 50, top=top, seed=1, tilt_rate=0.5)
    A, _, C = top.pivot_moments
    assert np.allclose(np.arccos(x[:, 5]), 0.2)
    assert np.allclose(x[:, 2] / C, 300.0)
    # theta' = (g x w)_3 / -sin(theta) for g3 = cos(theta): the asked rate.
    w = x[:, :3] / top.pivot_moments
    g3_rate = x[:, 3] * w[:, 1] - x[:, 4] * w[:, 0]
    assert np.allclose(-g3_rate / np.sin(0.2), 0.5)


def test_critical_spin_and_rates_of_the_worked_gyroscope():
    """Disk M = 0.1 kg, r = 3 cm, l = 4 cm (literature notes 5.3): threshold ~119 rad/s."""
    top = HeavyTop.disk(0.1, 0.03, 0.04, gravity=9.81)
    assert critical_spin(top) == pytest.approx(118.9, abs=0.1)
    assert sleeping_growth_rate(top, 0.0) == pytest.approx(math.sqrt(top.mgl / 1.825e-4))
    assert sleeping_growth_rate(top, 200.0) == 0.0
    slow, fast = sleeping_frequencies(top, 300.0)
    A, _, C = top.pivot_moments
    assert slow * fast == pytest.approx(top.mgl / A) and slow + fast == pytest.approx(C * 300 / A)


def test_sleeping_top_growth_matches_the_analytic_rate_on_both_sides():
    """Measured rates within 1e-4 of sqrt(4 A M g l - C^2 w3^2) / (2 A) below the threshold;
    bounded tilt (rate 0, amplification as the linear theory's |s+| + |s-| over |s+ - s-|)
    above it."""
    top = HeavyTop.disk(0.1, 0.03, 0.04)
    wc = critical_spin(top)
    spins = wc * np.array([0.0, 0.5, 0.9, 1.2, 2.0])
    ds = measure_sleeping_tops([top], spins, members=8,
                               options=stability.RunOptions(progress=False))
    below = spins < wc
    err = ds.relative_error.values[0, below]
    assert np.all(np.abs(err) < 1e-4), err
    assert np.all(ds.growth_rate_measured.values[0, ~below] == 0.0)
    slow, fast = sleeping_frequencies(top, spins[~below])
    bound = (slow + fast) / (fast - slow)  # |A| + |B| over the start, released with xi' = 0
    amp = ds.tilt_amplification.values[0, ~below]
    assert np.all(amp <= bound * (1 + 1e-3)) and np.all(amp > 0.9 * bound)
    assert ds.critical_spin.attrs["units"] == "rad s-1"


@pytest.mark.parametrize("kwargs,match", [
    ({"mass": -1.0, "length": 0.04, "central_moments": (1, 1, 2)}, "mass must be"),
    ({"mass": 0.1, "length": -0.01, "central_moments": (1, 1, 2)}, "length"),
    ({"mass": 0.1, "length": 0.04, "central_moments": (1, 1, 3)}, "triangle inequality"),
    ({"mass": 0.1, "length": 0.04, "central_moments": (1, 2)}, "3 principal moments"),
    ({"mass": 0.1, "length": 0.04, "central_moments": (1, 1, 1), "gravity": -9.8},
     "gravity"),
])
def test_unphysical_tops_are_refused_with_one_line(kwargs, match):
    with pytest.raises(ValueError, match=match):
        HeavyTop(**kwargs)


def test_pivot_moments_below_m_l_squared_are_refused():
    with pytest.raises(ValueError, match="parallel-axis"):
        HeavyTop.from_pivot_moments((1e-4, 1e-4, 4.5e-5), 0.1, 0.04)
    top = HeavyTop.from_pivot_moments((1.825e-4, 1.825e-4, 4.5e-5), 0.1, 0.04)
    assert np.allclose(top.central_moments, (2.25e-5, 2.25e-5, 4.5e-5))


def test_linear_theory_is_refused_for_an_asymmetric_top():
    top = HeavyTop(0.1, 0.04, (2e-5, 3e-5, 4.5e-5))
    with pytest.raises(ValueError, match="symmetric top"):
        critical_spin(top)


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
