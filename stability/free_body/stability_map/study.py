"""The stability map: measured against analytic Omega^2 for every shape of body and every axis.

Every shape of the triangle of allowed moments (:mod:`stability.free_body.stability_map.shapes`)
spins about each of its three axes: an ensemble per (shape, axis, method) runs summaries-only for
``horizon / |Omega|`` and is measured against linear theory
(:mod:`stability.free_body.stability_map.measure`); the finite-order methods run again at ``h / 2``
on every ``bias_stride``-th shape for their own O(h^p) bias. Also: the flip interval against
epsilon for a few shapes (:mod:`stability.free_body.tennis_racket.flipsweep`) and time series on
the equal-moment edges and the sphere
(:func:`stability.free_body.stability_map.shapes.edge_series`).

Outputs: the Dataset, the resolved configuration and four figures
(:mod:`stability.free_body.stability_map.figures`).
"""

from __future__ import annotations

import math
import resource
import time
from pathlib import Path

import numpy as np

from ...analysis.fits import richardson_bias
from ...core.body import RigidBody
from . import measure as smap
from ..ensemble_plan import ensemble_memory
from ..schema import FTLE_IN_MAP
from . import figures as figures
from ..tennis_racket.flipsweep import flip_sweep
from ..methods import method_names, method_spec
from ...output.dataset import software_attrs
from ...output.store import ChunkStore
from .ftle_map import ftle_map
from .shapes import amplitude_levels, analytic_omega_squared, edge_series, horizons, shape_grid
from ...util import conventions as cv
from ...util.threads import numba_threads
from ...version import __version__
from ...ensemble.options import RunOptions
from ...study.config import UNSET, ConfigError, Key, Schema, Section
from ...study.kind import StudyKind, StudyRun, StudySummary
from ...study.outputs import output_files, write_outputs
from ...study.sections import check_memory, check_run, output_section, scheduler_key

NAME = "stability_map"

#: Figure file stems: the map, measured against analytic, flip intervals, the edges.
FIGURES = ("fig1_map", "fig2_measured_vs_analytic", "fig3_flip_interval", "fig4_edges")
#: Figure 5's stem, drawn where ``[ftle] run`` is set.
FTLE_FIGURE = "fig5_ftle_map"


