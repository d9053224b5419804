"""The stability map's Dataset: measured against analytic Omega^2 for every shape and axis.

For every shape of the triangle (:mod:`stability.free_body.stability_map.shapes`) and each of its
three axes, an ensemble of ``members`` starts at steady spin ``W`` about the axis plus a
perturbation ``epsilon W`` in a random perpendicular direction, runs summaries-only, and is
classified and measured by :mod:`stability.analysis` (:func:`ensemble_estimates`: regime; growth
rate on the linear phase or frequency from zero crossings; Omega^2 = -rate^2 or +frequency^2; flips
against the exact 2K/nu and the asymptote (2/lambda) ln(4/k')). Each finite-order method also runs
at ``h / 2`` on some shapes: :func:`stability.analysis.fits.richardson_bias` gives its own O(h^p)
bias in Omega^2, reported beside the measured error, not hidden.

The Dataset (:func:`map_dataset`) has dims integrator, shape, axis (an integrator is a registry
method at its step h, not called "method" so that ``ds.sel(integrator="rk4")`` works), the flip
sweep on flip_shape, epsilon (:mod:`stability.free_body.tennis_racket.flipsweep`), the edge time
series on edge_case, edge_time (:func:`stability.free_body.stability_map.shapes.edge_series`).
:func:`headline` reads it back.
"""

from __future__ import annotations

import contextlib
import math

import numpy as np
import xarray as xr

from ...analysis.estimates import flip_estimate, omega_squared_estimates
from ...analysis.members import members as gather_members
from ..spin_ensembles import completed, run_ensembles
from ..keep import Keep
from ...ensemble.starts import perturbed_starts
from ...output.stream import stream_chunks
from ...output.untrusted import read_dataset
from ..schema import STABILITY_MAP
from ...util import conventions as cv
from ...util.conventions import (EDGE_EQUAL_12, EDGE_EQUAL_23, EDGE_FLAT, REGIME_ALGEBRAIC,
                                 REGIME_NEUTRAL)
from ..measure import exact_flip_intervals
from ...util.progress import progress_bar

#: Relative bias of the growth rate, lambda_h / lambda - 1, at step h for I = (1, 2, 3) and spin
#: W = 1 (literature notes 4.1, table of discretization biases): RK4 -(h lambda)^4 / 120; the
#: two-part Lie-Poisson split (lp2: I_ref = I2, axis 1 outer) -1.4e-4 at h = 0.1, O(h^2). The
#: relative error of Omega^2 = -lambda^2 is minus twice this. Arguments: h W and lambda / W.
LITERATURE_RATE_BIAS = {
    "rk4": lambda hw, lam: -((hw * lam) ** 4) / 120.0,
    "lp2": lambda hw, lam: -1.4e-4 * (hw / 0.1) ** 2,
}

#: Float estimates stored per (integrator, shape, axis).
MAP_FLOATS = (
    "omega_squared_measured", "omega_squared_measured_stderr", "relative_error",
    "growth_rate", "growth_rate_stderr", "oscillation_frequency",
    "oscillation_frequency_stderr", "drift_rate", "n_fitted", "n_flips_mean",
    "first_flip_time_mean", "first_flip_time_stderr", "flip_interval_mean",
    "flip_interval_stderr", "flip_interval_exact_mean", "flip_interval_asymptote_mean",
    "flip_interval_relative_error", "flip_interval_relative_error_stderr",
    "first_flip_time_relative_error", "energy_error_max",
)


