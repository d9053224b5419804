"""The tennis-racket study: an ensemble spun about the intermediate axis flips, again and again.

A real-looking body (a preset such as the tennis racket, or given moments) spins at ``rate``
about a principal axis (by default the intermediate one), each member perturbed by ``epsilon``
(relative to the spin) in a random direction perpendicular to it. The study runs the ensemble
with :func:`stability.run_ensemble`, adds the analytic answers (Omega^2, the growth rate
``sqrt(-Omega^2)``, each member's exact flip interval 2K/nu and its asymptote
(2/lambda) ln(4/k'), literature notes 1.5 and 2.1) and the measured growth rate, saves the
Dataset and draws the four figures of :mod:`stability.free_body.tennis_racket.figures`.

The ensemble is measured chunk by chunk where each chunk ran
(:mod:`stability.free_body.tennis_racket.measure`): every member's summaries and numbers are
kept, the time series only of ``[output] series_members`` members (256 by default, evenly
spread; ``"all"`` keeps every member's), and the amplitude quantiles come from histograms summed
over the chunks, so a run of a million members holds their summaries and one chunk's series.
The summary ends with where the time went (integration, measuring, chunk files, joining,
figures, the Dataset's write, compiling).

The measured growth rate is :func:`stability.measured_growth_rate` of the saved Dataset, which
records its window (``[analysis] fit_above`` and ``fit_below`` as the attributes
``growth_window_low_factor`` and ``growth_window_high_fraction``), so that
``ds.stability.measured_growth_rate()`` gives the number the summary prints: each member's
``ln sqrt(w_b^2 + w_c^2)`` fitted by a straight line over its *linear phase*, from
``fit_above`` times its start ``epsilon * rate`` (the decaying eigenmode has died out) to
``fit_below`` times the rate (before the nonlinearity bends the curve, whose relative effect on
the slope is about ``(a / rate)^2 / 2``), and the mean over members.
"""

from __future__ import annotations

import math
import re
import sys
import time
from pathlib import Path

from ...core.axes import MOMENT_NAMES, spin_axis
from ..attitude import FREE_BODY_SCENES, attitude_methods, carries_attitude
from ...core.body import RigidBody
from ..ensemble_plan import (DEFAULT_LEVELS, PEAK_COPIES, OutOfRange, check_random_starts,
                             ensemble_memory)
from ..streamed import run_streamed
from .measure import STUDY_MEMBER_NUMBERS, TennisChunks, analysis_headline, finish_analysis
from ...ensemble.combine import DEFAULT_SERIES_MEMBERS, series_count
from ...ensemble.options import RunOptions
from ...output.dataset import summary_bytes
from . import figures as tennis
from ...util.formatting import format_bytes
from ...study.config import UNSET, ConfigError, Key, Schema, Section
from ...study.kind import StudyKind, StudyRun, StudySummary
from ...study.outputs import output_files, write_outputs
from ..methods import method_names
from ...study.sections import (
    check_memory, check_run, output_section, preset_names, run_section
)

NAME = "tennis_racket"

#: Spin axes a study file may name: a body axis, or the axis with that moment.
AXIS_NAMES = MOMENT_NAMES

#: Figure file stems, in the order of the issue: flips, polhodes, growth, flip intervals.
FIGURES = ("fig1_flips", "fig2_polhodes", "fig3_growth", "fig4_flip_intervals")