SCHEMA = Schema(
    top=(Key("title", "str",
             "Stability map: Monte Carlo Omega^2 against linear theory over all body shapes",
             "one line describing the run (the Dataset's title)"),),
    sections=(
        Section("grid", "the shapes: a triangular grid over I1 <= I2 <= I3 = 1, I1 + I2 >= 1", (
            Key("divisions", "int", 32,
                "subdivisions n of the triangle: (n + 1)(n + 2) / 2 - 1 shapes", minimum=1),
        )),
        Section("spin", "the steady spin of every ensemble", (
            Key("rate", "float", 1.0, "spin rate W", unit="rad s-1", minimum=0.0,
                exclusive_minimum=True),
        )),
        Section("ensemble", "the perturbed members of each (shape, axis)", (
            Key("members", "int", 64, "members per ensemble", minimum=2),
            Key("epsilon", "float", 1e-7,
                "perturbation relative to the spin, random perpendicular direction",
                minimum=0.0, exclusive_minimum=True, maximum=1e-3),
            Key("seed", "int", 1, "seed of the random directions (numpy SeedSequence entropy)",
                minimum=0),
        )),
        Section("integration", "methods, steps and run lengths", (
            Key("methods", "strs", ["rk4", "lp2", "exact"], "integrators to run",
                choices=method_names),
            Key("h", "floats", [0.1, 0.05, 0.1], "step of each method, in the same order",
                unit="s", minimum=0.0, exclusive_minimum=True),
            Key("bias_check", "bool", True,
                "run each finite-order method again at h / 2 to measure its O(h^p) bias"),
            Key("bias_stride", "int", 8, "bias check on every n-th shape (1: all)", minimum=1),
            Key("horizon", "float", 70.0, "run length in units of 1 / |Omega|",
                minimum=0.0, exclusive_minimum=True),
            Key("t_max", "float", 2500.0, "longest run", unit="s",
                minimum=0.0, exclusive_minimum=True),
            Key("t_neutral", "float", 800.0, "run length where Omega^2 = 0 (equal moments)",
                unit="s", minimum=0.0, exclusive_minimum=True),
            Key("threads", "int", UNSET,
                "Numba threads for the map (default: all cores; the ensembles of a method run "
                "together, so every core is busy; stability run --threads overrides)",
                minimum=1),
        )),
        Section("analysis", "estimator window and the accuracy bar", (
            Key("window_low", "float", 300.0,
                "growth-rate window starts at this many times the initial amplitude",
                minimum=1.0, exclusive_minimum=True),
            Key("window_high", "float", 1e-2,
                "... and ends at this fraction of min(spin, saturation amplitude)",
                minimum=0.0, exclusive_minimum=True, maximum=0.5),
            Key("levels_per_decade", "int", 8, "passage-time amplitude levels per decade",
                minimum=2),
            Key("tolerance", "float", 1e-3,
                "accuracy bar: |measured - analytic| / |analytic| Omega^2",
                minimum=0.0, exclusive_minimum=True),
            Key("min_omega_squared", "float", 1e-3,
                "the bar applies where |Omega^2| / W^2 exceeds this", minimum=0.0),
        )),
        Section("flips", "flip interval against epsilon (figure 3)", (
            Key("shapes", "floats", [0.34375, 0.65625, 0.25, 0.75, 0.625, 0.875],
                "pairs I1, I2 (I3 = 1) with I1 < I2 < 1 and I1 + I2 >= 1"),
            Key("epsilons", "floats",
                [1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 1e-7, 1e-8,
                 1e-9],
                "perturbations along the smallest axis, relative to the spin",
                minimum=0.0, exclusive_minimum=True, maximum=0.5),
        )),
        Section("edges", "time series on the equal-moment edges and the sphere (figure 4)", (
            Key("epsilon", "float", 1e-3, "perturbation relative to the spin",
                minimum=0.0, exclusive_minimum=True, maximum=0.1),
            Key("t_end", "float", 400.0, "length of the time series", unit="s",
                minimum=0.0, exclusive_minimum=True),
        )),
        Section("ftle", "the map from tangents: finite-time Lyapunov exponents over a grid of "
                "inertia ratios (figure 5)", (
            Key("run", "bool", False, "draw it (the FTLE of each cell's state-transition "
                "matrix, beside the analytic rate)"),
            Key("axis", "int", 2, "the spin axis mapped", choices=(1, 2, 3)),
            Key("divisions", "int", 24, "cells per side of the grid of I1 / I3, I2 / I3",
                minimum=2),
            Key("horizon", "float", 10.0, "the FTLE's horizon T (in the linear phase: "
                "epsilon exp(rate T) << 1)", unit="s", minimum=0.0, exclusive_minimum=True),
            Key("epsilon", "float", 1e-8, "start off the axis, relative to the spin",
                minimum=0.0, maximum=1e-3),
            Key("members", "int", 2, "starts per cell, in random directions", minimum=1),
            Key("windows", "int", 10, "renormalisations over the horizon", minimum=1),
        )),
        Section("run", "where the batches of ensembles run",
                (scheduler_key("the batches of ensembles"),)),
        output_section(NAME, FIGURES + (FTLE_FIGURE,)),
    ),
)

#: ``--quick``: a coarse grid and small ensembles, for tests and a first look (seconds).
QUICK = {
    "grid": {"divisions": 4},
    "ensemble": {"members": 32},
    "integration": {"bias_stride": 2},
    "flips": {"epsilons": [1e-2, 1e-3, 1e-4, 1e-5, 1e-6]},
    "edges": {"t_end": 100.0},
}


def check(config: dict, source: str) -> dict:
    """Checks across keys: one step per method, valid flip shapes, a non-empty window."""
    integ, flips = config["integration"], config["flips"]
    if len(integ["h"]) != len(integ["methods"]):
        raise ConfigError(
            f"must give one step per method ({len(integ['methods'])}), got {len(integ['h'])}",
            source, "integration", "h",
        )
    if len(set(integ["methods"])) != len(integ["methods"]):
        raise ConfigError("must not name a method twice", source, "integration", "methods")
    pairs = flips["shapes"]
    if len(pairs) % 2:
        raise ConfigError("must hold pairs I1, I2 (an even count of numbers)", source,
                          "flips", "shapes")
    for I1, I2 in zip(pairs[::2], pairs[1::2]):
        if not (0.0 < I1 < I2 < 1.0 and I1 + I2 >= 1.0):
            raise ConfigError(
                f"pair ({I1:g}, {I2:g}) must satisfy 0 < I1 < I2 < 1 and I1 + I2 >= 1 (three "
                "distinct moments of a real body with I3 = 1)", source, "flips", "shapes",
            )
    eps, low = config["ensemble"]["epsilon"], config["analysis"]["window_low"]
    if low * eps >= config["analysis"]["window_high"]:
        raise ConfigError(
            f"must be > window_low * [ensemble] epsilon = {low * eps:g}: the growth-rate window "
            f"is empty, got {config['analysis']['window_high']}", source, "analysis",
            "window_high",
        )
    _check_memory(config, source)
    check_run(config, source)
    return config