def ensemble_estimates(run, analytic: float, exact=None, asymptote=None, *,
                       low_factor, high_fraction) -> dict:
    """Every number the map keeps of one summaries-only ensemble.

    Parameters
    ----------
    run : xarray.Dataset or stability.free_body.spin_ensembles.EnsembleSummary
        :func:`stability.run_ensemble` with ``keep=Keep(save_every=0)``, or the same ensemble from
        :func:`stability.free_body.spin_ensembles.run_ensembles` with ``datasets=False``.
    analytic : float
        Analytic Omega^2, s-2.
    exact, asymptote : ndarray, shape (N,), optional
        Each member's exact flip interval and its asymptote (unstable axes).
    low_factor, high_fraction : float
        The growth-rate window (:func:`stability.analysis.estimates.measured_growth_rate`).

    Returns
    -------
    dict
        The keys of :func:`stability.analysis.estimates.omega_squared_estimate` and
        :func:`stability.analysis.estimates.flip_estimate`, and ``members_failed``, ``status`` (the
        worst member status) and ``energy_error_max``.
    """
    return batch_estimates([run], [analytic], [(exact, asymptote)], low_factor=low_factor,
                           high_fraction=high_fraction)[0]


def batch_estimates(runs, analytic, flips, *, low_factor, high_fraction) -> list:
    """:func:`ensemble_estimates` of many ensembles, their member fits in one pass.

    Parameters
    ----------
    runs : sequence of xarray.Dataset or stability.free_body.spin_ensembles.EnsembleSummary
    analytic : sequence of float
        Analytic Omega^2 of each, s-2.
    flips : sequence of (exact, asymptote)
        Each ensemble's exact flip intervals and their asymptotes, or (None, None).
    low_factor, high_fraction : float
        The growth-rate window.

    Returns
    -------
    list of dict
        :func:`ensemble_estimates` of each ensemble, in order.
    """
    gathered = []
    for run in runs:
        if isinstance(run, xr.Dataset):
            gathered.append((gather_members(run), run.variables["status"].values,
                             run.variables["energy_error"].values))
        else:
            gathered.append((run.members, run.status, run.energy_error))
    omega = omega_squared_estimates([mem for mem, _, _ in gathered], analytic,
                                        low_factor=low_factor, high_fraction=high_fraction)
    out = []
    for (mem, status, energy), e, (exact, asymptote) in zip(gathered, omega, flips):
        f = flip_estimate(mem, exact, asymptote)
        out.append({**f, **e, "members_failed": int(np.sum(status != cv.STATUS_OK)),
                    "status": int(np.max(status)), "energy_error_max": _nanmax_abs(energy)})
    return out


def map_runs(specs, steps, n_shapes: int, bias_check: bool = True, bias_stride: int = 1):
    """The batches a map runs (:func:`measure_map`'s ``runs``): each method at its step over
    every shape and, with ``bias_check``, each finite-order method again at half its step over
    every ``bias_stride``-th shape (its O(h^p) bias,
    :func:`stability.analysis.fits.richardson_bias`). Exact flows come first: their first-flip
    times are the reference of the others.

    Parameters
    ----------
    specs : list of MethodSpec
    steps : sequence of float
        The step h of each method, s.
    n_shapes : int
        Shapes in the map.
    bias_check : bool
        Run the half-step bias runs.
    bias_stride : int
        Bias runs on every ``bias_stride``-th shape.

    Returns
    -------
    list of (int, float, ndarray, bool)
        (method index, h, shape indices, whether it is the half-step bias run).
    """
    runs = []
    for i in sorted(range(len(specs)), key=lambda i: not specs[i].is_exact):
        runs.append((i, steps[i], np.arange(n_shapes), False))
        if bias_check and not specs[i].is_exact:
            runs.append((i, steps[i] / 2, np.arange(0, n_shapes, bias_stride), True))
    return runs


