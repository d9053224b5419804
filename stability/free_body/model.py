"""Closed-form results for the torque-free rigid body: invariants and linear stability.

Plain numpy functions, vectorized: ``w`` is a body-frame angular velocity of shape (..., 3) in
rad/s, and ``body`` is a :class:`~stability.core.body.RigidBody` or an array of principal moments of
shape (..., 3) in kg m^2 (broadcast against ``w`` or ``spin``), so one call covers an ensemble or
a grid over inertia space. Moments may be in any order; axis labels 1, 2, 3 are the caller's.

- Invariants: :func:`kinetic_energy`, :func:`angular_momentum`, :func:`angular_momentum_norm`,
  and the cancellation-free combinations :func:`invariant_differences` (D1, D2, D3) whose
  sign (D2) decides the regime of the motion.
- Linear stability of steady spin about a principal axis: :func:`omega_squared` (with the sign
  of ERRATA 2: > 0 oscillation, < 0 growth), :func:`growth_rate`,
  :func:`oscillation_frequency`, :func:`axis_stability`.
- Axes: :func:`stability.util.conventions.perpendicular_axes`; which axis carries which moment is
  :mod:`stability.core.axes`.
- Euler's equations in w for NumPy and SciPy: :func:`euler_rhs`, :func:`euler_system`.

Non-finite angular velocities give non-finite results (masked ensemble members stay masked);
spins must be finite.
"""

from __future__ import annotations

import numbers
from typing import NamedTuple

import numpy as np

from ..core.axes import principal_moments as _moments
from ..util.checks import real_array

__all__ = [
    "InvariantDifferences",
    "angular_momentum",
    "angular_momentum_norm",
    "axis_stability",
    "euler_rhs",
    "euler_system",
    "growth_rate",
    "invariant_differences",
    "kinetic_energy",
    "omega_squared",
    "oscillation_frequency",
]

# --------------------------------------------------------------------------------- invariants


def kinetic_energy(body, w):
    """Rotational kinetic energy ``E = (I1 w1^2 + I2 w2^2 + I3 w3^2) / 2``.

    Parameters
    ----------
    body : RigidBody or array_like, shape (..., 3)
        Principal moments in kg m^2.
    w : array_like, shape (..., 3)
        Body-frame angular velocity in rad/s.

    Returns
    -------
    ndarray or float, shape (...)
        Kinetic energy in J. Conserved by the torque-free motion.
    """
    I, w = _moments_and_w(body, w)
    return 0.5 * np.sum(I * w * w, axis=-1)


def angular_momentum(body, w):
    """Body angular momentum ``m = I w`` (components along the principal axes).

    Parameters
    ----------
    body : RigidBody or array_like, shape (..., 3)
        Principal moments in kg m^2.
    w : array_like, shape (..., 3)
        Body-frame angular velocity in rad/s.

    Returns
    -------
    ndarray, shape (..., 3)
        ``m`` in kg m^2/s. Its length is conserved; the vector turns in the body frame
        (``m' = m x w``) while its space-frame image stays fixed.
    """
    I, w = _moments_and_w(body, w)
    return I * w


def angular_momentum_norm(body, w):
    """Length ``L = |I w|`` of the angular momentum.

    Parameters
    ----------
    body : RigidBody or array_like, shape (..., 3)
        Principal moments in kg m^2.
    w : array_like, shape (..., 3)
        Body-frame angular velocity in rad/s.

    Returns
    -------
    ndarray or float, shape (...)
        ``L`` in kg m^2/s. Conserved by the torque-free motion (a Casimir of the Lie-Poisson
        bracket, so Lie-Poisson integrators keep it to round-off).
    """
    I, w = _moments_and_w(body, w)
    return np.linalg.norm(I * w, axis=-1)


class InvariantDifferences(NamedTuple):
    """D1, D2, D3 in kg^2 m^4 s^-2, each of shape (...); see :func:`invariant_differences`."""

    D1: np.ndarray
    D2: np.ndarray
    D3: np.ndarray


