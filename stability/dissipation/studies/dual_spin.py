"""The dual-spin study: where a damper on a gyrostat's platform or in its rotor makes the
nutation decay.

A gyrostat (:mod:`stability.dissipation.model_gyrostat`): an axisymmetric platform spun at
``w_p`` about the axis of its rotor, a spherical damper on the platform, in the rotor, or one on
each. Over a map of the inertia ratio ``A3 / A_t`` and the rotor's speed relative to the
platform, each cell a few slightly nutating starts,
:func:`~stability.dissipation.measure_gyrostat.measure_dual_spin` measures the nutation's growth
or decay rate against the linear eigenvalue and sets the verdicts of the measurement, the
eigenvalues and the energy-sink criterion side by side. Outputs: the Dataset, two figures and
the configuration; resumable, and on dask, through the same stored grouped runs.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from ...study.config import ConfigError, Key, Schema, Section
from ...study.kind import StudyKind, StudyRun, StudySummary, SummaryTable, run_rows
from ...study.outputs import output_files, write_outputs
from ...study.sections import (check_memory, check_run, output_section, run_section,
                                study_run_options)
from ...util.threads import numba_threads
from .common import positive_key, worst
from ..figures import dual_spin_map_figure, dual_spin_rate_figure
from ..measure_gyrostat import PLACEMENTS, measure_dual_spin
from ..model_gyrostat import DualSpinBody

NAME = "dual_spin"
#: Figure stems: the maps against the criterion, the rates against the eigenvalues.
FIGURES = ("dual_spin_map", "dual_spin_rates")

SCHEMA = Schema(
    top=(Key("title", "str", "Dual-spin stabilisation: where a damper on the platform or in "
             "the rotor makes the nutation decay", "one line describing the run (the "
             "Dataset's title)"),),
    sections=(
        Section("body", "the gyrostat: an axisymmetric platform and a rotor on its axis, on a "
                "free bearing", (
            positive_key("transverse", 100.0, "the whole body's transverse moment A_t (rotor "
                      "included)", "kg m2"),
            positive_key("rotor", 25.0, "the rotor's axial moment Jr", "kg m2"),
            Key("platform_spin", "float", 1.0, "the platform's spin w_p about the rotor's axis",
                unit="rad/s"),
        )),
        Section("dampers", "the spherical dampers: one on the platform, one in the rotor", (
            positive_key("inertia", 5.0, "moment of inertia J of each damper's sphere", "kg m2"),
            positive_key("platform", 1.0, "the platform damper's viscous coefficient over its "
                      "energy-sink optimum c* = J h / A_t (h = A3 w_p + Jr Omega, per cell)",
                      "1"),
            positive_key("rotor", 0.3, "the rotor damper's, over the same c*", "1"),
            Key("placements", "strs", list(PLACEMENTS), "the maps: dampers on the platform, in "
                "the rotor, one on each", choices=PLACEMENTS),
        )),
        Section("map", "the inertia ratio A3 / A_t (below 1 minor axis, above 1 major axis) "
                "and the rotor's speed relative to the platform", (
            positive_key("ratio_min", 0.5, "smallest inertia ratio", "1"),
            positive_key("ratio_max", 1.5, "largest inertia ratio", "1"),
            Key("ratios", "int", 12, "inertia ratios, evenly spaced", minimum=2),
            Key("speed_min", "float", -1.5, "smallest relative speed of the rotor",
                unit="rad/s"),
            Key("speed_max", "float", 4.5, "largest relative speed of the rotor", unit="rad/s"),
            Key("speeds", "int", 12, "relative speeds, evenly spaced", minimum=2),
        )),
        Section("start", "the members of each cell", (
            Key("angles", "floats", [0.001, 0.002], "initial nutation angles between the "
                "rotor's axis and H", unit="degree", minimum=0.0, exclusive_minimum=True),
            Key("seed", "int", 0, "seed of the members' azimuths", minimum=0),
        )),
        Section("integration", "RK4, its step and the run length", (
            Key("step_angle", "float", 0.2, "h times a cell's fastest rate", unit="rad",
                minimum=0.0, exclusive_minimum=True, maximum=1.0),
            Key("efolds", "float", 4.0, "e-folds of a decaying nutation run past the settling",
                minimum=0.0, exclusive_minimum=True),
            positive_key("max_time", 3000.0, "the longest a cell runs past the settling (the "
                      "rates vanish near the boundary)", "s"),
            Key("samples", "int", 600, "states kept by the longest cell", minimum=64),
        )),
        Section("analysis", "what the run must show", (
            Key("fit_top", "float", 1e-3, "largest nutation angle of the linear regime fitted",
                unit="rad", minimum=0.0, exclusive_minimum=True, maximum=0.05),
            Key("claim", "float", 1e-3, "relative difference of the fitted rates from the "
                "linear eigenvalues", minimum=0.0, exclusive_minimum=True),
        )),
        run_section(),
        output_section(NAME, FIGURES),
    ),
)

#: ``--quick``: a 6 x 6 map, one start per cell, fewer kept states.
QUICK = {"map": {"ratios": 6, "speeds": 6}, "start": {"angles": [0.001]},
                   "integration": {"samples": 300}}


def body(config) -> DualSpinBody:
    """The study's gyrostat family from its ``[body]`` and ``[dampers]`` sections."""
    b, d = config["body"], config["dampers"]
    return DualSpinBody(b["transverse"], b["rotor"], d["inertia"], b["platform_spin"],
                        d["platform"], d["rotor"])


