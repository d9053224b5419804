"""The speed-against-error study: which integrator to use, at which accuracy, in numbers.

Every registered method (``stability.METHODS``, so methods added later join by themselves) runs two
ensembles over a sweep of step sizes h, the member loop's adaptive Dormand-Prince 5(4) over a
sweep of tolerances (each member its own steps), and scipy's DOP853 runs them as one system over
a sweep of tolerances, in the same process: **tennis** (spin about the intermediate axis, each member nudged
by ``epsilon`` in a random perpendicular direction, over a few flips: the hard, ill-conditioned
workload) and **stable** (spin about the largest or smallest axis). Each is scored against the
exact solution and the conditioning floor (:mod:`stability.free_body.accuracy`), timed
(:mod:`stability.free_body.work_precision.sweeps`), and every method also runs a **long horizon**
of ``>= 1e6`` steps to see what happens to the energy and |L|
(:mod:`stability.free_body.work_precision.drift`).

Outputs: the Dataset (:mod:`stability.free_body.work_precision.measure`), two figures
(:mod:`stability.free_body.work_precision.figures`) and ``work_precision.md``, the tables of the
fastest
method at each accuracy (shown in the documentation's "How to choose an integrator").
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from .. import accuracy as ref
from . import measure as wp
from ...core.axes import principal_axis
from ...core.body import RigidBody
from .drift import long_horizon
from ...ensemble.starts import perturbed_starts
from . import figures as figures
from ..methods import METHODS, method_names, method_spec
from ...output.dataset import software_attrs
from .sweeps import jittered_starts, step_grid, sweep_adaptive, sweep_method, sweep_scipy
from ...util.progress import progress_bar
from ...util.threads import numba_threads
from ...study.config import ConfigError, Key, Schema, Section
from ...study.kind import StudyKind, StudyRun, StudySummary
from ...study.outputs import output_files, write_outputs
from ...study.sections import check_memory, output_section

NAME = "work_precision"

#: Figure stems.
FIGURES = ("work_precision", "invariant_drift")


SCHEMA = Schema(
    top=(
        Key("title", "str", "Speed against error of every integrator on the free rigid body",
            "one line describing the run (the Dataset's title)"),
    ),
    sections=(
        Section("body", "the rigid body, by its principal moments", (
            Key("moments", "floats", [1.0, 2.0, 3.0], "principal moments I1, I2, I3 (distinct)",
                unit="kg m2", minimum=0.0, exclusive_minimum=True, length=3),
            Key("physical", "bool", True,
                "require the triangle inequality of real bodies (false: mathematical body)"),
            Key("name", "str", "body", "label of the body"),
        )),
        Section("tennis", "ensemble spun about the intermediate axis (the hard workload)", (
            Key("members", "int", 10_000, "number of members", minimum=1),
            Key("spin", "float", 1.0, "spin rate W", unit="rad s-1", minimum=0.0,
                exclusive_minimum=True),
            Key("epsilon", "float", 1e-2,
                "perturbation relative to the spin, random perpendicular direction",
                minimum=0.0, exclusive_minimum=True, maximum=1.0),
            Key("t_end", "float", 50.0, "horizon (a few flip intervals)", unit="s",
                minimum=0.0, exclusive_minimum=True),
            Key("seed", "int", 1, "seed of the random directions", minimum=0),
        )),
        Section("stable", "ensemble spun about a stable axis", (
            Key("axis", "str", "largest", "the stable axis: the one with this moment",
                choices=("smallest", "largest")),
            Key("members", "int", 10_000, "number of members", minimum=1),
            Key("spin", "float", 1.0, "spin rate W", unit="rad s-1", minimum=0.0,
                exclusive_minimum=True),
            Key("epsilon", "float", 0.1, "perturbation relative to the spin",
                minimum=0.0, exclusive_minimum=True, maximum=1.0),
            Key("t_end", "float", 50.0, "horizon", unit="s", minimum=0.0,
                exclusive_minimum=True),
            Key("seed", "int", 2, "seed of the random directions", minimum=0),
        )),
        Section("sweep", "the step sizes tried per method", (
            Key("methods", "strs", [], "methods to run; empty: every registered method",
                choices=method_names),
            Key("h_max", "float", 0.5, "largest step (times spin: the step's rotation angle)",
                unit="s", minimum=0.0, exclusive_minimum=True),
            Key("h_min", "float", 1e-4, "smallest step tried", unit="s", minimum=0.0,
                exclusive_minimum=True),
            Key("per_octave", "int", 1, "step sizes per halving of h", minimum=1),
            Key("budget", "float", 6.0,
                "kernel seconds per method and workload; a step size whose predicted time "
                "would exceed it is not run", unit="s", minimum=0.0, exclusive_minimum=True),
            Key("stop_error", "float", 1e-13,
                "stop refining a method once its median relative w error is below this",
                minimum=0.0, exclusive_minimum=True),
        )),
        Section("adaptive", "the member loop's adaptive Dormand-Prince 5(4), each member its "
                "own steps", (
            Key("enabled", "bool", True, "run it"),
            Key("rtols", "floats", [1e-4, 1e-6, 1e-8, 1e-10, 1e-12],
                "relative tolerances, one sweep point each", minimum=1e-15, maximum=0.1),
            Key("atols", "floats", [1e-7, 1e-9, 1e-11, 1e-13, 1e-15],
                "absolute tolerances on m = I w, one per rtol", unit="kg m2 s-1", minimum=0.0),
        )),
        Section("scipy", "scipy's DOP853 on each ensemble as one system", (
            Key("enabled", "bool", True, "run it"),
            Key("rtols", "floats", [1e-3, 1e-5, 1e-7, 1e-9, 1e-11, 1e-13],
                "relative tolerances (atol = rtol x spin)", minimum=1e-15, maximum=0.1),
        )),
        Section("attitude", "attitude errors, for the methods that carry the attitude", (
            Key("members", "int", 1000,
                "members of each ensemble (the first ones) also run with their attitude; 0: "
                "no attitude", minimum=0),
        )),
        Section("long", "the long-horizon run for invariant behaviour", (
            Key("steps", "int", 1_000_000, "steps per method", minimum=100),
            Key("h", "float", 0.1, "step", unit="s", minimum=0.0, exclusive_minimum=True),
            Key("members", "int", 8, "members (starts jittered around w0); errors are RMS over "
                "them", minimum=1),
            Key("w0", "floats", [0.3, 1.0, 0.9], "central start", unit="rad s-1", length=3),
            Key("samples", "int", 10_000, "states kept per member (evenly spaced)", minimum=10),
            Key("seed", "int", 3, "seed of the jitter", minimum=0),
        )),
        output_section(NAME, FIGURES, extra=(
            Key("table", "str", "work_precision.md", "file name of the Markdown tables"),)),
    ),
)

#: ``--quick``: small ensembles, a few step sizes, a short long-horizon run (used by the tests).
QUICK = {
    "tennis": {"members": 256, "t_end": 30.0},
    "stable": {"members": 256, "t_end": 30.0},
    "sweep": {"h_max": 0.5, "h_min": 0.03, "per_octave": 1, "budget": 2.0},
    "adaptive": {"rtols": [1e-6, 1e-9], "atols": [1e-9, 1e-12]},
    "scipy": {"rtols": [1e-4, 1e-8]},
    "attitude": {"members": 32},
    "long": {"steps": 20_000, "members": 4, "samples": 1000},
}


def check(config: dict, source: str) -> dict:
    """Checks across keys: distinct moments, h_min < h_max, the long run's samples fit."""
    try:
        _body(config)
    except ValueError as exc:
        raise ConfigError(str(exc), source, "body") from None
    moments = sorted(config["body"]["moments"])
    if moments[0] == moments[1] or moments[1] == moments[2]:
        raise ConfigError(
            f"must be three distinct moments (the study needs an intermediate axis), got "
            f"{config['body']['moments']}", source, "body", "moments",
        )
    adaptive = config["adaptive"]
    if len(adaptive["atols"]) != len(adaptive["rtols"]):
        raise ConfigError(f"must give one atol per rtol ({len(adaptive['rtols'])}), got "
                          f"{len(adaptive['atols'])}", source, "adaptive", "atols")
    sweep = config["sweep"]
    if sweep["h_min"] > sweep["h_max"]:
        raise ConfigError(f"must be <= h_max = {sweep['h_max']}, got {sweep['h_min']}",
                          source, "sweep", "h_min")
    long = config["long"]
    if long["samples"] > long["steps"]:
        raise ConfigError(f"must be <= steps = {long['steps']}, got {long['samples']}",
                          source, "long", "samples")
    if not all(math.isfinite(x) for x in long["w0"]) or not any(long["w0"]):
        raise ConfigError(f"must be finite and not zero, got {long['w0']}", source, "long", "w0")
    _check_memory(config, source)
    return config


