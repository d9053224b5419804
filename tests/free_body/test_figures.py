"""Poinsot's construction: the polhodes lie on the energy ellipsoid and the momentum sphere, the
herpolhode on the invariable plane at sqrt(2E)/|L|, between its two radii."""

import numpy as np
import pytest
from matplotlib.figure import Figure

import stability
from stability.core.quaternions import frame_along, quaternion_to_matrix
from stability.free_body.figures import poinsot_figure
from stability.plotting.style import missing_units
from stability.free_body.polhodes import (
    energy_ellipsoid_polhodes, energy_ellipsoid_separatrix, herpolhode, herpolhode_radii,
    poinsot_polhode,
)

RACKET = stability.RigidBody.preset("tennis_racket")
BODY123 = stability.RigidBody(1.0, 2.0, 3.0, physical=False)
#: Starts about each family: near the saddle (the flip), about the largest and the smallest axis.
STARTS = [(RACKET, (0.3, 10.0, 0.2)), (RACKET, (0.5, 1.0, 10.0)), (RACKET, (10.0, 0.5, 1.0)),
          (BODY123, (1.0, 0.3, 0.2)), (BODY123, (0.1, 0.4, 1.0))]


def _invariants(body, w0):
    w0 = np.asarray(w0, dtype=float)
    m0 = body.moments * w0
    return 0.5 * float(m0 @ w0), float(np.linalg.norm(m0))