def map_axes(config):
    """``(ratios, speeds)``: the map's axes from its ``[map]`` section."""
    m = config["map"]
    return (np.linspace(m["ratio_min"], m["ratio_max"], m["ratios"]),
            np.linspace(m["speed_min"], m["speed_max"], m["speeds"]))


def check(config: dict, source: str) -> dict:
    """Ranges in order, a platform with an axial moment of its own, an axial momentum of one
    sign over the map, starts in the fitted range, placements listed once."""
    b, m = config["body"], config["map"]
    for name in ("ratio", "speed"):
        if not m[f"{name}_min"] < m[f"{name}_max"]:
            raise ConfigError(f"must exceed {name}_min = {m[f'{name}_min']:g}, got "
                              f"{m[f'{name}_max']:g}", source, "map", f"{name}_max")
    if not m["ratio_min"] * b["transverse"] > b["rotor"]:
        raise ConfigError(f"times [body] transverse must exceed [body] rotor = {b['rotor']:g} "
                          f"kg m2 (the platform's own axial moment is A3 - Jr), got "
                          f"{m['ratio_min']:g}", source, "map", "ratio_min")
    corners = [b["transverse"] * r * b["platform_spin"] + b["rotor"] * s
               for r in (m["ratio_min"], m["ratio_max"]) for s in (m["speed_min"],
                                                                    m["speed_max"])]
    if min(corners) <= 0.0:
        raise ConfigError(f"must keep the axial momentum h = A3 w_p + Jr Omega positive over "
                          f"the map (it is {min(corners):g} kg m2/s at a corner)", source,
                          "map", "speed_min")
    placements = config["dampers"]["placements"]
    if not placements or len(set(placements)) != len(placements):
        raise ConfigError(f"must list at least one placement, each once, got {placements}",
                          source, "dampers", "placements")
    angles, top = config["start"]["angles"], config["analysis"]["fit_top"]
    if not angles:
        raise ConfigError("must list at least one angle", source, "start", "angles")
    if len(set(angles)) != len(angles):
        raise ConfigError(f"must list each angle once, got {angles}", source, "start",
                          "angles")
    if math.radians(max(angles)) >= top:
        raise ConfigError(f"must be below [analysis] fit_top = {top:g} rad "
                          f"({math.degrees(top):.3g} degrees), got {max(angles):g}", source,
                          "start", "angles")
    members = len(placements) * m["ratios"] * m["speeds"] * len(angles)
    samples = config["integration"]["samples"]
    check_memory(SCHEMA, config, source, members * samples * 10 * 8 * 4,
                 [("integration", "samples"), ("map", "ratios"), ("map", "speeds")],
                 f"the states of {members} members, {samples} each",
                 "keep fewer samples or map fewer cells")
    check_run(config, source)
    return config


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    return output_files(config, FIGURES)