def _check_memory(config: dict, source: str) -> None:
    """Refuse a map whose batch of ensembles would not fit in memory (before any allocation).

    The ensembles of one method and step run together: (shapes x 3 axes) ensembles of
    ``members`` members, each member holding its summaries (``ensemble_memory``) and about as
    much again while it is propagated.
    """

    n = config["grid"]["divisions"]
    members = config["ensemble"]["members"]
    n_shapes = (n + 1) * (n + 2) // 2 - 1
    n_levels = amplitude_levels(config["spin"]["rate"], config["ensemble"]["epsilon"],
                                config["analysis"]["levels_per_decade"]).size
    check_memory(SCHEMA, config, source,
                 3 * n_shapes * members * 2 * ensemble_memory(1, 0, n_levels),
                 [("ensemble", "members"), ("grid", "divisions")],
                 f"{members} members x {n_shapes} shapes x 3 axes (the ensembles of a method, "
                 "run together)", "lower [ensemble] members or [grid] divisions")


def figure_stems(config: dict) -> tuple:
    """The figures a run draws: figure 5 with ``[ftle] run``."""
    return FIGURES + ((FTLE_FIGURE,) if config["ftle"]["run"] else ())


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    return output_files(config, figure_stems(config))


# ----------------------------------------------------------------------------------- the run


def run(config: dict, out_dir: Path, options: StudyRun) -> StudySummary:
    """Run the map described by the resolved ``config``; write its files into ``out_dir``.

    Each finished batch of ensembles is kept in the store of ``options.run`` (the work folder),
    so that a stopped map continues with its ``resume``; the batches run on its ``scheduler``
    (default: the file's ``[run] scheduler``), one task each.
    """

    t_start = time.perf_counter()
    run = options.run
    threads = config["integration"].get("threads") if run.threads is None else run.threads
    with numba_threads(threads):
        ds, work = compute(config, progress=run.progress, work_dir=run.store, resume=run.resume,
                           scheduler=run.scheduler or config["run"]["scheduler"] or None)
    compute_time = time.perf_counter() - t_start
    draw = (figures.map_figure, figures.scatter_figure, figures.flip_interval_figure,
            figures.edges_figure, lambda ds: figures.ftle_map_figure(ftle_part(ds)))
    stages = {}
    ds, files = write_outputs(ds, config, out_dir, NAME,
                              dict(zip(figure_stems(config), draw)),
                              overwrite=options.overwrite, history=options.history,
                              threads=threads, timings=stages)
    wall = time.perf_counter() - t_start
    return summarize(ds, out_dir, files, wall, compute_time, work, stages)