def test_the_polhodes_lie_on_the_energy_ellipsoid_and_the_momentum_sphere():
    I = RACKET.moments
    a, b, c = np.argsort(I)
    levels = (0.2, 0.7, 0.95)
    for centre, curves in energy_ellipsoid_polhodes(RACKET, levels, samples=120):
        assert len(curves) == 2 * len(levels)
        for k, rho in enumerate(curves):
            f = levels[k // 2]
            two_e_over_l2 = 1.0 / I[centre] + f * (1.0 / I[b] - 1.0 / I[centre])  # the level
            energy = np.einsum("ni,i,ni->n", rho, I, rho)  # x . I x = 1
            sphere = np.sum((I * rho) ** 2, axis=1) * two_e_over_l2  # |I x|^2 = L^2 / 2E
            assert np.max(np.abs(energy - 1.0)) < 1e-12
            assert np.max(np.abs(sphere - 1.0)) < 1e-12
            assert np.all(np.sign(rho[:, centre]) == np.sign(rho[0, centre]))


def test_the_separatrix_on_the_ellipsoid_runs_through_the_saddles():
    I = RACKET.moments
    b = int(np.argsort(I)[1])
    for rho in energy_ellipsoid_separatrix(RACKET, samples=181):
        assert np.max(np.abs(np.einsum("ni,i,ni->n", rho, I, rho) - 1.0)) < 1e-12
        assert np.max(np.abs(np.sum((I * rho) ** 2, axis=1) / I[b] - 1.0)) < 1e-12
        np.testing.assert_allclose(rho[0], np.eye(3)[b] / np.sqrt(I[b]), atol=1e-12)


@pytest.mark.parametrize("body, w0", STARTS)
def test_one_start_polhode_closes_on_both_surfaces(body, w0):
    energy, momentum = _invariants(body, w0)
    I = body.moments
    rho = poinsot_polhode(body, w0, samples=300)
    np.testing.assert_array_equal(rho[0], np.asarray(w0) / np.sqrt(2.0 * energy))
    assert np.max(np.abs(np.einsum("ni,i,ni->n", rho, I, rho) - 1.0)) < 1e-12
    sphere = np.sum((I * rho) ** 2, axis=1) * 2.0 * energy / momentum**2
    assert np.max(np.abs(sphere - 1.0)) < 1e-12
    np.testing.assert_allclose(rho[-1], rho[0], atol=1e-9 * np.linalg.norm(rho[0]))


@pytest.mark.parametrize("body, w0", STARTS)
def test_the_herpolhode_lies_on_the_invariable_plane_between_its_radii(body, w0):
    energy, momentum = _invariants(body, w0)
    q0 = np.array([0.8, -0.2, 0.5, 0.26])
    q0 /= np.linalg.norm(q0)
    period = stability.full_period(body, w0)
    t = np.linspace(0.0, 3.0 * period, 6001)
    h = herpolhode(body, w0, t, q0)
    L = quaternion_to_matrix(q0) @ (body.moments * np.asarray(w0))
    np.testing.assert_allclose(h.normal, L / momentum, rtol=0, atol=1e-15)
    distance = np.sqrt(2.0 * energy) / momentum
    assert abs(h.distance - distance) <= 1e-15 * distance
    assert np.max(np.abs(h.points @ (L / momentum) - distance)) <= 1e-12 * distance
    # the plane coordinates are the points about the plane's centre
    rebuilt = distance * h.normal + h.plane @ h.frame[:, :2].T
    np.testing.assert_allclose(rebuilt, h.points, atol=1e-12 * np.abs(h.points).max())
    r = np.linalg.norm(h.plane, axis=1)
    r_min, r_max = h.radii
    assert (r_min, r_max) == herpolhode_radii(body, w0)
    assert r.min() >= r_min * (1.0 - 1e-9) and r.max() <= r_max * (1.0 + 1e-9)
    # ... and reaches both: the closed form is the sampled extreme, not just a bound
    assert r.max() >= r_max * (1.0 - 1e-4)
    assert r.min() <= r_min * (1.0 + 1e-4) + 1e-6 * r_max


def test_a_symmetric_body_draws_a_circle_and_a_steady_spin_a_point():
    top = stability.RigidBody(1.0, 1.0, 1.6)
    w0 = (0.3, 0.1, 2.0)
    h = herpolhode(top, w0, np.linspace(0.0, 10.0, 500))
    r_min, r_max = h.radii
    assert r_min == r_max
    np.testing.assert_allclose(np.linalg.norm(h.plane, axis=1), r_max, rtol=1e-12)
    assert herpolhode_radii(RACKET, (0.0, 0.0, 5.0)) == (0.0, 0.0)


def test_frame_along_is_a_rotation_with_its_third_axis_given():
    for n, hint in (((0.0, 0.0, 2.0), None), ((1.0, 1.0, 0.0), (0.0, 0.0, 1.0)),
                    ((0.3, -0.2, 0.9), (0.3, -0.2, 0.9))):  # a hint along n is ignored
        F = frame_along(n, hint)
        np.testing.assert_allclose(F.T @ F, np.eye(3), atol=1e-15)
        assert np.linalg.det(F) == pytest.approx(1.0)
        np.testing.assert_allclose(F[:, 2], np.asarray(n) / np.linalg.norm(n), atol=1e-15)
    np.testing.assert_allclose(frame_along((1.0, 1.0, 0.0), (0.0, 0.0, 1.0))[:, 0], (0, 0, 1))
    with pytest.raises(ValueError, match="n must be a non-zero vector"):
        frame_along((0.0, 0.0, 0.0))


@pytest.mark.parametrize("call, message", [
    (lambda: poinsot_polhode(RACKET, (0.0, 0.0, 0.0)), "w0 = 0: a body at rest"),
    (lambda: herpolhode(RACKET, (0.0, 1.0), [0.0]), r"w0 must have shape \(3,\)"),
    (lambda: herpolhode_radii((1.0, 2.0, 3.0), (1.0, 0.0, 0.0)), "body must be a stability"),
    (lambda: herpolhode(RACKET, (0.0, 10.0, 0.0), [0.0, 1.0]), "on the separatrix"),
])
def test_bad_input_is_one_line_saying_what_to_do(call, message):
    with pytest.raises(ValueError, match=message) as info:
        call()
    assert "\n" not in str(info.value)


def test_the_figure_builds_with_units_and_a_legend():
    fig = poinsot_figure(RACKET, (0.3, 10.0, 0.2), samples=400, levels=(0.5,))
    assert isinstance(fig, Figure)
    assert missing_units(fig) == []
    assert fig.legends
    assert len(fig.axes) == 3