def _check_memory(config: dict, source: str) -> None:
    """Refuse a study whose arrays would not fit in memory, before any is allocated.

    A rough upper bound: per workload member, its start, reference and end states and one
    error per method and step size (plus scipy's DOP853 stages on the ensemble as one system);
    the long run keeps ``samples`` states of each member for every method.
    """
    sweep, long = config["sweep"], config["long"]
    n_methods = len(sweep["methods"]) or len(METHODS)
    n_steps = 1 + sweep["per_octave"] * max(0.0, math.log2(sweep["h_max"] / sweep["h_min"]))
    per_member = 8 * (3 * 16 + n_methods * (int(n_steps) + 1) * 2)
    for section in ("tennis", "stable"):
        members = config[section]["members"]
        check_memory(SCHEMA, config, source, members * per_member, [(section, "members")],
                     f"the states and errors of {members} members for {n_methods} methods at "
                     f"up to {int(n_steps)} steps each", "use fewer members")
    check_memory(SCHEMA, config, source, n_methods * long["members"] * long["samples"] * 3 * 8 * 3,
                 [("long", "samples"), ("long", "members")],
                 f"{long['samples']} samples x {long['members']} members x {n_methods} methods",
                 "keep fewer samples or members")


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    return output_files(config, FIGURES, extra=("table",))


