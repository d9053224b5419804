r"""Three damped bodies: a rigid shell with a viscous spherical damper, one with a spring-mass
damper, and a gyrostat (a dual-spin body) with a spherical damper on its platform, in its rotor
or both. All keep :math:`|H|` and lose energy; the first two end spinning about their major
axis.

Scene ``sphere_damper``: the state is ``(m1, m2, m3, s1, s2, s3)``, the shell's angular
momentum :math:`m = I \omega` and the sphere's :math:`s = J \omega_s`, in the shell's principal
frame (canonical, :math:`I_1 \le I_2 \le I_3`). Parameters per body: ``(I1, I2, I3, J, c)``, the
shell's moments, the sphere's and the viscous coefficient (the fluid's torque on the shell is
:math:`c\, (\omega_s - \omega)`). Equations and methods: :mod:`stability.dissipation.methods`:

.. math::

    \dot m = m \times \omega + c\, (\omega_s - \omega), \qquad
    \dot s = s \times \omega - c\, (\omega_s - \omega).

Scene ``whip_damper``: four flexible whip antennas, radial from the body along :math:`\pm e_2`
and :math:`\pm e_3` at the arm :math:`b`, whose tips bend along the spin axis :math:`e_1`: each
opposite pair bends antisymmetrically (tips at :math:`\pm(b\, e_k + z_k e_1)`, so the centre of
mass stays put) on a spring :math:`k` with a dashpot :math:`c`, :math:`\mu` the mass of a pair.
The state is ``(H1, H2, H3, z2, z3, p2, p3)``: the total angular momentum, the pairs'
deflections and their momenta :math:`p_2 = \mu\, (\dot z_2 - b\, \omega_3)`,
:math:`p_3 = \mu\, (\dot z_3 + b\, \omega_2)`. From the kinetic energy
:math:`T = \omega \cdot I \omega / 2 + \sum_k \mu\, |\omega \times r_k + \dot z_k e_1|^2 / 2`,
:math:`r_k = b\, e_k + z_k e_1`, Lagrange's equations in the body frame give

.. math::

    \begin{gathered}
    \dot H = H \times \omega, \qquad \dot z_2 = p_2 / \mu + b\, \omega_3, \qquad
    \dot z_3 = p_3 / \mu - b\, \omega_2, \\
    \dot p_2 = \mu\, \big(z_2 (\omega_2^2 + \omega_3^2) - b\, \omega_1 \omega_2\big)
    - k z_2 - c\, \dot z_2, \\
    \dot p_3 = \mu\, \big(z_3 (\omega_2^2 + \omega_3^2) - b\, \omega_1 \omega_3\big)
    - k z_3 - c\, \dot z_3,
    \end{gathered}

with :math:`\omega` from the state (:func:`~stability.dissipation.methods.whip_rates`). One pair
alone would leave a spin about the axis across both its arm and :math:`e_1` undamped at linear
order; two pairs damp every spin. Parameters per body: ``(I1, I2, I3, mu, b, k, c)``, the body's
moments without the tips (:math:`e_1` the long axis).

Scene ``gyrostat``: a platform and an axisymmetric rotor on a frictionless bearing along the
platform's principal axis :math:`e_3`, with a viscous spherical damper on the platform (``Jp``,
``cp``) and one in the rotor (``Jq``, ``cq``); ``c = 0``: that damper is absent (its sphere at
rest, zero momentum, stays so). The state is ``(m1, m2, m3, hr, p1, p2, p3, q1, q2, q3)`` in the
platform's principal frame: the angular momentum of platform and rotor
:math:`m = A \omega + J_r \Omega\, e_3` (:math:`A = \mathrm{diag}(A_1, A_2, A_3)` the whole
body's moments, the rotor's included; :math:`\Omega` the rotor's spin relative to the platform),
the rotor's axial momentum :math:`h_r = J_r (\omega_3 + \Omega)` and the spheres' momenta.
Parameters ``(A1, A2, A3, Jr, Jp, cp, Jq, cq)``. Equations (2) of
:mod:`stability.dissipation.methods`, derived in :mod:`stability.dissipation.model_gyrostat`:

.. math::

    \begin{gathered}
    \dot m = m \times \omega + c_p u_p + c_q u_q, \qquad \dot h_r = c_q u_{q,3}, \qquad
    \dot p = p \times \omega - c_p u_p, \qquad \dot q = q \times \omega - c_q u_q, \\
    \omega = \big(m_1 / A_1,\ m_2 / A_2,\ (m_3 - h_r) / (A_3 - J_r)\big), \qquad
    u_p = p / J_p - \omega, \qquad u_q = q / J_q - (\omega_1, \omega_2, h_r / J_r).
    \end{gathered}

Invariant of all three: :math:`|H|` (``angular_momentum``; :math:`H = m + p + q` for the
gyrostat). The energy (:func:`sphere_energy`, :func:`whip_energy`) is not one: it falls at the
rate :math:`c\, |\omega_s - \omega|^2` (sphere) or :math:`c\, (\dot z_2^2 + \dot z_3^2)`
(whips), :math:`c_p |u_p|^2 + c_q |u_q|^2` (gyrostat, :func:`gyrostat_energy`), a Lyapunov
function. Tracking: the spin-axis component is :math:`H_a / |H|` (the cosine of the nutation
angle between body axis :math:`a` and :math:`H`: it changes sign when that axis turns
perpendicular to :math:`H`) and the amplitude across it :math:`\sqrt{H_b^2 + H_c^2} / |H|`, its
sine, returned as ``b`` with ``c = 0``.

Tangent equations (:func:`stability.engine.tangent.tangent_scene`): the sphere damper and the
gyrostat declare the exact products ``J v`` of their right-hand sides (:func:`~.methods.sphere_jvp`,
:func:`~.methods.gyrostat_jvp`); the whip damper none.
"""

