"""The Explorer study: a long satellite spun about its minor axis turns over into a flat spin.

An Explorer-1-like body (a uniform cylinder of the length, diameter and mass of the file; by
default Explorer 1's, :data:`~stability.dissipation.model.EXPLORER_1`) spins about its long axis,
or a body of measured ``[body] moments`` (a :class:`~stability.dissipation.model.Spinner`,
``studies/spinner.toml``) about the axis of least moment, and carries a spherical damper (moment
J; viscous coefficient c, a list of them in units of the energy sink's optimum
``c* = J W I_s / I_t``) and, beside it, four whip antennas (two pairs of tip masses on springs).
Members start at each initial nutation angle of a list;
:func:`~stability.dissipation.measure.measure_explorer` runs them past the flat spin and
measures each one's growth rate against the linear eigenvalue, its time to the flat spin, its
end state, |H| and the energy. Outputs: the Dataset, three figures
(:mod:`stability.dissipation.figures`) and the study's configuration; resumable, and on dask.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from ...core.axes import MOMENT_NAMES
from ...study.config import UNSET, ConfigError, Key, Schema, Section
from ...study.kind import StudyKind, StudyRun, StudySummary, run_rows
from ...study.outputs import output_files, write_outputs
from ...study.sections import (check_memory, check_run, output_section, run_section,
                                study_run_options)
from ...util.threads import numba_threads
from .common import positive_key, worst
from ..figures import end_state_figure, flat_time_figure, nutation_figure
from ..measure import Whips, measure_explorer
from ..methods import SPHERE_METHODS
from ..model import (EXPLORER_1, RPM, Cylinder, Spinner, energy_sink_optimum,
                     equivalent_transverse_moment)

NAME = "explorer"
#: Figure stems: the nutation angle, the flat-spin time against damping, the end state.
FIGURES = ("explorer_nutation", "explorer_flat_time", "explorer_end_state")


#: The keys of a uniform solid cylinder, Explorer 1's by default (this study's and the
#: dispersed Explorer's ``[body]``).
CYLINDER_KEYS = (
    positive_key("length", EXPLORER_1.length, "length of the cylinder", "m"),
    positive_key("diameter", EXPLORER_1.diameter, "diameter of the cylinder", "m"),
    positive_key("mass", EXPLORER_1.mass, "mass of the cylinder", "kg"),
)


SCHEMA = Schema(
    top=(Key("title", "str", "Why Explorer 1 tumbled: energy dissipation turns a minor-axis "
             "spin over", "one line describing the run (the Dataset's title)"),),
    sections=(
        Section("body", "the satellite: a uniform solid cylinder spun about its long axis, or "
                "measured principal moments spun about the smallest", (
            *CYLINDER_KEYS,
            Key("moments", "floats", UNSET, "measured principal moments I1, I2, I3 (instead "
                "of length, diameter and mass)", unit="kg m2", minimum=0.0,
                exclusive_minimum=True, length=3),
            Key("axis", ("int", "str"), "smallest", "the spin axis of a body given by "
                "moments: 1, 2, 3 or the name of its moment; the smallest's (a damper turns "
                "a minor-axis spin over)", choices=(1, 2, 3) + MOMENT_NAMES),
            Key("name", "str", UNSET, "label of a body given by moments"),
            positive_key("spin", 750.0, "spin about the spin axis at release", "rpm"),
            Key("rate", "float", UNSET, "spin about the spin axis at release (instead of "
                "spin)", unit="rad/s", minimum=0.0, exclusive_minimum=True),
        ), exclusive=(("moments", "length"), ("moments", "diameter"), ("moments", "mass"),
                      ("spin", "rate"))),
        Section("damper", "the spherical damper (standing for what flexes and dissipates)", (
            positive_key("inertia", 1e-4, "moment of inertia J of the sphere", "kg m2"),
            Key("dampings", "floats", [0.1, 0.3, 1.0, 3.0, 10.0],
                "viscous coefficients c in units of the energy sink's optimum "
                "c* = J W I_s / I_t, one group each", minimum=0.0, exclusive_minimum=True),
        )),
        Section("whips", "four whip antennas: two pairs of tip masses on springs, bending "
                "along the spin axis", (
            Key("run", "bool", True, "run the whip antennas beside the sphere (RK4)"),
            positive_key("mass", 0.02, "mass of a pair of tips", "kg"),
            positive_key("arm", 0.5, "distance of the tips from the long axis", "m"),
            positive_key("frequency_ratio", 0.3, "the tips' natural frequency over the nutation "
                      "frequency the body feels", "1"),
            positive_key("damping_ratio", 0.5, "the tips' damping ratio", "1"),
            Key("angles", "floats", [0.05, 1.0], "initial nutation angles of their members",
                unit="degree", minimum=0.0, exclusive_minimum=True),
            Key("step_angle", "float", 0.06, "h times the spin (RK4 damps the nutation by "
                "~W (h W)^5 / 144)", unit="rad", minimum=0.0, exclusive_minimum=True,
                maximum=0.5),
            Key("tail", "float", 25.0, "run past the flat spin, in e-folds of their growth "
                "(their approach to the major axis is slow, algebraic)", minimum=0.0),
        )),
        Section("start", "the members of each group", (
            Key("angles", "floats", [0.02, 0.1, 0.5, 2.0, 10.0],
                "initial nutation angles between the long axis and H", unit="degree",
                minimum=0.0, exclusive_minimum=True),
            Key("seed", "int", 0, "seed of the members' azimuths", minimum=0),
        )),
        Section("integration", "the sphere's integrator, its step and the run length", (
            Key("method", "str", "lp2", "a method of scene sphere_damper",
                choices=tuple(SPHERE_METHODS)),
            Key("step_angle", "float", 0.5, "h times the spin", unit="rad", minimum=0.0,
                exclusive_minimum=True, maximum=1.5),
            Key("tail", "float", 8.0, "run past the flat spin, in e-folds of the decay about "
                "the major axis", minimum=0.0),
            Key("samples", "int", 2000, "states kept by the longest group", minimum=16),
        )),
        Section("analysis", "what the run must show", (
            Key("fit_top", "float", 0.02, "largest nutation angle of the linear regime "
                "fitted", unit="rad", minimum=0.0, exclusive_minimum=True, maximum=0.2),
            Key("flat_angle", "float", 80.0, "nutation angle that counts as a flat spin",
                unit="degree", minimum=0.0, exclusive_minimum=True, maximum=89.0),
            Key("end_tolerance", "float", 1.0, "how close to 90 degrees an end state counts "
                "as the major axis", unit="degree", minimum=0.0, exclusive_minimum=True),
            Key("claim", "float", 1e-3, "relative difference of the fitted rates from the "
                "linear eigenvalues", minimum=0.0, exclusive_minimum=True),
            Key("drift_claim", "float", 1e-12, "largest relative change of |H| with the "
                "methods that keep it", minimum=0.0, exclusive_minimum=True),
        )),
        run_section(),
        output_section(NAME, FIGURES),
    ),
)

#: ``--quick``: a sphere 10 times heavier (a 10 times faster turn), three dampings, two angles,
#: whips 20 times heavier (:data:`QUICK_NOTE` says why).
QUICK = {"damper": {"inertia": 1e-3, "dampings": [0.3, 1.0, 3.0]},
         "start": {"angles": [0.02, 1.0]},
         "whips": {"mass": 0.4, "angles": [0.05]},
         "integration": {"samples": 600}}

#: Why ``--quick`` changes the physics: the run is as long as the turn.
QUICK_NOTE = ("the physics changes too: a sphere 10 times and whips 20 times heavier turn the "
              "body over about 10 and 20 times sooner, and a run lasts as long as its turn "
              "(at Explorer's own J and whips the quick run takes 20 times the member-steps); "
              "what the run checks holds at any J (rates against the eigenvalues, every member "
              "ending about the major axis, |H| kept), but its times to the flat spin are not "
              "Explorer 1's (12 to 20 min, not 119 to 200)")


def body(config) -> Cylinder | Spinner:
    """The study's body from its ``[body]`` section: measured moments (a
    :class:`~.model.Spinner`, the spin axis's first) or a cylinder."""
    b = config["body"]
    spin = b["rate"] if "rate" in b else b["spin"] * RPM
    if "moments" in b:
        return Spinner.about(b["moments"], b["axis"], spin, name=b.get("name", "body"),
                             sources="measured moments from the study file")
    return Cylinder(b["length"], b["diameter"], b["mass"], spin,
                    name=EXPLORER_1.name if _is_explorer(b) else "cylinder",
                    sources=EXPLORER_1.sources if _is_explorer(b) else "the study file")