def measure_map(bodies, omega2, t_end, levels, specs, runs, *, spin, epsilon, members, seed,
                low_factor, high_fraction, progress=None, checkpoint=None, scheduler=None,
                threads=None):
    """Run every ensemble of the map and keep its estimates.

    Every (shape, axis) runs ``members`` starts ``spin e_a`` nudged by ``epsilon spin`` in the
    same random perpendicular directions (:func:`stability.ensemble.starts.perturbed_starts` with
    ``seed``), summaries-only, for ``t_end`` rounded up to whole steps. Each entry of ``runs``
    is one batch (:class:`MapBatches`), the estimates of each batch independent of the others'.

    Parameters
    ----------
    bodies : list of RigidBody
        The shapes.
    omega2, t_end : ndarray, shape (S, 3)
        Analytic Omega^2 (s-2) and run length (s) per (shape, axis).
    levels : ndarray, shape (L,)
        Amplitude levels of the passage times, rad/s.
    specs : list of MethodSpec
    runs : list of (int, float, ndarray, bool)
        (method index, h, shape indices, whether it is the half-step bias run), exact flows
        first: their first-flip times are the reference of the others (:func:`map_runs`).
    spin, epsilon, members, seed
        The ensembles (rad/s, relative, count, seed of the directions).
    low_factor, high_fraction : float
        The growth-rate window.
    progress : bool, optional
        Progress bar over the ensembles; by default on a terminal.
    checkpoint : stability.output.store.ChunkStore, optional
        One chunk per entry of ``runs``: the estimates of each finished batch are kept there,
        and batches found there are not run again (``stability run --resume``).
    scheduler : str or distributed.Client, optional
        Run the batches as tasks of a dask.distributed cluster (needs ``checkpoint``:
        :func:`stability.output.stream.stream_chunks`).
    threads : int, optional
        Numba threads for the batches run in this process.

    Returns
    -------
    out, half : dict
        :func:`empty_estimates` filled in at h and at h / 2.
    work : dict
        ``member_steps`` and ``loop_time`` (s, in compiled code) summed over the runs.

    Raises
    ------
    KeyboardInterrupt
        When Ctrl-C stopped an ensemble.
    """

    job = MapBatches(bodies, omega2, t_end, levels, [spec.name for spec in specs], runs,
                     spin=spin, epsilon=epsilon, members=members, seed=seed,
                     low_factor=low_factor, high_fraction=high_fraction)
    if checkpoint is not None:
        stream_chunks(job, checkpoint, scheduler=scheduler, threads=threads, progress=progress,
                      compress=False)
        batches = (read_batch(checkpoint.path(j), len(job.cells(j))) for j in range(len(runs)))
    elif scheduler is not None:
        raise ValueError("a map on a dask scheduler needs a checkpoint store for its batches")
    else:
        batches = (job.batch(j) for j in range(len(runs)))
    out, half = empty_estimates(len(specs), len(bodies))
    first_exact = {}
    member_steps, loop_time = 0, 0.0
    total = sum(len(shapes) for _, _, shapes, _ in runs) * 3
    bar = progress_bar(total, progress if checkpoint is None else False, "stability_map",
                       unit="ensemble")
    with contextlib.closing(bar):  # closed however the loop ends, Ctrl-C included
        for j, batch in enumerate(batches):
            i, h, shapes, is_half = runs[j]
            for (s, a), (steps, seconds, x) in zip(job.cells(j), batch):
                member_steps += steps
                loop_time += seconds
                store(half if is_half else out, (i, s, a - 1), x)
                if specs[i].is_exact and not is_half:
                    first_exact[s, a] = x["first_flip_time"]
                elif not is_half and (s, a) in first_exact:
                    out["first_flip_time_relative_error"][i, s, a - 1] = (
                        first_flip_relative_error(x["first_flip_time"], first_exact[s, a]))
            bar.update(len(job.cells(j)))
    return out, half, {"member_steps": member_steps, "loop_time": loop_time}


