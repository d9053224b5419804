"""The gyrostat (stability.dissipation.model_gyrostat): its equations (|H| kept, the energy
falling at the dampers' dissipation), RK4's order and |H| over a whole run, the linear theory
(closed form against the Jacobian, a triaxial platform's rate measured against its Jacobian's)
and where Likins' energy-sink criterion holds."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from stability.dissipation import model_gyrostat as model
from stability.dissipation.model_gyrostat import DualSpinBody, linear_map
from stability.dissipation.measure import exponential_rate, nutation_angle
from stability.dissipation.methods import gyrostat_params, gyrostat_rhs
from stability.dissipation.scene import GYROSTAT, gyrostat_energy, gyrostat_momentum
from stability.engine import propagate_groups

#: A minor-axis gyrostat (A3 < A_t) with both dampers: A1, A2, A3, Jr, Jp, cp, Jq, cq.
BOTH = np.array([1.0, 1.0, 0.6, 0.25, 0.05, 0.02, 0.04, 0.03])
TRIAXIAL = np.array([1.0, 1.3, 0.8, 0.3, 0.05, 0.04, 0.05, 0.03])


def with_dampers(values, cp, cq):
    out = np.array(values, dtype=float)
    out[5], out[7] = cp, cq
    return out


def rhs(x, values):
    return np.array(gyrostat_rhs.py_func(*x, gyrostat_params(values)))


def numerical_gradient(f, x, step=1e-6):
    return np.array([(f(x + step * e) - f(x - step * e)) / (2 * step) for e in np.eye(x.size)])


@pytest.mark.parametrize("values", [BOTH, TRIAXIAL], ids=["axisymmetric", "triaxial"])
def test_h_is_kept_and_the_energy_falls_at_the_dampers_dissipation(values):
    rng = np.random.default_rng(3)
    A1, A2, A3, Jr, Jp, cp, Jq, cq = values
    for _ in range(4):
        x = rng.standard_normal(10)
        f = rhs(x, values)
        H = gyrostat_momentum(x)
        assert abs(H @ gyrostat_momentum(f)) < 1e-13 * (1 + np.abs(x).max() ** 3)
        w = np.array([x[0] / A1, x[1] / A2, (x[2] - x[3]) / (A3 - Jr)])
        u_p = x[4:7] / Jp - w
        u_q = x[7:10] / Jq - np.array([w[0], w[1], x[3] / Jr])
        rate = numerical_gradient(lambda y: gyrostat_energy(y, values), x) @ f
        assert rate == pytest.approx(-cp * u_p @ u_p - cq * u_q @ u_q, rel=1e-7)


def test_the_rotors_axial_momentum_changes_only_by_its_dampers_torque():
    x = np.random.default_rng(4).standard_normal(10)
    assert rhs(x, with_dampers(BOTH, 0.02, 0.0))[3] == 0.0  # free bearing, no damper in it


@pytest.mark.parametrize("spin, relative", [(1.0, 2.0), (0.0, 3.0), (1.0, -0.7)])
def test_steady_spins_and_the_jacobian_by_complex_step(spin, relative):
    p = gyrostat_params(BOTH)
    x = model.steady_spin(BOTH, spin, relative)
    assert np.allclose(rhs(x, BOTH), 0.0, atol=1e-15)
    exact = model.jacobian(BOTH, spin, relative)
    central = np.empty((10, 10))
    for j in range(10):
        up, down = x.copy(), x.copy()
        up[j] += 1e-6
        down[j] -= 1e-6
        central[:, j] = (np.array(gyrostat_rhs.py_func(*up, p))
                         - np.array(gyrostat_rhs.py_func(*down, p))) / 2e-6
    assert np.abs(central - exact).max() < 1e-8 * np.abs(exact).max()


@pytest.mark.parametrize("cp, cq", [(0.02, 0.0), (0.0, 0.03), (0.02, 0.03), (2.0, 0.5)])
@pytest.mark.parametrize("spin, relative", [(1.0, 2.0), (0.0, 3.0), (1.0, -0.7)])
def test_the_closed_forms_give_the_jacobians_eigenvalues(cp, cq, spin, relative):
    values = with_dampers(BOTH, cp, cq)
    numeric = np.sort_complex(model.eigenvalues(values, spin, relative))
    matrix = np.sort_complex(model.axisymmetric_eigenvalues(values, spin, relative))
    assert np.allclose(matrix, numeric, rtol=1e-10, atol=1e-13)
    if cp == 0.0 or cq == 0.0:
        on_rotor = cp == 0.0
        J, c = (values[6], cq) if on_rotor else (values[4], cp)
        quadratic = model.one_damper_eigenvalues(1.0, 0.6, 0.25, J, c, spin, relative,
                                                 on_rotor)
        assert np.allclose(np.sort_complex(quadratic), numeric, rtol=1e-10, atol=1e-13)


def test_a_weak_damper_gives_the_first_order_rate_and_the_energy_sink_agrees():
    """l = i lambda_p - c lambda_D / h + O(c^2) (equation 6); the energy sink is exact at
    that order, and its relative error grows as (c / c*)^2."""
    for cp, cq in ((1e-5, 0.0), (0.0, 1e-5), (1e-5, 2e-5)):
        values = with_dampers(BOTH, cp, cq)
        rate = model.growth_rate(model.eigenvalues(values, 1.0, 2.0))
        assert rate == pytest.approx(model.first_order_rate(values, 1.0, 2.0), rel=1e-3)
        assert model.energy_sink_rate(values, 1.0, 2.0) == pytest.approx(rate, rel=1e-3)
    h = model.axial_momentum(BOTH, 1.0, 2.0)
    star = float(model.energy_sink_optimum(BOTH[4], BOTH[0], h))
    errors = []
    for factor in (0.03, 0.3, 1.0):
        values = with_dampers(BOTH, factor * star, 0.0)
        rate = model.growth_rate(model.eigenvalues(values, 1.0, 2.0))
        errors.append(abs(model.energy_sink_rate(values, 1.0, 2.0) / rate - 1.0))
    assert errors[0] < 1e-3 < errors[1] < errors[2] and errors[2] > 1e-2, errors


def test_a_despun_platforms_damper_stabilises_a_minor_axis_spinner_and_the_rotors_does_not():
    """w_p = 0: lambda_p = h / A_t > 0 and lambda_r = w_r (Jr - A_t) / A_t < 0."""
    for ratio in (0.6, 0.9, 1.3):  # minor axis, and major axis too: the rotor alone is minor
        values = np.array([1.0, 1.0, ratio, 0.25, 0.05, 0.02, 0.05, 0.0])
        assert model.growth_rate(model.eigenvalues(values, 0.0, 3.0)) < 0.0
        assert model.energy_sink_stable(values, 0.0, 3.0)
        values = with_dampers(values, 0.0, 0.02)
        assert model.growth_rate(model.eigenvalues(values, 0.0, 3.0)) > 0.0
        assert not model.energy_sink_stable(values, 0.0, 3.0)
    # A rotor of axial moment above the transverse (Jr > A_t) is stable with its damper.
    values = np.array([1.0, 1.0, 1.6, 1.2, 0.05, 0.0, 0.05, 0.02])
    assert model.growth_rate(model.eigenvalues(values, 0.0, 3.0)) < 0.0


#: A map for the criterion's checks, its grid off the boundaries' exact zeros.
RATIOS = np.linspace(0.505, 1.495, 34)
SPEEDS = np.linspace(-1.49, 4.47, 37)


def lambdas(body):
    R, S = np.meshgrid(RATIOS, SPEEDS, indexing="ij")
    h = body.transverse_moment * R * body.platform_spin + body.rotor_moment * S
    lam_p = h / body.transverse_moment - body.platform_spin
    return lam_p, lam_p - S


@pytest.mark.parametrize("factor", [0.03, 1.0, 10.0])
def test_one_dampers_criterion_is_exact_in_sign_at_any_damping(factor):
    """The sign of the growth rate is that of -lambda_D, weak damping or strong: on
    lambda_D = 0 the undamped mode (u = 0) solves the linear equations for every c."""
    body = DualSpinBody(100.0, 25.0, 5.0, 1.0, factor, factor)
    lam_p, lam_r = lambdas(body)
    for placement, lam in (("platform", lam_p), ("rotor", lam_r)):
        linear, sink = linear_map(body, placement, RATIOS, SPEEDS)
        assert np.all(np.sign(linear) == -np.sign(lam)), placement
        assert np.all(np.sign(sink) == -np.sign(lam)), placement


def test_two_dampers_the_criterion_holds_when_weak_and_fails_near_its_boundary_when_strong():
    """Weak (c << c*): the criterion's verdict is the eigenvalues' in every cell. Strong
    (c ~ c*, dampers of different strength): it is wrong in a band along its boundary, only
    where the two dampers pull against each other (lambda_p lambda_r < 0) and the rate is a
    few per cent of the map's largest."""
    weak = DualSpinBody(100.0, 25.0, 5.0, 1.0, 0.03, 0.01)
    linear, sink = linear_map(weak, "both", RATIOS, SPEEDS)
    assert np.all(np.sign(linear) == np.sign(sink))
    assert np.abs(sink / linear - 1.0).max() < 0.05  # near the boundary too
    strong = DualSpinBody(100.0, 25.0, 5.0, 1.0, 1.0, 0.3)
    linear, sink = linear_map(strong, "both", RATIOS, SPEEDS)
    wrong = np.sign(linear) != np.sign(sink)
    lam_p, lam_r = lambdas(strong)
    assert 5 <= wrong.sum() <= 0.05 * wrong.size, wrong.sum()
    assert np.all(lam_p[wrong] * lam_r[wrong] < 0.0)
    top = np.abs(linear).max()
    assert np.abs(linear[wrong]).max() < 0.05 * top
    assert np.abs(sink[wrong]).max() < 0.05 * top


