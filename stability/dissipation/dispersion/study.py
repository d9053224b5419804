"""The dispersed Explorer study: which uncertainty of a damped minor-axis spinner dominates its
time to the flat spin?

The ``[dispersions]`` section names what is uncertain, each a table of a distribution
(:func:`stability.uncertainty.distributions.distribution`): the cylinder's ``length``,
``diameter`` and ``mass``, its ``spin`` (rpm), the damper's ``inertia`` J and ``damping``
(its coefficient c, N m s, about ``[damper] damping`` c* of the nominal body), and the initial
nutation ``angle`` (degree). The design of ``[sensitivity]`` (:mod:`stability.study.sensitivity`)
gives each member its values; every member's growth rate and time to the flat spin come from
the linear eigenvalue (:mod:`.measure`), the first ``[integration] members`` are integrated
too (each resumable), and the indices of both outputs are written with the draws and drawn.
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
from ...study.sensitivity import (
    analyse, analysis_figure, checked_dispersions, design_members, dispersions_section,
    dominant, draw_design, index_tables, sensitivity_section, summary_values
)
from ...util.threads import numba_threads
from ..methods import SPHERE_METHODS
from ..studies.common import positive_key
from ..studies.explorer import CYLINDER_KEYS, RELAXATION_STEP
from .measure import PARAMETERS, dispersion_dataset, integrated, linear, members, nominal

NAME = "explorer_dispersion"
FIGURES = ("indices",)
_UNITS = dict(zip(PARAMETERS, ("m", "m", "kg", "rpm", "kg m2", "N m s", "degree")))


SCHEMA = Schema(
    top=(Key("title", "str", "A dispersed Explorer: which uncertainty dominates its turn into "
             "a flat spin?", "one line describing the run (the Dataset's title)"),),
    sections=(
        Section("body", "the nominal satellite: a uniform solid cylinder spun about its long "
                "axis", (
            *CYLINDER_KEYS,
            positive_key("spin", 750.0, "spin about the long axis at release", "rpm"),
        )),
        Section("damper", "the nominal spherical damper", (
            positive_key("inertia", 1e-4, "moment of inertia J of the sphere", "kg m2"),
            positive_key("damping", 1.0, "viscous coefficient c in units of the energy sink's "
                      "optimum c* = J W I_s / I_t (of the nominal body)", "1"),
        )),
        Section("start", "the nominal start", (
            Key("angle", "float", 0.1, "initial nutation angle between the long axis and H",
                unit="degree", minimum=0.0, exclusive_minimum=True),
        )),
        dispersions_section(_UNITS),
        sensitivity_section(1024),
        Section("integration", "the first members integrated, checking the linear estimate", (
            Key("members", "int", 4, "members integrated (0: none)", minimum=0),
            Key("method", "str", "lp2", "a method of scene sphere_damper",
                choices=tuple(SPHERE_METHODS)),
            Key("step_angle", "float", 0.5, "h times the spin", unit="rad", minimum=0.0,
                exclusive_minimum=True, maximum=1.5),
            Key("tail", "float", 2.0, "run past the flat spin, in e-folds of the decay about "
                "the major axis", minimum=0.0),
            Key("samples", "int", 2000, "states kept by each integrated member", minimum=16),
        )),
        Section("analysis", "the flat spin and the fitted rate", (
            Key("fit_top", "float", 0.05, "largest nutation angle of the linear regime "
                "fitted", unit="rad", minimum=0.0, exclusive_minimum=True, maximum=0.2),
            Key("flat_angle", "float", 80.0, "nutation angle that counts as a flat spin",
                unit="degree", minimum=0.0, exclusive_minimum=True, maximum=89.0),
        )),
        run_section(),
        output_section(NAME, FIGURES),
    ),
)

#: ``--quick``: a sphere 10 times heavier (a turn about 10 times sooner), a small design.
QUICK = {"damper": {"inertia": 1e-3}, "sensitivity": {"base": 128, "trajectories": 16,
                                                       "resamples": 20},
         "integration": {"members": 2}}


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    return output_files(config, FIGURES)


def _dispersions(config: dict, source: str):
    """The checked dispersions of ``config``; a bad one is a one-line ConfigError."""
    b, d = config["body"], config["damper"]
    return checked_dispersions(config, source, nominal(
        b["length"], b["diameter"], b["mass"], b["spin"], d["inertia"], d["damping"],
        config["start"]["angle"]))


def check(config: dict, source: str) -> dict:
    """Dispersions that stay positive, a long body for every draw, angles below the flat
    spin, a step that resolves the damper of every member integrated, memory."""
    disp = _dispersions(config, source)
    bounds = {name: (value, value) for name, value in disp.nominal.items()}
    for name, dist in disp.distributions.items():
        if not dist.lower > 0.0:
            raise ConfigError(f"({dist.describe()}) can give a value <= 0 {_UNITS[name]}; "
                              "use a distribution bounded above 0", source, "dispersions", name)
        bounds[name] = (dist.lower, dist.upper)
    if bounds["length"][0] ** 2 <= 0.75 * bounds["diameter"][1] ** 2:
        raise ConfigError("can make the length less than sqrt(3)/2 times the diameter, where "
                          "the long axis is no longer the minor axis; narrow them", source,
                          "dispersions", "length" if "length" in disp.names else "diameter")
    flat = config["analysis"]["flat_angle"]
    if bounds["angle"][1] >= flat:
        raise ConfigError(f"must stay below [analysis] flat_angle = {flat:g} degrees, reaches "
                          f"{bounds['angle'][1]:g}", source,
                          "dispersions" if "angle" in disp.names else "start", "angle")
    n = design_members(config, source, disp)
    integ = config["integration"]
    if integ["members"] > n:
        raise ConfigError(f"must be at most the {n} members of the design", source,
                          "integration", "members")
    if integ["members"]:
        _check_step(config, source, disp)
    check_memory(SCHEMA, config, source, n * (MEMBER_BYTES + 24 * 8)
                 + integ["members"] * integ["samples"] * 6 * 8 * 4,
                 [("sensitivity", "base"), ("sensitivity", "trajectories")],
                 f"the {n} members of the design", "use fewer base points or trajectories")
    check_run(config, source)
    return config


def _check_step(config: dict, source: str, disp) -> None:
    """Refuse a step that does not resolve the damper's relaxation, ``h c (1/J + 1/I_s)``
    above the method's bound
    (:data:`~stability.dissipation.studies.explorer.RELAXATION_STEP`), for a
    member integrated."""
    integ = config["integration"]
    draws = members(disp, draw_design(config, disp).unit[:integ["members"]])
    v = draws["values"]
    hr = float(np.max(integ["step_angle"] * v[:, 4] * (1.0 / v[:, 3] + 1.0 / v[:, 0])
                      / draws["W"]))
    top = RELAXATION_STEP[integ["method"]]
    if hr > top:
        raise ConfigError(f"makes h times the damper's fastest relaxation rate "
                          f"c (1/J + 1/I_s) {hr:.2g} for a member integrated (above {top:g} "
                          f"for {integ['method']}); lower it to "
                          f"{integ['step_angle'] * top / hr:.2g}", source, "integration",
                          "step_angle")


def run(config: dict, out_dir: Path, options: StudyRun) -> StudySummary:
    """Draw the design, compute every member's outputs, integrate the first, write the
    Dataset and the figure of the analysis."""
    t_start = time.perf_counter()
    disp = _dispersions(config, "<study>")
    integ, a = config["integration"], config["analysis"]
    flat = math.radians(a["flat_angle"])
    design = draw_design(config, disp)
    draws = members(disp, design.unit)
    out = linear(draws, flat)
    run_out = None
    if integ["members"]:
        with numba_threads(options.run.threads):
            run_out = integrated(
                draws, integ["members"], flat_angle=flat, method=integ["method"],
                step_angle=integ["step_angle"], tail=integ["tail"], samples=integ["samples"],
                fit_top=a["fit_top"],
                options=study_run_options(config, options))
    described = {"flat_time": (out["flat_time"], "s", "time to the flat spin at the linear "
                               "growth rate"),
                 "growth_rate": (out["growth_rate"], "s-1", "growth rate of the nutation by "
                                 "the linear eigenvalue")}
    analysis = analyse(config, design, described)
    ds = dispersion_dataset(disp, draws, out, run_out, analysis)
    ds, files = write_outputs(ds, config, out_dir, NAME, {"indices": analysis_figure},
                              overwrite=options.overwrite, history=options.history,
                              threads=options.run.threads,
                              attrs={"flat_angle": a["flat_angle"]})
    return summarize(ds, out_dir, files, time.perf_counter() - t_start)


def summarize(ds, out_dir, files, wall) -> StudySummary:
    """The analysis of each output, what dominates the time to the flat spin, and the
    integrated check of the linear estimate."""
    top = dominant(ds, "flat_time")
    minutes = ds.flat_time.values / 60.0
    values = {"dominant": top, "dominant_growth_rate": dominant(ds, "growth_rate"),
              "wall_time": wall, "members": int(ds.member.size),
              "analysis": ds.attrs["analysis"], "indices": summary_values(ds)}
    rows = [(f"{ds.member.size} members: time to the flat spin",
             f"{minutes.min():.1f} to {minutes.max():.1f}", "min"),
            ("dominates the time to the flat spin", top, ""),
            ("dominates the growth rate", values["dominant_growth_rate"], "")]
    if "run_flat_time" in ds:
        n = ds.run.size
        time_error = np.abs(ds.run_flat_time.values / ds.flat_time.values[:n] - 1.0)
        rate_error = np.abs(ds.run_growth_rate.values / ds.growth_rate.values[:n] - 1.0)
        values["max_run_flat_time_error"] = float(np.nanmax(time_error))
        values["max_run_growth_rate_error"] = float(np.nanmax(rate_error))
        rows += [(f"integrated ({n} members): max |run / linear - 1|, time to the flat spin",
                  f"{values['max_run_flat_time_error']:.1e}", ""),
                 (f"integrated ({n} members): max |fitted / linear - 1|, growth rate",
                  f"{values['max_run_growth_rate_error']:.1e}", "")]
    rows.append(("wall time", f"{wall:.1f}", "s"))
    return StudySummary(NAME, Path(out_dir), files, rows, values, index_tables(ds))


STUDY = StudyKind(
    name=NAME,
    title="Which uncertainty of a damped minor-axis spinner dominates its time to the flat "
          "spin (Sobol' indices or Morris screening)",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    resumable=True,
)
