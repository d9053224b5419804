"""The start rule of an ensemble about a steady spin: a spin about a principal axis, perturbed
at random perpendicular to it (the free body's ensembles, and every family that starts its own
from theirs).

Member j of an ensemble is drawn from the SeedSequence child ``j // RNG_CHUNK`` of the
seed, so the draws never depend on how a run is chunked or threaded, and an ensemble of N
members is the first N members of any larger one with the same seed.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from ..util.conventions import perpendicular_axes
from ..util.checks import positive_float, positive_int, real_number, vectors3

__all__ = ["seed_sequence", "perturbed_starts"]

#: Members per SeedSequence child. Fixed, so that the draws never depend on how the
#: computation is chunked; changing it changes every random ensemble.
RNG_CHUNK = 4096


def seed_sequence(seed) -> np.random.SeedSequence:
    """``seed`` (int >= 0, ``None`` for fresh entropy, or a SeedSequence) as a SeedSequence.

    Parameters
    ----------
    seed : int, None or numpy.random.SeedSequence
        The seed; a SeedSequence is returned as it is.

    Returns
    -------
    numpy.random.SeedSequence

    Raises
    ------
    ValueError
        If ``seed`` is not one of these (a bool or a negative integer included).
    """
    if isinstance(seed, np.random.SeedSequence):
        return seed
    if seed is None:
        return np.random.SeedSequence()
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or seed < 0:
        raise ValueError(
            f"seed must be an integer >= 0, None (fresh entropy, recorded in the Dataset) or a "
            f"numpy.random.SeedSequence, got {seed!r}"
        )
    return np.random.SeedSequence(int(seed))


def perturbed_starts(axis, spin, epsilon, members, seed=0, direction=None) -> np.ndarray:
    """Initial angular velocities: steady spin about ``axis`` plus a perpendicular perturbation.

    ``w0_j = spin e_a + epsilon spin (cos(phi_j) e_b + sin(phi_j) e_c)`` with b < c the other
    two axes and ``phi_j`` uniform in [0, 2 pi), drawn from one PCG64 stream per
    :data:`RNG_CHUNK` members (child c of ``SeedSequence(seed)``), so member j gets the same start
    whatever ``members`` is; or ``w0_j = spin e_a + epsilon spin d / |d|`` for a fixed direction d.

    Parameters
    ----------
    axis : int
        Principal axis 1, 2 or 3 of the spin.
    spin : float
        Spin rate W in rad/s, > 0.
    epsilon : float
        Size of the perturbation relative to the spin, >= 0.
    members : int
        Number of members N.
    seed : int, None or numpy.random.SeedSequence, default 0
    direction : array_like, shape (3,), optional
        A fixed perturbation direction, perpendicular to ``axis``.

    Returns
    -------
    ndarray, shape (N, 3)
        Body-frame angular velocities in rad/s; the component along ``axis`` is exactly
        ``spin`` and the perpendicular part has norm ``epsilon spin`` (to rounding).
    """
    a = axis_index(axis)
    spin = positive_float("spin", spin, "rad/s")
    epsilon = nonnegative_float("epsilon", epsilon)
    members = positive_int("members", members)
    if direction is not None:
        w0 = np.zeros((members, 3))
        w0[:, a] = spin
        w0 += epsilon * spin * perpendicular_direction(direction, a)
        return w0
    return random_starts(a, spin, epsilon, seed_sequence(seed), 0, members)


def random_starts(a, spin, epsilon, ss, lo, hi) -> np.ndarray:
    """Members ``lo ... hi - 1`` of :func:`perturbed_starts` in random directions."""
    w0 = np.zeros((hi - lo, 3))
    w0[:, a] = spin
    phi = _random_angles(ss, lo, hi)
    b, c = (x - 1 for x in perpendicular_axes(a + 1))  # lowest first, as the tracking uses
    w0[:, b] = epsilon * spin * np.cos(phi)
    w0[:, c] = epsilon * spin * np.sin(phi)
    return w0


def _random_angles(ss: np.random.SeedSequence, lo: int, hi: int) -> np.ndarray:
    """Angles of members ``lo ... hi - 1``, uniform in [0, 2 pi).

    Block c of :data:`RNG_CHUNK` members is drawn in order from child c of ``ss``, so a
    member's angle does not depend on which members are drawn with it.
    """
    phi = np.empty(hi - lo)
    for c in range(lo // RNG_CHUNK, -(-hi // RNG_CHUNK)):
        # The c-th child of ss.spawn(...), built directly so that ss is not mutated.
        child = np.random.SeedSequence(
            ss.entropy, spawn_key=tuple(ss.spawn_key) + (c,), pool_size=ss.pool_size
        )
        rng = np.random.Generator(np.random.PCG64(child))
        first = c * RNG_CHUNK
        block = rng.uniform(0.0, 2.0 * math.pi, size=min(first + RNG_CHUNK, hi) - first)
        start = max(lo, first)
        phi[start - lo:first + block.size - lo] = block[start - first:]
    return phi


def axis_index(axis) -> int:
    """Principal axis 1, 2 or 3 as a 0-based index, else ValueError."""
    if isinstance(axis, bool) or not isinstance(axis, numbers.Integral) or axis not in (1, 2, 3):
        raise ValueError(f"axis must be the principal axis 1, 2 or 3, got {axis!r}")
    return int(axis) - 1


def nonnegative_float(name, value) -> float:
    x = real_number(name, value)
    if not math.isfinite(x) or x < 0.0:
        raise ValueError(f"{name} must be finite and >= 0, got {value!r}")
    return x


def perpendicular_direction(direction, a) -> np.ndarray:
    """``direction`` as a unit vector; ValueError unless it is perpendicular to axis a."""
    d = vectors3("direction", direction)
    if d.ndim != 1:
        raise ValueError(f"direction must have shape (3,), got {d.shape}")
    norm = float(np.linalg.norm(d))
    if norm == 0.0:
        raise ValueError("direction must be a nonzero vector perpendicular to the spin axis")
    if abs(d[a]) > 1e-12 * norm:
        raise ValueError(
            f"direction {d.tolist()} is not perpendicular to axis {a + 1}: its component "
            f"along that axis is {d[a]!r}; set it to 0"
        )
    d = d.copy()
    d[a] = 0.0
    return d / norm
