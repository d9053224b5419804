"""The sleeping-top study: a top spun upright is stable only above a critical spin.

A symmetric top (its mass, its moments about the centre of mass and the pivot distances l are
keys of the study file) is spun upright at each spin of a grid across the threshold
``w_c = 2 sqrt(A M g l) / C``; an ensemble of tops tilted by a tiny angle at random azimuths
runs at each (l, spin), and the measured growth rate of the tilt is set beside the analytic
``sqrt(4 A M g l - C^2 w3^2) / (2 A)`` (:mod:`stability.heavy_top.measure`). Outputs: the
Dataset, one figure (:func:`stability.heavy_top.figures.sleeping_top_figure`) and the study's
configuration.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from ...study.config import ConfigError, Key, Schema, Section
from ...study.kind import StudyKind, StudyRun, StudySummary
from ...study.outputs import output_files, write_outputs
from ...study.sections import (
    MEMBER_BYTES, check_memory, check_run, output_section, run_section, study_run_options
)
from .common import check_spins, symmetric_top, top_keys, top_methods
from ..figures import sleeping_top_figure
from ..measure import measure_sleeping_tops
from ...util.threads import numba_threads

NAME = "sleeping_top"
FIGURE = "sleeping_top"


SCHEMA = Schema(
    top=(Key("title", "str", "Stability of the sleeping top across the critical spin",
             "one line describing the run (the Dataset's title)"),),
    sections=(
        Section("top", "the symmetric top: a disk-like body on an axle over the pivot", top_keys(
            Key("lengths", "floats", [0.03, 0.04, 0.05],
                "distances l from the pivot to the centre of mass, one map each", unit="m",
                minimum=0.0, exclusive_minimum=True))),
        Section("spins", "the spins w3 of the map", (
            Key("min", "float", 0.0, "smallest spin", unit="rad s-1", minimum=0.0),
            Key("max", "float", 250.0, "largest spin", unit="rad s-1", minimum=0.0,
                exclusive_minimum=True),
            Key("count", "int", 26, "number of spins, evenly spaced", minimum=2),
        )),
        Section("ensemble", "the tilted members at each (l, spin)", (
            Key("members", "int", 64, "members per (l, spin)", minimum=1),
            Key("tilt", "float", 1e-9, "initial tilt from the vertical (linear regime)",
                unit="rad", minimum=0.0, exclusive_minimum=True, maximum=1e-3),
            Key("seed", "int", 0, "seed of the members' azimuths", minimum=0),
        )),
        Section("integration", "the integrator and its step", (
            Key("method", "str", "lp4", "a heavy-top method", choices=top_methods),
            Key("step_angle", "float", 0.02,
                "h times the fastest rate (spin, nutation, fall)", unit="rad", minimum=0.0,
                exclusive_minimum=True, maximum=0.5),
            Key("t_stable", "float", 2.0, "run time above the critical spin", unit="s",
                minimum=0.0, exclusive_minimum=True),
        )),
        Section("analysis", "the growth-rate fit over the linear phase", (
            Key("fit_above", "float", 1e3, "start each member's fit at this times its tilt",
                minimum=1.0, exclusive_minimum=True),
            Key("fit_below", "float", 1e-2, "end it at this sin(tilt)", minimum=0.0,
                exclusive_minimum=True, maximum=0.1),
            Key("claim", "float", 1e-3,
                "relative error the measured rate must stay within, away from the threshold",
                minimum=0.0, exclusive_minimum=True),
            Key("away", "float", 0.1,
                "'away from the threshold': analytic rate at least this fraction of its value "
                "at zero spin", minimum=0.0, maximum=1.0),
        )),
        run_section(),
        output_section(NAME, (FIGURE,)),
    ),
)

#: ``--quick``: fewer spins and members, one length.
QUICK = {"spins": {"count": 11}, "ensemble": {"members": 16}, "top": {"lengths": [0.04]}}


def _tops(config, source="<config>"):
    return [symmetric_top(config, length, source, name=f"l = {length:g} m")
            for length in config["top"]["lengths"]]


def check(config: dict, source: str) -> dict:
    """A symmetric, physical top; a non-empty spin range."""
    if not config["top"]["lengths"]:
        raise ConfigError("must list at least one distance", source, "top", "lengths")
    _tops(config, source)
    check_spins(config, source)
    members = len(config["top"]["lengths"]) * config["spins"]["count"]
    check_memory(SCHEMA, config, source, members * config["ensemble"]["members"] * MEMBER_BYTES,
                 [("ensemble", "members"), ("spins", "count")],
                 f"{members} (length, spin) cells x {config['ensemble']['members']} members",
                 "use fewer spins or members")
    check_run(config, source)
    return config


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    return output_files(config, (FIGURE,))


def run(config: dict, out_dir: Path, options: StudyRun) -> StudySummary:
    """Run the map, save the Dataset, draw the figure; the summary of measured against analytic.

    The tops run chunk by chunk into the store of ``options.run`` (so that a stopped run
    continues with its ``resume``), on its ``scheduler`` (default: the file's ``[run]
    scheduler``)."""

    t_start = time.perf_counter()
    tops = _tops(config)
    s, ens = config["spins"], config["ensemble"]
    integ, an = config["integration"], config["analysis"]
    spins = np.linspace(s["min"], s["max"], s["count"])
    with numba_threads(options.run.threads):
        ds = measure_sleeping_tops(
            tops, spins, members=ens["members"], tilt=ens["tilt"], method=integ["method"],
            step_angle=integ["step_angle"], t_stable=integ["t_stable"],
            low_factor=an["fit_above"], high_fraction=an["fit_below"], seed=ens["seed"],
            options=study_run_options(config, options))
    t = config["top"]
    ds, files = write_outputs(
        ds, config, out_dir, NAME, {FIGURE: lambda ds: sleeping_top_figure(ds, an["claim"])},
        overwrite=options.overwrite, history=options.history, threads=options.run.threads,
        attrs={"mass": t["mass"], "central_moments": np.array(t["central_moments"]),
               "gravity": t["gravity"], "claim": an["claim"], "away_fraction": an["away"]})
    return summarize(ds, out_dir, files, time.perf_counter() - t_start)


def summarize(ds, out_dir, files, wall) -> StudySummary:
    """Largest relative error away from the threshold, against the claim; the critical spins."""
    claim, away = ds.attrs["claim"], ds.attrs["away_fraction"]
    err = np.abs(ds.relative_error.values)
    counted = (ds.rate_fraction.values >= away) & np.isfinite(err)
    worst = float(err[counted].max()) if counted.any() else math.nan
    near = np.isfinite(err) & ~counted
    unstable = ds.growth_rate_analytic.values > 0
    wrong_side = int(np.sum(unstable != (ds.growth_rate_measured.values > 0)))
    crit = np.atleast_1d(ds.critical_spin.values)
    values = {"max_relative_error": worst, "claim": claim, "counted": int(counted.sum()),
              "max_relative_error_near": float(err[near].max()) if near.any() else math.nan,
              "wrong_side": wrong_side, "critical_spins": crit.tolist(), "wall_time": wall,
              "integration_time": float(ds.attrs["wall_time"]),
              "member_steps": int(ds.attrs["member_steps"])}
    rows = [("critical spins 2 sqrt(A M g l) / C",
             ", ".join(f"{w:.2f}" for w in crit), "rad s-1")]
    rows += [(f"max |relative error| of the growth rate ({values['counted']} cells, rate >= "
              f"{away:g} x its zero-spin value)", f"{worst:.1e}", ""),
             ("  the claim", f"{claim:g}", ""),
             ("  nearer the threshold (max)", f"{values['max_relative_error_near']:.1e}", "")
             if near.any() else
             (f"  nearer the threshold: no fitted cell below {away:g} x its zero-spin rate",
              "none", ""),
             ("cells on the wrong side of the threshold", f"{wrong_side}", ""),
             ("wall time (all) / integration", f"{wall:.1f} / {values['integration_time']:.1f}",
              "s"),
             ("member-steps", f"{values['member_steps']:.3g}", "")]
    return StudySummary(NAME, Path(out_dir), files, rows, values)


STUDY = StudyKind(
    name=NAME,
    title="a top spun upright: stable above its critical spin, growth rate below it",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    members_key=("ensemble", "members"),
    resumable=True,
)