def reference(values, x0, t_end):
    done = solve_ivp(lambda t, x: rhs(x, values), (0.0, t_end), x0, method="DOP853",
                     rtol=1e-13, atol=1e-15)
    return done.y[:, -1]


def test_rk4_is_of_order_4_against_dop853():
    x0 = model.tilted_spin(BOTH, 1.0, 2.0, [0.3], [0.4])[0]
    x0[4:] += 0.05  # the spheres off their bodies' rates
    exact = reference(BOTH, x0, 2.0)
    spec = GYROSTAT.method("rk4")
    errors = []
    for h in (0.1, 0.05, 0.025):
        run = propagate_groups(GYROSTAT, spec, x0[None], spec.params(BOTH, h)[None], [1], h,
                               round(2.0 / h), progress=False)
        errors.append(np.abs(run.x_final[0] - exact).max())
    slopes = np.log2(np.array(errors[:-1]) / errors[1:])
    assert np.all(np.abs(slopes - 4.0) < 0.2), (errors, slopes)


def test_rk4_keeps_h_through_a_whole_run_into_the_end_state_at_a_small_step():
    """A minor-axis gyrostat with its damper in the rotor (unstable) from 0.57 degrees to its
    end state at 71.6 degrees, 160 000 steps at h = 0.005 s: |H| within 1e-12, the energy
    falling between kept states to round-off."""
    values = np.array([1.0, 1.0, 0.6, 0.25, 0.05, 0.0, 0.05, 0.025])
    assert model.growth_rate(model.eigenvalues(values, 1.0, 3.0)) > 0.04
    x0 = model.tilted_spin(values, 1.0, 3.0, [0.01], [0.3])
    spec, h = GYROSTAT.method("rk4"), 0.005
    run = propagate_groups(GYROSTAT, spec, x0, spec.params(values, h)[None], [1], h, 160000,
                           save_every=10, progress=False)
    x = np.concatenate([x0[:, None], run.saved], axis=1)[0]
    H = np.linalg.norm(gyrostat_momentum(x), axis=-1)
    E = gyrostat_energy(x, values)
    theta = np.degrees(nutation_angle(gyrostat_momentum(x), 2))
    assert theta[0] == pytest.approx(np.degrees(0.01), rel=1e-12) and theta[-1] > 70.0
    assert np.abs(H / H[0] - 1.0).max() < 1e-12
    assert E[-1] < 0.5 * E[0] and np.max(np.diff(E) / E[0]) < 1e-15