def invariant_differences(body, w) -> InvariantDifferences:
    """The invariant combinations D1, D2, D3, written without cancellation.

    With the moments sorted, ``Ia <= Ib <= Ic`` (``Ib`` the body's intermediate moment,
    whatever its label) and ``wa, wb, wc`` the matching components of ``w``::

        D1 = L^2 - 2E Ia = Ib (Ib - Ia) wb^2 + Ic (Ic - Ia) wc^2   >= 0
        D2 = L^2 - 2E Ib = Ia (Ia - Ib) wa^2 + Ic (Ic - Ib) wc^2   (either sign)
        D3 = 2E Ic - L^2 = Ia (Ic - Ia) wa^2 + Ib (Ic - Ib) wb^2   >= 0

    The right-hand sides are sums of terms of one sign each (two in D2), so they keep full
    relative accuracy near the separatrix, where ``L^2`` and ``2E Ib`` agree to many digits.
    D2 > 0: ``w`` circles the largest-moment axis; D2 < 0: the smallest-moment axis; D2 = 0:
    the separatrix through the unstable steady spins about the intermediate axis. Conventions
    of the package's literature notes (Leroy, "On an article by Celledoni et al.", Principia
    documentation; Landau & Lifshitz, *Mechanics*, section 37).

    Parameters
    ----------
    body : RigidBody or array_like, shape (..., 3)
        Principal moments in kg m^2, any order.
    w : array_like, shape (..., 3)
        Body-frame angular velocity in rad/s, in the body's own axis order.

    Returns
    -------
    InvariantDifferences
        Named tuple ``(D1, D2, D3)``, each of shape (...), in kg^2 m^4 s^-2. With equal moments
        the labels of the sorted axes are ambiguous but the values are not.
    """
    I, w = _moments_and_w(body, w)
    I, w = np.broadcast_arrays(I, w)
    order = np.argsort(I, axis=-1, kind="stable")
    Is = np.take_along_axis(I, order, axis=-1)
    w2 = np.take_along_axis(w, order, axis=-1) ** 2
    Ia, Ib, Ic = Is[..., 0], Is[..., 1], Is[..., 2]
    D1 = Ib * (Ib - Ia) * w2[..., 1] + Ic * (Ic - Ia) * w2[..., 2]
    D2 = Ia * (Ia - Ib) * w2[..., 0] + Ic * (Ic - Ib) * w2[..., 2]
    D3 = Ia * (Ic - Ia) * w2[..., 0] + Ib * (Ic - Ib) * w2[..., 1]
    return InvariantDifferences(D1, D2, D3)


# ------------------------------------------------------------------------- Euler's equations


def _euler_coefficients(body):
    """``(a1, a2, a3)`` of ``w1' = a1 w2 w3`` and cyclic: ``a1 = (I2 - I3) / I1`` (ERRATA 1)."""
    I = _moments(body)
    I1, I2, I3 = I[..., 0], I[..., 1], I[..., 2]
    return (I2 - I3) / I1, (I3 - I1) / I2, (I1 - I2) / I3


def _euler_terms(a1, a2, a3, w1, w2, w3):
    # I1 w1' = (I2 - I3) w2 w3, cyclic (ERRATA 1), with the moments divided out first.
    return a1 * w2 * w3, a2 * w3 * w1, a3 * w1 * w2


def euler_rhs(body, w):
    """Torque-free Euler equations in w: ``w' = (a1 w2 w3, a2 w3 w1, a3 w1 w2)``.

    ``a1 = (I2 - I3) / I1`` and cyclic: the NumPy twin of the kernels' right-hand side (which
    work on ``m = I w``), for references and predictions outside the compiled loop.

    Parameters
    ----------
    body : RigidBody or array_like, shape (..., 3)
        Principal moments in kg m^2.
    w : array_like, shape (..., 3)
        Body-frame angular velocity in rad/s.

    Returns
    -------
    ndarray, shape (..., 3)
        ``dw/dt`` in rad s^-2.
    """
    I, w = _moments_and_w(body, w)
    terms = _euler_terms(*_euler_coefficients(I), w[..., 0], w[..., 1], w[..., 2])
    return np.stack(terms, axis=-1)


def euler_system(body, members: int):
    """Euler's equations in w for ``scipy.integrate.solve_ivp``, ``members`` starts as one system.

    The state is stacked component by component, ``y = (w1[:], w2[:], w3[:])`` of length
    ``3 members`` (``np.ascontiguousarray(w0.T).ravel()`` for starts ``w0`` (N, 3)), so the
    right-hand side is three NumPy expressions over all members (:func:`euler_rhs`'s terms).

    Parameters
    ----------
    body : RigidBody or array_like, shape (3,)
        Principal moments in kg m^2, one body shared by all members.
    members : int
        Number of starts integrated together.

    Returns
    -------
    callable
        ``rhs(t, y)`` returning ``dy/dt``, shape (3 members,).
    """
    a1, a2, a3 = (float(a) for a in _euler_coefficients(body))

    def rhs(t, y):
        w1, w2, w3 = y[:members], y[members : 2 * members], y[2 * members :]
        return np.concatenate(_euler_terms(a1, a2, a3, w1, w2, w3))

    return rhs


# ------------------------------------------------------------------------ linear stability