class MapBatches:
    """The map's batches as a chunk job (:func:`stability.output.stream.stream_chunks`): chunk j is
    batch j, every ensemble of one entry of ``runs`` run together (all cores busy, each
    ensemble bitwise what it gives alone), kept as :func:`batch_dataset`.

    Parameters
    ----------
    bodies : list of RigidBody
        The shapes.
    omega2, t_end : ndarray, shape (S, 3)
        Analytic Omega^2 (s-2) and run length (s) per (shape, axis).
    levels : ndarray, shape (L,)
        Amplitude levels of the passage times, rad/s.
    methods : list of str
        The integrators by name (a job goes to dask workers by pickle).
    runs : list of (int, float, ndarray, bool)
        The batches (:func:`map_runs`).
    spin, epsilon, members, seed
        The ensembles (rad/s, relative, count, seed of the directions).
    low_factor, high_fraction : float
        The growth-rate window.
    """

    def __init__(self, bodies, omega2, t_end, levels, methods, runs, *, spin, epsilon, members,
                 seed, low_factor, high_fraction):
        self.bodies, self.omega2, self.t_end, self.levels = bodies, omega2, t_end, levels
        self.methods, self.runs = list(methods), list(runs)
        self.spin, self.epsilon, self.members, self.seed = spin, epsilon, members, seed
        self.low_factor, self.high_fraction = low_factor, high_fraction
        self._exact_flip = {}  # (s, a) -> exact flip intervals of the common starts
        self._starts = {}  # a -> the common starts about axis a

    def __getstate__(self):
        return {**self.__dict__, "_exact_flip": {}, "_starts": {}}

    def cells(self, j: int) -> list:
        """The (shape, axis) cells of batch ``j``, in order."""
        return [(s, a) for s in self.runs[j][2] for a in cv.AXES]

    def __call__(self, lo: int, hi: int, progress, threads) -> xr.Dataset:
        return batch_dataset(self.batch(lo))

    def batch(self, j: int) -> list:
        """Per cell of batch ``j``: member-steps, loop seconds and :func:`ensemble_estimates`.

        Raises KeyboardInterrupt when Ctrl-C stopped it.
        """

        i, h, _, _ = self.runs[j]
        cells = self.cells(j)
        ensembles = run_ensembles([
            dict(body=self.bodies[s], axis=int(a), spin=self.spin, epsilon=self.epsilon,
                 members=self.members,
                 h=h, t_end=max(1, int(math.ceil(self.t_end[s, a - 1] / h - 1e-9))) * h,
                 seed=self.seed, method=self.methods[i],
                 keep=Keep(save_every=0, levels=self.levels))
            for s, a in cells], progress=False, datasets=False)
        completed(*ensembles)  # Ctrl-C stopped the batch: stop the map
        estimates = batch_estimates(
            ensembles, [self.omega2[s, a - 1] for s, a in cells],
            [self._exact_flips(s, a, run.members.w0) for (s, a), run in zip(cells, ensembles)],
            low_factor=self.low_factor, high_fraction=self.high_fraction)
        return [(run.member_steps, run.wall_time, x) for run, x in zip(ensembles, estimates)]

    def _exact_flips(self, s, a, w0):

        if self.omega2[s, a - 1] >= 0:
            return None, None
        if a not in self._starts:  # the same random directions for every ensemble about a
            self._starts[a] = perturbed_starts(a, self.spin, self.epsilon, self.members,
                                               self.seed)
        starts = self._starts[a]
        if not np.array_equal(w0, starts):
            return exact_flip_intervals(self.bodies[s], a, w0)
        if (s, a) not in self._exact_flip:
            self._exact_flip[s, a] = exact_flip_intervals(self.bodies[s], a, starts)
        return self._exact_flip[s, a]


def write_batch(checkpoint, j: int, batch) -> None:
    """Keep batch ``j`` as chunk ``j`` of ``checkpoint``, uncompressed, with its checksum.

    Parameters
    ----------
    checkpoint : stability.output.store.ChunkStore
        The run's chunk store.
    j : int
        Index of the batch in ``runs`` (:func:`measure_map`), the chunk number.
    batch : list of (int, float, dict)
        Per cell: member-steps, kernel loop time in s, and :func:`ensemble_estimates`
        (:func:`batch_dataset`).
    """
    checkpoint.write(j, batch_dataset(batch), compress=False)