def _is_explorer(b) -> bool:
    return (b["length"], b["diameter"], b["mass"], b.get("spin")) == (
        EXPLORER_1.length, EXPLORER_1.diameter, EXPLORER_1.mass, 750.0)


def whips(config) -> Whips | None:
    """The whip antennas of the ``[whips]`` section, or None if they are not run."""
    w = config["whips"]
    if not w["run"]:
        return None
    return Whips(w["mass"], w["arm"], w["frequency_ratio"], w["damping_ratio"])


def check(config: dict, source: str) -> dict:
    """A long body (spun about its minor axis), angles below the flat-spin angle, a damping."""
    b = config["body"]
    if "moments" in b:
        try:
            body(config)
        except ValueError as exc:
            raise ConfigError(f"are refused: {exc}", source, "body", "moments") from None
    else:
        for key in ("name", "axis"):
            if key in b and (key == "name" or b[key] not in (1, "smallest")):
                raise ConfigError("is for a body given by moments; a cylinder spins about its "
                                  "long axis: drop it or give moments", source, "body", key)
        if b["length"] ** 2 <= 0.75 * b["diameter"] ** 2:
            raise ConfigError(f"must exceed sqrt(3)/2 times the diameter ({b['diameter']:g} m) "
                              "for the long axis to be the minor axis, got "
                              f"{b['length']:g}", source, "body", "length")
    if not config["damper"]["dampings"]:
        raise ConfigError("must list at least one damping", source, "damper", "dampings")
    _check_step(config, source)
    flat = config["analysis"]["flat_angle"]
    for section in ("start", "whips"):
        angles = config[section]["angles"]
        if not angles:
            raise ConfigError("must list at least one angle", source, section, "angles")
        if max(angles) >= flat:
            raise ConfigError(f"must be below [analysis] flat_angle = {flat:g} degrees, got "
                              f"{max(angles):g}", source, section, "angles")
    _check_memory(config, source)
    check_run(config, source)
    return config


