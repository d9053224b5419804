"""Every shape of body: the triangle of allowed moments, its edges, and run lengths over it.

Shapes: the physically allowed moments ``I1 <= I2 <= I3`` with ``I1 + I2 >= I3``, normalised so
that ``I3 = 1``, fill a triangle in the (I1, I2) plane with corners at the thin rod (0, 1, 1),
the flat disk (1/2, 1/2, 1) and the sphere (1, 1, 1); its edges are the prolate symmetric
bodies ``I2 = I3``, the oblate ones ``I1 = I2`` and the flat bodies ``I1 + I2 = I3``. A grid of
``divisions`` n (rows ``I2 = 1 - k / 2n``, steps ``1 / n`` in I1, computed from integers so that
equal moments are exactly equal) holds ``(n + 1)(n + 2) / 2 - 1`` shapes (the rod corner, with
``I1 = 0``, is no body); n = 32 gives 560 (:func:`shape_grid`).

On the equal-moment edges Omega^2 = 0 exactly: linear theory says nothing, and the motion
departs algebraically (linearly in t) with the distinct-axis component constant and no flip
(ERRATA 3); :func:`edge_series` shows it on :data:`EDGE_CASES`.
"""

from __future__ import annotations

import math

import numpy as np

from ...analysis.members import zero_crossings

from ...analysis.regimes import member_regimes
from ..model import euler_rhs, omega_squared
from ...core.body import RigidBody
from ..spin_ensembles import completed
from ..integrate import integrate
from ...util import conventions as cv

# Edge flags of a shape (bit mask, CF flag_masks), declared with the other codes.
from ...util.conventions import EDGE_EQUAL_12, EDGE_EQUAL_23, EDGE_FLAT, perpendicular_axes

#: The time-series demonstrations on the edges: name, moments (I3 = 1), spin axis.
EDGE_CASES = (
    ("oblate_equal_I1_I2", (0.75, 0.75, 1.0), 1),
    ("prolate_equal_I2_I3", (0.5, 1.0, 1.0), 3),
    ("sphere", (1.0, 1.0, 1.0), 1),
)


def shape_grid(divisions: int):
    """The triangle of allowed shapes, normalised to I3 = 1.

    Row k = 0 .. n holds ``I2 = (2n - k) / 2n`` and ``I1 = (k + 2j) / 2n`` for j = 0 .. n - k,
    so ``I1 + I2 >= 1`` (j = 0 is the flat edge) and ``I1 <= I2`` (j = n - k is the edge
    I1 = I2, where the two moments are the same float). The rod corner (k = j = 0, I1 = 0) is
    left out.

    Parameters
    ----------
    divisions : int
        n >= 1.

    Returns
    -------
    moments : ndarray, shape (S, 3)
        (I1, I2, I3) of each shape, S = (n + 1)(n + 2) / 2 - 1.
    edges : ndarray of int8, shape (S,)
        Bit mask of ``EDGE_EQUAL_12``, ``EDGE_EQUAL_23``, ``EDGE_FLAT``.
    """
    n = int(divisions)
    moments, edges = [], []
    for k in range(n + 1):
        for j in range(n - k + 1):
            if k == 0 and j == 0:
                continue
            moments.append(((k + 2 * j) / (2 * n), (2 * n - k) / (2 * n), 1.0))
            edges.append(
                (EDGE_EQUAL_12 if j == n - k else 0)
                | (EDGE_EQUAL_23 if k == 0 else 0)
                | (EDGE_FLAT if j == 0 else 0)
            )
    return np.array(moments), np.array(edges, dtype=np.int8)


def analytic_omega_squared(moments, spin: float) -> np.ndarray:
    """Omega^2 of steady spin ``spin`` about each axis of each shape; (S, 3) in s-2.

    Parameters
    ----------
    moments : array_like, shape (S, 3)
        Principal moments of each shape (:func:`shape_grid`).
    spin : float
        Spin rate W, rad/s.
    """
    moments = np.asarray(moments, dtype=float)
    return np.stack([omega_squared(moments, a, spin) for a in cv.AXES], axis=-1)


def amplitude_levels(spin: float, epsilon: float, per_decade: int) -> np.ndarray:
    """Ascending perpendicular-amplitude levels (rad/s) from 1.5 epsilon W up to W.

    Parameters
    ----------
    spin : float
        Spin rate W, rad/s.
    epsilon : float
        Perturbation relative to the spin.
    per_decade : int
        Levels per decade, on the grid ``W 10 ** (k / per_decade)``.

    Returns
    -------
    ndarray, shape (L,)
        Levels in rad/s, from the grid level at or below ``1.5 epsilon W`` up to W included.
    """
    first = math.floor(per_decade * math.log10(1.5 * epsilon))
    return spin * 10.0 ** (np.arange(first, 1) / per_decade)