import math

import numpy as np
from numba import njit

from ..util import conventions as cv
from ..engine.scene import Scene, component
from ..engine.tangent import Linearisation
from ..integrators.spec import P_INV1, P_INV2, P_INV3
from .methods import (B_B, B_I1, B_I2, B_I3, B_K, B_MU, B_MU_B, GYROSTAT_METHODS, P_INV_J,
                      SPHERE_METHODS, WHIP_METHODS, gyrostat_jvp, gyrostat_params, gyrostat_rhs,
                      sphere_jvp, sphere_params, sphere_rhs, whip_params, whip_rates)


@njit(forceinline=True, error_model="numpy")
def nutation_components(H1, H2, H3, ia, ib, ic):
    """``(H_a / |H|, sqrt(H_b^2 + H_c^2) / |H|, 0)``: cosine and sine of body axis a's angle
    from H."""
    hb = component(H1, H2, H3, ib)
    hc = component(H1, H2, H3, ic)
    across = math.sqrt(hb * hb + hc * hc)
    norm = math.sqrt(H1 * H1 + H2 * H2 + H3 * H3)
    inv = 1.0 / norm if norm > 0.0 else 0.0
    return component(H1, H2, H3, ia) * inv, across * inv, 0.0


def nutation_tracked(H, axes):
    """:func:`nutation_components` in NumPy over angular momenta ``H`` (N, 3)."""
    norm = np.linalg.norm(H, axis=1)
    norm = np.where(norm > 0.0, norm, np.inf)
    across = np.hypot(H[:, axes[1]], H[:, axes[2]])
    return H[:, axes[0]] / norm, across / norm, np.zeros(H.shape[0])


def sphere_momentum(x):
    """The total angular momentum ``H = m + s`` (kg m2 s-1) of states ``x`` (..., 6)."""
    return x[..., 0:3] + x[..., 3:6]


@njit(inline="always")
def sphere_observe(m1, m2, m3, s1, s2, s3, p, ia, ib, ic):
    """Cosine and sine of body axis a's angle from ``H = m + s``."""
    return nutation_components(m1 + s1, m2 + s2, m3 + s3, ia, ib, ic)


def sphere_tracked(x, p, axes):
    """:func:`sphere_observe` in NumPy over states ``x`` (N, 6)."""
    return nutation_tracked(sphere_momentum(x), axes)


def sphere_angular_momentum(x, values):
    """``|H| = |m + s|`` (kg m2 s-1) of states ``x`` (N, 6); constant."""
    return np.linalg.norm(sphere_momentum(x), axis=-1)


def sphere_energy(x, values):
    """``E = (m . I^-1 m + |s|^2 / J) / 2`` (J) of states ``x`` (..., 6); falls at the rate
    ``c |s / J - I^-1 m|^2``."""
    p = sphere_params(values)
    inverse = np.array([p[P_INV1], p[P_INV2], p[P_INV3]])
    return 0.5 * (np.sum(x[..., 0:3] ** 2 * inverse, axis=-1)
                  + np.sum(x[..., 3:6] ** 2, axis=-1) * p[P_INV_J])


