"""Polhodes and Poinsot's construction: the paths of m / |L| on the unit sphere, of w on the
energy ellipsoid, and the herpolhode on the invariable plane.

The torque-free motion keeps |m| = L and the energy, so m moves on the intersection of a
sphere and an ellipsoid: closed curves around the axes of the smallest and the largest moment
(stable centres), separated by the separatrix D2 = L^2 - 2 E I2 = 0, two great circles through
the saddles at +-e2 of the intermediate axis (literature notes 1.5). Used by the polhode figure
of the tennis-racket study.

Poinsot's construction (Poinsot, *Theorie nouvelle de la rotation des corps*, 1834; Landau &
Lifshitz, *Mechanics*, section 37; Goldstein, *Classical Mechanics*, 3rd ed., section 5.6).
With I = diag(I1, I2, I3) and the scaled angular velocity rho = w / sqrt(2E), in kg^-1/2 m^-1:

- rho lies on Poinsot's (inertia) ellipsoid ``x . I x = 1`` (semi-axes 1/sqrt(I_i)), because
  w . I w = 2E; it also lies on ``|I x| = |L| / sqrt(2E)`` (|m| = |L|): their intersection is
  the polhode, the path of rho in the body (:func:`energy_ellipsoid_polhodes`,
  :func:`poinsot_polhode`).
- The ellipsoid's normal at rho is I rho = m / sqrt(2E), along L; its tangent plane there is
  ``{x : x . L = rho . L = sqrt(2E)}``, in space the *invariable plane*, perpendicular to the
  fixed L at the distance ``d = sqrt(2E) / |L|`` from the centre. The contact point rho has no
  velocity (it is on the rotation axis), so the ellipsoid rolls on the plane without slipping,
  and the contact point R(t) rho(t) traces the herpolhode on the plane (:func:`herpolhode`).
- Its distance from the plane's centre is ``r = sqrt(|rho|^2 - d^2) = sqrt(|w|^2 / (2E) -
  2E / L^2)``, between the extremes of |w|^2 over the polhode (:func:`herpolhode_radii`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .model import angular_momentum_norm, invariant_differences, kinetic_energy
from ..core.body import RigidBody
from ..core.quaternions import IDENTITY, frame_along, quaternion_to_matrix
from .exact import exact_omega, full_period
from .exact_attitude import exact_attitude
from ..util.checks import vectors3


def polhodes(body, levels=(0.12, 0.35, 0.6, 0.82, 0.96), samples: int = 400):
    """Polhodes around each stable axis, followed for one period with the exact solution.

    Around the axis of the smallest and of the largest moment, orbits at energies
    ``2E/L^2 = 1/I_centre + f (1/I_intermediate - 1/I_centre)`` for f in ``levels`` (f = 0 is
    the centre, f = 1 the separatrix), each with its mirror image ``-m``.

    Parameters
    ----------
    body : RigidBody
    levels : sequence of float
        Fractions f of the way from the centre to the separatrix, in (0, 1).
    samples : int
        Points per orbit.

    Returns
    -------
    list of (int, list of ndarray)
        ``(centre, curves)`` for the smallest- then the largest-moment axis: the 0-based body
        axis of the centre and the orbits, each of shape (samples, 3), unit vectors m / |L|.
        A steady spin (equal moments) has no orbit and is left out.
    """

    I = body.moments
    a, b, c = np.argsort(I, kind="stable")  # body axes (0-based) of the smallest ... largest
    families = []
    for centre in (a, c):
        curves = []
        for f in levels:
            # Start in the (e_centre, e_b) plane: 2E/L^2 = cos^2/I_centre + sin^2/Ib, so the
            # fraction f of the way to the separatrix is sin^2(theta) = f.
            theta = np.arcsin(np.sqrt(f))
            m0 = np.zeros(3)
            m0[centre], m0[b] = np.cos(theta), np.sin(theta)
            w0 = m0 / I
            period = float(full_period(body, w0))
            if not np.isfinite(period):
                continue  # a steady spin (equal moments): a fixed point, no orbit to draw
            t = np.linspace(0.0, period, samples)
            m = np.asarray(exact_omega(body, w0, t), dtype=float) * I
            m /= np.linalg.norm(m, axis=1, keepdims=True)
            curves += [m, -m]
        families.append((centre, curves))
    return families


def separatrix_circles(body, samples: int = 721):
    """The separatrix D2 = 0 on the unit sphere of m/|L|: two great circles through +-e_b.

    On |m| = 1, D2 = L^2 - 2E Ib = Ia (Ia - Ib) w_a^2 + Ic (Ic - Ib) w_c^2 vanishes where
    ``m_a^2 (Ib - Ia) / Ia = m_c^2 (Ic - Ib) / Ic``: the planes
    ``m_c = +-m_a sqrt(Ic (Ib - Ia) / (Ia (Ic - Ib)))`` through the intermediate axis e_b
    (sorted moments Ia <= Ib <= Ic).

    Parameters
    ----------
    body : RigidBody
        The body, its moments in any order (sorted here into Ia <= Ib <= Ic).
    samples : int, default 721
        Points per circle, over one turn (the first and last coincide).

    Returns
    -------
    list of two ndarrays, shape (samples, 3)
        Unit vectors along the body's own axes.
    """
    order = np.argsort(body.moments, kind="stable")
    a, b, c = order
    Ia, Ib, Ic = body.moments[order]
    s = np.linspace(0.0, 2.0 * np.pi, samples)
    circles = []
    for sign in (1.0, -1.0):
        n = np.zeros(3)
        # n spans the plane with e_b; n_c / n_a = +-sqrt(Ic (Ib - Ia) / (Ia (Ic - Ib))).
        n[a] = np.sqrt(Ia * (Ic - Ib))
        n[c] = sign * np.sqrt(Ic * (Ib - Ia))
        n /= np.linalg.norm(n)
        circles.append(np.cos(s)[:, None] * np.eye(3)[b] + np.sin(s)[:, None] * n)
    return circles


# --------------------------------------------------------------------- Poinsot's construction


def _on_poinsot_ellipsoid(u, moments) -> np.ndarray:
    """rho = w / sqrt(2E) from directions u = m / |L| (..., 3): (u / I) / sqrt(u . u / I)."""
    w = u / moments
    return w / np.sqrt(np.sum(u * w, axis=-1, keepdims=True))


def energy_ellipsoid_polhodes(body, levels=(0.12, 0.35, 0.6, 0.82, 0.96), samples: int = 400):
    """Polhodes on Poinsot's ellipsoid x . I x = 1: the paths of rho = w / sqrt(2E) in the body.

    The orbits of :func:`polhodes` (the same energies, ``2E/L^2 = 1/I_centre + f (1/I_b -
    1/I_centre)``) carried from the sphere to the energy ellipsoid: with u = m / |L| on an orbit,
    ``rho = I^-1 u / sqrt(u . I^-1 u)``, so ``rho . I rho = 1`` (the energy) and
    ``|I rho|^2 = L^2 / (2E)`` (the momentum sphere), see the module docstring.

    Parameters
    ----------
    body : RigidBody
    levels : sequence of float
        Fractions f of the way from the centre to the separatrix, in (0, 1).
    samples : int
        Points per orbit.

    Returns
    -------
    list of (int, list of ndarray)
        ``(centre, curves)`` as in :func:`polhodes`; each curve of shape (samples, 3) in
        kg^-1/2 m^-1, body axes.
    """
    I = body.moments
    return [(centre, [_on_poinsot_ellipsoid(u, I) for u in curves])
            for centre, curves in polhodes(body, levels, samples)]


def energy_ellipsoid_separatrix(body, samples: int = 721):
    """The separatrix on Poinsot's ellipsoid: :func:`separatrix_circles` as rho = w / sqrt(2E).

    On the separatrix 2E / L^2 = 1 / I_b, so rho = sqrt(I_b) I^-1 u for u on the circles: two
    ellipses through +-e_b / sqrt(I_b), the saddles (Landau & Lifshitz, section 37, fig. 50).

    Parameters
    ----------
    body : RigidBody
    samples : int, default 721
        Points per curve.

    Returns
    -------
    list of two ndarrays, shape (samples, 3)
        In kg^-1/2 m^-1, body axes.
    """
    I = body.moments
    return [_on_poinsot_ellipsoid(u, I) for u in separatrix_circles(body, samples)]


def poinsot_polhode(body, w0, samples: int = 400) -> np.ndarray:
    """The polhode of one motion: rho(t) = w(t) / sqrt(2E) over one period, from the exact w(t).

    Parameters
    ----------
    body : RigidBody
    w0 : array_like, shape (3,)
        Angular velocity at t = 0 along the body's axes, rad/s, not zero.
    samples : int, default 400
        Points over one period of w (:func:`stability.full_period`; a steady spin, without a
        period, repeats its one point).

    Returns
    -------
    ndarray, shape (samples, 3)
        rho in kg^-1/2 m^-1, body axes: on ``x . I x = 1`` and ``|I x|^2 = L^2 / (2E)``.
    """

    w0, energy, momentum = _start(body, w0)
    period = float(full_period(body, w0))
    t = np.linspace(0.0, period if np.isfinite(period) else 0.0, samples)
    return np.asarray(exact_omega(body, w0, t), dtype=float) / np.sqrt(2.0 * energy)


def herpolhode_radii(body, w0) -> tuple[float, float]:
    """Least and greatest distance of the herpolhode from the centre of the invariable plane.

    r^2 = |rho|^2 - d^2 = (|w|^2 L^2 - (w . m)^2) / (2E L^2) = |w x m|^2 / (2E L^2) (Lagrange's
    identity: no cancellation). On the polhode the squares s_i = m_i^2 lie on the line ``sum s_i =
    L^2``, ``sum s_i / I_i = 2E``, along which ``|w x m|^2 = sum_{i<j} s_i s_j (1/I_i - 1/I_j)^2``
    equals ``|w|^2 L^2 - 4 E^2``, affine in s: its extremes over the segment with all s_i >= 0 are
    at the ends (the polhode's turning points, where one m_j = 0), and there ``s_k = I_k (2E I_l -
    L^2) / (I_l - I_k)`` for {j, k, l} = {1, 2, 3}, with L^2 - 2E I_l from
    :func:`stability.free_body.model.invariant_differences`. A symmetric body keeps
    |w| constant: one circle; a steady spin about a principal axis: r = 0.

    Parameters
    ----------
    body : RigidBody
    w0 : array_like, shape (3,)
        Angular velocity at t = 0 along the body's axes, rad/s, not zero.

    Returns
    -------
    (float, float)
        r_min <= r_max in kg^-1/2 m^-1.
    """

    w0, energy, momentum = _start(body, w0)
    I = body.moments
    order = np.argsort(I, kind="stable")
    d1, d2, d3 = invariant_differences(body, w0)
    gap = np.empty(3)  # gap[l] = L^2 - 2E I_l, without cancellation
    gap[order] = (d1, d2, -d3)
    pairs = [(i, j, (1.0 / I[i] - 1.0 / I[j]) ** 2) for i in range(3) for j in range(i + 1, 3)]

    def cross2(s):  # |w x m|^2 from the squares m_i^2
        return sum(s[i] * s[j] * c for i, j, c in pairs)

    ends = [cross2((body.moments * w0) ** 2)]
    if np.unique(I).size == 3:  # else |w| is constant along the motion: the start is enough
        for j in range(3):
            k, l = [i for i in range(3) if i != j]
            s = np.zeros(3)
            s[k] = -I[k] * gap[l] / (I[l] - I[k])
            s[l] = -I[l] * gap[k] / (I[k] - I[l])
            if s.min() >= -1e-12 * momentum**2:  # an end of the segment the polhode sweeps
                ends.append(cross2(np.maximum(s, 0.0)))
    r = np.sqrt(np.array(ends) / (2.0 * energy)) / momentum
    return float(r.min()), float(r.max())


class Herpolhode(NamedTuple):
    """What :func:`herpolhode` returns.

    Attributes
    ----------
    points : ndarray, shape (n, 3)
        R(t) rho(t), the contact point, in space components, kg^-1/2 m^-1.
    plane : ndarray, shape (n, 2)
        The same points in the invariable plane, about its centre ``distance * normal``, along
        ``frame[:, 0]`` and ``frame[:, 1]`` (the first axis through the start), kg^-1/2 m^-1.
    normal : ndarray, shape (3,)
        L / |L| in space.
    distance : float
        sqrt(2E) / |L|, the distance of the plane from the centre, kg^-1/2 m^-1.
    frame : ndarray, shape (3, 3)
        Columns: the plane's two axes and the normal
        (:func:`stability.core.quaternions.frame_along`).
    radii : (float, float)
        :func:`herpolhode_radii`: the annulus the curve fills.
    """

    points: np.ndarray
    plane: np.ndarray
    normal: np.ndarray
    distance: float
    frame: np.ndarray
    radii: tuple


def herpolhode(body, w0, t, q0=None) -> Herpolhode:
    """The herpolhode: the path of the contact point rho = w / sqrt(2E) on the invariable plane.

    ``R(t) rho(t)`` with the exact attitude
    (:func:`stability.free_body.exact_attitude.exact_attitude`) and the exact w(t): a point of the
    plane ``x . L / |L| = sqrt(2E) / |L|`` at every t (module docstring; Poinsot 1834, Landau &
    Lifshitz section 37).

    Parameters
    ----------
    body : RigidBody
    w0 : array_like, shape (3,)
        Angular velocity at t = 0 along the body's axes, rad/s; off the separatrix and not a
        spin exactly about the smallest-moment axis (where the exact attitude is refused).
    t : array_like, shape (n,)
        Times in s.
    q0 : array_like, shape (4,), optional
        Attitude at t = 0 (body to space, scalar first); default the identity.

    Returns
    -------
    Herpolhode
        The points in space and in the plane, the plane's normal and distance, the radii.
    """

    w0, energy, momentum = _start(body, w0)
    q = exact_attitude(body, w0, t, q0)
    if not np.all(np.isfinite(q)):
        raise ValueError("w0 is on the separatrix (or within round-off of it): the motion has "
                         "no period and no exact attitude; perturb w0 off the separatrix")
    t = np.atleast_1d(np.asarray(t, dtype=float))
    rho = np.asarray(exact_omega(body, w0, t), dtype=float) / np.sqrt(2.0 * energy)
    points = np.einsum("nij,nj->ni", quaternion_to_matrix(q), rho)
    R0 = quaternion_to_matrix(IDENTITY if q0 is None else q0)
    normal = R0 @ (body.moments * w0) / momentum
    distance = float(np.sqrt(2.0 * energy) / momentum)
    frame = frame_along(normal, hint=points[0])
    plane = (points - distance * normal) @ frame[:, :2]
    return Herpolhode(points, plane, normal, distance, frame, herpolhode_radii(body, w0))


def _start(body, w0):
    """w0 checked (shape (3,), finite, not zero), the energy (J) and |L| (kg m^2/s)."""

    if not isinstance(body, RigidBody):
        raise ValueError(f"body must be a stability.RigidBody, got {type(body).__name__}")
    w0 = vectors3("w0", w0, "rad/s")
    if w0.ndim != 1:
        raise ValueError(f"w0 must have shape (3,), got {w0.shape}")
    momentum = float(angular_momentum_norm(body, w0))
    if momentum == 0.0:
        raise ValueError("w0 = 0: a body at rest has no polhode; give it an angular velocity")
    return w0, float(kinetic_energy(body, w0)), momentum