SCHEMA = Schema(
    top=(Key("title", "str", UNSET,
             "one line describing the run (the Dataset's title); unset: named from the body, "
             "'Tennis-racket flips of a perturbed spin about the intermediate axis' for the "
             "racket, 'Phone flips ...' for the phone"),),
    sections=(
        Section("body", "the rigid body: a preset, or its principal moments", (
            Key("preset", "str", "tennis_racket", "a body from RigidBody.presets()",
                choices=preset_names),
            Key("moments", "floats", UNSET, "principal moments I1, I2, I3 (instead of preset)",
                unit="kg m2", minimum=0.0, exclusive_minimum=True, length=3),
            Key("physical", "bool", True,
                "require the triangle inequality of real bodies (false: mathematical body)"),
            Key("name", "str", UNSET, "label of a body given by moments"),
        ), exclusive=(("preset", "moments"),)),
        Section("spin", "the steady spin that is perturbed", (
            Key("axis", ("int", "str"), "intermediate",
                "principal axis of the spin: 1, 2, 3, or the axis with that moment",
                choices=(1, 2, 3) + AXIS_NAMES),
            Key("rate", "float", 10.0, "spin rate W", unit="rad s-1",
                minimum=0.0, exclusive_minimum=True),
        )),
        Section("ensemble", "the perturbed members", (
            Key("members", "int", 10_000, "number of members", minimum=1),
            Key("epsilon", "float", 1e-4,
                "perturbation size relative to the spin, in a random perpendicular direction",
                minimum=0.0, exclusive_minimum=True, maximum=1.0),
            Key("seed", "int", 1, "seed of the random directions (numpy SeedSequence entropy)",
                minimum=0),
        )),
        Section("integration", "what is integrated, the integrator and the time grid", (
            Key("scene", "str", "free_body",
                "what is integrated: w alone (free_body), or w and each member's attitude q "
                "(free_body_attitude, with a method that carries it)", choices=FREE_BODY_SCENES),
            Key("method", "str", "rk4", "integrator (stability methods lists them)",
                choices=method_names),
            Key("h", "float", 2e-3, "step", unit="s", minimum=0.0, exclusive_minimum=True),
            Key("t_end", "float", 10.0, "horizon: a whole number of save_every steps", unit="s",
                minimum=0.0, exclusive_minimum=True),
            Key("save_every", "int", 25, "keep w every save_every steps", minimum=1),
        )),
        Section("analysis", "the growth-rate fit over the linear phase", (
            Key("fit_above", "float", 10.0,
                "start each member's fit when its amplitude exceeds this times epsilon * rate",
                minimum=1.0, exclusive_minimum=True),
            Key("fit_below", "float", 0.03,
                "end it before the amplitude exceeds this times rate (or its saturation)",
                minimum=0.0, exclusive_minimum=True, maximum=1.0),
        )),
        run_section(
            Key("chunk_members", "int", 32768,
                "members per chunk: each finished chunk is measured and kept at once, so a "
                "stopped run continues from there (stability run --resume); a chunk's time "
                "series are held while it is measured", minimum=1),
            extra=(Key("device", "str", "cpu",
                       "where the member loop runs: 'cpu', or 'gpu' (a CUDA GPU, the gpu extra)",
                       choices=("cpu", "gpu")),),
            title="how the ensemble is cut into chunks, and where they run"),
        output_section(NAME, FIGURES, dataset=Key(
            "dataset", "str", UNSET, "file name of the Dataset (netCDF); unset: named from the "
            f"body, {NAME}.nc for the racket (or a body by moments without a name), phone.nc "
            "for the phone", suffix=".nc"), extra=(Key(
                "series_members", ("int", "str"), DEFAULT_SERIES_MEMBERS,
                "members whose time series w are kept, evenly spread over the ensemble "
                "('all': every member's); every member's summaries are kept whatever this is"),)),
    ),
)

#: ``--quick``: a small ensemble over two flip intervals, for tests and a first look.
QUICK = {"ensemble": {"members": 256}, "integration": {"t_end": 5.0}}


def named_from_body(config: dict) -> tuple[str, str]:
    """The title and the Dataset's file name of a run whose file sets neither: from the preset
    (or the ``[body] name`` of moments), the tennis racket's own for the racket.

    Returns
    -------
    title, dataset : str
        E.g. ``"Phone flips of a perturbed spin about the intermediate axis"``, ``"phone.nc"``.
    """
    body, axis = config["body"], config["spin"]["axis"]
    label = body.get("name") if "moments" in body else body.get("preset", NAME)
    about = f"axis {axis}" if isinstance(axis, int) else f"the {axis} axis"
    if label is None or label == NAME:
        head = "Tennis-racket flips" if label == NAME else "Flips"
        return f"{head} of a perturbed spin about {about}", f"{NAME}.nc"
    words = label.replace("_", " ").strip()
    stem = re.sub(r"[^A-Za-z0-9_.-]+", "_", label).strip("_.") or NAME
    return f"{words[:1].upper()}{words[1:]} flips of a perturbed spin about {about}", f"{stem}.nc"