def batch_dataset(batch) -> xr.Dataset:
    """A batch's (member-steps, loop seconds, estimates) per cell as one small Dataset.

    Each number is one netCDF variable over the batch's cells (per-member arrays: cells x
    members; arrays whose lengths differ between cells are kept end to end beside their
    lengths), so :func:`read_batch` gives back the same values bit for bit, and a batch of
    thousands of cells is a few dozen variables, written in milliseconds.

    Parameters
    ----------
    batch : list of (int, float, dict)
        Per cell (shape, axis) of the batch: member-steps, kernel loop time in s, and
        :func:`ensemble_estimates`.
    """
    columns: dict[str, list] = {}
    for steps, seconds, x in batch:
        for name, value in {"member_steps": steps, "loop_time": seconds, **x}.items():
            value = np.asarray(value)
            if value.dtype == bool:  # netCDF has no bool; the estimate arrays hold int8
                value = value.astype(np.int8)
            columns.setdefault(name, []).append(value)
    data = {}
    for name, values in columns.items():
        if len({v.shape for v in values}) == 1:
            dims = ("cell",) + tuple(f"{name}.n{k}" for k in range(values[0].ndim))
            data[name] = (dims, np.stack(values))
        else:  # ragged: end to end, with each cell's length
            data[name] = ((f"{name}.all",), np.concatenate([v.ravel() for v in values]))
            data[f"{name}.length"] = (("cell",), np.array([v.size for v in values]))
    return xr.Dataset(data)


def read_batch(path, n_cells: int) -> list:
    """The batch :func:`write_batch` kept in ``path``.

    Parameters
    ----------
    path : path-like
        The chunk file (netCDF).
    n_cells : int
        Number of cells (shape, axis) in the batch.

    Returns
    -------
    list of (int, float, dict)
        Per cell: member-steps, kernel loop time in s, and the estimates (scalars as Python
        numbers, per-member arrays as ndarrays; booleans come back as int8).

    Raises
    ------
    ValueError
        One line naming the file, if it is not one to read
        (:func:`stability.output.untrusted.read_dataset`).
    """
    ds = read_dataset(path, engine="netcdf4")
    cells = [{} for _ in range(n_cells)]
    for name in ds.data_vars:
        if name.endswith(".length"):
            continue
        values = ds[name].values
        if f"{name}.length" in ds:
            ends = np.cumsum(ds[f"{name}.length"].values)
            parts = np.split(values, ends[:-1])
        else:
            parts = [v.item() if v.ndim == 0 else v for v in values]
        for x, part in zip(cells, parts):
            x[name] = part
    return [(x.pop("member_steps"), x.pop("loop_time"), x) for x in cells]


def empty_estimates(n_methods: int, n_shapes: int):
    """Arrays (methods, shapes, 3) for the estimates at h (``out``) and at h / 2 (``half``).

    Parameters
    ----------
    n_methods : int
        Number of integrators (entries of ``specs``).
    n_shapes : int
        Number of shapes.

    Returns
    -------
    out : dict
        ``MAP_FLOATS`` (float, NaN), ``regime``, ``sign_agrees``, ``status`` (int8, 0) and
        ``members_failed`` (int32, 0), each of shape (n_methods, n_shapes, 3).
    half : dict
        ``omega_squared_measured`` (float, NaN) and ``regime`` (int8, 0), same shape.
    """
    shape3 = (n_methods, n_shapes, 3)
    nan = np.full(shape3, np.nan)
    out = {name: nan.copy() for name in MAP_FLOATS}
    out["regime"] = np.zeros(shape3, dtype=np.int8)
    out["sign_agrees"] = np.zeros(shape3, dtype=np.int8)
    out["members_failed"] = np.zeros(shape3, dtype=np.int32)
    out["status"] = np.zeros(shape3, dtype=np.int8)
    half = {"omega_squared_measured": nan.copy(), "regime": np.zeros(shape3, dtype=np.int8)}
    return out, half


def store(arrays: dict, index, estimates: dict) -> None:
    """Put one ensemble's :func:`ensemble_estimates` at ``index`` of every array it has.

    Parameters
    ----------
    arrays : dict
        Name -> ndarray, shape (methods, shapes, 3) (:func:`empty_estimates`); changed in place.
    index : tuple of int
        ``(method, shape, axis)``, the axis 0-based.
    estimates : dict
        :func:`ensemble_estimates` of the ensemble; names without an array are skipped.
    """
    for name, values in arrays.items():
        if name in estimates:
            values[index] = estimates[name]