def compute(config: dict, progress=None, work_dir=None, resume=False, scheduler=None):
    """All the runs of the map; returns the Dataset and the work done (member-steps, s).

    With ``work_dir``, each finished batch of ensembles is kept there (a
    :class:`~stability.output.store.ChunkStore` of one batch per chunk) and, with ``resume``, batches
    found there are not run again; with ``scheduler`` (needs ``work_dir``) the batches run as
    tasks of that dask.distributed cluster.

    Returns
    -------
    ds : xarray.Dataset
    work : dict
        ``member_steps`` and ``loop_time`` (s, in compiled code) summed over the map's runs.
    """
    spin = config["spin"]["rate"]
    ens, integ, ana = config["ensemble"], config["integration"], config["analysis"]
    members, eps, seed = ens["members"], ens["epsilon"], ens["seed"]
    moments, edges = shape_grid(config["grid"]["divisions"])
    n_shapes = moments.shape[0]
    bodies = [RigidBody(*I, name=f"shape {s}") for s, I in enumerate(moments)]
    omega2 = analytic_omega_squared(moments, spin)
    t_end = horizons(omega2, integ["horizon"], integ["t_max"], integ["t_neutral"])
    levels = amplitude_levels(spin, eps, ana["levels_per_decade"])
    specs = [method_spec(m) for m in integ["methods"]]
    runs = smap.map_runs(specs, integ["h"], n_shapes, integ["bias_check"], integ["bias_stride"])
    checkpoint = None
    if work_dir is not None:

        identity = {"config": {k: v for k, v in config.items()  # not where it runs
                               if k not in ("output", "title", "run")},
                    "software": f"stability {__version__}"}
        identity["config"]["integration"] = {
            k: v for k, v in config["integration"].items() if k != "threads"}
        checkpoint = ChunkStore(work_dir, identity, len(runs), 1, resume=resume,
                                unit="ensemble batches")
    try:
        out, half, work = smap.measure_map(
            bodies, omega2, t_end, levels, specs, runs, spin=spin, epsilon=eps,
            members=members, seed=seed, low_factor=ana["window_low"],
            high_fraction=ana["window_high"], progress=progress, checkpoint=checkpoint,
            scheduler=scheduler)
    finally:
        if checkpoint is not None:
            checkpoint.close()

    p = np.array([spec.order if not spec.is_exact else np.inf for spec in specs])
    with np.errstate(invalid="ignore", divide="ignore"):
        bias = richardson_bias(out["omega_squared_measured"],
                                   half["omega_squared_measured"],
                                   p[:, None, None]) / np.abs(omega2)[None]
    pairs = config["flips"]["shapes"]
    sweep = flip_sweep(np.array([(I1, I2, 1.0) for I1, I2 in zip(pairs[::2], pairs[1::2])]),
                       config["flips"]["epsilons"], spin, [spec.name for spec in specs],
                       integ["h"])
    edge = edge_series(spin, config["edges"]["epsilon"], config["edges"]["t_end"],
                       specs[0].name, integ["h"][0])
    attrs = {
        "title": config["title"], **software_attrs(),
        "references": "literature notes 1.4-1.5, 2.1-2.3; course-notes ERRATA 2-3",
        "spin": spin, "spin_units": cv.UNITS_ANGULAR_VELOCITY, "epsilon": eps,
        "members": members, "seed_entropy": str(seed), "horizon": integ["horizon"],
        "t_max": integ["t_max"], "t_neutral": integ["t_neutral"],
        "bias_stride": integ["bias_stride"],
        "window": f"[{ana['window_low']:g} x initial amplitude, {ana['window_high']:g} x "
                  "min(spin, saturation amplitude))",
        "tolerance": ana["tolerance"], "min_omega_squared": ana["min_omega_squared"],
        "edge_method": edge["method"], "edge_h": edge["h"],
        "edge_epsilon": config["edges"]["epsilon"],
    }
    ds = smap.map_dataset(specs, integ["h"], spin, moments, edges, omega2, t_end, levels, out,
                          half, bias, sweep, edge, attrs)
    if config["ftle"]["run"]:
        ds = with_ftle(ds, config, work_dir, resume, scheduler, progress)
    return ds, work


def with_ftle(ds, config: dict, work_dir, resume: bool, scheduler, progress):
    """The map with the FTLE map of ``[ftle]`` (:func:`~.ftle_map.ftle_map`, resumable in
    ``work_dir/ftle``) merged in, its names as :data:`~stability.free_body.schema.FTLE_IN_MAP`
    gives them and its settings as ``ftle_*`` attributes."""
    f = config["ftle"]
    options = RunOptions(store=None if work_dir is None else Path(work_dir) / "ftle",
                         resume=resume, scheduler=scheduler if work_dir is not None else None,
                         progress=progress)
    t0 = time.perf_counter()
    fm = ftle_map(f["divisions"], axis=f["axis"], spin=config["spin"]["rate"],
                  horizon=f["horizon"], epsilon=f["epsilon"], members=f["members"],
                  windows=f["windows"], seed=config["ensemble"]["seed"], options=options)
    fm = fm.rename({old: new for old, new in FTLE_IN_MAP.items() if old != new})
    out = ds.merge(fm, combine_attrs="drop_conflicts")
    out.attrs = {**ds.attrs, **{f"ftle_{key}": fm.attrs[key] for key in FTLE_ATTRS},
                 "ftle_run_time": time.perf_counter() - t0}
    return out


