"""The dispersion study: which uncertainty of a tossed body dominates its flip interval?

The ``[dispersions]`` section names what is uncertain, each a table of a distribution
(:func:`stability.uncertainty.distributions.distribution`): the moments (``moments`` alike, or
``I1``, ``I2``, ``I3``), the misalignment of the axes (``axes``, rad), the spin ``rate``, the
nudge ``epsilon`` and its ``direction``. The design of ``[sensitivity]``
(:mod:`stability.study.sensitivity`: a Saltelli design for Sobol' indices, trajectories for
Morris screening) gives each member its values; every member's flip interval and growth rate
come in closed form (:mod:`.measure`), the first ``[integration] members`` are integrated too
(chunk by chunk, resumable), and the indices of both outputs are written with the draws and
drawn.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ...core.body import RigidBody
from ...study.config import ConfigError, Key, Schema, Section
from ...study.kind import StudyKind, StudyRun, StudySummary
from ...study.outputs import output_files, write_outputs
from ..methods import method_names
from ...study.sections import (
    MEMBER_BYTES, check_memory, check_run, output_section, run_section,
    study_run_options, tossed_body_sections
)
from ...study.sensitivity import (
    analyse, analysis_figure, checked_dispersions, design_members, dispersions_section,
    dominant, draw_design, index_tables, sensitivity_section, summary_values
)
from ...uncertainty.dispersions import ALL_MOMENTS, AXES, MOMENTS
from ...util.threads import numba_threads
from .measure import TOSS, closed_form, dispersion_dataset, integrated, members, nominal

NAME = "dispersion"
FIGURES = ("indices",)
BODY, RATE = tossed_body_sections()
#: What a dispersion may name, and its unit.
_UNITS = {ALL_MOMENTS: "kg m2", **{m: "kg m2" for m in MOMENTS}, AXES: "rad",
          **dict(zip(TOSS, ("rad/s", "1", "rad")))}

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
        dispersions_section(_UNITS, truncate=True),
        sensitivity_section(),
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

QUICK = {"sensitivity": {"base": 256, "trajectories": 16, "resamples": 20},
         "integration": {"members": 4}}


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    return output_files(config, FIGURES)


def _dispersions(config: dict, source: str):
    """The checked dispersions of ``config``; a bad one is a one-line ConfigError."""
    body = RigidBody.preset(config["body"]["preset"])
    toss = config["toss"]
    return checked_dispersions(config, source, nominal(body.moments, toss["rate"],
                                                       toss["epsilon"], toss["direction"]))


def check(config: dict, source: str) -> dict:
    """Dispersions that are physical and known, a design ``[sensitivity]`` can draw, and the
    members within memory."""
    n = design_members(config, source, _dispersions(config, source))
    if config["integration"]["members"] > n:
        raise ConfigError(f"must be at most the {n} members of the design", source,
                          "integration", "members")
    check_memory(SCHEMA, config, source, n * (MEMBER_BYTES + 30 * 8),
                 [("sensitivity", "base"), ("sensitivity", "trajectories")],
                 f"the {n} members of the design", "use fewer base points or trajectories")
    check_run(config, source)
    return config


def run(config: dict, out_dir: Path, options: StudyRun) -> StudySummary:
    """Draw the design, compute every member's outputs, integrate the first, write the
    Dataset and the figure of the indices."""
    t_start = time.perf_counter()
    disp = _dispersions(config, "<study>")
    integ = config["integration"]
    design = draw_design(config, disp)
    draws = members(disp, design.unit)
    with numba_threads(options.run.threads):
        out = closed_form(draws)
        run_ds = None
        if integ["members"]:
            run_ds = integrated(draws, integ["members"], method=integ["method"],
                                steps_per_flip=integ["steps_per_flip"], flips=integ["flips"],
                                options=study_run_options(config, options))
    described = {"flip_interval": (out["flip_interval"], "s", "exact flip interval 2K/nu"),
                 "growth_rate": (out["growth_rate"], "s-1", "linear growth rate")}
    indices = analyse(config, design, described)
    ds = dispersion_dataset(disp, draws, out, run_ds, indices)
    ds, files = write_outputs(ds, config, out_dir, NAME, {"indices": analysis_figure},
                              overwrite=options.overwrite, history=options.history,
                              threads=options.run.threads,
                              attrs={"body": config["body"]["preset"]})
    return summarize(ds, out_dir, files, time.perf_counter() - t_start)


def summarize(ds, out_dir, files, wall) -> StudySummary:
    """The indices of each output, the dominant parameter, and the integrated check."""
    top = dominant(ds, "flip_interval")
    values = {"dominant": top, "wall_time": wall, "members": int(ds.member.size),
              "analysis": ds.attrs["analysis"], "indices": summary_values(ds)}
    rows = [(f"{ds.member.size} members of {ds.attrs['body']}: flip interval",
             "{:.3f} to {:.3f}".format(float(ds.flip_interval.min()),
                                       float(ds.flip_interval.max())), "s"),
            ("dominates the flip interval", top, "")]
    if "run_flip_interval" in ds:
        n = ds.run.size
        error = np.abs(ds.run_flip_interval.values / ds.flip_interval.values[:n] - 1.0)
        values["max_run_error"] = float(np.nanmax(error))
        rows.append((f"integrated ({n} members): max |run / exact - 1|",
                     f"{values['max_run_error']:.1e}", ""))
    rows.append(("wall time", f"{wall:.1f}", "s"))
    return StudySummary(NAME, Path(out_dir), files, rows, values, index_tables(ds))


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