def first_flip_relative_error(first, reference) -> float:
    """Mean over members of (first flip - reference) / reference, finite members only.

    Parameters
    ----------
    first, reference : ndarray, shape (N,)
        Each member's first-flip time and the exact flow's, s (NaN: no flip).

    Returns
    -------
    float
        Mean relative difference, dimensionless; NaN if no member is finite.
    """
    with np.errstate(invalid="ignore", divide="ignore"):
        return _finite_mean((first - reference) / reference)


def _finite_mean(x):
    x = np.asarray(x, dtype=float)
    x = x[np.isfinite(x)]
    return float(x.mean()) if x.size else math.nan


def _nanmax_abs(x):
    x = np.abs(np.asarray(x, dtype=float))
    x = x[np.isfinite(x)]
    return float(x.max()) if x.size else math.nan


def map_dataset(specs, steps, spin, moments, edges, omega2, t_end, levels, out, half, bias,
                sweep, edge, attrs) -> xr.Dataset:
    """Assemble the map's Dataset (see the module docstring).

    Parameters
    ----------
    specs : list of MethodSpec
        The integrators, in the order of ``integrator``.
    steps : sequence of float
        Their steps h, s.
    spin : float
        W, rad/s.
    moments, edges : ndarray, shapes (S, 3) and (S,)
        The shapes and their edge flags
        (:func:`stability.free_body.stability_map.shapes.shape_grid`).
    omega2, t_end : ndarray, shape (S, 3)
        Analytic Omega^2 (s-2) and run length (s) per (shape, axis).
    levels : ndarray, shape (L,)
        The passage-time amplitude levels, rad/s.
    out, half : dict
        The estimates at h and h / 2 (:func:`empty_estimates`, :func:`store`).
    bias : ndarray, shape (M, S, 3)
        Relative Richardson bias of Omega^2 (:func:`stability.analysis.fits.richardson_bias`).
    sweep, edge : dict
        :func:`stability.free_body.tennis_racket.flipsweep.flip_sweep` and :func:`stability.free_body.stability_map.shapes.edge_series`.
    attrs : dict
        Global attributes.
    """
    data = {
        "omega_squared": omega2,
        "omega_squared_normalised": omega2 / spin**2,
        "t_end": t_end,
        "edge": edges,
        "regime": out["regime"],
        "sign_agrees": out["sign_agrees"],
        "status": out["status"],
        "members_failed": out["members_failed"],
        "energy_error_max": out["energy_error_max"],
        "first_flip_time_relative_error": out["first_flip_time_relative_error"],
        "omega_squared_measured_half_step": half["omega_squared_measured"],
        "regime_half_step": half["regime"],
        "step_bias": bias,
    }
    for name in MAP_FLOATS:
        if name not in data:
            data[name] = out[name]
    data.update({
        "sweep_flip_interval": sweep["measured"],
        "sweep_flip_interval_exact": sweep["exact"],
        "sweep_flip_interval_asymptote": sweep["asymptote"],
        "sweep_growth_rate": sweep["growth_rate"],
        "edge_w": edge["w"],
        "edge_slope_predicted": edge["slope_predicted"],
        "edge_slope_measured": edge["slope_measured"],
        "edge_distinct_change": edge["distinct_change"],
        "edge_flips": edge["flips"],
        "edge_regime": edge["regime"],
        "edge_linear_residual": edge["linear_residual"],
        "edge_exponential_residual": edge["exponential_residual"],
    })
    coords = {
        "integrator": [spec.name for spec in specs],
        "h": np.array(steps, dtype=float),
        "method_order": np.array([spec.order for spec in specs], dtype=float),
        "shape": np.arange(moments.shape[0]),
        "I1": moments[:, 0],
        "I2": moments[:, 1],
        "I3": moments[:, 2],
        cv.AXIS: np.array(cv.AXES),
        "level": levels,
        "flip_shape": np.arange(sweep["moments"].shape[0]),
        "flip_I1": sweep["moments"][:, 0],
        "flip_I2": sweep["moments"][:, 1],
        "epsilon": sweep["epsilons"],
        "edge_case": edge["names"],
        "edge_I1": edge["moments"][:, 0],
        "edge_I2": edge["moments"][:, 1],
        "edge_I3": edge["moments"][:, 2],
        "edge_axis": edge["axis"],
        "edge_time": edge["time"],
    }
    return xr.Dataset(STABILITY_MAP.entries(data), coords=STABILITY_MAP.entries(coords),
                      attrs=attrs)