def sphere_rigid_state(values, w):
    """States (N, 6) of the body turning rigidly at ``w`` (N, 3), the sphere with the shell:
    ``m = I w``, ``s = J w``."""
    values = np.asarray(values, dtype=float)
    w = np.atleast_2d(np.asarray(w, dtype=float))
    return np.hstack([w * values[:3], w * values[3]])


def sphere_moments(values) -> np.ndarray:
    """The whole system's principal moments ``A_k = I_k + J`` (kg m2): the shell and the
    sphere turning with it."""
    values = np.asarray(values, dtype=float)
    return values[:3] + values[3]


def sphere_example(n, seed=0):
    """Starts near a spin about the minor axis, the sphere turning with the shell, and three
    bodies (generic tests)."""
    rng = np.random.default_rng(seed)
    w = np.column_stack([np.full(n, 2.0), 1e-2 * rng.standard_normal((n, 2))])
    sets = [np.array([1.0, 2.0, 3.0, 0.2, 0.1]), np.array([1.0, 1.5, 2.2, 0.5, 2.0]),
            np.array([0.5, 2.0, 2.0, 0.05, 0.01])]
    return sphere_rigid_state(sets[0], w), sets


SPHERE_DAMPER = Scene(
    name="sphere_damper",
    module=__name__,
    title="rigid body with a viscous spherical damper (shell and sphere angular momenta)",
    equations="m' = m x w + c (w_s - w), s' = s x w - c (w_s - w) (m = I w, s = J w_s)",
    latex=(r"\dot m = m \times \omega + c\, (\omega_s - \omega), \qquad"
           r" \dot s = s \times \omega - c\, (\omega_s - \omega)"
           r" \qquad (m = I \omega,\ s = J \omega_s)"),
    components=("m1", "m2", "m3", "s1", "s2", "s3"),
    units=(cv.UNITS_ANGULAR_MOMENTUM,) * 6,
    methods=SPHERE_METHODS,
    observe=sphere_observe,
    tracked=sphere_tracked,
    invariants={"angular_momentum": sphere_angular_momentum},
    example=sphere_example,
    parameters=("I1", "I2", "I3", "J", "c"),
    tracked_units=cv.UNITS_DIMENSIONLESS,
    linearisation=Linearisation(sphere_rhs, sphere_jvp, sphere_params),
)


@njit(inline="always")
def whip_observe(H1, H2, H3, z2, z3, p2, p3, p, ia, ib, ic):
    """Cosine and sine of body axis a's angle from H."""
    return nutation_components(H1, H2, H3, ia, ib, ic)


def whip_tracked(x, p, axes):
    """:func:`whip_observe` in NumPy over states ``x`` (N, 7)."""
    return nutation_tracked(x[:, 0:3], axes)


def whip_momentum(x):
    """The total angular momentum H (kg m2 s-1) of states ``x`` (..., 7)."""
    return x[..., 0:3]


def whip_angular_momentum(x, values):
    """``|H|`` (kg m2 s-1) of states ``x`` (N, 7); constant."""
    return np.linalg.norm(whip_momentum(x), axis=-1)


def whip_energy(x, values):
    """``E = (H . w + p2 z2' + p3 z3' + k (z2^2 + z3^2)) / 2`` (J) of states ``x`` (..., 7);
    falls at the rate ``c (z2'^2 + z3'^2)``."""
    p = whip_params(values)
    x = np.asarray(x, dtype=float)
    H1, H2, H3, z2, z3, p2, p3 = (x[..., k] for k in range(7))
    w1, w2, w3, dz2, dz3 = whip_rates.py_func(H1, H2, H3, z2, z3, p2, p3, p)
    return 0.5 * (H1 * w1 + H2 * w2 + H3 * w3 + p2 * dz2 + p3 * dz3
                  + p[B_K] * (z2 * z2 + z3 * z3))


def whip_rigid_state(values, w):
    """States (N, 7) of the body turning rigidly at ``w`` (N, 3), the tips at rest in it:
    ``H = A w`` (:func:`whip_moments`), ``z = 0``, ``p2 = -mu b w3``, ``p3 = mu b w2``."""
    p = whip_params(values)
    w = np.atleast_2d(np.asarray(w, dtype=float))
    mu_b = p[B_MU_B]
    return np.column_stack([w * whip_moments(values), np.zeros((w.shape[0], 2)),
                            -mu_b * w[:, 2], mu_b * w[:, 1]])


