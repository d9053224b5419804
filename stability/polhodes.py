"""Polhodes: the paths of the body angular momentum m / |L| on the unit sphere, and the separatrix.

The torque-free motion keeps |m| = L and the energy, so m moves on the intersection of a
sphere and an ellipsoid: closed curves around the axes of the smallest and the largest moment
(stable centres), separated by the separatrix D2 = L^2 - 2 E I2 = 0, two great circles through
the saddles at +-e2 of the intermediate axis (literature notes 1.5). Used by the polhode figure
of the tennis-racket study.
"""

from __future__ import annotations

import numpy as np


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
    from .exact import exact_omega, full_period

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