def test_a_triaxial_platforms_rate_is_its_jacobians():
    """A1 != A2: the nutation is elliptic, so ln(theta) wobbles at twice its frequency about the
    exponential; the fit over four e-folds still gives the Jacobian's eigenvalue to 1e-2."""
    values = np.array([1.0, 1.1, 0.6, 0.25, 0.05, 0.0, 0.05, 0.02])
    lam = model.eigenvalues(values, 1.0, 3.0)
    rate, gap = lam[0].real, lam[0].real - lam[2].real
    settle, h = 12.0 / gap, 0.01
    steps = int((settle + 4.0 / rate) / h)
    x0 = model.tilted_spin(values, 1.0, 3.0, [1e-5], [0.3])
    spec = GYROSTAT.method("rk4")
    run = propagate_groups(GYROSTAT, spec, x0, spec.params(values, h)[None], [1], h, steps,
                           save_every=steps // 2000, progress=False)
    x = np.concatenate([x0[:, None], run.saved], axis=1)[0]
    t = np.arange(x.shape[0]) * (steps // 2000) * h
    theta = nutation_angle(gyrostat_momentum(x), 2)
    fitted = exponential_rate(t, theta, (t >= settle) & (theta < 1e-3))
    assert fitted == pytest.approx(rate, rel=1e-2)


def test_tilted_spin_starts_at_the_angle_asked_and_turns_rigidly():
    x = model.tilted_spin(BOTH, 1.0, 2.0, [1e-3, 0.2], [0.0, 1.0])
    assert np.allclose(nutation_angle(gyrostat_momentum(x), 2), [1e-3, 0.2], rtol=1e-12)
    u_p = x[:, 4:7] / BOTH[4] - np.column_stack([x[:, 0] / BOTH[0], x[:, 1] / BOTH[1],
                                                  (x[:, 2] - x[:, 3]) / (BOTH[2] - BOTH[3])])
    assert np.abs(u_p).max() < 1e-15


@pytest.mark.parametrize("values, message", [
    ([1.0, 1.0, 0.6, 0.25, 0.05, 0.02, 0.04], "8 numbers"),
    ([1.0, 1.0, 0.2, 0.25, 0.05, 0.02, 0.04, 0.03], "must exceed the rotor's"),
    ([1.0, 1.0, 0.6, 0.25, 0.0, 0.02, 0.04, 0.03], "must be positive"),
    ([1.0, 1.0, 0.6, 0.25, 0.05, -0.02, 0.04, 0.03], "cp, cq >= 0"),
    ([1.0, np.nan, 0.6, 0.25, 0.05, 0.02, 0.04, 0.03], "all finite"),
])
def test_bad_parameter_sets_are_refused_in_one_line(values, message):
    with pytest.raises(ValueError, match=message):
        gyrostat_params(values)
