"""The dispersion study: which uncertainty of a tossed body dominates its flip interval?

The ``[dispersions]`` section names what is uncertain, each a table of a distribution
(:func:`stability.uncertainty.distributions.distribution`): the moments (``moments`` alike, or
``I1``, ``I2``, ``I3``), the misalignment of the axes (``axes``, rad), the spin ``rate``, the
nudge ``epsilon`` and its ``direction``. A Saltelli design of ``[sensitivity] base`` points
(:func:`stability.uncertainty.sobol.sobol_design`) gives each member its values; every member's
flip interval and growth rate come in closed form (:mod:`.measure`), the first
``[integration] members`` are integrated too (chunk by chunk, resumable), and the Sobol'
indices of both outputs (:func:`stability.uncertainty.sobol.sobol_indices`) are written with
the draws and drawn as bars (:func:`stability.uncertainty.figures.indices_figure`).
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ...core.body import RigidBody
from ...study.config import UNSET, ConfigError, Key, Schema, Section
from ...study.kind import StudyKind, StudySummary, SummaryTable
from ...study.outputs import output_files, write_outputs
from ...study.sections import (
    MEMBER_BYTES, check_memory, check_run, method_names, output_section, run_section,
    study_run_options, tossed_body_sections
)
from ...uncertainty.dispersions import ALL_MOMENTS, AXES, MOMENTS, dispersions
from ...uncertainty.figures import indices_figure
from ...uncertainty.sobol import sobol_design, sobol_indices
from ...util.threads import numba_threads
from .measure import TOSS, closed_form, dispersion_dataset, integrated, members, nominal

NAME = "dispersion"
FIGURES = ("indices",)
BODY, RATE = tossed_body_sections()
_NAMES = (ALL_MOMENTS, *MOMENTS, AXES, *TOSS)
_UNITS = {"I1": "kg m2", "I2": "kg m2", "I3": "kg m2", ALL_MOMENTS: "kg m2", AXES: "rad",
          "rate": "rad/s", "epsilon": "1", "direction": "rad"}

SCHEMA = Schema(
    top=(Key("title", "str", "A dispersed tossed body: which uncertainty dominates its flip?",
             "one line describing the run (the Dataset's title)"),),
    sections=(
        BODY,
        Section("toss", "the nominal toss about the middle axis", (
            RATE,
            Key("epsilon", "float", 1e-3, "nudge across the axis, relative to W", minimum=0.0,
                exclusive_minimum=True, maximum=0.5),
            Key("direction", "float", 0.0, "direction of the nudge from the smallest-moment "
                "axis towards the largest", unit="rad"),
        )),
        Section("dispersions", "what is uncertain: a table {distribution = ..., ...} each", (
            *(Key(name, "table", UNSET, f"dispersion of {name} (in {_UNITS[name]})")
              for name in _NAMES),
            Key("truncate", "bool", False, "truncate the largest moment to the triangle "
                "inequality where the moments' dispersions could break it"),
        )),
        Section("sensitivity", "the Saltelli design and the Sobol' indices", (
            Key("base", "int", 4096, "base points N (a power of 2); N (d + 2) members",
                minimum=2),
            Key("seed", "int", 1, "seed of the scrambled Sobol' design", minimum=0),
            Key("resamples", "int", 100, "bootstrap resamples of the indices", minimum=10),
            Key("conf_level", "float", 0.95, "level of the confidence intervals", minimum=0.5,
                maximum=0.999),
        )),
        Section("integration", "the first members integrated, checking the closed form", (
            Key("members", "int", 16, "members integrated (0: none)", minimum=0),
            Key("method", "str", "lp4", "integrator", choices=method_names),
            Key("steps_per_flip", "int", 400, "steps per exact flip interval", minimum=16),
            Key("flips", "int", 3, "flip intervals run (and a half)", minimum=2),
        )),
        run_section(),
        output_section(NAME, FIGURES),
    ),
)

QUICK = {"sensitivity": {"base": 256, "resamples": 20}, "integration": {"members": 4}}


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    return output_files(config, FIGURES)


def _dispersions(config: dict, source: str):
    """The checked dispersions of ``config``; a bad one is a one-line ConfigError."""
    body = RigidBody.preset(config["body"]["preset"])
    toss = config["toss"]
    spec = {k: v for k, v in config["dispersions"].items() if k != "truncate"}
    try:
        return dispersions(spec, nominal(body.moments, toss["rate"], toss["epsilon"],
                                         toss["direction"]),
                           truncate=config["dispersions"]["truncate"])
    except ValueError as exc:
        key = next((k for k in spec if repr(k) in str(exc)), "")
        raise ConfigError(str(exc), source, "dispersions", key if key else "") from None


def check(config: dict, source: str) -> dict:
    """Dispersions that are physical and known, a power of 2 of base points, and the members
    within memory."""
    _dispersions(config, source)
    base = config["sensitivity"]["base"]
    if base & (base - 1):
        raise ConfigError(f"must be a power of 2 (the Sobol' sequence's balance), got {base}",
                          source, "sensitivity", "base")
    d = len(_dispersions(config, source).names)
    n = base * (d + 2)
    if config["integration"]["members"] > n:
        raise ConfigError(f"must be at most the {n} members of the design", source,
                          "integration", "members")
    check_memory(SCHEMA, config, source, n * (MEMBER_BYTES + 30 * 8),
                 [("sensitivity", "base")], f"the {n} members of the design",
                 "use fewer base points")
    check_run(config, source)
    return config


def run(config: dict, out_dir: Path, *, overwrite=False, threads=None, progress=None,
        history=None, work=None, resume=False, scheduler=None) -> StudySummary:
    """Draw the design, compute every member's outputs, integrate the first, write the
    Dataset and the figure of the indices."""
    t_start = time.perf_counter()
    disp = _dispersions(config, "<study>")
    sens, integ = config["sensitivity"], config["integration"]
    design = sobol_design(disp, sens["base"], sens["seed"])
    draws = members(disp, design.unit)
    with numba_threads(threads):
        out = closed_form(draws)
        run_ds = None
        if integ["members"]:
            run_ds = integrated(draws, integ["members"], method=integ["method"],
                                steps_per_flip=integ["steps_per_flip"], flips=integ["flips"],
                                options=study_run_options(config, work, resume, scheduler,
                                                          threads, progress))
    described = {"flip_interval": (out["flip_interval"], "s", "exact flip interval 2K/nu"),
                 "growth_rate": (out["growth_rate"], "s-1", "linear growth rate")}
    indices = sobol_indices(design, described, resamples=sens["resamples"],
                            conf_level=sens["conf_level"], seed=sens["seed"])
    ds = dispersion_dataset(disp, draws, out, run_ds, indices)
    ds, files = write_outputs(ds, config, out_dir, NAME, {"indices": indices_figure},
                              overwrite=overwrite, history=history, threads=threads,
                              attrs={"body": config["body"]["preset"]})
    return summarize(ds, out_dir, files, time.perf_counter() - t_start)


def summarize(ds, out_dir, files, wall) -> StudySummary:
    """The indices of each output, the dominant parameter, and the integrated check."""
    flip = ds.sel(output="flip_interval")
    dominant = str(flip.parameter.values[int(np.argmax(flip.total.values))])
    values = {"dominant": dominant, "wall_time": wall, "members": int(ds.member.size),
              "indices": {str(o): {str(p): (float(ds.first_order.sel(output=o, parameter=p)),
                                            float(ds.total.sel(output=o, parameter=p)))
                                   for p in ds.parameter.values} for o in ds.output.values}}
    rows = [(f"{ds.member.size} members of {ds.attrs['body']}: flip interval",
             "{:.3f} to {:.3f}".format(float(ds.flip_interval.min()),
                                       float(ds.flip_interval.max())), "s"),
            ("dominates the flip interval (largest total index)", dominant, "")]
    if "run_flip_interval" in ds:
        n = ds.run.size
        error = np.abs(ds.run_flip_interval.values / ds.flip_interval.values[:n] - 1.0)
        values["max_run_error"] = float(np.nanmax(error))
        rows.append((f"integrated ({n} members): max |run / exact - 1|",
                     f"{values['max_run_error']:.1e}", ""))
    rows.append(("wall time", f"{wall:.1f}", "s"))
    tables = [SummaryTable(f"Sobol' indices of the {o.replace('_', ' ')} "
                           f"({float(ds.attrs['conf_level']):g} intervals)",
                           [("parameter", ""), ("S_i", ""), ("+-", ""), ("S_Ti", ""), ("+-", "")],
                           [(str(p), *(f"{float(ds[v].sel(output=o, parameter=p)):.3f}"
                                       for v in ("first_order", "first_order_conf", "total",
                                                 "total_conf")))
                            for p in ds.parameter.values])
              for o in ds.output.values]
    return StudySummary(NAME, Path(out_dir), files, rows, values, tables)


STUDY = StudyKind(
    name=NAME,
    title="Which uncertainty of a tossed body dominates its flip interval (Sobol' indices)",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    resumable=True,
)
