"""Tangent scenes: the tangent is the derivative of the computed RK4 map, to round-off.

Checked against a central finite difference of two nearby runs (to 1e-7 relative), the
complex-step derivative of the same RK4 map written in Python (to round-off), the scene's own
state run (bitwise), the families' closed-form Jacobians, the heavy top's and the gyrostat's
products against a complex step of their own right-hand sides, and for a scene of the user's
own a complex step against the Jacobian written by hand.
"""

import math

import numpy as np
import pytest

import stability
from stability import define_scene
from stability.dissipation.model import sphere_jacobian, sphere_steady_spin
from stability.engine import propagate_groups
from stability.engine.tangent import tangent_scene
from stability.registry import SCENES

FREE_BODY = SCENES["free_body"]
SPHERE = SCENES["sphere_damper"]
MOMENTS = np.array([1.0, 2.0, 3.0])
H, STEPS = 0.01, 400


def duffing_rhs(x, v, p):
    """x'' = -k x - b x^3 - c x'."""
    return v, -p[0] * x - p[1] * x * x * x - p[2] * v


def duffing_jacobian(x, v, dx, dv, p):
    return dv, -(p[0] + 3.0 * p[1] * x * x) * dx - p[2] * dv


def root_rhs(x, v, p):
    """x'' = -sqrt(1 + x^2) x: math.sqrt, which Numba does not take complex numbers in."""
    return v, -math.sqrt(1.0 + x * x) * x


def root_jacobian(x, v, dx, dv, p):
    r = math.sqrt(1.0 + x * x)
    return dv, -(r + x * x / r) * dx


def kink_rhs(x, v, p):
    """x'' = -|x|: abs compiles for complex numbers but is not analytic."""
    return v, -abs(x)


DUFFING = define_scene("tangent_duffing", ["x", "v"], ["m", "m s-1"], duffing_rhs,
                       ["k", "b", "c"])
DUFFING_BY_HAND = define_scene("tangent_duffing_by_hand", ["x", "v"], ["m", "m s-1"],
                               duffing_rhs, ["k", "b", "c"], jacobian=duffing_jacobian)
ROOT = define_scene("tangent_root", ["x", "v"], ["m", "m s-1"], root_rhs)
ROOT_BY_HAND = define_scene("tangent_root_by_hand", ["x", "v"], ["m", "m s-1"], root_rhs,
                            jacobian=root_jacobian)
KINK = define_scene("tangent_kink", ["x", "v"], ["m", "m s-1"], kink_rhs)


def run(scene, x0, row, steps=STEPS, h=H):
    x0 = np.atleast_2d(np.asarray(x0, dtype=float))
    out = propagate_groups(scene, "rk4", x0, row[None], np.array([x0.shape[0]]),
                           np.array([h]), np.array([steps]))
    assert np.all(out.status == 0)
    return out.x_final


def start(x, v):
    return np.concatenate([x, v])


def rk4_map(x, p, steps=STEPS, h=H):
    """The free body's RK4 map in Python, for complex starts (the loop's arithmetic, summed
    plainly)."""
    a1, a2, a3 = p[6], p[7], p[8]

    def f(m):
        return np.array([a1 * m[1] * m[2], a2 * m[2] * m[0], a3 * m[0] * m[1]])

    for _ in range(steps):
        k1 = f(x)
        k2 = f(x + 0.5 * h * k1)
        k3 = f(x + 0.5 * h * k2)
        k4 = f(x + h * k3)
        x = x + h / 6.0 * (k1 + 2.0 * (k2 + k3) + k4)
    return x


def test_the_state_part_is_the_scenes_own_rk4_run_bitwise():
    scene = tangent_scene(FREE_BODY)
    row = scene.method("rk4").params(MOMENTS, H)
    x0 = np.array([0.1, 2.0, 0.05])
    both = run(scene, start(x0, np.array([1.0, 0.0, 0.0])), row)
    alone = run(FREE_BODY, x0, row)
    assert np.array_equal(both[:, :3], alone)