def run(config: dict, out_dir: Path, options: StudyRun) -> StudySummary:
    """Run the map, save the Dataset, draw the figures; the summary against the theory.

    The members run chunk by chunk into the store of ``options.run`` (a stopped run continues
    with its ``resume``), on its ``scheduler`` (default: the file's ``[run] scheduler``)."""
    t_start = time.perf_counter()
    s, integ, a = config["start"], config["integration"], config["analysis"]
    ratios, speeds = map_axes(config)
    with numba_threads(options.run.threads):
        ds = measure_dual_spin(
            body(config), ratios, speeds, np.radians(s["angles"]),
            placements=config["dampers"]["placements"], step_angle=integ["step_angle"],
            efolds=integ["efolds"], max_time=integ["max_time"], fit_top=a["fit_top"],
            samples=integ["samples"], seed=s["seed"],
            options=study_run_options(config, options))
    claim = a["claim"]
    ds, files = write_outputs(
        ds, config, out_dir, NAME,
        {FIGURES[0]: dual_spin_map_figure,
         FIGURES[1]: lambda ds: dual_spin_rate_figure(ds, claim=claim)},
        overwrite=options.overwrite, history=options.history,
        threads=options.run.threads, attrs={"claim": claim})
    return summarize(ds, out_dir, files, time.perf_counter() - t_start)


def summarize(ds, out_dir, files, wall) -> StudySummary:
    """Per placement: the verdicts of the measurement, the eigenvalues and the energy-sink
    criterion against each other, the fitted rates against the eigenvalues; |H|, the energy."""
    claim = float(ds.attrs["claim"])
    table = SummaryTable(
        "verdicts per placement (cells agreeing, of all) and rates against the eigenvalues",
        [("placement", ""), ("cells", ""), ("measured = eigenvalue", ""),
         ("criterion = eigenvalue", ""), ("measured = criterion", ""), ("members fitted", ""),
         ("fitted rate", "max |rel. diff.|"), ("energy-sink rate", "max |rel. diff.|")])
    values = {"claim": claim, "placements": {}}
    for placement in ds.placement.values:
        d = ds.sel(placement=placement)
        linear, sink, measured = (d[f"verdict_{k}"].values for k in
                                  ("linear", "energy_sink", "measured"))
        row = {
            "cells": int(linear.size),
            "measured_vs_linear": int((measured == linear).sum()),
            "sink_vs_linear": int((sink == linear).sum()),
            "measured_vs_sink": int((measured == sink).sum()),
            "undetermined": int((measured == 2).sum()),
            "stable_linear": int((linear == 1).sum()),
            "members_fitted": int(np.isfinite(d.rate_error.values).sum()),
            "members": int(d.rate_error.size),
            "max_rate_error": worst(d.rate_error),
            "max_sink_error": worst(d.rate_sink_error),
        }
        values["placements"][str(placement)] = row
        table.rows.append((str(placement), f"{row['cells']}", f"{row['measured_vs_linear']}",
                           f"{row['sink_vs_linear']}", f"{row['measured_vs_sink']}",
                           f"{row['members_fitted']} of {row['members']}",
                           f"{row['max_rate_error']:.1e}", f"{row['max_sink_error']:.1e}"))
    per = values["placements"].values()
    values.update({
        "cells": sum(r["cells"] for r in per),
        "measured_vs_linear": sum(r["measured_vs_linear"] for r in per),
        "sink_vs_linear": sum(r["sink_vs_linear"] for r in per),
        "measured_vs_sink": sum(r["measured_vs_sink"] for r in per),
        "members": int(ds.rate_error.size),
        "members_fitted": int(np.isfinite(ds.rate_error.values).sum()),
        "max_rate_error": worst(ds.rate_error),
        "max_angular_momentum_drift": worst(ds.angular_momentum_drift),
        "max_energy_rise": worst(ds.energy_rise),
        "wall_time": wall, "integration_time": float(ds.attrs["wall_time"]),
        "member_steps": int(ds.attrs["member_steps"]),
        "members_failed": int((ds.status != 0).sum()),
    })
    rows = [
        ("fitted rate vs linear eigenvalue, max |rel. diff.|",
         f"{values['max_rate_error']:.1e} ({values['members_fitted']} of {values['members']} "
         "fitted)", ""),
        ("  the claim", f"{claim:g}", ""),
        ("cells where the measurement agrees with the eigenvalues",
         f"{values['measured_vs_linear']} of {values['cells']}", ""),
        ("cells where the energy-sink criterion agrees with the eigenvalues",
         f"{values['sink_vs_linear']} of {values['cells']}", ""),
        ("|H| largest relative change (rk4)", f"{values['max_angular_momentum_drift']:.1e}",
         ""),
        ("energy's largest rise between kept states", f"{values['max_energy_rise']:.1e}", ""),
        *run_rows(values, wall),
    ]
    return StudySummary(NAME, Path(out_dir), files, rows, values, tables=[table])


STUDY = StudyKind(
    name=NAME,
    title="where a damper on a gyrostat's platform or in its rotor makes the nutation decay "
          "(dual-spin stabilisation)",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    resumable=True,
)