def _body(config: dict) -> RigidBody:
    b = config["body"]
    return RigidBody(*b["moments"], physical=b["physical"], name=b["name"])


# ----------------------------------------------------------------------------------- the run


def run(config: dict, out_dir: Path, options: StudyRun) -> StudySummary:
    """Run the study described by the resolved ``config``; write its files into ``out_dir``.

    Returns
    -------
    StudySummary
        Rows: the fastest method per accuracy target on the tennis workload, the conditioning
        floor, the long-horizon behaviour per method, and the run time.
    """

    with numba_threads(options.run.threads):
        ds, wall = measure(config, progress=options.run.progress)
    ds, files = write_outputs(
        ds, config, out_dir, NAME,
        dict(zip(FIGURES, (figures.work_precision_figure, figures.invariant_drift_figure))),
        overwrite=options.overwrite, history=options.history, threads=options.run.threads,
        texts={config["output"]["table"]: wp.markdown_report(ds)})
    return summarize(ds, out_dir, files, wall)


def measure(config: dict, progress=None):
    """Do every measurement of the study; return the Dataset and the wall time in s."""
    t_start = time.perf_counter()
    body = _body(config)
    methods = [method_spec(m) for m in _selected_methods(config)]
    sweep = config["sweep"]
    bar = progress_bar(2 * (len(methods) + 2) + len(methods), progress, NAME)
    results, floors, reference_errors = {}, {}, {}
    for workload in wp.WORKLOADS:
        section = config[workload]
        which = "intermediate" if workload == "tennis" else section["axis"]
        w0 = perturbed_starts(principal_axis(body, which), section["spin"], section["epsilon"],
                              section["members"], seed=section["seed"])
        t_end = section["t_end"]
        w_ref = ref.exact_final_w(body, w0, t_end)
        floors[workload] = ref.error_statistics(
            ref.conditioning_floor(body, w0, t_end, w_ref, section["seed"]))
        counts = step_grid(t_end, sweep["h_max"], sweep["h_min"], sweep["per_octave"])
        k = min(config["attitude"]["members"], len(w0))
        attitude = None
        if k > 0:
            q_ref, reference_error = ref.attitude_reference(body, w0[:k], t_end)
            reference_errors[workload] = ref.error_statistics(reference_error)
            attitude = (k, q_ref)
        for spec in methods:
            bar.set_postfix_str(f"{workload}: {spec.name}")
            results[(workload, spec.name)] = sweep_method(
                spec, body, w0, w_ref, t_end, counts, sweep["budget"], sweep["stop_error"],
                attitude)
            bar.update(1)
        if config["adaptive"]["enabled"]:
            bar.set_postfix_str(f"{workload}: {wp.ADAPTIVE}")
            results[(workload, wp.ADAPTIVE)] = sweep_adaptive(
                body, w0, w_ref, t_end, config["adaptive"]["rtols"], config["adaptive"]["atols"])
        bar.update(1)
        if config["scipy"]["enabled"]:
            bar.set_postfix_str(f"{workload}: scipy {wp.SCIPY}")
            results[(workload, wp.SCIPY)] = sweep_scipy(
                body, w0, w_ref, t_end, config["scipy"]["rtols"], section["spin"])
        bar.update(1)
    long = config["long"]
    w0_long = jittered_starts(np.asarray(long["w0"], dtype=float), long["members"], long["seed"])
    long_results = {}
    for spec in methods:
        bar.set_postfix_str(f"long horizon: {spec.name}")
        long_results[spec.name] = long_horizon(
            spec, body, w0_long, long["h"], long["steps"], long["samples"])
        bar.update(1)
    bar.close()
    wall = time.perf_counter() - t_start
    ds = wp.work_precision_dataset(_selected_methods(config), results, floors, long_results,
                                   reference_errors, _global_attrs(config, body, wall))
    return ds, wall


