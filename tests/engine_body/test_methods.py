"""The engines' update rules (scene ``engine_body``): energy gain and loss, the |L| rescaling's
drift toward the separatrix, the missing flip without the gyroscopic term, order one."""

import numpy as np
import pytest

from stability import RigidBody
from stability.engine import propagate_groups
from stability.free_body.exact import exact_omega
from stability.engine_body.methods import ENGINE_RULES
from stability.engine_body.model import body_state, world_state
from stability.integrators.spec import body_params
from stability.registry import SCENES

SCENE = SCENES["engine_body"]
I = np.array([1.0, 2.0, 3.0])  # canonical already
GENERIC = np.array([1.0, 2.0, 1.5])  # body w (rad/s), far from every axis
HS = np.array([1 / 60, 1 / 120, 1 / 240, 1 / 480])
CONSISTENT = ["explicit_euler", "semi_implicit_euler", "implicit_euler", "rescaled_momentum",
              "rescaled_energy"]


def run(rule, w0, hs, t_end, save_every=0, q0=(1.0, 0.0, 0.0, 0.0)):
    """One member per step in ``hs``, each from body angular velocity ``w0`` to ``t_end``."""
    hs = np.atleast_1d(np.asarray(hs, dtype=float))
    x0 = world_state(I, np.tile(I * w0, (hs.size, 1)), q0)
    params = np.array([body_params(I, h) for h in hs])
    steps = np.rint(t_end / hs).astype(np.int64)
    return propagate_groups(SCENE, rule, x0, params, np.ones(hs.size, int), hs, steps,
                            save_every=save_every, progress=False)


def energy(x):
    return SCENE.invariants["energy"](x, I)


def momentum(x):
    return SCENE.invariants["angular_momentum"](x, I)


def body_w(x):
    return body_state(x, I)[0] / I


def at_start(f, w0):
    return f(world_state(I, I * w0, [1.0, 0.0, 0.0, 0.0]))[0]


def relative(f, x, w0):
    return f(x) / at_start(f, w0) - 1.0


def slope(hs, errors):
    return np.polyfit(np.log(hs), np.log(np.abs(errors)), 1)[0]


@pytest.mark.parametrize("rule,sign", [("semi_implicit_euler", 1), ("explicit_euler", -1)])
def test_euler_rules_change_the_energy_in_proportion_to_the_step(rule, sign):
    """Semi-implicit Euler's body motion is explicit Euler on Euler's equations: energy grows.
    The explicit rule turns the new velocity about the old one by the step angle as well, which
    takes twice that gain off: it loses energy at the same rate."""
    de = relative(energy, run(rule, GENERIC, HS, 2.0).x_final, GENERIC)
    assert np.all(sign * de > 0), de
    assert 0.9 < slope(HS, de) < 1.1, de


def test_implicit_euler_loses_energy_and_momentum_monotonically_in_proportion_to_the_step():
    out = run("implicit_euler", GENERIC, 1 / 60, 20.0, save_every=6)
    e, m = energy(out.saved[0]), momentum(out.saved[0])
    assert e[0] < at_start(energy, GENERIC) and m[0] < at_start(momentum, GENERIC)
    assert np.all(np.diff(e) < 0) and np.all(np.diff(m) < 0)
    de = relative(energy, run("implicit_euler", GENERIC, HS, 2.0).x_final, GENERIC)
    assert np.all(de < 0) and 0.9 < slope(HS, de) < 1.1, de
    assert np.all(out.iterations == out.steps_done[0])  # one Newton step per step


def test_rescaling_keeps_its_invariant_and_drifts_toward_the_separatrix():
    """Near the major axis, 2 E I2 < L^2; both rescalings bring it up to L^2 (the separatrix):
    keeping |L|, the energy grows; keeping the energy, |L| shrinks."""
    near_major = np.array([0.2, 0.3, 3.0])
    for rule, kept, drifting, sign in (("rescaled_momentum", momentum, energy, 1),
                                    ("rescaled_energy", energy, momentum, -1)):
        x = run(rule, near_major, 1 / 60, 150.0, save_every=900).saved[0]
        assert np.abs(relative(kept, x, near_major)).max() < 1e-12, rule
        drift = relative(drifting, x, near_major)
        assert np.all(sign * drift > 1e-6), (rule, drift)
        gap = np.abs(2.0 * energy(x) * I[1] - momentum(x) ** 2)
        gap0 = abs(2.0 * at_start(energy, near_major) * I[1] - at_start(momentum, near_major) ** 2)
        assert gap[0] < gap0 and np.all(np.diff(gap) < 0) and gap[-1] < 0.01 * gap0, (rule, gap)


def test_without_the_gyroscopic_term_the_body_never_flips():
    """Spin about the intermediate axis, perturbed by 1e-3: body w stays what it was (the body
    turns about a fixed space axis), while semi-implicit Euler at a small step flips it."""
    start = np.array([1e-3, 2.0, 1e-3])
    frozen = body_w(run("no_gyroscopic", start, 1 / 240, 30.0, save_every=24).saved[0])
    np.testing.assert_allclose(frozen, np.tile(start, (frozen.shape[0], 1)), rtol=1e-12,
                               atol=1e-12 * np.linalg.norm(start))
    assert np.all(frozen[:, 1] > 0)
    flipping = body_w(run("semi_implicit_euler", start, 1 / 240, 30.0, save_every=24).saved[0])
    assert np.any(flipping[:, 1] < -1.0)


@pytest.mark.parametrize("rule", list(ENGINE_RULES))
def test_every_rule_keeps_the_quaternion_unit(rule):
    x = run(rule, GENERIC, 1 / 60, 30.0, save_every=60).saved[0]
    assert np.abs(np.linalg.norm(x[:, 3:], axis=1) - 1.0).max() < 1e-12


@pytest.mark.parametrize("rule", CONSISTENT)
def test_consistent_rules_converge_at_order_one(rule):
    exact = exact_omega(RigidBody(*I, physical=False), GENERIC, 1.0)
    hs = np.array([1 / 100, 1 / 200, 1 / 400])
    errors = np.linalg.norm(body_w(run(rule, GENERIC, hs, 1.0).x_final) - exact, axis=1)
    ratios = errors[:-1] / errors[1:]
    assert np.all((ratios > 1.8) & (ratios < 2.2)), (errors, ratios)


def test_rules_start_from_any_attitude():
    """The body motion does not depend on the attitude: a turned start gives the same body w
    (to rounding) for every rule."""
    q = np.array([0.3, -0.5, 0.7, 0.4])
    q /= np.linalg.norm(q)
    for rule in ENGINE_RULES:
        a = body_w(run(rule, GENERIC, 1 / 60, 2.0).x_final)
        b = body_w(run(rule, GENERIC, 1 / 60, 2.0, q0=q).x_final)
        np.testing.assert_allclose(b, a, rtol=1e-11, atol=1e-11)