def test_a_tangent_scene_of_over_thirty_numbers_is_the_narrow_ones_bitwise():
    """The free body with its moments as state (6 numbers) and six tangents: 42 numbers and
    the step's h, p, s, more arguments than CPython passes one by one, so its kernels are
    LLVM-inlined instead of Numba-inlined (the loop the flip sensitivities run); the state and
    each tangent are those of the one-tangent scene, bitwise."""
    from stability.free_body.flip_sensitivity import FREE_BODY_MOMENTS as scene
    from stability.integrators.spec import body_params

    x0 = np.array([[1e-3, 2.0, 0.0, 1.0, 2.0, 3.0], [0.2, 1.0, -0.1, 1.0, 1.5, 2.2]])
    v = np.random.default_rng(2).standard_normal((6, 2, 6))
    wide, narrow = tangent_scene(scene, 6), tangent_scene(scene, 1)
    rows = np.array([body_params(x[3:]) for x in x0])
    both = propagate_groups(wide, "rk4", np.hstack([x0, *v]), rows, [1, 1], H, 100,
                            progress=False).x_final
    for j in (0, 5):
        one = propagate_groups(narrow, "rk4", np.hstack([x0, v[j]]), rows, [1, 1], H, 100,
                               progress=False).x_final
        assert np.array_equal(both[:, :6], one[:, :6])
        assert np.array_equal(both[:, 6 * (j + 1):6 * (j + 2)], one[:, 6:])


def test_the_tangent_is_a_central_difference_of_two_nearby_runs():
    """Near the separatrix, through the linear phase into the first flip (the tangent grows
    ~100-fold): to 1e-7 relative with a step of 1e-6 of the state (truncation ~1e-12 times the
    map's curvature, rounding ~1e-10 times the growth)."""
    scene = tangent_scene(FREE_BODY)
    row = scene.method("rk4").params(MOMENTS, H)
    x0 = np.array([1e-3, 2.0, 1e-3])
    v = np.array([0.3, -0.2, 1.0]) / np.linalg.norm([0.3, -0.2, 1.0])
    steps = 1000
    tangent = run(scene, start(x0, v), row, steps)[0, 3:]
    eps = 1e-6
    diff = (run(FREE_BODY, x0 + eps * v, row, steps)
            - run(FREE_BODY, x0 - eps * v, row, steps))[0] / (2 * eps)
    assert np.linalg.norm(tangent) > 50.0  # it grew: a real test of the linear phase
    assert np.linalg.norm(tangent - diff) < 1e-7 * np.linalg.norm(tangent)


def test_the_tangent_is_the_derivative_of_the_rk4_map_to_round_off():
    """The complex-step derivative of the same RK4 map (no difference taken, so exact to
    round-off): the tangent meets it to 1e-12 relative, where the exact flow's derivative
    differs from it by RK4's error."""
    scene = tangent_scene(FREE_BODY, 3)
    row = scene.method("rk4").params(MOMENTS, H)
    x0 = np.array([1e-3, 2.0, 1e-3])
    stm = run(scene, start(x0, np.eye(3).T.reshape(-1)), row)[0, 3:].reshape(3, 3).T
    t = 1e-30
    exact_map = np.column_stack([rk4_map(x0 + 1j * t * e, row).imag / t for e in np.eye(3)])
    assert np.max(np.abs(stm - exact_map)) < 1e-12 * np.max(np.abs(stm))


def test_the_sphere_dampers_jacobian_is_the_closed_form_at_a_steady_spin():
    values = np.array([1.0, 2.0, 3.0, 0.2, 0.1])
    scene = tangent_scene(SPHERE, 6)
    module = scene.methods["rk4"].step.py_func.__globals__
    row = SPHERE.linearisation.params(values, H)
    for axis in range(3):
        x = sphere_steady_spin(values, axis, 2.0)
        jacobian = np.column_stack([module["jvp_at"](x, e, row) for e in np.eye(6)])
        closed = sphere_jacobian(values, axis, 2.0)
        assert np.max(np.abs(jacobian - closed)) < 1e-14 * np.max(np.abs(closed))