#: The largest ``h r`` (the step times the damper's fastest relaxation rate ``r = c (1/J +
#: 1/I_s)``) of each method: the splittings' error grows as ``(h r)^2`` (0.15 (h r)^2 in the
#: rates), RK4 blows up past 2.8.
RELAXATION_STEP = {"lp2": 0.08, "lp4": 0.08, "dmv": 0.08, "rk4": 2.0}


def _check_step(config: dict, source: str) -> None:
    """Refuse a step that does not resolve the damper's relaxation. On a long body (Explorer,
    ``I_s / I_t = 0.008``) the sphere relaxes at ``r = c*/J = W I_s / I_t``, far slower than
    the spin; on a body nearly round it relaxes about as fast as it spins."""
    integ, d = config["integration"], config["damper"]
    the = body(config)
    I = np.asarray(the.moments, dtype=float)
    c = max(d["dampings"]) * energy_sink_optimum(I[0], equivalent_transverse_moment(I),
                                                 d["inertia"], the.spin)
    hr = integ["step_angle"] * c * (1.0 / d["inertia"] + 1.0 / I[0]) / the.spin
    top = RELAXATION_STEP[integ["method"]]
    if hr > top:
        fix = (f"lower it to {integ['step_angle'] * top / hr:.2g}" if integ["method"] == "rk4"
               else f"lower it to {integ['step_angle'] * top / hr:.2g}, or set method = "
               f"\"rk4\" with step_angle <= {min(0.1, 2.0 * integ['step_angle'] / hr):.2g}")
        raise ConfigError(
            f"makes h times the damper's fastest relaxation rate c (1/J + 1/I_s) {hr:.2g} at "
            f"c = {max(d['dampings']):g} c* (above {top:g} for {integ['method']}: the sphere "
            f"relaxes about as fast as the body spins); {fix}", source, "integration",
            "step_angle")


