"""The gyroscope study: precession and nutation of released tops, against exact and fast-top values.

A symmetric top (its mass, moments, pivot distance and gravity are keys of the study file) is
released at each tilt of a list with each spin of a grid, at rest or with a given initial
precession rate; :func:`stability.heavy_top.measure.measure_gyroscopes` measures from each run
the mean precession rate, the nutation frequency and the nutation amplitude and sets them beside
the exact values and the fast-top formulas ``M g l / (C w3)``, ``C w3 / A`` and
``2 A M g l sin(theta0) / (C w3)^2``. Outputs: the Dataset, two figures
(:func:`stability.heavy_top.figures.gyroscope_paths_figure`,
:func:`~stability.heavy_top.figures.gyroscope_rates_figure`) and the study's configuration.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from ...study.config import ConfigError, Key, Schema, Section
from ...study.kind import StudyKind, StudyRun, StudySummary, run_rows
from ...study.outputs import output_files, write_outputs
from ...study.sections import (check_memory, check_run, output_section, run_section,
                                study_run_options)
from .common import check_spins, symmetric_top, top_keys, top_methods
from ..figures import gyroscope_paths_figure, gyroscope_rates_figure
from ..measure import measure_gyroscopes
from ...util.threads import numba_threads

NAME = "gyroscope"
#: Figure stems: the paths of the figure axis, the rates against spin.
FIGURES = ("gyroscope_paths", "gyroscope_rates")


SCHEMA = Schema(
    top=(Key("title", "str", "Precession and nutation of a gyroscope",
             "one line describing the run (the Dataset's title)"),),
    sections=(
        Section("top", "the symmetric top: a disk on a light axle over the pivot", top_keys(
            Key("length", "float", 0.04, "distance l from the pivot to the centre of mass",
                unit="m", minimum=0.0, exclusive_minimum=True))),
        Section("spins", "the spins w3 (evenly spaced in log)", (
            Key("min", "float", 150.0, "smallest spin", unit="rad s-1", minimum=0.0,
                exclusive_minimum=True),
            Key("max", "float", 1500.0, "largest spin", unit="rad s-1", minimum=0.0,
                exclusive_minimum=True),
            Key("count", "int", 10, "number of spins", minimum=2),
        )),
        Section("release", "how each top is let go", (
            Key("tilts", "floats", [30.0, 60.0, 90.0], "tilts theta0 of the figure axis from "
                "the vertical", unit="degree", minimum=0.0, exclusive_minimum=True,
                maximum=180.0),
            Key("precession", "floats", [-1.0, 0.0, 0.5],
                "initial precession rates phi'(0) in units of M g l / (C w3): 0 at rest "
                "(cusps), < 0 loops, between 0 and 1 waves"),
            Key("seed", "int", 0, "seed of the members' azimuths", minimum=0),
        )),
        Section("integration", "the integrator, its step and the run length", (
            Key("method", "str", "lp4", "a heavy-top method", choices=top_methods),
            Key("step_angle", "float", 0.02, "h times the faster of spin and nutation",
                unit="rad", minimum=0.0, exclusive_minimum=True, maximum=0.5),
            Key("periods", "float", 40.0, "run length in nutation periods", minimum=3.0),
            Key("samples_per_period", "int", 64, "states kept per nutation period",
                minimum=8),
        )),
        Section("paths", "the (tilt, spin) cell whose figure-axis paths are drawn", (
            Key("tilt", "float", 60.0, "tilt (nearest of the list)", unit="degree",
                minimum=0.0, maximum=180.0),
            Key("spin", "float", 150.0, "spin (nearest of the grid)", unit="rad s-1",
                minimum=0.0),
            Key("periods", "float", 3.0, "length of the drawn paths in nutation periods",
                minimum=0.5),
        )),
        Section("analysis", "what the run must show", (
            Key("claim", "float", 1e-6,
                "relative error of the measured rates and amplitude against the exact motion",
                minimum=0.0, exclusive_minimum=True),
        )),
        run_section(),
        output_section(NAME, FIGURES),
    ),
)

#: ``--quick``: four spins, one tilt, a shorter run.
QUICK = {"spins": {"count": 4}, "release": {"tilts": [60.0]}, "integration": {"periods": 20.0}}


def _top(config, source="<config>"):
    length = config["top"]["length"]
    return symmetric_top(config, length, source, name=f"disk top, l = {100 * length:g} cm")


def check(config: dict, source: str) -> dict:
    """A symmetric, physical top; a spin range; tilts strictly between 0 and 180 degrees."""
    _top(config, source)
    check_spins(config, source)
    r = config["release"]
    if not r["tilts"]:
        raise ConfigError("must list at least one tilt", source, "release", "tilts")
    if max(r["tilts"]) >= 180.0:
        raise ConfigError(f"must be below 180 degrees (a top hanging straight down has no "
                          f"precession), got {max(r['tilts']):g}", source, "release", "tilts")
    if not r["precession"]:
        raise ConfigError("must list at least one initial precession rate", source, "release",
                          "precession")
    _check_memory(config, source)
    check_run(config, source)
    return config


def _check_memory(config: dict, source: str) -> None:
    """Refuse a run whose kept states would not fit in memory, before any is allocated.

    Each member keeps about ``periods x samples_per_period`` states (up to twice that where a
    slow member sets its group's length) of 6 numbers, held about three times over while they
    are read (the samples, their observables, the engine's buffer).
    """
    integ = config["integration"]
    members = (config["spins"]["count"] * len(config["release"]["tilts"])
               * len(config["release"]["precession"]))
    samples = 2 * integ["periods"] * integ["samples_per_period"]
    check_memory(SCHEMA, config, source, members * samples * 6 * 8 * 3,
                 [("integration", "samples_per_period"), ("integration", "periods"),
                  ("spins", "count")],
                 f"the states of {members} members, {integ['samples_per_period']} per period "
                 f"over {integ['periods']:g} periods", "keep fewer samples, periods or spins")


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    return output_files(config, FIGURES)


def run(config: dict, out_dir: Path, options: StudyRun) -> StudySummary:
    """Run the grid, save the Dataset, draw the figures; the summary of run against exact.

    The tops run chunk by chunk into the store of ``options.run`` (so that a stopped run
    continues with its ``resume``), on its ``scheduler`` (default: the file's ``[run]
    scheduler``)."""

    t_start = time.perf_counter()
    top = _top(config)
    s, r, integ, paths = (config["spins"], config["release"], config["integration"],
                          config["paths"])
    spins = np.geomspace(s["min"], s["max"], s["count"])
    with numba_threads(options.run.threads):
        ds = measure_gyroscopes(
            top, spins, np.radians(r["tilts"]), r["precession"], method=integ["method"],
            step_angle=integ["step_angle"], periods=integ["periods"],
            samples_per_period=integ["samples_per_period"], seed=r["seed"],
            path_tilt=math.radians(paths["tilt"]), path_spin=paths["spin"],
            path_periods=paths["periods"],
            options=study_run_options(config, options))
    claim = config["analysis"]["claim"]
    ds, files = write_outputs(
        ds, config, out_dir, NAME,
        {FIGURES[0]: gyroscope_paths_figure,
         FIGURES[1]: lambda ds: gyroscope_rates_figure(ds, claim=claim)},
        overwrite=options.overwrite, history=options.history,
        threads=options.run.threads, attrs={"claim": claim})
    return summarize(ds, out_dir, files, time.perf_counter() - t_start)


_QUANTITIES = (("precession_rate", "mean precession rate"),
               ("nutation_frequency", "nutation frequency"),
               ("nutation_amplitude", "nutation amplitude"))


def summarize(ds, out_dir, files, wall) -> StudySummary:
    """Worst relative errors against the exact motion; how far the fast-top values are off."""
    claim = ds.attrs["claim"]
    values = {"claim": claim, "wall_time": wall,
              "integration_time": float(ds.attrs["wall_time"]),
              "member_steps": int(ds.attrs["member_steps"]),
              "members_failed": int((ds.status != 0).sum())}
    rows = []
    for name, text in _QUANTITIES:
        worst = float(np.abs(ds[f"{name}_error"]).max())
        values[f"max_relative_error_{name}"] = worst
        rows.append((f"max |run - exact| / exact, {text}", f"{worst:.1e}", ""))
    rows.append(("  the claim", f"{claim:g}", ""))
    at_rest = ds.release.values == 0.0
    for label, spin in (("lowest", ds.spin.values[0]),
                        ("highest", ds.spin.values[-1])):
        cell = ds.sel(spin=spin)
        prec = np.abs(cell.precession_rate_exact / cell.precession_rate_gyroscopic - 1.0).max()
        nut = np.abs(cell.nutation_frequency_exact / cell.nutation_frequency_gyroscopic
                     - 1.0).max()
        values[f"fast_top_offset_{label}"] = [float(prec), float(nut)]
        rows.append((f"exact / fast-top value - 1 at {spin:.0f} rad/s (precession, nutation)",
                     f"{float(prec):.1e}, {float(nut):.1e}", ""))
        if at_rest.any():
            amp = cell.isel(release=np.flatnonzero(at_rest)[0])
            ratio = np.abs(amp.nutation_amplitude_exact / amp.nutation_amplitude_gyroscopic
                           - 1.0).max()
            values[f"fast_top_amplitude_offset_{label}"] = float(ratio)
            rows.append((f"  amplitude released at rest, at {spin:.0f} rad/s", f"{ratio:.1e}",
                         ""))
    rows += run_rows(values, wall)
    return StudySummary(NAME, Path(out_dir), files, rows, values)


STUDY = StudyKind(
    name=NAME,
    title="precession and nutation of released tops against the exact and fast-top values",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    resumable=True,
)