def test_the_sphere_dampers_jacobian_is_a_complex_step_of_its_rhs_anywhere():
    values = np.array([1.0, 1.5, 2.2, 0.5, 2.0])
    scene = tangent_scene(SPHERE)
    module = scene.methods["rk4"].step.py_func.__globals__
    row = SPHERE.linearisation.params(values, H)
    rhs = module["base_rhs"].py_func
    rng = np.random.default_rng(3)
    x, v = rng.standard_normal(6), rng.standard_normal(6)
    t = 1e-30
    stepped = np.array(rhs(*(x + 1j * t * v), row)).imag / t
    assert np.max(np.abs(module["jvp_at"](x, v, row) - stepped)) < 1e-14 * np.max(
        np.abs(stepped))


@pytest.mark.parametrize("name", ["heavy_top", "gyrostat"])
def test_the_declared_jacobians_are_a_complex_step_of_the_scenes_own_rhs(name):
    """The heavy top's and the gyrostat's hand-written products against the complex step of
    the vector field the scene declares, at random states of each of its example's parameter
    sets: to 1e-13 relative (round-off of a few products; measured ~2e-16)."""
    scene = SCENES[name]
    module = tangent_scene(scene).methods["rk4"].step.py_func.__globals__
    rhs = module["base_rhs"].py_func
    rng = np.random.default_rng(7)
    t = 1e-30
    for values in scene.example(1)[1]:
        row = scene.linearisation.params(values, H)
        for _ in range(3):
            x, v = rng.standard_normal(scene.width), rng.standard_normal(scene.width)
            stepped = np.array(rhs(*(x + 1j * t * v), row)).imag / t
            assert np.max(np.abs(module["jvp_at"](x, v, row) - stepped)) < 1e-13 * np.max(
                np.abs(stepped))


def test_a_user_scenes_complex_step_tangent_is_its_hand_written_jacobians():
    row = np.array([1.0, 0.5, 0.1])
    x0 = start(np.array([0.8, 0.0]), np.array([0.0, 1.0]))
    stepped = run(tangent_scene(DUFFING), x0, row)
    by_hand = run(tangent_scene(DUFFING_BY_HAND), x0, row)
    assert np.array_equal(stepped[:, :2], by_hand[:, :2])
    assert np.max(np.abs(stepped[:, 2:] - by_hand[:, 2:])) < 1e-13 * np.max(np.abs(by_hand))


def test_a_rhs_numba_cannot_complex_step_is_refused_in_one_line_and_jacobian_mends_it():
    with pytest.raises(TypeError) as info:
        tangent_scene(ROOT)
    message = str(info.value)
    assert "\n" not in message and "complex step" in message and "jacobian=" in message
    x = run(tangent_scene(ROOT_BY_HAND), start(np.array([0.5, 0.0]), np.array([1.0, 0.0])),
            np.ones(0))
    assert np.all(np.isfinite(x))


def test_a_rhs_that_is_not_analytic_is_refused_in_one_line():
    with pytest.raises(ValueError) as info:
        tangent_scene(KINK)
    assert "\n" not in str(info.value) and "not analytic" in str(info.value)


@pytest.mark.parametrize("vectors", [0, 4, 1.5, True])
def test_a_number_of_tangents_out_of_range_is_refused_in_one_line(vectors):
    with pytest.raises(ValueError, match="vectors must be a whole number from 1 to its 3") as info:
        tangent_scene(FREE_BODY, vectors)
    assert "\n" not in str(info.value)


def test_a_scene_without_a_linearisation_is_refused_in_one_line():
    with pytest.raises(ValueError, match="declares no linearisation") as info:
        tangent_scene(SCENES["whip_damper"])
    assert "\n" not in str(info.value)