def _check_memory(config: dict, source: str) -> None:
    """Refuse a run whose kept states would not fit in memory: each member keeps up to
    ``samples`` states of 6 numbers, held about four times over while they are measured."""
    members = len(config["damper"]["dampings"]) * len(config["start"]["angles"])
    samples = config["integration"]["samples"]
    check_memory(SCHEMA, config, source, members * samples * 6 * 8 * 4,
                 [("integration", "samples")],
                 f"the states of {members} members, {samples} each",
                 "keep fewer samples, dampings or angles")


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    return output_files(config, FIGURES)


def run(config: dict, out_dir: Path, options: StudyRun) -> StudySummary:
    """Run the ensembles, save the Dataset, draw the figures; the summary against the theory.

    The members run chunk by chunk into the store of ``options.run`` (a stopped run continues
    with its ``resume``), on its ``scheduler`` (default: the file's ``[run] scheduler``)."""
    t_start = time.perf_counter()
    d, s, w, integ, a = (config["damper"], config["start"], config["whips"],
                         config["integration"], config["analysis"])
    with numba_threads(options.run.threads):
        ds = measure_explorer(
            body(config), d["inertia"], d["dampings"], np.radians(s["angles"]),
            method=integ["method"], step_angle=integ["step_angle"], tail=integ["tail"],
            samples=integ["samples"], fit_top=a["fit_top"],
            flat_angle=math.radians(a["flat_angle"]),
            end_tolerance=math.radians(a["end_tolerance"]), whips=whips(config),
            whip_angles=np.radians(w["angles"]), whip_step_angle=w["step_angle"],
            whip_tail=w["tail"], seed=s["seed"],
            options=study_run_options(config, options))
    claim = a["claim"]
    ds, files = write_outputs(
        ds, config, out_dir, NAME,
        {FIGURES[0]: nutation_figure, FIGURES[1]: flat_time_figure,
         FIGURES[2]: lambda ds: end_state_figure(ds, claim=claim)},
        overwrite=options.overwrite, history=options.history, threads=options.run.threads,
        attrs={"claim": claim, "drift_claim": a["drift_claim"]})
    return summarize(ds, out_dir, files, time.perf_counter() - t_start)