def _global_attrs(config, body, wall_total) -> dict:
    tennis, stable, long = config["tennis"], config["stable"], config["long"]
    return {
        "title": config["title"],
        **software_attrs(),
        "references": "literature notes (shared/notes/literature.md) sections 1.5, 3, 4; "
                      "Hairer, Lubich & Wanner, Geometric Numerical Integration (2006)",
        "body": repr(body),
        "I1": body.I1, "I2": body.I2, "I3": body.I3,
        "tennis_workload": (
            f"{tennis['members']} members, spin {tennis['spin']} rad/s about the intermediate "
            f"axis {principal_axis(body, 'intermediate')}, epsilon {tennis['epsilon']}, "
            f"t_end {tennis['t_end']} s, seed {tennis['seed']}"),
        "stable_workload": (
            f"{stable['members']} members, spin {stable['spin']} rad/s about the "
            f"{stable['axis']}-moment axis {principal_axis(body, stable['axis'])}, epsilon "
            f"{stable['epsilon']}, t_end {stable['t_end']} s, seed {stable['seed']}"),
        "long_workload": (
            f"{long['members']} members jittered by 1e-3 around w0 = {long['w0']} rad/s, "
            f"h = {long['h']} s, {long['steps']} steps"),
        "wall_time_total": float(wall_total),
    }


def _selected_methods(config) -> list[str]:
    return list(config["sweep"]["methods"]) or list(METHODS)


def summarize(ds, out_dir: Path, files, wall: float) -> StudySummary:
    """Headline numbers (:func:`stability.free_body.work_precision.measure.headline`) and the run time."""
    rows, values = wp.headline(ds)
    rows.append(("run time", f"{wall:.1f}", "s"))
    values["wall_time"] = wall
    return StudySummary(study=NAME, out_dir=Path(out_dir), files=list(files), rows=rows,
                        values=values)


STUDY = StudyKind(
    name=NAME,
    title="speed against error of every integrator, and its invariants over long runs",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    members_key=("tennis", "members"),
)
