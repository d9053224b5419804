r"""The stability map from tangents: finite-time Lyapunov exponents over the shapes of bodies.

A grid of inertia ratios ``(I1 / I3, I2 / I3)`` (cell centres over ``(0, 1] x [1/2, 1]``; the
cells outside the triangle of real bodies, ``I1 <= I2 <= I3 <= I1 + I2``, are left NaN), each
body spun at ``W`` about one principal axis and started ``epsilon W`` off it in a few random
directions across it. Each member carries the state-transition matrix ``Phi`` of its computed
RK4 map (:func:`stability.tangents.ftle.run_tangents`, three tangents) over the horizon ``T``,
and the cell's FTLE is the members' mean of

.. math::

    \mathrm{FTLE} = \log \sigma_{\max}(\Phi(T)) / T,

the largest growth over every direction of perturbation (Haller, Physica D 149, 248 (2001)),
so no first tangent can miss the unstable direction. Beside it, the analytic rate
``sqrt(-Omega^2)`` (:func:`stability.free_body.model.growth_rate`). What linear theory says it
should be, in the linear phase (``epsilon e^(sigma T) << 1``): about the intermediate axis,
``sigma <= FTLE <= sigma + log((1 + rho) / 2) / T`` with ``rho >= 1`` the aspect ratio of the
saddle's eigenvectors (:func:`eigenvector_aspect`); about a stable axis ``0 <= FTLE <= log(rho)
/ T`` (the linearised ellipse), tending to 0. The figure (:func:`~.figures.ftle_map_figure`) is a
map like REBOUND's MEGNO maps, the FTLE coloured and the analytic rate's contours over it.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ...output.dataset import header_attrs
from ...tangents.ftle import run_tangents
from ...util import conventions as cv
from ...util.checks import positive_float, positive_int
from ..model import growth_rate, omega_squared
from ...util.conventions import perpendicular_axes
from ..scene import FREE_BODY
from ..schema import FTLE_MAP

#: The most step of the map's RK4 as a fraction of one turn's time 1 / |W| (its error on a rate
#: is then ~(h sigma)^4 / 120 < 1e-9 relative over the triangle).
STEP_FRACTION = 0.01


def ratio_grid(divisions: int):
    """The cell centres of a ``divisions`` x ``divisions`` grid over the triangle's box:
    ``I1 / I3 = (i + 1/2) / n`` and ``I2 / I3 = 1/2 + (j + 1/2) / 2n``; none lies on an edge of
    the triangle (the half-integers never meet ``I1 = I2`` or ``I1 + I2 = I3``).

    Parameters
    ----------
    divisions : int
        n >= 2.

    Returns
    -------
    i1, i2 : ndarray, shape (n,)
        The ratios I1 / I3 and I2 / I3, ascending.
    """
    n = _divisions(divisions)
    k = np.arange(n) + 0.5
    return k / n, 0.5 + k / (2 * n)


def physical(i1, i2) -> np.ndarray:
    """Where ``(I1, I2, 1)`` is a real body: ``I1 <= I2 <= 1 <= I1 + I2``; (len(i2), len(i1))."""
    x, y = np.meshgrid(np.asarray(i1, dtype=float), np.asarray(i2, dtype=float))
    return (x <= y) & (y <= 1.0) & (x + y >= 1.0)


def eigenvector_aspect(moments, axis: int) -> np.ndarray:
    """``rho = max(r, 1 / r)``, ``r = sqrt(|A_b / A_c|)``: the aspect ratio of the eigenvectors of
    Euler's equations linearised about spin about ``axis`` (``dm_b' = A_b W I_a dm_c``,
    ``dm_c' = A_c W I_a dm_b``, ``A_b = (I_c - I_a) / (I_c I_a)`` and cyclic), the ellipse of a
    stable axis or the skew of a saddle; it bounds the alignment term of the FTLE.

    Parameters
    ----------
    moments : array_like, shape (..., 3)
        Principal moments (I1, I2, I3), kg m2.
    axis : int
        1, 2 or 3.
    """
    moments = np.asarray(moments, dtype=float)
    a = axis - 1
    b, c = (k - 1 for k in perpendicular_axes(axis))
    Ia, Ib, Ic = moments[..., a], moments[..., b], moments[..., c]
    ab = (Ic - Ia) / (Ic * Ia)  # the coefficient of dm_b' (Euler's A_b)
    ac = (Ia - Ib) / (Ia * Ib)  # that of dm_c'
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.sqrt(np.abs(ab / ac))
    return np.maximum(r, 1.0 / r)


def ftle_map(divisions: int = 12, *, axis: int = 2, spin: float = 1.0, horizon: float = 10.0,
             epsilon: float = 1e-8, members: int = 2, windows: int = 10, ratios=None,
             seed: int = 0, options=None) -> xr.Dataset:
    """The FTLE of spin about ``axis`` over a grid of inertia ratios (the module docstring).

    Parameters
    ----------
    divisions : int, default 12
        Cells per side of the grid (:func:`ratio_grid`), >= 2.
    axis : int, default 2
        Spin axis: 1 (smallest moment), 2 (intermediate), 3 (largest).
    spin : float, default 1.0
        ``W``, rad s-1.
    horizon : float, default 10.0
        ``T``, s: in the linear phase of the intermediate axis where ``epsilon e^(sigma T) <<
        1`` over the grid.
    epsilon : float, default 1e-8
        The start's angular velocity across the axis, in units of ``W``, >= 0.
    members : int, default 2
        Starts per cell, at random directions across the axis.
    windows : int, default 10
        Renormalisations over the horizon (they change the FTLE by round-off only).
    ratios : (array_like, array_like), optional
        The grid's ``I1 / I3`` and ``I2 / I3`` values instead of :func:`ratio_grid`: at least two
        each, ascending, in ``(0, 1]``.
    seed : int, default 0
        Seed of the directions.
    options : RunOptions, optional
        How the run goes (:func:`~stability.ensemble.chunks.run_plan`); no number depends on it.

    Returns
    -------
    xarray.Dataset
        As :data:`stability.free_body.schema.FTLE_MAP` declares it.

    Raises
    ------
    ValueError
        One line, before any work: a grid of fewer than 2 cells a side, a ratio that is no
        body, an axis not 1, 2 or 3, a horizon, spin or count not positive.
    """
    if axis not in cv.AXES or isinstance(axis, bool):
        raise ValueError(f"axis must be 1, 2 or 3 (the principal axis spun about), got {axis!r}")
    i1, i2 = ratio_grid(divisions) if ratios is None else _ratios(ratios)
    horizon = positive_float("horizon", horizon, "s")
    spin = positive_float("spin", spin, "rad s-1")
    members = positive_int("members", members)
    windows = positive_int("windows", windows)
    epsilon = float(epsilon)
    if not (math.isfinite(epsilon) and epsilon >= 0.0):
        raise ValueError(f"epsilon must be a finite number >= 0, got {epsilon!r}")
    inside = physical(i1, i2)
    if not inside.any():
        raise ValueError("the grid of ratios holds no real body (I1 <= I2 <= I3 <= I1 + I2)")
    x, y = np.meshgrid(i1, i2)
    moments = np.stack([x, y, np.ones_like(x)], axis=-1)
    cells = moments[inside]
    every = math.ceil(horizon / windows / (STEP_FRACTION / spin))
    h = horizon / (windows * every)
    ds = run_tangents(FREE_BODY, _starts(cells, axis, spin, epsilon, members, seed),
                      list(cells), h=h, every=every, windows=windows, vectors=3,
                      sizes=np.full(len(cells), members), options=options)
    member_ftle = ds.stm_log_singular_value.values / horizon
    ftle = np.full(inside.shape, np.nan)
    ftle[inside] = member_ftle.reshape(len(cells), members).mean(axis=1)
    spread = np.full(inside.shape, np.nan)
    spread[inside] = np.ptp(member_ftle.reshape(len(cells), members), axis=1)
    return _dataset(i1, i2, inside, moments, ftle, spread, axis, spin, horizon, epsilon,
                    members, h, windows)


def _dataset(i1, i2, inside, moments, ftle, spread, axis, spin, horizon, epsilon, members, h,
             windows) -> xr.Dataset:
    omega2 = np.where(inside, omega_squared(moments, axis, spin), np.nan)
    values = {
        "ftle": ftle,
        "ftle_spread": spread,
        "growth_rate_analytic": np.where(inside, growth_rate(moments, axis, spin), np.nan),
        "omega_squared": omega2,
        "eigenvector_aspect": np.where(inside, eigenvector_aspect(moments, axis), np.nan),
        "physical": inside.astype(np.int8),
    }
    coords = {"I1": FTLE_MAP.entry("I1", i1), "I2": FTLE_MAP.entry("I2", i2)}
    ds = xr.Dataset(FTLE_MAP.entries(values), coords=coords)
    ds.attrs = {**header_attrs(
        f"finite-time Lyapunov exponents of spin about axis {axis} over the shapes of bodies",
        f"stability.free_body.stability_map.ftle_map.ftle_map(divisions={len(i1)}, axis={axis}, "
        f"spin={spin!r}, horizon={horizon!r}, epsilon={epsilon!r}, members={members})",
        "Benettin et al., Meccanica 15, 9 (1980); Haller, Physica D 149, 248 (2001)"),
        "axis": axis, "spin": spin, "horizon": horizon, "epsilon": epsilon,
        "members": members, "step": h, "windows": windows, "method": "rk4"}
    return ds


def _starts(cells, axis, spin, epsilon, members, seed) -> np.ndarray:
    """``m = I w`` of each cell's members (cell after cell): ``w = W e_a + epsilon W (cos phi
    e_b + sin phi e_c)``, ``phi`` uniform."""
    phi = 2.0 * np.pi * np.random.default_rng(seed).random((len(cells), members))
    b, c = (k - 1 for k in perpendicular_axes(axis))
    w = np.zeros((len(cells), members, 3))
    w[..., axis - 1] = spin
    w[..., b] = epsilon * spin * np.cos(phi)
    w[..., c] = epsilon * spin * np.sin(phi)
    return (w * cells[:, None, :]).reshape(-1, 3)


def _divisions(divisions) -> int:
    if isinstance(divisions, bool) or not isinstance(divisions, (int, np.integer)) \
            or divisions < 2:
        raise ValueError(f"divisions (cells per side of the grid) must be a whole number >= 2, "
                         f"got {divisions!r}")
    return int(divisions)


def _ratios(ratios):
    """The grid's given ``(I1 / I3, I2 / I3)``: two ascending arrays of >= 2 values in (0, 1]."""
    try:
        i1, i2 = (np.asarray(r, dtype=float).reshape(-1) for r in ratios)
    except (TypeError, ValueError):
        raise ValueError(f"ratios must be two arrays, the I1 / I3 and the I2 / I3 of the grid, "
                         f"got {ratios!r:.80}") from None
    for name, r in (("I1 / I3", i1), ("I2 / I3", i2)):
        if r.size < 2 or np.any(np.diff(r) <= 0):
            raise ValueError(f"ratios: {name} must hold at least 2 ascending values, got "
                             f"{r.tolist()!r:.80}")
        bad = r[~((r > 0.0) & (r <= 1.0))]
        if bad.size:
            raise ValueError(f"ratios: {name} = {bad[0]!r} is no body (a principal moment over "
                             "the largest lies in (0, 1])")
    return i1, i2


__all__ = ["STEP_FRACTION", "eigenvector_aspect", "ftle_map", "physical", "ratio_grid"]
