"""The equinoxes study: the precession and nutation of a rigid Earth's axis under Sun and Moon.

:func:`stability.earth.precession.measure_equinoxes` runs the full model (spin, attitude and the two
prescribed orbits: scene ``lunisolar_earth``) for a century or more with the Sun alone, the Moon
alone and both, an ensemble of orbital phases each, and the orbit-averaged model (scene
``precessing_axis``) beside it and over a full turn of the axis; the measured precession rate and
nutation amplitudes are set beside the averaged formula and the published values. Outputs: the
Dataset, one figure (:func:`stability.earth.figures.equinoxes_figure`) and the configuration.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

from ..precession import measure_equinoxes
from ..figures import equinoxes_figure
from ..methods import METHODS
from ...util.threads import numba_threads
from ...study.config import Key, Schema, Section
from ...study.kind import StudyKind, StudySummary
from ...study.outputs import output_files, write_outputs
from ...study.sections import check_run, output_section, run_keys, study_run_options

NAME = "equinoxes"
FIGURE = "equinoxes"


def _methods() -> tuple:

    return tuple(METHODS)


SCHEMA = Schema(
    top=(Key("title", "str", "Precession of the equinoxes of a rigid Earth",
             "one line describing the run (the Dataset's title)"),),
    sections=(
        Section("run", "length and ensemble, how it is cut into chunks and where they run", (
            Key("years", "float", 100.0, "run length (at least a century: the 18.6-year terms)",
                unit="yr", minimum=40.0, maximum=10000.0),
            Key("members", "int", 4, "members per torque (0: J2000; others: random orbital "
                "phases)", minimum=1, maximum=1000),
            Key("seed", "int", 0, "seed of the phases", minimum=0),
            *run_keys(),
        )),
        Section("integration", "the two models' integrators", (
            Key("method", "str", "lp4", "a method of the full model", choices=_methods),
            Key("steps_per_day", "int", 4, "steps of the full model per day", minimum=1,
                maximum=1000),
            Key("averaged_step", "float", 5.0, "step of the orbit-averaged model", unit="d",
                minimum=0.0, exclusive_minimum=True, maximum=1000.0),
            Key("cycle_years", "float", 26000.0, "long run of the averaged model for a full turn "
                "(0: none)", unit="yr", minimum=0.0, maximum=1e6),
        )),
        Section("analysis", "what the run must show", (
            Key("claim", "float", 0.01,
                "relative difference allowed from the published precession and nutation",
                minimum=0.0, exclusive_minimum=True),
        )),
        output_section(NAME, (FIGURE,)),
    ),
)

#: ``--quick``: a shorter run, two members, no full turn.
QUICK = {"run": {"years": 40.0, "members": 2}, "integration": {"cycle_years": 0.0}}


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    return output_files(config, (FIGURE,))


def check(config: dict, source: str) -> dict:
    """A scheduler that is this machine, a local cluster or an address."""
    check_run(config, source)
    return config


def run(config: dict, out_dir: Path, *, overwrite=False, threads=None, progress=None,
        history=None, work=None, resume=False, scheduler=None) -> StudySummary:
    """Run both models, save the Dataset, draw the figure; the summary against published values.

    The runs go chunk by chunk into folders of ``work`` (so that a stopped run continues with
    ``resume``), on ``scheduler`` (default: the file's ``[run] scheduler``)."""

    t_start = time.perf_counter()
    r, integ = config["run"], config["integration"]
    with numba_threads(threads):
        ds = measure_equinoxes(years=r["years"], members=r["members"],
                               steps_per_day=integ["steps_per_day"], method=integ["method"],
                               averaged_step_days=integ["averaged_step"],
                               cycle_years=integ["cycle_years"], seed=r["seed"],
                               options=study_run_options(config, work, resume,
                                                         scheduler, threads, progress))
    ds, files = write_outputs(ds, config, out_dir, NAME, {FIGURE: equinoxes_figure},
                              overwrite=overwrite, history=history, threads=threads,
                              attrs={"claim": config["analysis"]["claim"]})
    return summarize(ds, out_dir, files, time.perf_counter() - t_start)


def summarize(ds, out_dir, files, wall) -> StudySummary:
    """Measured against the formula and the published values; the method's speed and error."""
    a = ds.attrs
    full = ds.sel(model="full")
    both = full.sel(torque="both")
    rate = float(both.precession_rate.mean())
    spread = float(both.precession_rate.std()) if both.sizes["member"] > 1 else 0.0
    formula = float(ds.precession_rate_formula.sel(torque="both"))
    nut_lon = float(both.nutation_longitude.mean())
    nut_obl = float(both.nutation_obliquity.mean())
    averaged = float(ds.precession_rate.sel(model="averaged", torque="both").mean())
    shares = {t: float(full.precession_rate.sel(torque=t).mean()) for t in ("sun", "moon")}
    values = {
        "precession_rate": rate, "precession_spread": spread, "formula": formula,
        "published": a["published_precession"],
        "relative_to_published": rate / a["published_precession"] - 1.0,
        "relative_to_formula": rate / formula - 1.0,
        "sun": shares["sun"], "moon": shares["moon"],
        "nutation_longitude": nut_lon, "nutation_obliquity": nut_obl,
        "nutation_longitude_relative": nut_lon / a["published_nutation_longitude"] - 1.0,
        "nutation_obliquity_relative": nut_obl / a["published_nutation_obliquity"] - 1.0,
        "averaged_rate": averaged, "step_error": float(ds.step_error.max()),
        "period_years": a.get("precession_period_years", float("nan")),
        "claim": a["claim"], "wall_time": wall, "integration_time": a["wall_time"],
        "member_steps": a["member_steps"],
        "member_steps_per_second": a["member_steps"] / a["wall_time"],
    }
    rows = [
        ("precession rate, full model, Sun + Moon", f"{rate:.4f} +- {spread:.4f}", "\"/yr"),
        ("  averaged formula", f"{formula:.4f}  ({values['relative_to_formula']:+.1e})",
         "\"/yr"),
        ("  published (IAU 2006 lunisolar)",
         f"{a['published_precession']:.4f}  ({values['relative_to_published']:+.2%})", "\"/yr"),
        ("  Sun's share / Moon's share", f"{shares['sun']:.4f} / {shares['moon']:.4f}", "\"/yr"),
        ("  orbit-averaged model", f"{averaged:.4f}", "\"/yr"),
        ("18.6-year nutation in longitude (IAU 1980 17.1996)",
         f"{nut_lon:.4f}  ({values['nutation_longitude_relative']:+.2%})", "\""),
        ("18.6-year nutation in obliquity (IAU 1980 9.2025)",
         f"{nut_obl:.4f}  ({values['nutation_obliquity_relative']:+.2%})", "\""),
        ("one turn of the axis (averaged model)", f"{values['period_years']:.0f}", "yr")
        if math.isfinite(values["period_years"]) else
        ("one turn of the axis (averaged model): no long run, [integration] cycle_years = 0",
         "not run", ""),
        ("estimated integration error of the rate (steps halved)",
         f"{values['step_error']:.1e}", "\"/yr"),
        ("full model: steps, member-steps/s",
         f"{values['member_steps']:.3g}, {values['member_steps_per_second']:.3g}", ""),
        ("the claim (relative, against published)", f"{a['claim']:g}", ""),
        ("wall time (all) / full model", f"{wall:.1f} / {a['wall_time']:.1f}", "s"),
    ]
    return StudySummary(NAME, Path(out_dir), files, rows, values)


STUDY = StudyKind(
    name=NAME,
    title="precession of the equinoxes",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    quick_note="the averaged model's long run for a full turn of the axis is left out "
               "(cycle_years = 0): the quick run measures the rate, not the 26,000-year period",
    members_key=("run", "members"),
    resumable=True,
)