def check(config: dict, source: str) -> dict:
    """Checks across keys: body given once, a whole number of samples, a non-empty fit window;
    the title and the Dataset's file named from the body where the file sets neither
    (:func:`named_from_body`)."""
    body, integ, analysis = config["body"], config["integration"], config["analysis"]
    if "moments" not in body and "name" in body:
        raise ConfigError("name labels a body given by moments; a preset has its own name",
                          source, "body", "name")
    title, dataset = named_from_body(config)
    config.setdefault("title", title)
    config["output"].setdefault("dataset", dataset)
    n_steps = integ["t_end"] / integ["h"]
    if abs(n_steps - round(n_steps)) > 1e-9 * n_steps or round(n_steps) < 1:
        raise ConfigError(
            f"must be a whole number of steps h = {integ['h']} s, got t_end / h = {n_steps:.12g}",
            source, "integration", "t_end",
        )
    n_steps = round(n_steps)
    if n_steps % integ["save_every"]:
        raise ConfigError(
            f"must divide the number of steps t_end / h = {n_steps}, got {integ['save_every']}",
            source, "integration", "save_every",
        )
    start = analysis["fit_above"] * config["ensemble"]["epsilon"]
    if start >= analysis["fit_below"]:
        raise ConfigError(
            f"must be > fit_above * [ensemble] epsilon = {start:g} (the fit window is "
            f"empty), got {analysis['fit_below']}",
            source, "analysis", "fit_below",
        )
    try:
        rigid = _body(config)
    except ValueError as exc:  # "[body] moments (1, 2, 4) violate ...", naming the key
        key = "moments" if "moments" in body else ""
        text = str(exc).removeprefix("moments ") if key else str(exc)
        raise ConfigError(text, source, "body", key) from None
    _check_spin_range(config, rigid, source)
    if carries_attitude(integ["scene"]):
        if integ["method"] not in attitude_methods():
            raise ConfigError(
                f"must carry the attitude with scene = 'free_body_attitude': one of "
                f"{', '.join(attitude_methods())}, got {integ['method']!r}",
                source, "integration", "method")
        if config["run"]["device"] != "cpu":
            raise ConfigError("must be 'cpu' with scene = 'free_body_attitude' (the GPU loop "
                              "carries w alone)", source, "run", "device")

    try:
        _kept_count(config)
    except ValueError as exc:  # "series_members must be ...", naming the key
        raise ConfigError(str(exc).removeprefix("series_members "), source, "output",
                          "series_members") from None
    members = config["ensemble"]["members"]
    check_memory(  # every member's summaries, one chunk's series, the sample's
        SCHEMA, config, source, held_bytes(config),
        [("ensemble", "members"), ("output", "series_members"), ("run", "chunk_members")],
        f"the summaries of {members} members with the series of "
        f"{_kept_count(config)} of them", "use fewer members, fewer [output] series_members, "
        "fewer [run] chunk_members or a larger [integration] save_every")
    check_run(config, source)
    return config


def _kept_count(config: dict) -> int:
    """Members whose series the run keeps (:func:`~stability.ensemble.combine.series_count`)."""
    return series_count(config["ensemble"]["members"], config["output"]["series_members"])


def _series_bytes(config: dict, members: int) -> int:
    """Bytes of the time series of ``members`` members (``w``, and ``q`` with the attitude)."""
    integ = config["integration"]
    saved = round(integ["t_end"] / integ["h"]) // integ["save_every"]
    return ensemble_memory(members, saved, scene=integ["scene"]) - members * summary_bytes(
        DEFAULT_LEVELS.size)


def _summaries_bytes(config: dict) -> int:
    """Bytes of every member's summaries, with the study's own per-member numbers."""
    return config["ensemble"]["members"] * (summary_bytes(DEFAULT_LEVELS.size)
                                            + 8 * STUDY_MEMBER_NUMBERS)


#: Every member's summaries held while the run is joined and written, in copies (the joined
#: arrays, and what the figures and the write hold beside them: measured 1.6 on a million
#: members, 0.27 GB of summaries).
SUMMARY_COPIES = 1.6