def summarize(ds, out_dir, files, wall) -> StudySummary:
    """Rates against the linear theory, the end states, |H| and the energy; the times to the
    flat spin and the optimum damping."""
    minutes = 60.0
    fitted = int(np.isfinite(ds.growth_rate_error).sum())
    values = {
        "claim": float(ds.attrs["claim"]), "drift_claim": float(ds.attrs["drift_claim"]),
        "members": int(ds.growth_rate_error.size), "members_fitted": fitted,
        "max_growth_rate_error": worst(ds.growth_rate_error),
        "max_decay_rate_error": worst(ds.decay_rate_error),
        "members_fitted_decay": int(np.isfinite(ds.decay_rate_error).sum()),
        "members_major_axis": int(ds.major_axis_end.sum()),
        "max_angular_momentum_drift": worst(ds.angular_momentum_drift),
        "max_energy_rise": worst(ds.energy_rise),
        "max_end_energy_error": worst(ds.end_energy_error),
        "energy_lost_error_smallest_angle": worst(ds.energy_lost_error.isel(angle=0)),
        "c_linear_optimum": float(ds.attrs["c_linear_optimum"]),
        "c_energy_sink_optimum": float(ds.attrs["c_energy_sink_optimum"]),
        "wall_time": wall, "integration_time": float(ds.attrs["wall_time"]),
        "member_steps": int(ds.attrs["member_steps"]),
        "members_failed": int((ds.status != 0).sum()),
    }
    g = int(np.argmin(np.abs(np.log(ds.damping.values))))
    flat = ds.flat_time.isel(damping=g)
    values["flat_time_at_c_star"] = [float(v) for v in flat.values]
    sink = ds.growth_rate_energy_sink.isel(damping=g, angle=0)
    linear = ds.growth_rate_linear.isel(damping=g, angle=0)
    values["growth_rate_at_c_star"] = [float(linear), float(sink)]
    rows = [
        ("growth rate vs linear eigenvalue, max |rel. diff.|",
         f"{values['max_growth_rate_error']:.1e} ({fitted} of {values['members']} fitted)", ""),
        ("decay about the major axis vs eigenvalue, max |rel. diff.|",
         f"{values['max_decay_rate_error']:.1e} ({values['members_fitted_decay']} fitted)", ""),
        ("  the claim", f"{values['claim']:g}", ""),
        ("members ending about the major axis",
         f"{values['members_major_axis']} of {values['members']}", ""),
        ("|H| largest relative change", f"{values['max_angular_momentum_drift']:.1e}", ""),
        ("  the claim", f"{values['drift_claim']:g}", ""),
        ("energy's largest rise between kept states", f"{values['max_energy_rise']:.1e}", ""),
        ("end energy vs |H|^2/(2 A_max), max |rel. diff.|",
         f"{values['max_end_energy_error']:.1e}", ""),
        (f"energy lost vs |H|^2/2 (1/A_min - 1/A_max) at {ds.angle.values[0]:g} degrees",
         f"{values['energy_lost_error_smallest_angle']:.1e}", ""),
        (f"time to the flat spin at c = {ds.damping.values[g]:g} c*, "
         f"{ds.angle.values[0]:g} to {ds.angle.values[-1]:g} degrees",
         f"{flat.values[0] / minutes:.1f} to {flat.values[-1] / minutes:.1f}", "min"),
        ("growth rate there: linear, energy sink",
         f"{values['growth_rate_at_c_star'][0]:.4g}, {values['growth_rate_at_c_star'][1]:.4g}",
         "s-1"),
        ("optimum damping: linear, energy sink c*",
         f"{values['c_linear_optimum']:.4g}, {values['c_energy_sink_optimum']:.4g}", "N m s"),
    ]
    if "whip_growth_rate_error" in ds:
        values.update({
            "whip_max_growth_rate_error": worst(ds.whip_growth_rate_error),
            "whip_members_fitted": int(np.isfinite(ds.whip_growth_rate_error).sum()),
            "whip_members_major_axis": int(ds.whip_major_axis_end.sum()),
            "whip_max_angular_momentum_drift": worst(ds.whip_angular_momentum_drift),
            "whip_end_angle": [float(v) for v in ds.whip_end_angle.values],
            "whip_flat_time": [float(v) for v in ds.whip_flat_time.values],
            "whip_energy_lost_error": [float(v) for v in ds.whip_energy_lost_error.values],
        })
        rows += [
            ("whips: growth rate vs linear eigenvalue, max |rel. diff.|",
             f"{values['whip_max_growth_rate_error']:.1e} "
             f"({values['whip_members_fitted']} of {ds.whip_angle.size} fitted)", ""),
            ("whips: time to the flat spin", ", ".join(
                f"{v / minutes:.1f}" for v in values["whip_flat_time"]), "min"),
            ("whips: end angle, members about the major axis",
             ", ".join(f"{v:.2f}" for v in values["whip_end_angle"])
             + f" degrees; {values['whip_members_major_axis']} of {ds.whip_angle.size}", ""),
            ("whips: energy lost vs formula - 1", ", ".join(
                f"{v:.1e}" for v in values["whip_energy_lost_error"]), ""),
            ("whips: |H| largest relative change (rk4)",
             f"{values['whip_max_angular_momentum_drift']:.1e}", ""),
        ]
    rows += run_rows(values, wall)
    return StudySummary(NAME, Path(out_dir), files, rows, values)


STUDY = StudyKind(
    name=NAME,
    title="a long body spun about its minor axis turns over into a flat spin (Explorer 1)",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    quick_note=QUICK_NOTE,
    resumable=True,
)