def headline(ds: xr.Dataset):
    """The numbers a map ends with: per integrator the accuracy against the bar, the sign, the
    step bias beside the literature's, the flips; the edges, classified; the flip sweep.

    Parameters
    ----------
    ds : xarray.Dataset
        The map's Dataset (:func:`map_dataset`), with the attributes ``tolerance``,
        ``min_omega_squared``, ``spin``, ``members`` and ``epsilon``.

    Returns
    -------
    rows : list of (str, str, str)
        Label, value and unit or note, for the printed summary.
    values : dict
        ``<method>_worst_relative_error``, ``<method>_passed``, ``<method>_sign_right``,
        ``bar_size``, ``all_passed``.
    """
    tol, floor = ds.attrs["tolerance"], ds.attrs["min_omega_squared"]
    spin = float(ds.attrs["spin"])
    norm = ds.omega_squared_normalised.values
    bar_set = np.abs(norm) > floor
    rows, values = [], {}
    n_shapes, members = ds.sizes["shape"], ds.attrs["members"]
    rows.append(("shapes x axes (ensembles per method)", f"{n_shapes} x 3 = {3 * n_shapes}", ""))
    rows.append(("members per ensemble, perturbation epsilon",
                 f"{members}, {ds.attrs['epsilon']:g}", ""))
    passed_all = True
    for k, method in enumerate(ds.integrator.values):
        h = float(ds.h.values[k])
        rel = ds.relative_error.values[k]
        sign = ds.sign_agrees.values[k].astype(bool)
        in_bar = rel[bar_set]
        worst = float(np.nanmax(np.abs(in_bar))) if np.isfinite(in_bar).any() else math.nan
        missing = int(np.sum(~np.isfinite(in_bar)))
        passed = int(np.sum(np.abs(in_bar) <= tol))
        ok = passed == in_bar.size and missing == 0 and bool(sign.all())
        passed_all &= ok
        where = np.unravel_index(np.nanargmax(np.where(bar_set, np.abs(rel), -1.0)), rel.shape)
        I = [float(ds[f"I{i}"].values[where[0]]) for i in (1, 2, 3)]
        tag = f"{method} (h = {h:g} s)"
        rows.append((f"{tag}: worst |rel. error| of Omega^2 where |Omega^2|/W^2 > {floor:g}",
                     f"{worst:.2e}", f"at I = ({I[0]:.4g}, {I[1]:.4g}, 1), axis {where[1] + 1}"))
        rows.append((f"{tag}: within the bar {tol:g}", f"{passed} / {in_bar.size}",
                     "PASS" if ok else "FAIL"))
        rows.append((f"{tag}: regime sign right", f"{int(sign.sum())} / {sign.size}", ""))
        med = float(np.nanmedian(np.abs(in_bar))) if np.isfinite(in_bar).any() else math.nan
        rows.append((f"{tag}: median |rel. error|", f"{med:.1e}", ""))
        bias = ds.step_bias.values[k][bar_set]
        if np.isfinite(bias).any():
            rows.append((f"{tag}: O(h^p) bias in Omega^2 (h vs h/2), median / max |.|",
                         f"{np.nanmedian(np.abs(bias)):.1e} / {np.nanmax(np.abs(bias)):.1e}",
                         f"{int(np.isfinite(bias).sum())} ensembles"))
        if method in LITERATURE_RATE_BIAS:
            # The grid shape nearest I = (1, 2, 3) / 3, spin about axis 2: literature notes 4.1.
            s = int(np.argmin((ds.I1.values - 1 / 3) ** 2 + (ds.I2.values - 2 / 3) ** 2))
            lam = math.sqrt(-float(ds.omega_squared.values[s, 1]))
            predicted = -2.0 * LITERATURE_RATE_BIAS[method](h * spin, lam / spin)
            shape = f"I = ({float(ds.I1[s]):.4g}, {float(ds.I2[s]):.4g}, 1), axis 2"
            stderr = float(ds.omega_squared_measured_stderr[k, s, 1]) / lam**2
            rows.append((f"{tag}: rel. error of Omega^2 at {shape}", f"{rel[s, 1]:.1e}",
                         f"standard error {stderr:.0e}"))
            rows.append((f"{tag}: the same, predicted by the step's bias", f"{predicted:.1e}",
                         "literature notes 4.1"))
        flip_rel = ds.flip_interval_relative_error.values[k]
        if np.isfinite(flip_rel).any():
            rows.append((f"{tag}: flip interval vs exact 2K/nu, median / max |rel.|",
                         f"{np.nanmedian(np.abs(flip_rel)):.1e} / "
                         f"{np.nanmax(np.abs(flip_rel)):.1e}", "unstable axes"))
        first_rel = ds.first_flip_time_relative_error.values[k]
        if np.isfinite(first_rel).any():
            rows.append((f"{tag}: first flip vs the exact flow, max |rel.|",
                         f"{np.nanmax(np.abs(first_rel)):.1e}", "member by member"))
        values[f"{method}_worst_relative_error"] = worst
        values[f"{method}_passed"] = passed
        values[f"{method}_sign_right"] = int(sign.sum())
    values["bar_size"] = int(bar_set.sum())
    values["all_passed"] = bool(passed_all)

    # The edges, classified rather than fitted.
    edge = ds.edge.values
    zero = norm == 0.0
    reg = ds.regime.values
    for label, mask in (("I1 = I2 edge", (edge & EDGE_EQUAL_12) > 0),
                        ("I2 = I3 edge", (edge & EDGE_EQUAL_23) > 0)):
        not_sphere = edge != (EDGE_EQUAL_12 | EDGE_EQUAL_23)
        sel = (mask & not_sphere)[:, None] & zero
        alg = int(np.sum(reg[:, sel] == REGIME_ALGEBRAIC))
        flips = float(np.nanmax(ds.n_flips_mean.values[:, sel])) if sel.any() else 0.0
        rows.append((f"{label}, equal-moment axes (Omega^2 = 0): algebraic drift",
                     f"{alg} / {reg[:, sel].size}", f"flips per member at most {flips:g}"))
    sphere = edge == (EDGE_EQUAL_12 | EDGE_EQUAL_23)
    if sphere.any():
        neutral = int(np.sum(reg[:, sphere, :] == REGIME_NEUTRAL))
        rows.append(("sphere: no departure (neutral)", f"{neutral} / {reg[:, sphere, :].size}", ""))
    flat = (edge & EDGE_FLAT) > 0
    flat_rel = ds.relative_error.values[:, flat, :][:, bar_set[flat]]
    if np.isfinite(flat_rel).any():
        rows.append(("flat edge I1 + I2 = I3: worst |rel. error| (all methods)",
                     f"{np.nanmax(np.abs(flat_rel)):.2e}", ""))
    for c, name in enumerate(ds.edge_case.values):
        rows.append((f"edge series {name}: slope measured / predicted",
                     f"{float(ds.edge_slope_measured[c]):.4e} / "
                     f"{float(ds.edge_slope_predicted[c]):.4e}", "rad s-2"))
        rows.append((f"edge series {name}: distinct component change, flips",
                     f"{float(ds.edge_distinct_change[c]):.1e}, {int(ds.edge_flips[c])}",
                     "rad s-1"))

    sweep = ds.sweep_flip_interval.values
    exact = ds.sweep_flip_interval_exact.values
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.abs(sweep - exact[None]) / exact[None]
    for k, method in enumerate(ds.integrator.values):
        for lo in (1e-6,):
            sel = ds.epsilon.values >= lo
            if np.isfinite(rel[k][:, sel]).any():
                rows.append((f"flip sweep {method}: max |rel.| vs 2K/nu, epsilon >= {lo:g}",
                             f"{np.nanmax(rel[k][:, sel]):.1e}", ""))

    return rows, values
