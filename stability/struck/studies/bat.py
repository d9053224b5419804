"""The bat study: the centre of percussion and the sweet zone from an ensemble of strikes.

A baseball bat (tapered, from cylinders and cones) or the tennis-racket preset is struck across
its axis at a grid of points, with the hands at each of a list of pivots, held (a hinge) and
free; :func:`stability.struck.measure.measure_strikes` integrates each strike through its contact
(scene ``struck_body``) and finds the centre of percussion (zero reaction at the held hands,
the free body's hands at rest) and the sweet zone (reaction below ``sting`` J) from the runs,
beside ``q = I_P / (M d)``. Outputs: the Dataset, the figure
(:func:`stability.struck.figures.bat_figure`) and the study's configuration.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ...study.config import ConfigError, Key, Schema, Section
from ...study.kind import StudyKind, StudyRun, StudySummary
from ...study.outputs import output_files, write_outputs
from ...study.sections import (
    MEMBER_BYTES, check_memory, check_run, output_section, run_section, study_run_options
)
from ...util.threads import numba_threads
from ..figures import bat_figure
from ..measure import measure_strikes
from ..model import baseball_bat, check_pivot, tennis_racket

NAME = "bat"
FIGURE = "bat"
BODY_CHOICES = ("baseball_bat", "tennis_racket")

SCHEMA = Schema(
    top=(Key("title", "str", "The centre of percussion of a baseball bat",
             "one line describing the run (the Dataset's title)"),),
    sections=(
        Section("body", "what is struck", (
            Key("kind", "str", "baseball_bat", "a 33-inch tapered wooden bat, or the "
                "tennis-racket preset", choices=BODY_CHOICES),
            Key("mass", "float", 0.850, "mass of the bat (the racket preset keeps its own)",
                unit="kg", minimum=0.0, exclusive_minimum=True),
        )),
        Section("hands", "where the body is held", (
            Key("pivots", "floats", [0.10, 0.1524, 0.20], "pivots (the hands), from the end "
                "held", unit="m", minimum=0.0),
        )),
        Section("strikes", "the strike points, evenly spaced", (
            Key("first", "float", 0.30, "first strike point, from the end held", unit="m",
                minimum=0.0),
            Key("last", "float", None, "last strike point (default: the tip)", unit="m",
                minimum=0.0),
            Key("count", "int", 121, "number of strike points", minimum=3),
        )),
        Section("hit", "the ball's push", (
            Key("impulse", "float", 12.0, "impulse J of the hit", unit="N s", minimum=0.0,
                exclusive_minimum=True),
            Key("contact_time", "float", 7e-4, "duration of the half-sine contact force",
                unit="s", minimum=0.0, exclusive_minimum=True),
            Key("steps_per_contact", "int", 64, "RK4 steps over the contact", minimum=4),
        )),
        Section("analysis", "what the run must show", (
            Key("sting", "float", 0.1, "the sweet zone: reaction at the hands at most this "
                "fraction of J", minimum=0.0, exclusive_minimum=True, maximum=1.0),
            Key("claim", "float", 1e-9, "held: |measured - formula| centre of percussion",
                unit="m", minimum=0.0, exclusive_minimum=True),
        )),
        run_section(),
        output_section(NAME, (FIGURE,)),
    ),
)

QUICK = {"strikes": {"count": 41}, "hit": {"steps_per_contact": 16}}


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    return output_files(config, (FIGURE,))


def _body(config):

    b = config["body"]
    return baseball_bat(b["mass"]) if b["kind"] == "baseball_bat" else tennis_racket()


def _last_strike(config, body) -> float:
    """``[strikes] last``, the tip when unset."""
    last = config["strikes"].get("last")
    return body.length if last is None else last


def check(config: dict, source: str) -> dict:
    """Pivots on the body and off its centre of mass; strike points on the body."""

    body = _body(config)
    if not config["hands"]["pivots"]:
        raise ConfigError("must list at least one pivot", source, "hands", "pivots")
    for pivot in config["hands"]["pivots"]:
        try:
            check_pivot(body, pivot)
        except ValueError as exc:
            raise ConfigError(f"= {pivot:g}: {exc}", source, "hands", "pivots") from None
    s = config["strikes"]
    last = _last_strike(config, body)
    for key, value in (("first", s["first"]), ("last", last)):
        if value > body.length:
            raise ConfigError(f"= {value:g} m is off the {body.name} (0 to {body.length:g} m "
                              "from the end held)", source, "strikes", key)
    if not s["first"] < last:
        raise ConfigError(f"must be beyond first ({s['first']:g} m), got {last:g} m", source,
                          "strikes", "last")
    members = 2 * len(config["hands"]["pivots"]) * s["count"]  # held and free, per pivot
    check_memory(SCHEMA, config, source,
                 members * 2 * MEMBER_BYTES,  # parameters as arrays in a list
                 [("strikes", "count")], f"{members} strikes (held and free, per pivot)",
                 "use fewer strike points")
    check_run(config, source)
    return config


def run(config: dict, out_dir: Path, options: StudyRun) -> StudySummary:
    """Run the strikes, save the Dataset, draw the bat; the centre of percussion measured.

    The strikes run chunk by chunk into the store of ``options.run`` (so that a stopped run
    continues with its ``resume``), on its ``scheduler`` (default: the file's ``[run]
    scheduler``)."""

    t_start = time.perf_counter()
    body = _body(config)
    s, hit, analysis = config["strikes"], config["hit"], config["analysis"]
    last = _last_strike(config, body)
    with numba_threads(options.run.threads):
        ds = measure_strikes(body, config["hands"]["pivots"],
                             np.linspace(s["first"], last, s["count"]), hit["impulse"],
                             hit["contact_time"], hit["steps_per_contact"],
                             sting=analysis["sting"],
                             options=study_run_options(config, options))
    ds, files = write_outputs(ds, config, out_dir, NAME, {FIGURE: bat_figure},
                              overwrite=options.overwrite, history=options.history,
                              threads=options.run.threads,
                              attrs={"claim": analysis["claim"]})
    return summarize(ds, out_dir, files, time.perf_counter() - t_start)


def summarize(ds, out_dir, files, wall) -> StudySummary:
    """Centre of percussion and sweet zone per pivot, run against formula."""
    q = ds.percussion_centre_formula.values
    held = ds.percussion_centre_measured.sel(hold="held").values
    free = ds.percussion_centre_measured.sel(hold="free").values
    zone = ds.sweet_zone_measured.values
    values = {"claim": ds.attrs["claim"], "wall_time": wall,
              "percussion_centre_formula": q.tolist(),
              "percussion_centre_held": held.tolist(), "percussion_centre_free": free.tolist(),
              "max_error_held": float(np.nanmax(np.abs(held - q))),
              "max_error_free": float(np.nanmax(np.abs(free - q))),
              "max_error_sweet_zone": float(np.nanmax(np.abs(zone - ds.sweet_zone_formula))),
              "members_failed": int((ds.status != 0).sum())}
    rows = [(f"{ds.attrs['body']}: mass, centre of mass, I_cm",
             f"{ds.attrs['mass']:.3f}, {ds.attrs['centre_of_mass']:.4f}, "
             f"{ds.attrs['inertia_cm']:.4f}", "kg, m, kg m2")]
    for i, pivot in enumerate(ds.pivot.values):
        rows.append((f"hands at {pivot:.4f} m: centre of percussion I_P / (M d) + pivot",
                     f"{q[i]:.5f}", "m"))
        rows.append(("  from the runs, held / free", f"{held[i]:.5f} / {free[i]:.5f}", "m"))
        rows.append((f"  sweet zone (sting < {ds.attrs['sting']:g} J), from the runs",
                     f"{zone[i, 0]:.4f} to {zone[i, 1]:.4f}", "m"))
    rows += [("max |run - formula|, held / free",
              f"{values['max_error_held']:.1e} / {values['max_error_free']:.1e}", "m"),
             ("  the claim (held)", f"{values['claim']:g}", "m"),
             ("members not ok", f"{values['members_failed']}", ""),
             ("wall time", f"{wall:.1f}", "s")]
    return StudySummary(NAME, Path(out_dir), files, rows, values)


STUDY = StudyKind(
    name=NAME,
    title="centre of percussion of a struck bat or racket",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    resumable=True,
)