def horizons(omega2: np.ndarray, horizon: float, t_max: float, t_neutral: float) -> np.ndarray:
    """Run length per (shape, axis) in s: ``horizon / |Omega|`` up to ``t_max``; ``t_neutral``
    where Omega^2 = 0.

    Enough, with ``horizon`` of a few tens, for two flips of an unstable axis (the first comes
    after about ln(1/epsilon) / lambda, then one every 2 ln(1/epsilon) / lambda) and for ten
    periods of a stable one; it depends on |Omega^2| only, never on its sign.

    Parameters
    ----------
    omega2 : ndarray, shape (S, 3)
        Analytic Omega^2 per (shape, axis), s-2 (:func:`analytic_omega_squared`).
    horizon : float
        Run length in units of ``1 / |Omega|``, dimensionless.
    t_max : float
        Longest run, s.
    t_neutral : float
        Run length where Omega^2 = 0, s.

    Returns
    -------
    ndarray, shape (S, 3)
        Run lengths, s.
    """
    rate = np.sqrt(np.abs(omega2))
    with np.errstate(divide="ignore"):
        return np.where(rate > 0, np.minimum(t_max, horizon / rate), t_neutral)


def edge_series(spin: float, epsilon: float, t_end: float, method: str, h: float) -> dict:
    """Time series on the equal-moment edges and the sphere: drift, not growth (ERRATA 3).

    Each of :data:`EDGE_CASES` spins about an axis whose moment equals another one, perturbed
    by ``epsilon W / sqrt(2)`` along both other axes, for ``t_end`` (rounded up to whole
    steps). Linear theory: Omega^2 = 0; exactly, the distinct-axis component stays constant and
    the other perpendicular one moves off linearly in t at its initial rate of change (Euler's
    equations at the start, :func:`stability.free_body.model.euler_rhs`), with no flip.

    Parameters
    ----------
    spin : float
        Spin rate W, rad/s.
    epsilon : float
        Perturbation relative to the spin.
    t_end : float
        Run length, s; rounded up to a whole number of steps.
    method : str
        Registry name of the integrator.
    h : float
        Step, s.

    Returns
    -------
    dict
        ``names`` (C,), ``moments`` (C, 3), ``axis`` (C,), ``time`` (T,), ``w`` (C, T, 3) in
        rad/s, ``slope_predicted`` and ``slope_measured`` (C,) in rad s-2 (of the drifting
        component), ``distinct_change`` (C,) in rad/s (largest change of the component along
        the distinct axis), ``flips`` (C,), ``regime``, ``linear_residual``,
        ``exponential_residual`` (C,), and the ``method`` and ``h`` used.
    """

    t_end = h * math.ceil(t_end / h - 1e-9)
    save_every = max(1, int(round(t_end / h / 400)))
    while round(t_end / h) % save_every:
        save_every -= 1
    names, moments, axis = [], [], []
    series, predicted, measured, distinct, flips = [], [], [], [], []
    regime, lin, expo = [], [], []
    for name, I, a in EDGE_CASES:
        body = RigidBody(*I, physical=False)
        w0 = np.full(3, epsilon * spin / math.sqrt(2.0))
        w0[a - 1] = spin
        ds = integrate(body, w0, t_end, h, method=method, save_every=save_every)
        completed(ds)
        w = ds.w.values
        t = ds.time.values
        others = perpendicular_axes(a)
        equal = [b for b in others if I[b - 1] == I[a - 1]]
        c = ([b for b in others if b not in equal] or [others[0]])[0]  # the distinct axis
        e = [b for b in others if b != c][0]  # the drifting one
        rhs = euler_rhs(np.asarray(I), w0)
        slope = np.polyfit(t, w[:, e - 1], 1)[0]
        reg = member_regimes(ds, axis=a, spin=spin)
        names.append(name)
        moments.append(I)
        axis.append(a)
        series.append(w)
        predicted.append(rhs[e - 1])
        measured.append(slope)
        distinct.append(float(np.max(np.abs(w[:, c - 1] - w0[c - 1]))))
        flips.append(int(zero_crossings(t, w[None, :, a - 1])[0][0]))
        regime.append(int(reg.regime.values[0]))
        lin.append(float(reg.linear_residual.values[0]))
        expo.append(float(reg.exponential_residual.values[0]))
    return {
        "names": names, "moments": np.array(moments), "axis": np.array(axis), "time": t,
        "w": np.array(series), "slope_predicted": np.array(predicted),
        "slope_measured": np.array(measured), "distinct_change": np.array(distinct),
        "flips": np.array(flips), "regime": np.array(regime, dtype=np.int8),
        "linear_residual": np.array(lin), "exponential_residual": np.array(expo),
        "method": method, "h": h,
    }