def test_after_whole_periods_the_state_transition_matrix_is_the_free_bodys_exact_identity():
    """After n whole periods T of a periodic member, the flow's state-transition matrix is
    exactly I - n f(x0) grad T(x0)^T (differentiate x(nT(y), y) = y: the orbit closes, and a
    start moved by dy closes at nT(y + dy), so the end moves back along f by n dT). RK4's
    tangent over 100 periods (400 steps each) meets it to 1e-6 of its size (measured 4.7e-7;
    at 200 steps a period 7.5e-6, 16 times as much: the method's fourth order)."""
    from stability.free_body.exact import full_period

    body = stability.RigidBody(*MOMENTS, physical=False)
    x0 = np.array([0.2, 0.6, 3.0])  # m about the largest axis: w = (0.2, 0.3, 1.0)

    def period(m):
        return full_period(body, m / MOMENTS)

    T, n, per_period = period(x0), 100, 400
    d = 1e-6 * np.linalg.norm(x0)  # T is smooth: truncation ~1e-12, rounding ~1e-10 of grad T
    grad = np.array([(period(x0 + d * e) - period(x0 - d * e)) / (2 * d) for e in np.eye(3)])
    a = (MOMENTS[1] - MOMENTS[2]) / (MOMENTS[1] * MOMENTS[2])  # m' = m x I^-1 m, cyclic
    b = (MOMENTS[2] - MOMENTS[0]) / (MOMENTS[2] * MOMENTS[0])
    c = (MOMENTS[0] - MOMENTS[1]) / (MOMENTS[0] * MOMENTS[1])
    f = np.array([a * x0[1] * x0[2], b * x0[2] * x0[0], c * x0[0] * x0[1]])
    expected = np.eye(3) - n * np.outer(f, grad)

    scene = tangent_scene(FREE_BODY, 3)
    h = T / per_period
    row = scene.method("rk4").params(MOMENTS, h)
    stm = run(scene, start(x0, np.eye(3).T.reshape(-1)), row, n * per_period, h)
    stm = stm[0, 3:].reshape(3, 3).T
    assert np.max(np.abs(expected - np.eye(3))) > 10.0  # the secular term is there to meet
    assert np.max(np.abs(stm - expected)) < 1e-6 * np.max(np.abs(expected))


def test_the_tangent_is_an_independent_integration_of_the_variational_equations():
    """Through the linear phase into the first flip (the tangent grows ~100-fold), RK4's
    tangent at h = 1 ms over 10 s equals scipy's DOP853 integration of m' = f(m), v' = J(m) v
    at rtol 1e-13 to 1e-8 relative (measured 3e-14: RK4's own error, (h sigma)^4 t / 120, is
    ~1e-13)."""
    from scipy.integrate import solve_ivp

    a = (MOMENTS[1] - MOMENTS[2]) / (MOMENTS[1] * MOMENTS[2])
    b = (MOMENTS[2] - MOMENTS[0]) / (MOMENTS[2] * MOMENTS[0])
    c = (MOMENTS[0] - MOMENTS[1]) / (MOMENTS[0] * MOMENTS[1])

    def variational(t, y):
        m, v = y[:3], y[3:]
        jac = np.array([[0.0, a * m[2], a * m[1]], [b * m[2], 0.0, b * m[0]],
                        [c * m[1], c * m[0], 0.0]])
        return np.concatenate([[a * m[1] * m[2], b * m[2] * m[0], c * m[0] * m[1]], jac @ v])

    x0 = np.array([1e-3, 2.0, 1e-3])
    v0 = np.array([0.3, -0.2, 1.0]) / np.linalg.norm([0.3, -0.2, 1.0])
    h, steps = 1e-3, 10000
    scene = tangent_scene(FREE_BODY)
    tangent = run(scene, start(x0, v0), scene.method("rk4").params(MOMENTS, h), steps, h)[0, 3:]
    reference = solve_ivp(variational, (0.0, h * steps), start(x0, v0), method="DOP853",
                          rtol=1e-13, atol=1e-15).y[3:, -1]
    assert np.linalg.norm(reference) > 50.0
    assert np.linalg.norm(tangent - reference) < 1e-8 * np.linalg.norm(reference)
