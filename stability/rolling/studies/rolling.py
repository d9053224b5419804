"""The rolling study: rolling or slipping down inclines, and balls launched along a floor.

Two ensembles on scene ``rolling_body`` (:mod:`stability.rolling.model`): bodies released at
rest on inclines over a grid of (theta, mu_s), each member with its own scattered mu_s, mu_k and
shape, whose measured regime (did friction do work?) is set against
``tan(theta) <= mu_s (1 + M R^2 / I)``; and balls launched along a level floor with scattered
speeds and spins, whose time, place and speed of the start of pure rolling and heat are set
against the formulas. Outputs: one Dataset, two figures
(:func:`stability.rolling.figures.rolling_map_figure`,
:func:`~stability.rolling.figures.rolling_launch_figure`) and the study's configuration.
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
from ..figures import rolling_launch_figure, rolling_map_figure
from ..measure import measure_incline, measure_launches
from ..model import SHAPES

NAME = "rolling"
FIGURES = ("rolling_map", "rolling_launch")


def _shapes():

    return tuple(SHAPES)


SCHEMA = Schema(
    top=(Key("title", "str", "Rolling with and without slipping",
             "one line describing the run (the Dataset's title)"),),
    sections=(
        Section("incline", "bodies released at rest on inclines: the (theta, mu_s) map", (
            Key("shapes", "strs", ["sphere", "cylinder", "hoop"], "shapes mapped",
                choices=_shapes),
            Key("angle_min", "float", 2.0, "smallest incline angle", unit="degree"),
            Key("angle_max", "float", 70.0, "largest incline angle", unit="degree"),
            Key("angle_count", "int", 35, "angles", minimum=2),
            Key("mu_s_min", "float", 0.02, "smallest static friction coefficient",
                minimum=0.0),
            Key("mu_s_max", "float", 0.6, "largest static friction coefficient", minimum=0.0),
            Key("mu_s_count", "int", 30, "static friction coefficients", minimum=2),
            Key("mu_k_ratio", "float", 0.8, "mu_k / mu_s (kinetic friction is at most static)",
                minimum=0.0),
            Key("mu_scatter", "float", 0.05, "relative scatter of each member's mu_s",
                minimum=0.0, maximum=0.5),
            Key("shape_scatter", "float", 0.02, "relative scatter of each member's I / (M R^2)",
                minimum=0.0, maximum=0.5),
            Key("members", "int", 4, "members per cell", minimum=1),
            Key("duration", "float", 1.0, "run length", unit="s", minimum=0.0,
                exclusive_minimum=True),
            Key("seed", "int", 0, "seed of the scatter", minimum=0),
        )),
        Section("launch", "balls launched along a level floor (default: billiard balls)", (
            Key("radius", "float", 0.028575, "ball radius R", unit="m", minimum=0.0,
                exclusive_minimum=True),
            Key("mass", "float", 0.17, "ball mass M", unit="kg", minimum=0.0,
                exclusive_minimum=True),
            Key("shape", "str", "sphere", "the ball's shape (its I / (M R^2))",
                choices=_shapes),
            Key("mu_s", "float", 0.25, "static friction coefficient", minimum=0.0),
            Key("mu_k", "float", 0.2, "kinetic friction coefficient (cloth on a ball)",
                minimum=0.0),
            Key("mu_scatter", "float", 0.1, "relative scatter of each member's mu_k",
                minimum=0.0, maximum=0.5),
            Key("speed_min", "float", 0.5, "slowest launch", unit="m s-1", minimum=0.0),
            Key("speed_max", "float", 4.0, "fastest launch", unit="m s-1", minimum=0.0),
            Key("spin_min", "float", -1.5, "R w0 / v0 at the least (negative: backspin, a draw "
                "shot)"),
            Key("spin_max", "float", 2.5, "R w0 / v0 at the most (above 1: topspin beyond "
                "rolling)"),
            Key("members", "int", 1000, "balls", minimum=2),
            Key("samples", "int", 200, "states kept per ball (exact at any spacing)",
                minimum=2),
            Key("seed", "int", 0, "seed of the launches", minimum=0),
        )),
        Section("analysis", "what the run must show", (
            Key("claim", "float", 1e-12, "relative error of the switch times, places, speeds "
                "and heat against the formulas", minimum=0.0, exclusive_minimum=True),
        )),
        run_section(),
        output_section(NAME, FIGURES),
    ),
)

QUICK = {"incline": {"angle_count": 12, "mu_s_count": 10, "members": 2},
         "launch": {"members": 100, "samples": 50}}


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    return output_files(config, FIGURES)


def check(config: dict, source: str) -> dict:
    """Angles inside (-90, 90) degrees, ascending ranges, kinetic friction at most static."""
    inc, launch = config["incline"], config["launch"]
    for key in ("angle_min", "angle_max"):
        if not -90.0 < inc[key] < 90.0:
            raise ConfigError(f"must be inside (-90, 90) degrees (a wall is not an incline), "
                              f"got {inc[key]:g}", source, "incline", key)
    for section, lo, hi in (("incline", "angle_min", "angle_max"),
                            ("incline", "mu_s_min", "mu_s_max"),
                            ("launch", "speed_min", "speed_max"),
                            ("launch", "spin_min", "spin_max")):
        if not config[section][lo] < config[section][hi]:
            raise ConfigError(f"must be above {lo} ({config[section][lo]:g}), got "
                              f"{config[section][hi]:g}", source, section, hi)
    if inc["mu_k_ratio"] > 1.0:
        raise ConfigError(f"= {inc['mu_k_ratio']:g} makes mu_k > mu_s; kinetic friction is at "
                          "most static friction (mu_k / mu_s <= 1)", source, "incline",
                          "mu_k_ratio")
    if launch["mu_k"] > launch["mu_s"]:
        raise ConfigError(f"= {launch['mu_k']:g} exceeds mu_s = {launch['mu_s']:g}; kinetic "
                          "friction is at most static friction", source, "launch", "mu_k")
    if launch["mu_k"] == 0.0:
        raise ConfigError("= 0 never stops a slip; give the floor some friction", source,
                          "launch", "mu_k")
    cells = len(inc["shapes"]) * inc["angle_count"] * inc["mu_s_count"]
    check_memory(SCHEMA, config, source, cells * inc["members"] * MEMBER_BYTES,
                 [("incline", "angle_count"), ("incline", "mu_s_count"), ("incline", "members")],
                 f"{cells} cells x {inc['members']} members", "use fewer angles, friction "
                 "coefficients or members per cell")
    paths = 5  # the launches kept at every sample (measure_launches' paths)
    check_memory(SCHEMA, config, source, launch["members"] * MEMBER_BYTES
                 + paths * (launch["samples"] + 1) * 9 * 8 * 2,
                 [("launch", "members"), ("launch", "samples")],
                 f"{launch['members']} balls and {launch['samples']} states of {paths} of them",
                 "use fewer balls or samples")
    check_run(config, source)
    return config


def run(config: dict, out_dir: Path, options: StudyRun) -> StudySummary:
    """Run both ensembles, save one Dataset, draw the map and the launches.

    Each ensemble runs chunk by chunk into its own folder inside the store of ``options.run``
    (so that a stopped run continues with its ``resume``), on its ``scheduler`` (default: the
    file's ``[run] scheduler``)."""
    import xarray as xr


    run_options = study_run_options(config, options)

    t_start = time.perf_counter()
    inc, launch = config["incline"], config["launch"]
    with numba_threads(options.run.threads):
        incline = measure_incline(
            inc["shapes"], np.radians(np.linspace(inc["angle_min"], inc["angle_max"],
                                                  inc["angle_count"])),
            np.linspace(inc["mu_s_min"], inc["mu_s_max"], inc["mu_s_count"]),
            members=inc["members"], mu_ratio=inc["mu_k_ratio"], mu_scatter=inc["mu_scatter"],
            shape_scatter=inc["shape_scatter"], duration=inc["duration"], seed=inc["seed"],
            options=run_options.within("incline"))
        launches = measure_launches(
            radius=launch["radius"], mass=launch["mass"], k=SHAPES[launch["shape"]],
            mu_k=launch["mu_k"], speeds=(launch["speed_min"], launch["speed_max"]),
            spin_ratios=(launch["spin_min"], launch["spin_max"]), members=launch["members"],
            mu_scatter=launch["mu_scatter"], samples=launch["samples"], seed=launch["seed"],
            options=run_options.within("launches"))
    ds = xr.merge([incline, launches], combine_attrs="override")  # variables keep theirs
    ds.attrs = {}
    ds.attrs.update({f"incline_{k}": v for k, v in incline.attrs.items()})
    ds.attrs.update({f"launch_{k}": v for k, v in launches.attrs.items()})
    ds, files = write_outputs(ds, config, out_dir, NAME,
                              {FIGURES[0]: rolling_map_figure,
                               FIGURES[1]: rolling_launch_figure},
                              overwrite=options.overwrite, history=options.history,
                              threads=options.run.threads,
                              attrs={"claim": config["analysis"]["claim"]})
    return summarize(ds, out_dir, files, time.perf_counter() - t_start)


def _worst(ds, name, floor=0.0):
    """max |run - formula| / |formula| (``floor``: the scale under which errors are absolute)."""
    formula = ds[f"{name}_formula"]
    return float((np.abs(ds[name] - formula) / np.maximum(np.abs(formula), floor)).max())


def summarize(ds, out_dir, files, wall) -> StudySummary:
    """Cells on the wrong side; worst errors of the launches against the formulas."""
    slipped, expected = ds.slipped.values, 1 - ds.rolls_formula.values
    speed = float(ds.v0.max())
    values = {
        "claim": ds.attrs["claim"], "wall_time": wall,
        "cells": int(ds.slip_fraction.size), "cells_wrong_side": int(ds.wrong_side.sum()),
        "cells_straddling": int(ds.scatter_straddles.sum()),
        "members_against_own_formula": int((slipped != expected).sum()),
        "max_error_acceleration": _worst(ds, "acceleration"),
        "max_error_spin_rate": _worst(ds, "spin_rate"),
        "max_error_t_roll": _worst(ds, "t_roll"),
        "max_error_x_roll": _worst(ds, "x_roll"),
        "max_error_v_final": _worst(ds, "v_final", 1e-3 * speed),
        "max_error_heat": float((np.abs(ds.heat - ds.energy_lost_formula)
                                 / ds.energy_lost_formula).max()),
        "members_failed": int((ds.incline_status != 0).sum() + (ds.launch_status != 0).sum()),
    }
    rows = [
        ("incline cells on the wrong side of tan(theta) = mu_s (1 + M R^2 / I)",
         f"{values['cells_wrong_side']} of {values['cells']}", ""),
        ("  cells whose scatter spans the boundary", f"{values['cells_straddling']}", ""),
        ("  members against their own formula", f"{values['members_against_own_formula']} of "
         f"{slipped.size}", ""),
        ("max relative error, acceleration / spin rate",
         f"{values['max_error_acceleration']:.1e} / {values['max_error_spin_rate']:.1e}", ""),
        ("launches: max relative error, time to rolling", f"{values['max_error_t_roll']:.1e}",
         ""),
        ("  distance to rolling / final speed",
         f"{values['max_error_x_roll']:.1e} / {values['max_error_v_final']:.1e}", ""),
        ("  heat against M (v0 - R w0)^2 k / (2 (1 + k))", f"{values['max_error_heat']:.1e}",
         ""),
        ("  the claim", f"{values['claim']:g}", ""),
        ("members not ok", f"{values['members_failed']}", ""),
        ("wall time", f"{wall:.1f}", "s"),
    ]
    return StudySummary(NAME, Path(out_dir), files, rows, values)


STUDY = StudyKind(
    name=NAME,
    title="rolling with and without slipping",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    members_key=("launch", "members"),
    resumable=True,
)