def whip_moments(values) -> np.ndarray:
    """The whole system's principal moments (kg m2), tips at rest:
    ``(I1 + 2 mu b^2, I2 + mu b^2, I3 + mu b^2)``."""
    p = whip_params(values)
    extra = p[B_MU] * p[B_B] ** 2
    return np.array([p[B_I1] + 2.0 * extra, p[B_I2] + extra, p[B_I3] + extra])


def whip_example(n, seed=0):
    """Starts near a spin about the long axis e1, the tips at rest, and three bodies."""
    rng = np.random.default_rng(seed)
    sets = [np.array([1.0, 2.0, 3.0, 0.05, 0.5, 3.0, 0.2]),
            np.array([0.5, 2.0, 2.0, 0.02, 0.8, 1.0, 0.05]),
            np.array([1.0, 1.5, 2.2, 0.1, 0.3, 5.0, 0.5])]
    w = np.column_stack([np.full(n, 2.0), 1e-2 * rng.standard_normal((n, 2))])
    return whip_rigid_state(sets[0], w), sets


WHIP_DAMPER = Scene(
    name="whip_damper",
    module=__name__,
    title="rigid body with four whip antennas (two pairs of spring-mass dampers)",
    equations="H' = H x w, z2' = p2 / mu + b w3, z3' = p3 / mu - b w2, "
              "p_k' = mu (z_k (w2^2 + w3^2) - b w1 w_k) - k z_k - c z_k'",
    latex=(r"\begin{gathered} \dot H = H \times \omega, \quad \dot z_2 = p_2/\mu + b\, \omega_3,"
           r" \quad \dot z_3 = p_3/\mu - b\, \omega_2, \\"
           r" \dot p_k = \mu\, \big(z_k (\omega_2^2 + \omega_3^2) - b\, \omega_1 \omega_k\big)"
           r" - k z_k - c\, \dot z_k \end{gathered}"),
    components=("H1", "H2", "H3", "z2", "z3", "p2", "p3"),
    units=(cv.UNITS_ANGULAR_MOMENTUM,) * 3 + ("m", "m", "kg m s-1", "kg m s-1"),
    methods=WHIP_METHODS,
    observe=whip_observe,
    tracked=whip_tracked,
    invariants={"angular_momentum": whip_angular_momentum},
    example=whip_example,
    parameters=("I1", "I2", "I3", "mu", "b", "k", "c"),
    tracked_units=cv.UNITS_DIMENSIONLESS,
)


@njit(inline="always")
def gyrostat_observe(m1, m2, m3, hr, p1, p2, p3, q1, q2, q3, p, ia, ib, ic):
    """Cosine and sine of platform axis a's angle from ``H = m + p + q``."""
    return nutation_components(m1 + p1 + q1, m2 + p2 + q2, m3 + p3 + q3, ia, ib, ic)


def gyrostat_momentum(x):
    """The total angular momentum ``H = m + p + q`` (kg m2 s-1) of states ``x`` (..., 10)."""
    x = np.asarray(x, dtype=float)
    return x[..., 0:3] + x[..., 4:7] + x[..., 7:10]


def gyrostat_tracked(x, p, axes):
    """:func:`gyrostat_observe` in NumPy over states ``x`` (N, 10)."""
    return nutation_tracked(gyrostat_momentum(x), axes)


def gyrostat_angular_momentum(x, values):
    """``|H| = |m + p + q|`` (kg m2 s-1) of states ``x`` (N, 10); constant."""
    return np.linalg.norm(gyrostat_momentum(x), axis=-1)


def gyrostat_energy(x, values):
    """``E = (m1^2 / A1 + m2^2 / A2 + (m3 - hr)^2 / (A3 - Jr) + hr^2 / Jr + |p|^2 / Jp
    + |q|^2 / Jq) / 2`` (J) of states ``x`` (..., 10): the platform's (with the rotor's
    transverse motion), the rotor's spin, the spheres'; falls at the rate
    ``cp |u_p|^2 + cq |u_q|^2``."""
    A1, A2, A3, Jr, Jp, _, Jq, _ = np.asarray(values, dtype=float)
    x = np.asarray(x, dtype=float)
    m1, m2, m3, hr = (x[..., k] for k in range(4))
    return 0.5 * (m1 * m1 / A1 + m2 * m2 / A2 + (m3 - hr) ** 2 / (A3 - Jr) + hr * hr / Jr
                  + np.sum(x[..., 4:7] ** 2, axis=-1) / Jp
                  + np.sum(x[..., 7:10] ** 2, axis=-1) / Jq)


