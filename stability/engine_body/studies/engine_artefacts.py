"""The engine-artefacts study: the tennis-racket ensemble stepped with physics engines' update rules.

The ensemble of :mod:`stability.free_body.tennis_racket.study` (a racket tossed about its middle
axis, nudged by epsilon of the spin) is run with each engine rule (explicit, semi-implicit and
implicit Euler, |L| or energy rescaled, no gyroscopic term) and, beside them, with the package's
integrators, at the frame rates engines use;
:func:`stability.engine_body.measure.measure_artefacts` measures what each does to the flip and
the invariants and the step each needs for the flip interval within a tolerance. Outputs: the
Dataset, the figure (:mod:`stability.engine_body.figures`) and the study's configuration.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ...core.body import RigidBody
from ...ensemble.starts import perturbed_starts
from ...study.config import ConfigError, Key, Schema, Section
from ...study.kind import StudyKind, StudyRun, StudySummary, SummaryTable
from ...study.outputs import output_files, write_outputs
from ...study.sections import (
    MEMBER_BYTES, check_memory, check_run, output_section, run_section, study_run_options,
    tossed_body_sections
)
from ...util.threads import numba_threads
from ..figures import artefacts_figure
from ..measure import integrator_rules, measure_artefacts
from ..methods import ENGINE_RULES

BODY, RATE = tossed_body_sections()

NAME = "engine_artefacts"
FIGURE = "engine_artefacts"

SCHEMA = Schema(
    top=(Key("title", "str", "What physics engines do to the tennis-racket flip",
             "one line describing the run (the Dataset's title)"),),
    sections=(
        BODY,
        Section("toss", "the spin and its nudge", (
            RATE,
            Key("epsilon", "float", 1e-4, "nudge across the axis relative to W, random "
                "direction", minimum=0.0, exclusive_minimum=True, maximum=0.5),
        )),
        Section("ensemble", "the members", (
            Key("members", "int", 256, "number of tossed bodies", minimum=2),
            Key("seed", "int", 1, "seed of the nudges' directions", minimum=0),
        )),
        Section("rules", "what steps the ensemble", (
            Key("engine", "strs", ["explicit_euler", "semi_implicit_euler", "implicit_euler",
                                   "rescaled_momentum", "rescaled_energy", "no_gyroscopic"],
                "engine update rules (stability.engine_body.methods.ENGINE_RULES)"),
            Key("methods", "strs", ["rk4", "lp2", "dmv", "midpoint", "exact"],
                "the package's methods beside them (attitude methods, or exact)"),
            Key("frame_rates", "floats", [60.0, 120.0, 240.0], "steps per second engines use "
                "(h = 1 / rate)", unit="1/s", minimum=0.0, exclusive_minimum=True),
            Key("t_end", "float", 10.0, "simulated time, a whole number of every step",
                unit="s", minimum=0.0, exclusive_minimum=True),
        )),
        Section("analysis", "the step each rule needs", (
            Key("tolerance", "float", 0.01, "flip interval (and, separately, the energy) within "
                "this fraction of the exact",
                minimum=0.0, exclusive_minimum=True, maximum=0.5),
            Key("search_members", "int", 64, "members used to search that step", minimum=2),
            Key("halvings", "int", 12, "search down to the first step / 2^halvings",
                minimum=0, maximum=20),
        )),
        run_section(),
        output_section(NAME, (FIGURE,)),
    ),
)

QUICK = {"ensemble": {"members": 32}, "analysis": {"search_members": 16, "halvings": 6},
         "rules": {"methods": ["rk4", "lp2", "exact"]}}


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    return output_files(config, (FIGURE,))


def check(config: dict, source: str) -> dict:
    """Known rules and methods, and a horizon that is a whole number of steps."""

    rules = config["rules"]
    for rule in rules["engine"]:
        if rule not in ENGINE_RULES:
            raise ConfigError(f"has {rule!r}, not an engine rule; rules: "
                              f"{', '.join(ENGINE_RULES)}", source, "rules", "engine")
    allowed = integrator_rules()
    for method in rules["methods"]:
        if method not in allowed:
            raise ConfigError(f"has {method!r}; methods that can run here: "
                              f"{', '.join(allowed)}", source, "rules", "methods")
    if not rules["engine"] + rules["methods"]:
        raise ConfigError("lists no rule and no method: nothing to run", source, "rules",
                          "engine")
    for rate in rules["frame_rates"]:
        steps = rules["t_end"] * rate
        if abs(steps - round(steps)) > 1e-9 * steps:
            raise ConfigError(f"= {rules['t_end']:g} s is not a whole number of steps at "
                              f"{rate:g} per second", source, "rules", "t_end")
    if not rules["frame_rates"]:
        raise ConfigError("must list at least one frame rate", source, "rules", "frame_rates")
    members, n_rules = config["ensemble"]["members"], len(rules["engine"] + rules["methods"])
    trace = rules["t_end"] * min(rules["frame_rates"]) + 1  # each rule's w2 at its largest step
    check_memory(SCHEMA, config, source, members * MEMBER_BYTES + n_rules * trace * 8 * 2,
                 [("ensemble", "members"), ("rules", "t_end")],
                 f"{members} members and {n_rules} traces of {trace:.0f} steps",
                 "use fewer members or a shorter t_end")
    check_run(config, source)
    return config


def run(config: dict, out_dir: Path, options: StudyRun) -> StudySummary:
    """Step the ensemble with every rule at every frame rate; save the Dataset and the figure.

    Every run goes chunk by chunk into a folder of its own in the store of ``options.run`` (so
    that a stopped run continues with its ``resume``), on its ``scheduler`` (default: the file's
    ``[run] scheduler``)."""

    t_start = time.perf_counter()
    toss, ens, rules, analysis = (config["toss"], config["ensemble"], config["rules"],
                                  config["analysis"])
    body = RigidBody.preset(config["body"]["preset"])
    moments = np.sort(body.moments)
    w0 = perturbed_starts(2, toss["rate"], toss["epsilon"], ens["members"], ens["seed"])
    steps = [1.0 / rate for rate in sorted(rules["frame_rates"])]  # the largest step first
    with numba_threads(options.run.threads):
        ds = measure_artefacts(rules["engine"] + rules["methods"], moments, w0, steps,
                               rules["t_end"], tolerance=analysis["tolerance"],
                               search_members=min(analysis["search_members"], ens["members"]),
                               halvings=analysis["halvings"],
                               options=study_run_options(config, options))
    ds, files = write_outputs(ds, config, out_dir, NAME, {FIGURE: artefacts_figure},
                              overwrite=options.overwrite, history=options.history,
                              threads=options.run.threads,
                              attrs={"body": body.name})
    return summarize(ds, out_dir, files, time.perf_counter() - t_start)


def summarize(ds, out_dir, files, wall) -> StudySummary:
    """Per rule at the largest step: flips, flip interval, growth, drifts; the step it needs."""
    h = float(ds.step[0])
    first = ds.isel(step=0)
    values = {"wall_time": wall, "step": h, "rules": {}}
    rows = [(f"{ds.attrs['members']} members, h = {h:.4g} s; exact flip interval",
             f"{ds.attrs['flip_interval_exact']:.4f}", "s"),
            ("exact growth rate sqrt(-Omega^2)", f"{ds.attrs['growth_rate_exact']:.4f}", "1/s")]
    table = SummaryTable(
        f"each rule at h = {h:.4g} s; steps: the largest keeping the flip interval (the energy) "
        f"within {100 * ds.attrs['tolerance']:g} %",
        [("rule", ""), ("flipping", "%"), ("flip interval", "rel. error"),
         ("growth rate", "rel. error"), ("energy drift", "rel."), ("|L| drift", "rel."),
         ("step for flips", "s"), ("step for energy", "s")])
    for k, rule in enumerate(ds.rule.values):
        r = {name: float(first[name][k]) for name in (
            "fraction_flipping", "flip_interval_error", "growth_rate_error", "energy_drift",
            "momentum_drift", "l_direction_drift", "cost_per_step")}
        r["step_needed"] = float(ds.step_needed[k])
        r["step_needed_energy"] = float(ds.step_needed_energy[k])
        values["rules"][str(rule)] = r
        table.rows.append((str(rule), f"{100 * r['fraction_flipping']:.0f}",
                           _error(r["flip_interval_error"], "no flip"),
                           _error(r["growth_rate_error"], "no growth"),
                           _error(r["energy_drift"]), _error(r["momentum_drift"]),
                           _step(r["step_needed"]), _step(r["step_needed_energy"])))
    rows.append(("wall time", f"{wall:.1f}", "s"))
    return StudySummary(NAME, Path(out_dir), files, rows, values, [table])


def _step(h) -> str:
    return "not reached" if np.isnan(h) else f"{h:.2e}"


def _error(value, why="") -> str:
    """A relative error, signed; ``why`` in words where there is none (NaN)."""
    return why if np.isnan(value) else f"{value:+.1e}"


STUDY = StudyKind(
    name=NAME,
    title="physics engines' update rules on the tennis-racket flip",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    resumable=True,
)
