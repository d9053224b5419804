"""Figures of the speed-against-error study (``stability run studies/work_precision.toml``).

1. :func:`work_precision_figure`: relative error of w at the end against the ensemble's wall
   time, log-log, one line per method (scipy's DOP853 included), a column per workload and a
   row per statistic over members (max, p99, median), with the conditioning floor drawn.
2. :func:`invariant_drift_figure`: energy and |L| error against time over the long horizon,
   log-log, one line per method, with t^(1/2) and t^1 guides: bounded for Poisson splittings,
   linear for RK4, a round-off random walk for methods that keep the energy.

Each takes the study's Dataset
(:func:`stability.free_body.work_precision.measure.work_precision_dataset`) and returns a
``matplotlib.figure.Figure`` whose every axis is labelled with its unit.
"""

from __future__ import annotations

import numpy as np

from .drift import envelope
from .measure import ADAPTIVE
from ..methods import METHODS
from ...plotting.style import EXACT_COLOR, label, new_figure, styled
from ...util import conventions as cv

#: Line style per method family, so families read at a glance; colours cycle within a family.
_FAMILY_STYLE = {
    "Runge-Kutta": "-",
    "Lie-Poisson splitting": "--",
    "exact flow": ":",
}
_MARKERS = "osD^v<>ph*Xd"
SCIPY_COLOR = "0.35"


def _method_styles(ds):
    """(color, linestyle, marker) per method name, stable across figures."""
    import matplotlib as mpl


    tab20 = mpl.colormaps["tab20"].colors
    # tab20's dark shades, then its light ones, without its greys (SciPy's reference is grey)
    colors = [tab20[i] for i in (*range(0, 20, 2), *range(1, 20, 2)) if i not in (14, 15)]
    styles = {}
    for k, m in enumerate(str(x) for x in ds.method.values):
        spec = METHODS.get(m)
        if m == ADAPTIVE:  # the member loop's adaptive steps: black, dashed, over the others
            styles[m] = ("k", "--", "P")
            continue
        if spec is None:  # scipy
            styles[m] = (SCIPY_COLOR, "-.", "x")
            continue
        dash = _FAMILY_STYLE.get(spec.family, "-." if spec.implicit else "-")
        styles[m] = (colors[k % len(colors)], dash, _MARKERS[k % len(_MARKERS)])
    return styles


@styled
def work_precision_figure(ds, metrics=("max", "p99", "median")):
    """Figure 1: error at the end against wall time, log-log; a column per workload, a row per
    statistic over members.

    The conditioning floor (one rounding of D2 at each start) is drawn in every panel: on the
    tennis ensemble the max of the compositions stalls near it while the p99 and the median go
    on falling.

    Parameters
    ----------
    ds : xarray.Dataset
        The study's Dataset (``w_error``, ``wall_time``, ``failed``, ``floor``).
    metrics : sequence of str
        Statistics over members, one row each: ``"max"``, ``"p99"``, ``"median"``.
    """
    styles = _method_styles(ds)
    workloads = [str(w) for w in ds.workload.values]
    metrics = list(metrics)
    fig = new_figure(5.0 * len(workloads) + 1.8, 3.4 * len(metrics) + 0.6)
    axes = np.array(fig.subplots(len(metrics), len(workloads), sharex="col", sharey="row",
                                 squeeze=False))
    for row, metric in enumerate(metrics):
        for col, workload in enumerate(workloads):
            ax = axes[row, col]
            for m in (str(x) for x in ds.method.values):
                sel = ds.sel({"workload": workload, "method": m})
                err = sel.w_error.sel(metric=metric).values
                wall = sel.wall_time.values
                ok = np.isfinite(err) & np.isfinite(wall) & (sel.failed.values == 0) & (err > 0)
                if not ok.any():
                    continue
                color, dash, marker = styles[m]
                ax.plot(wall[ok], err[ok], dash, marker=marker, ms=4, lw=1.2, color=color,
                        label=m)  # in sweep order: h (or rtol) decreasing
            floor = float(ds.floor.sel(workload=workload, metric=metric))
            if np.isfinite(floor) and floor > 0:
                ax.axhline(floor, color=EXACT_COLOR, lw=0.8, ls=(0, (1, 2)),
                           label="conditioning floor (one rounding of D2 at the start)")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_xlabel(label("kernel wall time for the ensemble", cv.UNITS_TIME))
            ax.set_ylabel(label(f"w error, {metric} over members", cv.UNITS_DIMENSIONLESS))
            members = ds.attrs.get(f"{workload}_workload", "").split(" members")[0]
            ax.set_title(f"{workload} ({members} members): {metric}", loc="left")
    seen = {}
    for ax in axes.ravel():
        for h, lab in zip(*ax.get_legend_handles_labels()):
            seen.setdefault(lab, h)
    fig.legend(list(seen.values()), list(seen.keys()), loc="outside right center")
    fig.suptitle(f"Relative error of w at the end against kernel time, body I = "
                 f"({ds.attrs.get('I1')}, {ds.attrs.get('I2')}, {ds.attrs.get('I3')}) kg m²")
    return fig


@styled
def invariant_drift_figure(ds):
    """Figure 2: energy and |L| errors against time over the long horizon, log-log.

    The error reached so far (running maximum over [0, t] of the RMS over the long run's
    members, so a bounded oscillation shows as a plateau); zeros (exact to the last bit) are
    left out of the log plot. Guides: t^(1/2) (round-off random walk, Brouwer's law) and t^1
    (linear drift).
    """
    styles = _method_styles(ds)
    t = ds.long_time.values
    fig = new_figure(11.0, 4.8)
    axes = fig.subplots(1, 2, sharex=True)
    for ax, name, what in ((axes[0], "drift_energy", "energy"),
                           (axes[1], "drift_momentum", "|L|")):
        for m in (str(x) for x in ds.method.values):
            err = envelope(ds[name].sel({"method": m}).values)
            ok = np.isfinite(err) & (err > 0)
            if not ok.any():
                continue
            color, dash, _ = styles[m]
            ax.plot(t[ok], err[ok], dash, lw=1.1, color=color, label=m)
        _guides(ax, t)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(label("time", cv.UNITS_TIME))
        ax.set_ylabel(label(f"relative {what} error so far", cv.UNITS_DIMENSIONLESS))
        ax.set_title(f"{what}: max over [0, t] of the RMS over members", loc="left")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside right center")
    fig.suptitle(f"Invariants over the long horizon: {ds.attrs.get('long_workload', '')}")
    return fig


def _guides(ax, t):
    """Dotted t^(1/2) and t^1 lines anchored at 1e-16 at the first time."""
    if t.size < 2:
        return
    t0 = t[0]
    ax.plot(t, 1e-16 * np.sqrt(t / t0), color="0.5", lw=0.8, ls=":", label="∝ t^(1/2)")
    ax.plot(t, 1e-16 * (t / t0), color="0.5", lw=0.8, ls=(0, (5, 5)), label="∝ t")