def held_bytes(config: dict) -> int:
    """Memory a run holds at its peak, at most: the larger of its two phases (each chunk's
    series in their working copies while it runs and is measured, then every member's
    summaries while the chunks are joined, analysed, drawn and written), and the series of
    the sample in both."""
    chunk = min(config["run"]["chunk_members"], config["ensemble"]["members"])
    running = PEAK_COPIES * _series_bytes(config, chunk)
    joined = SUMMARY_COPIES * _summaries_bytes(config)
    return int(max(running, joined) + 2 * _series_bytes(config, _kept_count(config)))


def _check_spin_range(config: dict, body, source: str) -> None:
    """Refuse a spin (or a nudge) that no step can follow to t_end, naming its key."""
    spin, ens, integ = config["spin"]["rate"], config["ensemble"], config["integration"]
    try:
        check_random_starts(body, spin_axis(body, config["spin"]["axis"]), spin,
                            ens["epsilon"], ens["members"], h=integ["h"], t_end=integ["t_end"],
                            seed=ens["seed"], method=integ["method"])
    except OutOfRange as exc:
        if exc.argument == "h":  # the step, not the spin: named as the key to change
            raise ConfigError(f"= {integ['h']:g} s is {exc.reason}", source, "integration",
                              "h") from None
        section, key, value = (("spin", "rate", f"{spin:g} rad/s") if exc.argument == "spin"
                               else ("ensemble", "epsilon", f"{ens['epsilon']:g}"))
        raise ConfigError(f"= {value} is out of range: {exc.reason}; use a smaller {key}",
                          source, section, key) from None


def expected_bytes(config: dict) -> int:
    """Disk space of a run at most: its chunk files and the Dataset (uncompressed), each with
    every member's summaries and the sample's series."""
    return 2 * (_summaries_bytes(config) + _series_bytes(config, _kept_count(config)))


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    return output_files(config, FIGURES)


# ----------------------------------------------------------------------------------- the run


def run(config: dict, out_dir: Path, options: StudyRun) -> StudySummary:
    """Run the study described by the resolved ``config``; write its files into ``out_dir``.

    The ensemble is streamed chunk by chunk into the store of ``options.run`` (the work folder,
    of uncompressed scratch files, :mod:`stability.output.stream`), so that a stopped run
    continues with its ``resume``; its chunks run on its ``scheduler`` (default: the file's
    ``[run] scheduler``).

    Returns
    -------
    StudySummary
        Rows: analytic Omega^2 and growth rate, fitted rate and its relative error, median
        flip interval (measured and exact), invariant errors, wall time, member-steps/s.
    """
    run = options.run
    say = _reporter(run.progress)
    t_start = time.perf_counter()
    body = _body(config)
    axis = spin_axis(body, config["spin"]["axis"])
    spin = config["spin"]["rate"]
    ens, integ = config["ensemble"], config["integration"]
    steps = round(integ["t_end"] / integ["h"])
    say(f"{body.name}: {ens['members']} members x {steps} steps of {integ['method']} "
        f"(h = {integ['h']:g} s), measured chunk by chunk; w kept every "
        f"{integ['save_every']} steps for {_kept_count(config)} members: "
        f"{format_bytes(_summaries_bytes(config) + _series_bytes(config, _kept_count(config)))}"
        " of results")
    ds = _ensemble(config, body, axis, run.store or out_dir / ".ensemble", run.resume,
                   run.scheduler or config["run"]["scheduler"] or None, run.threads,
                   run.progress, options.history or f"stability run ({NAME})")
    t_ensemble = time.perf_counter() - t_start
    ds = finish_analysis(ds, body, axis, spin, ens["epsilon"],
                         low_factor=config["analysis"]["fit_above"],
                         high_fraction=config["analysis"]["fit_below"])
    t_analysis = time.perf_counter() - t_start - t_ensemble

    say(f"writing {config['output']['dataset']} and drawing the figures ...")
    figures = (tennis.flips_figure, tennis.polhode_figure, tennis.growth_figure,
               tennis.flip_interval_figure)
    stages = {"analysis": t_analysis}
    ds, files = write_outputs(ds, config, out_dir, NAME, dict(zip(FIGURES, figures)),
                              overwrite=options.overwrite, history=False, threads=run.threads,
                              timings=stages)
    wall = time.perf_counter() - t_start
    return summarize(ds, out_dir, files, wall, t_ensemble, stages=stages)


