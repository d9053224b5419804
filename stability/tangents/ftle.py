r"""Finite-time Lyapunov exponents of each member: :func:`run_tangents`.

Each member carries ``k`` tangent vectors under the derivative of its computed RK4 map
(:func:`stability.engine.tangent.tangent_scene`: exact to round-off, not to the method's order).
The run is cut into ``windows`` windows of ``every`` steps; at the end of each the tangents
``V = (v_1 ... v_k)`` are orthonormalised, ``V = Q R`` with ``R_ii > 0`` (Gram-Schmidt, the
Benettin et al. (Meccanica 15, 9 (1980)) algorithm), and the run goes on from ``(x, Q)``. Then,
with ``dt = every h`` and ``T = windows dt``:

- ``window_rate_j = log R_11^(j) / dt``: the leading tangent's growth over window ``j``;
- ``ftle_running(t_j) = sum_{i <= j} log R_11^(i) / t_j`` and ``ftle = ftle_running(T)``:
  ``log(|v_1(T)| / |v_1(0)|) / T``, the finite-time Lyapunov exponent (the renormalisation
  changes nothing but the scale, the tangent equations being linear; it keeps the numbers
  finite);
- ``exponents_i = sum_j log R_ii^(j) / T``: the finite-time spectrum (``k > 1``);
- ``stm_log_singular_value = log sigma_max(Phi(T))`` (``k = n``): the state-transition matrix
  is ``Phi(T) Q_0 = Q_m R_m ... R_1``, so its largest singular value is that of the product of
  the ``R``, kept scaled by its norm;
- ``growth_rate(t_j) = q_1 . J(x) q_1``: the instantaneous rate ``d log|v_1| / dt`` at the
  window's end.

The windows of a chunk of members run where the chunk runs (the measurement of
:func:`stability.ensemble.chunks.run_plan`: in this process, chunk by chunk into a store,
resumed, on dask): the result is bitwise the same however the members are cut. A run cut into
windows differs from one run in one piece in the last bits of ``x``: the loop's compensated sum
restarts at each window.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

import numpy as np
import xarray as xr

from ..engine.scene import checked_scene
from ..engine.tangent import tangent_scene
from ..ensemble.chunks import run_plan
from ..ensemble.options import run_options
from ..ensemble.plan import Plan
from ..output.dataset import header_attrs
from ..util import conventions as cv
from ..util.checks import positive_float, positive_int, real_array
from ..version import __version__
from .schema import TANGENT, TANGENTS


@dataclass(frozen=True)
class TangentWindows:
    """The measurement of a chunk of a tangent run: its windows after the first, renormalised,
    and what they measure (the module docstring), as a Dataset of its members.

    Parameters
    ----------
    windows : int
        Windows in the run (the plan runs the first; this runs the others).
    """

    windows: int

    def identity(self, run: Plan) -> dict:
        """The store's fingerprint: the plan's (the starts hold the first tangents) and the
        number of windows."""
        return {"grouped_run": run.identity(), "measurement": "tangent_windows",
                "windows": self.windows, "software": f"stability {__version__}"}

    def __call__(self, part: Plan, propagation, lo: int, hi: int, threads=None) -> xr.Dataset:
        scene = part.scene
        n, k = scene.base.width, scene.vectors
        m = hi - lo
        group = np.repeat(np.arange(part.sizes.size), part.sizes)
        dt = part.h[group] * part.n_steps[group]
        logs = np.zeros((m, self.windows, k))
        rate = np.zeros((m, self.windows))
        product = np.broadcast_to(np.eye(k), (m, k, k)).copy()
        scale = np.zeros(m)
        status = np.zeros(m, dtype=np.int8)
        state = part.x0
        for j in range(self.windows):
            if j:
                propagation = replace(part, x0=state).propagate()
            x = propagation.x_final
            status = np.where(status == cv.STATUS_OK, propagation.status, status).astype(np.int8)
            bad = status != cv.STATUS_OK
            x = np.where(bad[:, None], part.x0, x)  # a failed member idles on its start
            q, r = np.linalg.qr(x[:, n:].reshape(m, k, n).transpose(0, 2, 1))
            sign = np.sign(np.diagonal(r, axis1=1, axis2=2))
            sign[sign == 0.0] = 1.0
            q = q * sign[:, None, :]
            r = r * sign[:, :, None]
            with np.errstate(divide="ignore"):
                logs[:, j] = np.log(np.diagonal(r, axis1=1, axis2=2))
            if k == n:
                product = r @ product
                norm = np.linalg.norm(product, axis=(1, 2))
                product /= norm[:, None, None]
                scale += np.log(norm)
            state = np.ascontiguousarray(np.hstack([x[:, :n],
                                                    q.transpose(0, 2, 1).reshape(m, -1)]))
            rate[:, j] = scene.rate(state, part.params, group)
        return self._dataset(part, lo, hi, group, dt, logs, rate, product, scale, status)

    def _dataset(self, part, lo, hi, group, dt, logs, rate, product, scale, status):
        n, k = part.scene.base.width, part.scene.vectors
        bad = status != cv.STATUS_OK
        ends = dt[:, None] * np.arange(1, self.windows + 1)
        running = np.cumsum(logs[:, :, 0], axis=1) / ends
        values = {
            "status": status,
            "ftle": running[:, -1],
            "ftle_running": running,
            "window_rate": logs[:, :, 0] / dt[:, None],
            "growth_rate": rate,
        }
        if k > 1:
            values["exponents"] = logs.sum(axis=1) / ends[:, -1:]
        if k == n:
            values["stm_log_singular_value"] = (
                np.log(np.linalg.svd(product, compute_uv=False)[:, 0]) + scale)
        for name, value in values.items():
            if name != "status":
                value[bad] = np.nan
        step = float(part.h[0] * part.n_steps[0]) if part.h.size else 0.0
        coords = {
            cv.MEMBER: TANGENTS.entry(cv.MEMBER, np.arange(lo, hi)),
            cv.TIME: TANGENTS.entry(cv.TIME, step * np.arange(1, self.windows + 1)),
            TANGENT: TANGENTS.entry(TANGENT, np.arange(1, k + 1)),
        }
        return xr.Dataset(TANGENTS.entries(values), coords=coords)


def run_tangents(scene, x0, parameters, *, h, every, windows, vectors=1, sizes=None,
                 tangents=None, options=None) -> xr.Dataset:
    """Members of ``scene`` with their tangents, renormalised every ``every`` steps: their
    finite-time Lyapunov exponents (the module docstring).

    Parameters
    ----------
    scene : str or Scene
        A scene with a linearisation (``free_body``, ``heavy_top``, ``sphere_damper``,
        ``gyrostat``, ``relaxing_tumbler``, a scene of :func:`stability.define_scene`): a
        registered scene's name (looked up by :func:`stability.run_tangents`) or the scene.
        This function itself takes the Scene alone.
    x0 : array_like, shape (N, n)
        Initial states, group after group, in the scene's kernels' frame and units.
    parameters : parameter set, or sequence of them
        Each group's parameter set, as the scene's ``rk4`` takes it (``spec.params(set, h)``).
    h : float
        Step, s (one for every group, so that the windows end at the same times).
    every : int
        Steps per renormalisation window.
    windows : int
        Windows in the run; the run lasts ``T = windows every h``.
    vectors : int, default 1
        Tangents per member, 1 to n; n: the state-transition matrix.
    sizes : array_like of int, shape (G,), optional
        Members per group; by default all in one group.
    tangents : array_like, shape (n, k) or (N, n, k), optional
        The first tangents (orthonormalised before the run): by default the identity's first
        ``k`` columns for ``k = n``, else the first ``k`` of an orthonormal basis whose first
        vector is ``(1, ..., 1) / sqrt(n)``.
    options : RunOptions, optional
        How and where it runs (:func:`~stability.ensemble.chunks.run_plan`); never changes a
        number of the result.

    Returns
    -------
    xarray.Dataset
        As :data:`stability.tangents.schema.TANGENTS` declares it.

    Raises
    ------
    ValueError, TypeError
        One line, before any work: a count that is not a positive whole number, a step that is
        not positive, starts or tangents of the wrong shape, a scene without a linearisation.
    """
    scene = checked_scene(scene, "run_tangents")
    every = positive_int("every (steps per renormalisation window)", every)
    windows = positive_int("windows", windows)
    h = positive_float("h", h, "s")
    options = run_options(options)
    tscene = tangent_scene(scene, vectors)
    n = scene.width
    x0 = real_array("x0", x0)
    if x0.ndim != 2 or x0.shape[1] != n or x0.shape[0] == 0:
        raise ValueError(f"x0 must be the starts of shape (N, {n}) for scene {scene.name!r}, "
                         f"got shape {x0.shape}")
    sets = _parameter_sets(parameters)
    sizes = _sizes(sizes, len(sets), x0.shape[0])
    spec = tscene.method("rk4")
    rows = [np.asarray(spec.params(values, h), dtype=float).reshape(-1) for values in sets]
    first = _first_tangents(tangents, x0.shape[0], n, tscene.vectors)
    start = np.hstack([x0, first.transpose(0, 2, 1).reshape(x0.shape[0], -1)])
    plan = Plan(tscene, "rk4", start, np.array(rows), sizes, h, every, label="tangents")
    ds = run_plan(plan, options, measure=TangentWindows(windows)).load()
    group = np.repeat(np.arange(sizes.size), sizes)  # a chunk knows only its own groups
    ds = ds.assign({"group": TANGENTS.entry("group", group)})
    ds = ds[[name for name in TANGENTS.variables if name in ds.data_vars]]  # declared order
    ds.attrs = {**header_attrs(f"finite-time Lyapunov exponents, scene {scene.name}",
                               f"stability.run_tangents(scene={scene.name!r}, h={h!r}, "
                               f"every={every}, windows={windows}, vectors={tscene.vectors})",
                               "Benettin, Galgani, Giorgilli & Strelcyn, Meccanica 15, 9 (1980)"),
                "scene": scene.name, "method": "rk4", "step": h,
                "renormalisation_interval": every * h, "vectors": tscene.vectors}
    return ds


def _parameter_sets(parameters) -> list:
    if isinstance(parameters, Mapping) or (isinstance(parameters, np.ndarray)
                                           and parameters.ndim <= 1):
        return [parameters]
    sets = list(parameters) if hasattr(parameters, "__len__") else []
    if sets and all(isinstance(s, (int, float, np.number)) for s in sets):
        return [np.asarray(sets, dtype=float)]  # a list of numbers is one set
    if not sets or not all(isinstance(s, (Mapping, np.ndarray, list, tuple)) for s in sets):
        raise ValueError(f"parameters must be a parameter set (an array or a mapping) or a "
                         f"list of them, one per group, got {parameters!r:.80}")
    return sets


def _sizes(sizes, groups, members) -> np.ndarray:
    if sizes is None:
        if groups != 1:
            raise ValueError(f"give sizes=, the members of each of the {groups} parameter "
                             "sets")
        return np.array([members], dtype=np.int64)
    out = np.array([positive_int("sizes", s) for s in np.asarray(sizes).reshape(-1).tolist()],
                   dtype=np.int64)
    if out.size != groups or int(out.sum()) != members:
        raise ValueError(f"sizes must give the members of each of the {groups} parameter sets, "
                         f"adding up to the {members} rows of x0; got {out.tolist()}")
    return out


def _first_tangents(tangents, members: int, n: int, k: int) -> np.ndarray:
    """The first tangents (N, n, k), orthonormal (Q of their QR, R_ii > 0)."""
    if tangents is None:
        if k == n:
            return np.broadcast_to(np.eye(n), (members, n, n)).copy()
        basis = np.eye(n)
        basis[:, 0] = 1.0
        tangents = basis[:, :k]
    t = real_array("tangents", tangents)
    if t.shape == (n, k):
        t = np.broadcast_to(t, (members, n, k))
    if t.shape != (members, n, k):
        raise ValueError(f"tangents must be of shape ({n}, {k}) or ({members}, {n}, {k}), got "
                         f"{t.shape}")
    lengths = np.linalg.norm(t, axis=1)
    if not np.all(np.isfinite(t)) or np.any(lengths == 0.0):
        raise ValueError("tangents must be finite and linearly independent for each member")
    q, r = np.linalg.qr(t)
    diagonal = np.diagonal(r, axis1=1, axis2=2)
    if np.any(np.abs(diagonal) <= 1e-12 * lengths):
        raise ValueError("tangents must be finite and linearly independent for each member")
    return q * np.sign(diagonal)[:, None, :]


__all__ = ["TangentWindows", "run_tangents"]
