"""The Earth's free wobble study: a rigid Earth's rotation axis circles its figure axis.

The Earth is built from published ratios (keys of the study file, sources in
:mod:`stability.earth.model`), spun once a sidereal day with its rotation axis ``offset``
arcseconds from the figure axis; :func:`stability.earth.measure.measure_free_wobble` measures the
period of the free (Euler) wobble and draws its cones. The Dataset's attributes carry the note that
the observed Chandler period (about 433 d) is longer because the Earth is not rigid.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

from ...core.body import RigidBody
from ..model import ARCSEC, earth_moments
from ..figures import wobble_cones_figure
from ...util.threads import numba_threads
from ..measure import measure_free_wobble, wobble_memory, wobble_methods
from ...study.config import ConfigError, Key, Schema, Section
from ...study.kind import StudyKind, StudyRun, StudySummary
from ...study.outputs import output_files, write_outputs
from ...study.sections import (check_memory, check_run, output_section, run_section,
                                study_run_options)

NAME = "earth_wobble"
FIGURE = "earth_wobble"


def _attitude_methods() -> tuple:

    return wobble_methods()


SCHEMA = Schema(
    top=(Key("title", "str", "The free (Euler) wobble of a rigid Earth",
             "one line describing the run (the Dataset's title)"),),
    sections=(
        Section("earth", "the rigid Earth, from published ratios (stability.earth)", (
            Key("mass", "float", 5.9722e24, "mass M", unit="kg", minimum=0.0,
                exclusive_minimum=True),
            Key("radius", "float", 6378136.6, "equatorial radius a", unit="m", minimum=0.0,
                exclusive_minimum=True),
            Key("polar_factor", "float", 0.3307, "C / (M a^2)", minimum=0.0,
                exclusive_minimum=True, maximum=0.4),
            Key("ellipticity", "float", 3.27379448e-3,
                "dynamical ellipticity H = (C - (A + B) / 2) / C", minimum=0.0,
                exclusive_minimum=True, maximum=0.1),
            Key("asymmetry", "float", 7.260e-6, "(B - A) / (M a^2)", minimum=0.0),
            Key("sidereal_day", "float", 86164.0905, "one turn", unit="s", minimum=0.0,
                exclusive_minimum=True),
        )),
        Section("wobble", "the offset of the rotation axis and the ensemble", (
            Key("offset", "float", 0.3, "angle between rotation and figure axes at the start",
                unit="arcsec", minimum=0.0, exclusive_minimum=True, maximum=3600.0),
            Key("members", "int", 16, "members (random directions of the offset)", minimum=1),
            Key("periods", "float", 3.0, "run length in Euler periods", minimum=2.0),
            Key("seed", "int", 0, "seed of the directions", minimum=0),
        )),
        Section("integration", "the integrator", (
            Key("method", "str", "lp4", "a free-body method that carries the attitude",
                choices=_attitude_methods),
            Key("steps_per_turn", "int", 20, "steps per sidereal day", minimum=4),
        )),
        run_section(),
        output_section(NAME, (FIGURE,)),
    ),
)

QUICK = {"wobble": {"members": 4, "periods": 2.0}}


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    return output_files(config, (FIGURE,))


def check(config: dict, source: str) -> dict:
    """Moments of a real body (the triangle inequality) from the ratios given."""

    e = config["earth"]
    moments = earth_moments(e["mass"], e["radius"], e["polar_factor"], e["ellipticity"],
                            e["asymmetry"])
    if not moments[0] > 0:
        raise ConfigError("leaves no positive equatorial moment A; lower it", source, "earth",
                          "asymmetry")
    try:
        RigidBody(*moments)
    except ValueError as exc:
        raise ConfigError(str(exc), source, "earth", "polar_factor") from None
    members = config["wobble"]["members"]
    check_memory(SCHEMA, config, source, wobble_memory(members), [("wobble", "members")],
                 f"the summaries of {members} members", "use fewer members")
    check_run(config, source)
    return config


def run(config: dict, out_dir: Path, options: StudyRun) -> StudySummary:
    """Measure the wobble, save the Dataset, draw the cones; the period against Euler's.

    The ensemble runs chunk by chunk into the store of ``options.run`` (so that a stopped run
    continues with its ``resume``), on its ``scheduler`` (default: the file's ``[run]
    scheduler``)."""

    t_start = time.perf_counter()
    e, w, integ = config["earth"], config["wobble"], config["integration"]
    body = RigidBody(*earth_moments(e["mass"], e["radius"], e["polar_factor"],
                                    e["ellipticity"], e["asymmetry"]), name="Earth")
    spin = 2.0 * math.pi / e["sidereal_day"]
    with numba_threads(options.run.threads):
        ds = measure_free_wobble(body, spin, w["offset"] * ARCSEC, members=w["members"],
                                 periods=w["periods"], steps_per_turn=integ["steps_per_turn"],
                                 method=integ["method"], seed=w["seed"],
                                 options=study_run_options(config, options))
    ds, files = write_outputs(ds, config, out_dir, NAME, {FIGURE: wobble_cones_figure},
                              overwrite=options.overwrite, history=options.history,
                              threads=options.run.threads,
                              attrs={"sidereal_day": e["sidereal_day"]})
    wall = time.perf_counter() - t_start
    sidereal = e["sidereal_day"] / 86400.0
    values = {name: float(ds[name]) for name in (
        "wobble_period_measured", "wobble_period_stderr", "wobble_period_euler",
        "wobble_period_oblate", "relative_error")}
    values.update(chandler=float(ds.attrs["chandler_period_days"]), wall_time=wall,
                  space_cone_mas=1e3 * float(ds.space_cone_angle.mean()))
    rows = [
        ("wobble period, measured (mean over members)",
         f"{values['wobble_period_measured']:.4f}", "d"),
        ("  standard error", f"{values['wobble_period_stderr']:.1e}", "d"),
        ("Euler period 2 pi / (W sqrt((C - A)(C - B) / (A B)))",
         f"{values['wobble_period_euler']:.4f}", "d"),
        ("  relative difference", f"{values['relative_error']:.1e}", ""),
        ("A / (C - A) sidereal days (A the mean equatorial moment)",
         f"{values['wobble_period_oblate'] / sidereal:.2f}", "sidereal d"),
        ("space cone half-angle (offset 0.3 arcsec in the body)" if w["offset"] == 0.3 else
         "space cone half-angle", f"{values['space_cone_mas']:.4f}", "mas"),
        ("observed Chandler period (the Earth is not rigid)", f"{values['chandler']:g}", "d"),
        ("wall time", f"{wall:.1f}", "s"),
    ]
    return StudySummary(NAME, Path(out_dir), files, rows, values)


STUDY = StudyKind(
    name=NAME,
    title="free wobble of the rigid Earth",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    members_key=("wobble", "members"),
    resumable=True,
)