def gyrostat_rigid_state(values, w, relative_spin):
    """States (N, 10) of a gyrostat whose platform turns at ``w`` (N, 3) and whose rotor spins
    at ``relative_spin`` (rad s-1, (N,) or one number) relative to it, each damper's sphere
    turning with its body: ``m = A w + Jr Omega e3``, ``hr = Jr (w3 + Omega)``, ``p = Jp w``,
    ``q = Jq (w1, w2, w3 + Omega)``; an absent damper's sphere (c = 0) at rest."""
    A1, A2, A3, Jr, Jp, cp, Jq, cq = np.asarray(values, dtype=float)
    w = np.atleast_2d(np.asarray(w, dtype=float))
    omega = np.broadcast_to(np.asarray(relative_spin, dtype=float), (w.shape[0],))
    rotor = w.copy()
    rotor[:, 2] += omega
    return np.column_stack([w * [A1, A2, A3] + np.outer(Jr * omega, [0.0, 0.0, 1.0]),
                            Jr * rotor[:, 2], (Jp if cp > 0 else 0.0) * w,
                            (Jq if cq > 0 else 0.0) * rotor])


def gyrostat_example(n, seed=0):
    """Starts near a spin of the platform about the rotor's axis (1 rad s-1), the rotor at
    2 rad s-1 relative to it, both spheres turning with their bodies; and three gyrostats: a
    minor-axis one with both dampers, a triaxial one with the platform's only, a major-axis one
    with the rotor's only (generic tests)."""
    rng = np.random.default_rng(seed)
    sets = [np.array([1.0, 1.0, 0.6, 0.25, 0.05, 0.02, 0.04, 0.03]),
            np.array([1.0, 1.3, 0.8, 0.3, 0.05, 0.04, 0.05, 0.0]),
            np.array([1.0, 1.0, 1.4, 0.3, 0.05, 0.0, 0.05, 0.05])]
    w = np.column_stack([1e-2 * rng.standard_normal((n, 2)), np.full(n, 1.0)])
    return gyrostat_rigid_state(sets[0], w, 2.0), sets


GYROSTAT = Scene(
    name="gyrostat",
    module=__name__,
    title="gyrostat (dual-spin body): platform, rotor on a free bearing, a spherical damper on "
          "each",
    equations="m' = m x w + cp u_p + cq u_q, hr' = cq u_q3, p' = p x w - cp u_p, "
              "q' = q x w - cq u_q (w = (m1/A1, m2/A2, (m3 - hr)/(A3 - Jr)), "
              "u_p = p/Jp - w, u_q = q/Jq - (w1, w2, hr/Jr))",
    latex=(r"\begin{gathered} \dot m = m \times \omega + c_p u_p + c_q u_q, \quad"
           r" \dot h_r = c_q u_{q,3}, \\ \dot p = p \times \omega - c_p u_p, \quad"
           r" \dot q = q \times \omega - c_q u_q, \\ \omega = \big(m_1/A_1,\ m_2/A_2,\ "
           r"(m_3 - h_r)/(A_3 - J_r)\big), \\ u_p = p/J_p - \omega, \quad"
           r" u_q = q/J_q - (\omega_1, \omega_2, h_r/J_r) \end{gathered}"),
    components=("m1", "m2", "m3", "hr", "p1", "p2", "p3", "q1", "q2", "q3"),
    units=(cv.UNITS_ANGULAR_MOMENTUM,) * 10,
    methods=GYROSTAT_METHODS,
    observe=gyrostat_observe,
    tracked=gyrostat_tracked,
    invariants={"angular_momentum": gyrostat_angular_momentum},
    example=gyrostat_example,
    parameters=("A1", "A2", "A3", "Jr", "Jp", "cp", "Jq", "cq"),
    tracked_units=cv.UNITS_DIMENSIONLESS,
    linearisation=Linearisation(gyrostat_rhs, gyrostat_jvp, gyrostat_params),
)
