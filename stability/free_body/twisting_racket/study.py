"""The twisting-racket study: Montgomery's angle and the twist of rackets tossed about the middle axis.

An ensemble of rackets (the preset, and shapes scattered about it) is tossed about the middle axis
with nudges across it; :func:`stability.free_body.twisting_racket.measure.measure_twisting` runs
each member with its attitude and measures, from the run and from the exact motion, Montgomery's
angle over one period (against 2 E T / |L| - S) and the twist about the handle over the window
centred on a flip in which the handle turns once about L. Outputs: the Dataset, two figures
(:mod:`stability.free_body.twisting_racket.figures`) and the study's configuration.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ..attitude import attitude_methods
from ...core.body import RigidBody
from .figures import flip_figure, twist_figure
from .geometric_phase import wrap
from .measure import measure_twisting, tossed_members
from ...util.threads import numba_threads
from ...study.config import ConfigError, Key, Schema, Section
from ...study.kind import StudyKind, StudyRun, StudySummary
from ...study.outputs import output_files, write_outputs
from ...study.sections import (
    MEMBER_BYTES, check_memory, check_run, output_section, run_section, study_run_options,
    tossed_body_sections
)

BODY, RATE = tossed_body_sections()

NAME = "twisting_racket"
FIGURES = ("twist", "flip")

SCHEMA = Schema(
    top=(Key("title", "str", "The twisting tennis racket",
             "one line describing the run (the Dataset's title)"),),
    sections=(
        BODY,
        Section("toss", "the spin and its nudge", (
            RATE,
            Key("epsilon_min", "float", 1e-4, "smallest nudge across the axis, relative to W",
                minimum=0.0, exclusive_minimum=True),
            Key("epsilon_max", "float", 0.1, "largest nudge (log-uniform between the two)",
                minimum=0.0, exclusive_minimum=True, maximum=0.5),
        )),
        Section("ensemble", "the members", (
            Key("members", "int", 128, "number of tossed bodies", minimum=2),
            Key("shape_scatter", "float", 0.5, "the second half scatter I1 and I2 by exp(u), u "
                "uniform in [-s, s], keeping the flatness I3 / (I1 + I2)", minimum=0.0,
                maximum=2.0),
            Key("seed", "int", 1, "seed of the nudges and shapes", minimum=0),
        )),
        Section("integration", "the runs (each member over two periods of its motion)", (
            Key("method", "str", "lp8", "an integrator that carries the attitude"),
            Key("steps_per_period", "int", 2000, "steps per period T of each member",
                minimum=16),
            Key("save_every", "int", 4, "saved states every so many steps", minimum=1),
        )),
        Section("analysis", "what the run must show", (
            Key("claim", "float", 1e-8, "both angles: |run - independent route|", unit="rad",
                minimum=0.0, exclusive_minimum=True),
        )),
        run_section(),
        output_section(NAME, FIGURES),
    ),
)

QUICK = {"ensemble": {"members": 16}, "integration": {"steps_per_period": 1000}}


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    return output_files(config, FIGURES)


def check(config: dict, source: str) -> dict:
    """A nudge range in order; an attitude method; whole saved intervals per period."""

    toss = config["toss"]
    if not toss["epsilon_min"] <= toss["epsilon_max"]:
        raise ConfigError(f"must be at least epsilon_min ({toss['epsilon_min']:g}), got "
                          f"{toss['epsilon_max']:g}", source, "toss", "epsilon_max")
    method = config["integration"]["method"]
    if method not in attitude_methods():
        raise ConfigError(f"= {method!r} cannot carry the attitude; use one of "
                          f"{', '.join(attitude_methods())}", source, "integration", "method")
    integration = config["integration"]
    if integration["steps_per_period"] % integration["save_every"]:
        raise ConfigError(f"= {integration['save_every']} must divide steps_per_period "
                          f"({integration['steps_per_period']})", source, "integration",
                          "save_every")
    members = config["ensemble"]["members"]
    saved = 2 * integration["steps_per_period"] // integration["save_every"] + 1
    check_memory(SCHEMA, config, source, members * (MEMBER_BYTES + saved * 7 * 8 * 2),  # q and w kept
                 [("ensemble", "members"), ("integration", "steps_per_period")],
                 f"the attitudes of {members} members at {saved} times each",
                 "use fewer members or steps per period, or a larger save_every")
    check_run(config, source)
    return config


def run(config: dict, out_dir: Path, options: StudyRun) -> StudySummary:
    """Toss the ensemble, measure both angles both ways, save the Dataset and the figures.

    The bodies run chunk by chunk into the store of ``options.run`` (so that a stopped run
    continues with its ``resume``), on its ``scheduler`` (default: the file's ``[run]
    scheduler``)."""

    t_start = time.perf_counter()
    toss, ens, integration = config["toss"], config["ensemble"], config["integration"]
    body = RigidBody.preset(config["body"]["preset"])
    moments, w0, epsilon = tossed_members(
        body.moments, ens["members"], toss["rate"], (toss["epsilon_min"], toss["epsilon_max"]),
        ens["shape_scatter"], ens["seed"])
    with numba_threads(options.run.threads):
        ds = measure_twisting(moments, w0, method=integration["method"],
                              steps_per_period=integration["steps_per_period"],
                              save_every=integration["save_every"], epsilon=epsilon,
                              options=study_run_options(config, options))
    ds, files = write_outputs(ds, config, out_dir, NAME,
                              {"twist": twist_figure, "flip": flip_figure},
                              overwrite=options.overwrite, history=options.history,
                              threads=options.run.threads,
                              attrs={"claim": config["analysis"]["claim"], "body": body.name})
    return summarize(ds, out_dir, files, time.perf_counter() - t_start)


def summarize(ds, out_dir, files, wall) -> StudySummary:
    """Both angles' agreement, and the twist of the body itself."""

    ok = ds.status.values == 0
    same = np.isclose(ds.moments.values[:, 0], ds.moments.values[0, 0], rtol=1e-12)
    body_defect = ds.twist_defect.values[same & ok]
    values = {
        "claim": ds.attrs["claim"], "wall_time": wall,
        "max_montgomery_error": float(np.nanmax(ds.montgomery_error.values[ok])),
        "max_twist_error": float(np.nanmax(ds.twist_error.values[ok])),
        "max_montgomery_exact_vs_formula": float(np.nanmax(np.abs(
            wrap(ds.montgomery_exact - ds.montgomery_formula)))),
        "twist_member0": float(ds.twist_exact[0]),
        "twist_defect_member0": float(ds.twist_defect[0]),
        "twist_defect_body_range": [float(body_defect.min()), float(body_defect.max())],
        "twist_defect_range": [float(np.nanmin(ds.twist_defect)),
                               float(np.nanmax(ds.twist_defect))],
        "members_failed": int((~ok).sum()),
        # the window about the flip nearest T did not fit in the run of 2 T, or a root failed
        "members_without_twist": int((ok & ~np.isfinite(ds.twist_run.values)).sum()),
    }
    rows = [
        (f"{ds.member.size} members ({int(same.sum())} of the {ds.attrs['body']} itself), "
         f"{ds.attrs['method']}", f"{ds.attrs['steps_per_period']}", "steps per period"),
        ("Montgomery's angle: max |run - (2 E T/|L| - S)|",
         f"{values['max_montgomery_error']:.1e}", "rad"),
        ("  max |exact phi(T) - formula|", f"{values['max_montgomery_exact_vs_formula']:.1e}",
         "rad"),
        ("twist: max |run - exact|", f"{values['max_twist_error']:.1e}", "rad"),
        ("  the claim", f"{values['claim']:g}", "rad"),
        ("twist of member 0 (defect pi - |twist|)",
         f"{values['twist_member0']:+.6f} ({values['twist_defect_member0']:.4f})", "rad"),
        (f"defect, the {ds.attrs['body']} at every nudge",
         "{:.4f} to {:.4f}".format(*values["twist_defect_body_range"]), "rad"),
        ("defect, all shapes", "{:.4f} to {:.4f}".format(*values["twist_defect_range"]), "rad"),
        ("members not ok; ok members without a twist from the run",
         f"{values['members_failed']}; {values['members_without_twist']}", ""),
        ("wall time", f"{wall:.1f}", "s"),
    ]
    return StudySummary(NAME, Path(out_dir), files, rows, values)


STUDY = StudyKind(
    name=NAME,
    title="Montgomery's angle and the twist of a tossed racket",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    resumable=True,
)