def _ensemble(config, body, axis, work, resume, scheduler, threads, progress, command):
    """The ensemble, streamed through the chunk folder ``work`` and read back into memory."""

    ens, integ = config["ensemble"], config["integration"]
    kwargs = dict(
        body=body, axis=axis, spin=config["spin"]["rate"], epsilon=ens["epsilon"],
        members=ens["members"], h=integ["h"], t_end=integ["t_end"], seed=ens["seed"],
        method=integ["method"], save_every=integ["save_every"],
        chunk_members=config["run"]["chunk_members"], config=config, command=command,
        device=config["run"]["device"], scene=integ["scene"],
    )
    window = (config["analysis"]["fit_above"], config["analysis"]["fit_below"])
    kept = config["output"]["series_members"]
    started = time.perf_counter()
    ds = run_streamed(kwargs, RunOptions(store=work, resume=resume, scheduler=scheduler,
                                         threads=threads, progress=progress), compress=False,
                      measurement=lambda kw, plan: TennisChunks(kw, window, kept, plan))
    ds.attrs["combine_time"] = time.perf_counter() - started - float(ds.attrs["wall_time"])
    return ds


def _reporter(progress):
    """Print a stage of the run on stderr, unless progress output is off."""
    if progress is False:
        return lambda message: None
    return lambda message: print(message, file=sys.stderr, flush=True)


def _body(config: dict):

    b = config["body"]
    if "moments" in b:
        return RigidBody(*b["moments"], physical=b["physical"], name=b.get("name", "body"))
    return RigidBody.preset(b["preset"])


def summarize(ds, out_dir, files, wall, t_ensemble, stages=None) -> StudySummary:
    """The summary table of a finished run: the analysis
    (:func:`stability.free_body.tennis_racket.measure.analysis_headline`), then where its
    time went.

    ``stages``: seconds of the stages after the ensemble (``analysis``; ``figures`` and
    ``dataset`` as :func:`~stability.study.outputs.write_outputs` times them)."""
    rows, values = analysis_headline(ds)
    stages = stages or {}
    attrs = ds.attrs
    n, steps = values["members"], int(attrs["steps_done"])
    loop = float(attrs.get("chunk_time", attrs["wall_time"]))  # summed over the chunks
    streamed = float(attrs["wall_time"])  # the chunks' run: loop, measurement, chunk files
    measuring = float(attrs.get("measure_time", 0.0))
    compiling = float(attrs["compile_time"])
    figures = stages.get("figures", 0.0)
    values.update({
        "wall_time": wall, "ensemble_time": t_ensemble, "integration_time": loop,
        "compile_time": compiling, "measure_time": measuring,
        "chunk_files_time": max(0.0, streamed - loop - measuring - compiling),
        "combine_time": float(attrs.get("combine_time", 0.0)),
        "analysis_time": stages.get("analysis", 0.0), "figures_time": figures,
        "write_time": stages.get("dataset", 0.0),
        "member_steps_per_s": n * steps / loop if loop > 0 else math.nan,
    })
    v = values
    rows += [
        ("wall time (all: compile, run, analysis, files)", f"{wall:.1f}", "s"),
        ("  integration (member loop) / Numba compile", f"{loop:.2f} / {compiling:.1f}", "s"),
        ("  measuring, per chunk where it ran", f"{measuring:.2f}", "s"),
        ("  chunk files and launch", f"{v['chunk_files_time']:.2f}", "s"),
        ("  joining the chunks / the ensemble's numbers",
         f"{v['combine_time']:.2f} / {v['analysis_time']:.2f}", "s"),
        ("  figures / the Dataset's write after them",
         f"{figures:.2f} / {v['write_time']:.2f}", "s"),
        (f"member-steps per second ({n} x {steps} steps)",
         f"{values['member_steps_per_s']:.3g}", "s-1"),
    ]
    return StudySummary(NAME, Path(out_dir), files, rows, values)


STUDY = StudyKind(
    name=NAME,
    title="the tennis-racket flip: growth rate and flip intervals of a tossed ensemble",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    members_key=("ensemble", "members"),
    expected_bytes=expected_bytes,
    resumable=True,
)