def ftle_rows(ds) -> tuple[list, dict]:
    """The FTLE map against linear theory: about the middle axis the FTLE lies in
    ``[sigma, sigma + log((1 + rho) / 2) / T]``, about a stable one in ``[0, log(rho) / T]``
    (:mod:`.ftle_map`); how many cells do, the largest departure from sigma, the cost."""
    part = ftle_part(ds)
    axis, horizon = int(part.attrs["axis"]), float(part.attrs["horizon"])
    inside = part.physical.values == 1
    ftle, rate = part.ftle.values[inside], part.growth_rate_analytic.values[inside]
    rho = part.eigenvector_aspect.values[inside]
    top = np.log((1.0 + rho) / 2.0) if axis == 2 else np.log(rho)
    slack = 1e-9 * np.maximum(np.abs(rate), 1.0)
    within = (ftle >= rate - slack) & (ftle <= rate + top / horizon + slack)
    gap = float(np.max(np.abs(ftle - rate)))
    rows = [(f"FTLE map, axis {axis}, T = {horizon:g} s: cells within the linear bound",
             f"{int(within.sum())} of {within.size}", ""),
            ("  largest |FTLE - sqrt(-Omega^2)|", f"{gap:.2e}", "s-1"),
            ("  its run", f"{float(ds.attrs['ftle_run_time']):.1f}", "s")]
    return rows, {"ftle_cells": int(within.size), "ftle_cells_within": int(within.sum()),
                  "ftle_largest_gap": gap, "ftle_run_time": float(ds.attrs["ftle_run_time"])}


#: The FTLE map's settings the study's Dataset keeps (as ``ftle_<name>``).
FTLE_ATTRS = ("axis", "spin", "horizon", "epsilon", "members", "step", "windows", "method")


def ftle_part(ds):
    """The FTLE map inside a study's Dataset, as :func:`~.ftle_map.ftle_map` returns it (what
    :func:`~.figures.ftle_map_figure` draws)."""
    names = [new for new in FTLE_IN_MAP.values() if new in ds.variables]
    part = ds[names].rename({new: old for old, new in FTLE_IN_MAP.items() if old != new})
    part.attrs = {key: ds.attrs[f"ftle_{key}"] for key in FTLE_ATTRS}
    return part


def summarize(ds, out_dir, files, wall, compute_time, work, stages=None) -> StudySummary:
    """The map's headline (:func:`stability.free_body.stability_map.measure.headline`), then
    where its time went (``stages``: ``figures`` and ``dataset`` as
    :func:`~stability.study.outputs.write_outputs` times them)."""
    rows, values = smap.headline(ds)
    if "ftle" in ds:
        more, extra = ftle_rows(ds)
        rows += more
        values.update(extra)
    stages = stages or {}
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # KiB on Linux
    rate = work["member_steps"] / work["loop_time"] if work["loop_time"] > 0 else math.nan
    rows.append(("wall time (all, with compile, figures and files)", f"{wall:.1f}", "s"))
    rows.append(("  of which the runs", f"{compute_time:.1f}", "s"))
    rows.append(("    integration (member loops, summed) / the rest of the runs",
                 f"{work['loop_time']:.1f} / {max(0.0, compute_time - work['loop_time']):.1f}",
                 "s"))
    rows.append(("  figures / the Dataset's write after them",
                 f"{stages.get('figures', 0.0):.1f} / {stages.get('dataset', 0.0):.1f}", "s"))
    rows.append(("member-steps in the map, per second in compiled code",
                 f"{work['member_steps']:.3g}, {rate:.3g}", "s-1"))
    rows.append(("peak memory (resident set, getrusage)", f"{peak:.0f}", "MiB"))
    values.update({"wall_time": wall, "compute_time": compute_time, "peak_memory_mib": peak,
                   "member_steps": work["member_steps"], "integration_time": work["loop_time"],
                   "figures_time": stages.get("figures", 0.0),
                   "write_time": stages.get("dataset", 0.0)})
    return StudySummary(NAME, Path(out_dir), files, rows, values)


STUDY = StudyKind(
    name=NAME,
    title="measured against analytic Omega^2 for every shape of body and every axis",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    members_key=("ensemble", "members"),
    resumable=True,
)
