"""The work-precision Dataset: built from timed sweeps, read as "which method is fastest".

The Dataset (dims ``workload``, ``method``, ``sweep``, ``metric``, and ``long_time`` for the long
horizon) holds, per (workload, method, sweep point), the step h or tolerance, the kernel time for
the whole ensemble and per member-step, the work, the failed members and the (max, p99, median)
over members of the final errors of w, the energy, |L| and the attitude
(:mod:`stability.free_body.work_precision.sweeps`); per workload the conditioning floor
(:func:`stability.free_body.accuracy.conditioning_floor`) and the attitude reference's own error;
per method the long-horizon energy and |L| errors and their log-log slope
(:mod:`stability.free_body.work_precision.drift`).

Reading it: :func:`time_to_reach` (the kernel time at which a method brings an error statistic
under a target), :func:`fastest`, and the Markdown tables of :func:`markdown_report`.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from .drift import drift_kind, envelope, log_slope
from ..methods import METHODS
from ..accuracy import METRICS
from ..schema import WORK_PRECISION

#: Name of scipy's DOP853 in the ``method`` dimension (run as one system over all members).
SCIPY = "dop853"
#: Name of the member loop's adaptive Dormand-Prince 5(4) in the ``method`` dimension, and its
#: order.
ADAPTIVE, ADAPTIVE_ORDER = "dopri5", 5.0

#: Workloads in the order of the ``workload`` dimension: spin about the intermediate axis (the
#: hard, ill-conditioned one) and about a stable axis.
WORKLOADS = ("tennis", "stable")

#: Accuracy targets of the tables (relative w error reached by the p99 member).
TARGETS = (1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12)


def _sweep_arrays(results, methods, n_sweep):
    """Stack per-point dicts into arrays (workload, method, sweep[, metric]), NaN-padded."""
    shape = (len(WORKLOADS), len(methods), n_sweep)
    scalars = ("h", "rtol", "steps", "wall_time", "member_step_time", "evaluations",
               "iterations", "failed")
    vectors = ("w_error", "energy_error", "momentum_error", "attitude_error")
    out = {k: np.full(shape, np.nan) for k in scalars}
    out.update({k: np.full(shape + (len(METRICS),), np.nan) for k in vectors})
    for i, workload in enumerate(WORKLOADS):
        for j, method in enumerate(methods):
            for k, point in enumerate(results.get((workload, method), [])):
                for key in scalars + vectors:
                    out[key][i, j, k] = point[key]
    return out


#: Variables stacked per (workload, method, sweep[, metric]) from the sweep points.
_SWEPT = ("w_error", "energy_error", "momentum_error", "attitude_error", "wall_time",
          "member_step_time", "steps", "evaluations", "iterations", "failed")


def work_precision_dataset(methods, results, floors, long_results, reference_errors,
                           attrs) -> xr.Dataset:
    """Assemble the work-precision Dataset from the measurements (see the module docstring).

    Parameters
    ----------
    methods : list of str
        Registry names of the methods that ran, in order; ``ADAPTIVE`` and ``SCIPY`` are
        appended where they ran.
    results : dict
        ``(workload, method) -> list of sweep points``
        (:func:`stability.free_body.work_precision.sweeps.sweep_method`,
        :func:`stability.free_body.work_precision.sweeps.sweep_scipy`).
    floors : dict
        ``workload -> (max, p99, median)`` of the conditioning floor.
    long_results : dict
        ``method -> (t, energy, momentum, wall)``
        (:func:`stability.free_body.work_precision.drift.long_horizon`).
    reference_errors : dict
        ``workload -> (max, p99, median)`` of the attitude reference's w error; a workload
        without an attitude run is NaN.
    attrs : dict
        Global attributes (title, provenance, the workloads in words, ...).
    """
    methods = list(methods) + [name for name in (ADAPTIVE, SCIPY)
                               if any(key[1] == name for key in results)]
    n_sweep = max((len(p) for p in results.values()), default=1)
    arrays = _sweep_arrays(results, methods, n_sweep)
    data = {name: arrays[name] for name in _SWEPT}
    data["floor"] = np.array([floors[w] for w in WORKLOADS])
    long_methods = [m for m in methods if m in long_results]
    t = next(iter(long_results.values()))[0] if long_results else np.zeros(0)
    drift_e = np.array([long_results[m][1] for m in long_methods]).reshape(len(long_methods), -1)
    drift_l = np.array([long_results[m][2] for m in long_methods]).reshape(len(long_methods), -1)
    full_e = np.full((len(methods), t.size), np.nan)
    full_l = np.full((len(methods), t.size), np.nan)
    slope = np.full(len(methods), np.nan)
    for j, m in enumerate(methods):
        if m in long_results:
            k = long_methods.index(m)
            full_e[j], full_l[j] = drift_e[k], drift_l[k]
            slope[j] = log_slope(t, drift_e[k])
    data.update({"drift_energy": full_e, "drift_momentum": full_l, "drift_slope": slope})
    specs = {m: METHODS.get(m) for m in methods}
    coords = {
        "workload": list(WORKLOADS),
        "method": methods,
        "sweep": np.arange(n_sweep),
        "metric": list(METRICS),
        "long_time": t,
        "h": arrays["h"],
        "rtol": arrays["rtol"],
        "order": np.array([
            (np.inf if specs[m].is_exact else float(specs[m].order)) if specs[m]
            else ADAPTIVE_ORDER if m == ADAPTIVE else 8.0 for m in methods]),
    }
    ds = xr.Dataset(WORK_PRECISION.entries(data), coords=WORK_PRECISION.entries(coords))
    ds.attrs.update(attrs)
    ds["attitude_reference_error"] = WORK_PRECISION.entry(
        "attitude_reference_error",
        np.array([reference_errors.get(w, np.full(len(METRICS), np.nan)) for w in WORKLOADS]))
    return ds


def time_to_reach(ds: xr.Dataset, workload: str, method: str, target: float,
                  metric: str = "p99") -> float:
    """Ensemble wall time at which ``method`` reaches relative w error ``target`` (NaN: never).

    Among the sweep points without failed members, the cheapest one whose error is <= target;
    the time is interpolated in log-log between it and the costlier-error point before it
    (the next coarser step), since the sweep is a discrete ladder.

    Parameters
    ----------
    ds : xarray.Dataset
        The work-precision Dataset (:func:`work_precision_dataset`).
    workload : str
        ``"tennis"`` or ``"stable"`` (``WORKLOADS``).
    method : str
        Name in the ``method`` dimension: a registry name, or ``"dop853"`` (``SCIPY``).
    target : float
        Relative w error to reach, dimensionless.
    metric : str, default "p99"
        Statistic over members of the w error: ``"max"``, ``"p99"`` or ``"median"``.

    Returns
    -------
    float
        Kernel wall time for the whole ensemble, s; NaN if no sweep point without failed
        members reaches ``target``.
    """
    sel = ds.sel({"workload": workload, "method": method})
    err = sel.w_error.sel(metric=metric).values
    wall = sel.wall_time.values
    good = np.isfinite(err) & np.isfinite(wall) & (sel.failed.values == 0) & (wall > 0)
    err, wall = err[good], wall[good]
    if err.size == 0:
        return np.nan
    order = np.argsort(wall)
    err, wall = err[order], wall[order]
    hits = np.nonzero(err <= target)[0]
    if hits.size == 0:
        return np.nan
    k = hits[0]
    if k == 0 or err[k - 1] <= err[k]:
        return float(wall[k])
    # log-log interpolation between (wall[k-1], err[k-1] > target) and (wall[k], err[k]).
    x = (math.log(target) - math.log(err[k - 1])) / (math.log(err[k]) - math.log(err[k - 1]))
    return float(math.exp(math.log(wall[k - 1]) + x * (math.log(wall[k]) - math.log(wall[k - 1]))))


def fastest(ds: xr.Dataset, workload: str, target: float, metric: str = "p99"):
    """Every method's :func:`time_to_reach` ``target``, and the methods that reach it, fastest
    first.

    Parameters
    ----------
    ds : xarray.Dataset
        The work-precision Dataset (:func:`work_precision_dataset`).
    workload : str
        ``"tennis"`` or ``"stable"`` (``WORKLOADS``).
    target : float
        Relative w error to reach, dimensionless.
    metric : str, default "p99"
        Statistic over members of the w error: ``"max"``, ``"p99"`` or ``"median"``.

    Returns
    -------
    times : dict
        ``method -> seconds`` (NaN: not reached), for every method of ``ds``.
    ranked : list of (float, str)
        ``(seconds, method)`` of the methods that reach the target, ascending.
    stepping : list of (float, str)
        The same without the exact flow: the time-stepping integrators.
    """
    times = {m: time_to_reach(ds, workload, m, target, metric)
             for m in (str(x) for x in ds.method.values)}
    ranked = sorted((t, m) for m, t in times.items() if np.isfinite(t))
    stepping = [(t, m) for t, m in ranked if not _is_exact_flow(m)]
    return times, ranked, stepping


def format_time(seconds: float) -> str:
    """Seconds in the tables' units (µs, ms, s; "–" for NaN: not reached).

    Parameters
    ----------
    seconds : float
        A time in s; NaN or infinite for "not reached".

    Returns
    -------
    str
        ``"12 µs"`` below 1 ms, ``"3.45 ms"`` below 1 s, else ``"1.23 s"``; ``"–"`` if not finite.
    """
    if not np.isfinite(seconds):
        return "–"
    if seconds < 1e-3:
        return f"{seconds * 1e6:.0f} µs"
    if seconds < 1.0:
        return f"{seconds * 1e3:.3g} ms"
    return f"{seconds:.3g} s"


def _is_exact_flow(name) -> bool:
    spec = METHODS.get(str(name))
    return spec is not None and spec.is_exact


def winner_table(ds: xr.Dataset, workload: str, metric: str = "p99", targets=TARGETS) -> str:
    """Markdown table: per accuracy target, the fastest method and every method's time.

    Times are kernel seconds for the whole ensemble ("–": not reached within the sweep). The
    third column leaves out the exact flow, which exists for the torque-free body only: it is
    the answer for a user who will add torques.

    Parameters
    ----------
    ds : xarray.Dataset
        The work-precision Dataset (:func:`work_precision_dataset`).
    workload : str
        ``"tennis"`` or ``"stable"`` (``WORKLOADS``).
    metric : str, default "p99"
        Statistic over members of the w error: ``"max"``, ``"p99"`` or ``"median"``.
    targets : sequence of float, default TARGETS
        Relative w errors, one row each; a target below the workload's conditioning floor is
        marked so.

    Returns
    -------
    str
        The table, one row per target, one time column per method.
    """
    methods = [str(m) for m in ds.method.values]
    floor = float(ds.floor.sel(workload=workload, metric=metric))
    header = [f"w error ({metric}) <=", "fastest", "fastest integrator (exact flow aside)"]
    header += methods
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for target in targets:
        times, ranked, stepping = fastest(ds, workload, target, metric)
        best = f"**{ranked[0][1]}**" if ranked else "none"
        integrator = (f"{stepping[0][1]} ({format_time(stepping[0][0])})" if stepping else "none")
        label = f"{target:.0e}" + (" (under the floor)" if target < floor else "")
        row = [label, best, integrator] + [format_time(times[m]) for m in methods]
        lines.append("| " + " | ".join(row) + " |")
    return "\n".join(lines)


def invariants_table(ds: xr.Dataset) -> str:
    """Markdown table of the long-horizon run: final energy and |L| errors, slope, behaviour.

    Parameters
    ----------
    ds : xarray.Dataset
        The work-precision Dataset (:func:`work_precision_dataset`); methods without a
        long-horizon run are left out.

    Returns
    -------
    str
        The table: per method the RMS energy and ``|L|`` errors at the end, the log-log slope
        and :func:`stability.free_body.work_precision.drift.drift_kind`.
    """
    lines = ["| method | energy error at end | |L| error at end | log-log slope | behaviour |",
             "|---|---|---|---|---|"]
    for m in ds.method.values:
        e = ds.drift_energy.sel({"method": m}).values
        if e.size == 0 or not np.any(np.isfinite(e)):
            continue
        l_err = ds.drift_momentum.sel({"method": m}).values
        slope = float(ds.drift_slope.sel({"method": m}))
        kind = drift_kind(slope, float(np.nanmax(envelope(e))))
        lines.append(f"| {m} | {e[-1]:.2g} | {l_err[-1]:.2g} | {slope:.2f} | {kind} |")
    return "\n".join(lines)


def cost_table(ds: xr.Dataset, workload: str = "tennis") -> str:
    """Markdown table of the cost per member-step and the work per step, per method.

    Parameters
    ----------
    ds : xarray.Dataset
        The work-precision Dataset (:func:`work_precision_dataset`).
    workload : str, default "tennis"
        The workload whose sweeps are read.

    Returns
    -------
    str
        The table: per method (scipy's DOP853 left out) its order, the median kernel time per
        member-step (ns), the evaluations per step and the solver iterations per step.
    """
    lines = ["| method | order | time per member-step | evaluations per step | "
             "solver iterations per step |", "|---|---|---|---|---|"]
    for m in ds.method.values:
        sel = ds.sel({"workload": workload, "method": m})
        if str(m) == SCIPY:
            continue
        per = np.nanmedian(sel.member_step_time.values) if np.any(
            np.isfinite(sel.member_step_time.values)) else np.nan
        steps = sel.steps.values
        evals = np.nanmax(sel.evaluations.values / steps) if np.any(np.isfinite(steps)) else np.nan
        iters = np.nanmedian(sel.iterations.values) if np.any(
            np.isfinite(sel.iterations.values)) else np.nan
        order = float(ds.order.sel({"method": m}))
        lines.append(f"| {m} | {'exact' if np.isinf(order) else int(order)} | "
                     f"{per * 1e9:.3g} ns | {evals:.0f} | {iters:.2g} |")
    return "\n".join(lines)


def attitude_table(ds: xr.Dataset) -> str:
    """Markdown table: attitude error (p99, rad) at each method's finest step, per workload.

    Parameters
    ----------
    ds : xarray.Dataset
        The work-precision Dataset (:func:`work_precision_dataset`); methods without an
        attitude error in every workload are left out.

    Returns
    -------
    str
        The table: per method and workload the finest step h run (s), its p99 attitude error
        (rad) and its p99 relative w error.
    """
    header = "| method | " + " | ".join(
        f"{w}: h | {w}: attitude error p99 | {w}: w error p99" for w in WORKLOADS) + " |"
    lines = [header, "|" + "---|" * (1 + 3 * len(WORKLOADS))]
    for m in ds.method.values:
        cells = []
        for w in WORKLOADS:
            sel = ds.sel({"workload": w, "method": m})
            att = sel.attitude_error.sel(metric="p99").values
            ran = np.flatnonzero(np.isfinite(att))
            if ran.size == 0:
                cells = []
                break
            k = ran[-1]
            cells += [f"{float(sel.h.values[k]):.3g} s", f"{att[k]:.1e}",
                      f"{float(sel.w_error.sel(metric='p99').values[k]):.1e}"]
        if cells:
            lines.append(f"| {m} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def headline(ds: xr.Dataset):
    """The numbers a run ends with: the fastest method per target (tennis, p99), the floor,
    each method's long-run energy behaviour.

    Parameters
    ----------
    ds : xarray.Dataset
        The work-precision Dataset (:func:`work_precision_dataset`).

    Returns
    -------
    rows : list of (str, str, str)
        Label, value and unit or note, for the printed summary.
    values : dict
        The same numbers by key (``fastest_1e-08``, ``floor_p99``, ``drift_slope_rk4``, ...).
    """
    rows, values = [], {}
    for target in TARGETS:
        _, ranked, stepping = fastest(ds, "tennis", target)
        if ranked:
            text = f"{ranked[0][1]} {format_time(ranked[0][0])}"
            if stepping and stepping[0] != ranked[0]:
                text += f"; integrator: {stepping[0][1]} {format_time(stepping[0][0])}"
            rows.append((f"fastest to p99 error {target:.0e} (tennis)", text, ""))
            values[f"fastest_{target:.0e}"] = ranked[0][1]
            if stepping:
                values[f"fastest_integrator_{target:.0e}"] = stepping[0][1]
    for metric in METRICS:
        floor = float(ds.floor.sel(workload="tennis", metric=metric))
        rows.append((f"conditioning floor, {metric} (tennis)", f"{floor:.2e}", "1"))
        values[f"floor_{metric}"] = floor
    for m in (str(x) for x in ds.method.values):
        slope = float(ds.drift_slope.sel({"method": m}))
        if np.isfinite(slope):
            size = float(np.nanmax(envelope(ds.drift_energy.sel({"method": m}).values)))
            rows.append((f"long-run energy error, {m}", f"{drift_kind(slope, size)} "
                         f"(slope {slope:.2f}, max {size:.1e})", ""))
            values[f"drift_slope_{m}"] = slope
    return rows, values


def markdown_report(ds: xr.Dataset) -> str:
    """The whole Markdown report: winners per workload, the floor, costs, invariants.

    Parameters
    ----------
    ds : xarray.Dataset
        The work-precision Dataset (:func:`work_precision_dataset`), with the attributes
        ``body``, ``tennis_workload``, ``stable_workload`` and ``long_workload`` (and optionally
        ``title`` and ``numba_num_threads``).

    Returns
    -------
    str
        The report, Markdown.
    """
    floor = ds.floor
    parts = [
        f"# {ds.attrs.get('title', 'Work-precision study')}",
        "",
        f"Body {ds.attrs['body']}. Times are kernel wall times for the whole ensemble "
        f"(compilation excluded) with {ds.attrs.get('numba_num_threads', '?')} threads; "
        "errors are relative errors of w at the end against the exact solution; dopri5 is "
        "the member loop's adaptive Dormand-Prince 5(4), each member with its own steps "
        "(time per member-step: per step tried); dop853 is scipy's solve_ivp on the ensemble "
        "as one vectorized system (wall time of the call).",
        "",
        f"## Tennis racket: {ds.attrs['tennis_workload']}",
        "",
        winner_table(ds, "tennis"),
        "",
        "Conditioning floor (one rounding of D2 = L^2 - 2 E I2 at each start, exact solution at "
        "the end): "
        + ", ".join(f"{m} {float(floor.sel(workload='tennis', metric=m)):.1e}" for m in METRICS)
        + ". It is the error of one rounding of the whole state (ulp of |m|) during the run: "
        "the compositions, which round the state at every stage, stall near it in the max; the "
        "members near the separatrix set the max, which is why the p99 and the median are the "
        "columns to read.",
        "",
        f"## Stable axis: {ds.attrs['stable_workload']}",
        "",
        winner_table(ds, "stable"),
        "",
        "Conditioning floor: "
        + ", ".join(f"{m} {float(floor.sel(workload='stable', metric=m)):.1e}" for m in METRICS)
        + ".",
        "",
        "## Cost per step (tennis workload)",
        "",
        cost_table(ds),
        "",
        "## Attitude (methods that carry it), at each method's finest step",
        "",
        attitude_table(ds),
        "",
        "Reference: scipy DOP853 at rtol = atol = 1e-13 on (w, q) (the exact attitude is not in "
        "the package), on the first members of each ensemble as one system; its own w error "
        "against the exact solution (p99 / max over those members) is "
        + ", ".join(
            f"{w} {float(ds.attitude_reference_error.sel(workload=w, metric='p99')):.0e} / "
            f"{float(ds.attitude_reference_error.sel(workload=w, metric='max')):.0e}"
            for w in WORKLOADS)
        + ": attitude errors below about that are not resolved.",
        "",
        f"## Invariants over the long horizon: {ds.attrs['long_workload']}",
        "",
        invariants_table(ds),
        "",
    ]
    return "\n".join(parts)