def omega_squared(body, axis, spin):
    """Omega^2 of steady spin about a principal axis: > 0 oscillation, < 0 exponential growth.

    For steady spin ``W`` about principal axis ``a``, with ``b`` and ``c`` the other two, the
    linearised Euler equations give ``d2x/dt2 = -Omega^2 x`` for the perpendicular components::

        Omega^2 = (Ia - Ib) (Ia - Ic) W^2 / (Ib Ic)

    (ERRATA 2 of the course notes, which had the opposite sign; literature notes 2.1). It is
    positive (a stable oscillation at ``sqrt(Omega^2)``, the body-frame free precession) for
    the largest and the smallest moment, negative (growth at ``sqrt(-Omega^2)``) for the
    intermediate one, and exactly 0 for an axis whose moment equals another one: the
    differences are taken directly, as ``((Ia - Ib) / Ib) ((Ia - Ic) / Ic) W^2``, with no
    cancellation.

    Parameters
    ----------
    body : RigidBody or array_like, shape (..., 3)
        Principal moments in kg m^2, any order.
    axis : int
        The spin axis: 1, 2 or 3, the label of the moment ``body.I1``, ``I2`` or ``I3``.
    spin : float or array_like
        Spin rate ``W`` in rad/s (finite; the sign does not matter). Broadcast against the
        moments' leading shape.

    Returns
    -------
    ndarray or float
        Omega^2 in s^-2 (rad^2 s^-2).

    Raises
    ------
    ValueError
        If ``axis`` is not 1, 2 or 3, ``spin`` is not finite, or the moments are not finite
        and > 0.

    Examples
    --------
    >>> body = stability.RigidBody(1.0, 2.0, 3.0)
    >>> [float(omega_squared(body, a, 1.0)) for a in (1, 2, 3)]
    [0.3333333333333333, -0.3333333333333333, 1.0]
    """
    Ia, Ib, Ic = _axis_moments(body, axis)
    W = _spin(spin)
    return (Ia - Ib) / Ib * ((Ia - Ic) / Ic) * (W * W)


def growth_rate(body, axis, spin):
    """Exponential growth rate ``sqrt(-Omega^2)`` of a small perturbation of steady spin.

    Nonzero only for the intermediate axis, where perturbations along the unstable
    eigenvector grow like ``exp(lambda t)`` with
    ``lambda = |W| sqrt((Ib - Ia)(Ic - Ib) / (Ia Ic))`` (sorted moments; literature notes 2.1),
    the same rate as the separatrix's tanh/sech solution.

    Parameters
    ----------
    body, axis, spin
        As in :func:`omega_squared`.

    Returns
    -------
    ndarray or float
        Growth rate in s^-1 where Omega^2 < 0, else 0 (stable or neutral axis).
    """
    return np.sqrt(np.maximum(-omega_squared(body, axis, spin), 0.0))


def oscillation_frequency(body, axis, spin):
    """Angular frequency ``sqrt(Omega^2)`` of small oscillations about steady spin.

    The body-frame precession of ``w`` about a stable axis (largest or smallest moment); for a
    symmetric top ``I1 = I2`` spinning about axis 3 it is ``|I3 - I1| |W| / I1``.

    Parameters
    ----------
    body, axis, spin
        As in :func:`omega_squared`.

    Returns
    -------
    ndarray or float
        Frequency in rad/s where Omega^2 > 0, else 0 (unstable or neutral axis).
    """
    return np.sqrt(np.maximum(omega_squared(body, axis, spin), 0.0))


def axis_stability(body, axis):
    """Linear stability of steady spin about a principal axis, as a word.

    - ``"stable"``: the axis of the largest or the smallest moment (Omega^2 > 0); small
      perturbations oscillate (and stay small: the motion is Lyapunov stable).
    - ``"unstable"``: the intermediate axis (Omega^2 < 0); perturbations grow exponentially
      and the body flips (the tennis-racket effect).
    - ``"neutral"``: the moment equals another one (Omega^2 = 0). Every axis in the
      equal-moment plane is principal; a perturbation makes ``w`` drift slowly around that
      plane, departing linearly in time, not exponentially, and never flipping (ERRATA 3).
      A sphere is neutral about every axis.

    Parameters
    ----------
    body : RigidBody or array_like, shape (..., 3)
        Principal moments in kg m^2, any order.
    axis : int
        1, 2 or 3.

    Returns
    -------
    str, or ndarray of str with the moments' leading shape
    """
    Ia, Ib, Ic = _axis_moments(body, axis)
    sign = np.sign(Ia - Ib) * np.sign(Ia - Ic)
    words = np.where(sign > 0, "stable", np.where(sign < 0, "unstable", "neutral"))
    return str(words) if words.ndim == 0 else words


# -------------------------------------------------------------------------------- validation


def _moments_and_w(body, w) -> tuple[np.ndarray, np.ndarray]:
    I = _moments(body)
    w = real_array("w", w, "rad/s")
    if w.ndim == 0 or w.shape[-1] != 3:
        raise ValueError(
            f"w must have shape (..., 3) (components along body axes 1, 2, 3 in rad/s), "
            f"got shape {w.shape}"
        )
    return I, w


def _axis_moments(body, axis) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Moments (Ia, Ib, Ic) about the spin axis ``axis`` (1-based) and the other two."""
    if isinstance(axis, bool) or not isinstance(axis, numbers.Integral) or axis not in (1, 2, 3):
        raise ValueError(
            f"axis must be 1, 2 or 3 (the principal axis of I1, I2 or I3; axes are numbered "
            f"from 1), got {axis!r}"
        )
    I = _moments(body)
    a = int(axis) - 1
    return I[..., a], I[..., (a + 1) % 3], I[..., (a + 2) % 3]


def _spin(spin) -> np.ndarray:
    W = real_array("spin", spin, "rad/s")
    if not np.all(np.isfinite(W)):
        raise ValueError(f"spin must be finite (rate in rad/s), got {spin!r}")
    return W
