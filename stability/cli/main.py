"""The ``stability`` command: run a study file, list the integrators, time them.

::

    stability run STUDY.toml [--out DIR] [--members N] [--threads N] [--overwrite] [--quick]
                             [--resume] [--scheduler dask|ADDRESS]
                             [--set SECTION.KEY=VALUE ...] [--dry-run] [--no-progress]
    stability status DIR              # how far a run writing into DIR has got
    stability studies [KIND]          # the study kinds and the keys of their files
    stability methods                 # the integrator registry as a table
    stability bench [--members N] [--steps N] [--threads N ...] [--methods NAME ...] [--repeat N]
                    [--scene free_body|heavy_top|all] [--top-members N]
    stability animate racket|top|PRESET|body OUT.gif [--moments I1 I2 I3] [--spin W] [--epsilon E]
                      [--axis 1|2|3] [--duration S] [--fps N] [--speed X] [--size PX]

A mistake by the user (a bad study file, a bad option, an output that exists) is reported as one
line on stderr with exit status 2, never a traceback; ``--debug`` shows the traceback instead.
Ctrl-C (SIGINT) or SIGTERM stops a run within seconds: one line says what was kept and how to
continue, nothing is published, and the exit status is 130 (143 for SIGTERM).
``python -m stability`` is the same command.
"""

from __future__ import annotations

import argparse
import os
import shlex
import sys

from ..core.body import RigidBody  # loaded with the package already: no start-up cost
from ..util.numba_env import check_threads_variable

EXIT_USAGE = 2
EXIT_INTERRUPTED = 130
EXIT_TERMINATED = 143


class _Parser(argparse.ArgumentParser):
    """argparse, but a usage error is one line (no usage block) and exit status 2."""

    def error(self, message):
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a whole number >= 1, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be a whole number >= 1, got {text!r}")
    return value


def _scheduler(text: str) -> str:
    if text.strip() != "dask" and "://" not in text:
        raise argparse.ArgumentTypeError(
            f"must be 'dask' (a local cluster) or a scheduler address such as tcp://host:8786, "
            f"got {text!r}; leave --scheduler out to run on this machine")
    return text.strip()


def _positive_float(text: str) -> float:
    import math

    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0.0):
        raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {text!r}")
    return value


def _animated() -> tuple:
    """What ``stability animate`` draws: the racket, the top, a preset, or a body by moments."""
    return ("racket", "top", *RigidBody.presets(), "body")


def _assignment(text: str) -> tuple[str, str]:
    key, sep, value = text.partition("=")
    if not sep or "." not in key:
        raise argparse.ArgumentTypeError(
            f"must look like SECTION.KEY=VALUE (e.g. ensemble.epsilon=1e-5), got {text!r}"
        )
    return key.strip(), value.strip()


def build_parser() -> argparse.ArgumentParser:
    from ..version import __version__

    parser = _Parser(
        prog="stability",
        description="Monte Carlo studies of rigid-body rotation (the tennis-racket effect).",
    )
    parser.add_argument("--version", action="version", version=f"stability {__version__}")
    parser.add_argument("--debug", action="store_true", help="show tracebacks for errors")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    run = sub.add_parser(
        "run",
        help="run a study file: write its Dataset and figures, print a summary",
        description="Run a study file (TOML): validate it, run the ensemble, write the Dataset "
        "(netCDF) and the figures into the output folder, print a summary table.",
    )
    run.add_argument("study", metavar="STUDY.toml",
                     help="study file, e.g. studies/tennis_racket.toml")
    run.add_argument("--out", metavar="DIR",
                     help="output folder (default: [output] dir of the file)")
    run.add_argument("--members", type=_positive_int, metavar="N", help="ensemble size")
    run.add_argument(
        "--threads", type=_positive_int, metavar="N", help="Numba threads (default: all cores)"
    )
    run.add_argument("--overwrite", action="store_true",
                     help="replace existing output files (and start afresh over the finished "
                     "chunks of a stopped run)")
    run.add_argument("--resume", action="store_true",
                     help="finish a stopped run of the same study: only its missing chunks run")
    run.add_argument("--scheduler", metavar="ADDRESS", type=_scheduler,
                     help="run the chunks on dask.distributed: 'dask' for a local cluster, or "
                     "a scheduler address such as tcp://host:8786")
    run.add_argument(
        "--quick", action="store_true",
        help="small, fast version of the study for tests and a first look (fewer members or "
        "cells, a shorter run; `stability studies KIND` lists what it sets, and the summary "
        "repeats it)",
    )
    run.add_argument(
        "--set", dest="overrides", action="append", default=[], type=_assignment,
        metavar="SECTION.KEY=VALUE",
        help="override one key of the file (TOML value), e.g. --set ensemble.epsilon=1e-5",
    )
    run.add_argument(
        "--dry-run", action="store_true",
        help="validate and print the resolved configuration; run and write nothing",
    )
    run.add_argument("--no-progress", action="store_true", help="no progress bar")
    run.set_defaults(func=_cmd_run)

    status = sub.add_parser(
        "status", help="how far a run has got (from another terminal)",
        description="Show the chunks done, the speed and the time left of a run writing into "
        "DIR (its output folder, or a run_ensemble store= folder).",
    )
    status.add_argument("dir", metavar="DIR", help="output folder of the run")
    status.set_defaults(func=_cmd_status)

    studies = sub.add_parser(
        "studies", help="list the study kinds, or the keys of one kind's study files"
    )
    studies.add_argument("kind", nargs="?", help="a study kind, e.g. tennis_racket")
    studies.set_defaults(func=_cmd_studies)

    methods = sub.add_parser("methods", help="list the registered integrators and their properties")
    methods.add_argument("--references", action="store_true", help="also list each reference")
    methods.set_defaults(func=_cmd_methods)

    bench = sub.add_parser(
        "bench",
        help="member-steps per second of every integrator, against scipy DOP853 and NumPy RK4; "
        "the heavy top's work and precision",
        description="Free body: time every registered integrator on one ensemble (1 and 2 "
        "threads), and on the same workload scipy's solve_ivp DOP853 (the whole ensemble as one "
        "system) and a plain NumPy RK4; print member-steps/s, the speed ratios and each one's "
        "error against the exact solution. Then what the engine costs on the fixed workload W1 "
        "(10,000 members, T = 100 s, h = 0.01, rk4, all threads; best of at least 7 rounds): "
        "a plain RK4 loop against the engine's loop and run_ensemble. Heavy top: run each of "
        "its methods at a ladder of "
        "steps on released gyroscopes and print wall time, member-steps/s and the error of "
        "cos(theta) against the exact motion per step, and each method's measured order.",
    )
    bench.add_argument("--scene", choices=("free_body", "heavy_top", "all"),
                       default="free_body", help="what to time (default free_body)")
    bench.add_argument("--members", type=_positive_int, default=10_000, metavar="N",
                       help="free-body ensemble size (default 10000)")
    bench.add_argument("--top-members", type=_positive_int, default=256, metavar="N",
                       help="heavy-top ensemble size (default 256)")
    bench.add_argument("--steps", type=_positive_int, default=1000, metavar="N",
                       help="free-body steps per member (default 1000)")
    bench.add_argument("--threads", type=_positive_int, nargs="+", metavar="N",
                       help="thread counts to time (default: 1 and 2); the heavy top runs "
                       "on the largest (default: all)")
    bench.add_argument("--methods", nargs="+", metavar="NAME",
                       help="integrators to time (default: all registered; with --scene all, "
                       "the heavy top times those of them it has)")
    bench.add_argument("--repeat", type=_positive_int, default=3, metavar="N",
                       help="runs per timing, the best kept (default 3)")
    bench.add_argument("--no-scipy", action="store_true", help="skip scipy DOP853")
    bench.add_argument("--no-adaptive", action="store_true",
                       help="skip the member loop's adaptive Dormand-Prince 5(4)")
    bench.add_argument("--no-numpy", action="store_true", help="skip the NumPy RK4")
    bench.add_argument("--no-engine", action="store_true",
                       help="skip the table of what the engine costs on W1 (about 4 s)")
    bench.set_defaults(func=_cmd_bench)

    animate = sub.add_parser(
        "animate", help="write an animation of the exact motion: a body flipping (the racket, "
        "a preset such as the phone, or given moments), or a heavy top nutating (.gif, or .mp4 "
        "where ffmpeg is installed)",
        description="Write an animation from the exact solution: 'racket' (or any preset of "
        "RigidBody.presets(), such as 'phone'; or 'body' with --moments) spun about its "
        "intermediate axis and nudged, turning over while L stays fixed "
        "(stability.animate_flip); 'top', a disk top released at a tilt, nutating and "
        "precessing (stability.animate_top). A body other than the racket is drawn as its box "
        "of inertia, its two large faces in two colours (the phone's screen and back). The "
        "suffix of OUT picks GIF or MP4.",
    )
    animate.add_argument("what", choices=_animated(), metavar="WHAT",
                         help="racket, top, a preset (" + ", ".join(_animated()[2:-1])
                         + ") or body (with --moments)")
    animate.add_argument("out", metavar="OUT.gif", help="output file, .gif or .mp4")
    animate.add_argument("--moments", type=_positive_float, nargs=3, metavar=("I1", "I2", "I3"),
                         help="principal moments in kg m^2 of the body (WHAT = body)")
    animate.add_argument("--spin", type=_positive_float, metavar="W",
                         help="spin in rad/s (default 6 for a body, 200 for the top)")
    animate.add_argument("--epsilon", type=_positive_float, metavar="E",
                         help="the nudge across the spin, relative to it (default 0.05; smaller: "
                         "longer between flips); not for the top")
    animate.add_argument("--axis", type=int, choices=(1, 2, 3),
                         help="the body axis spun about (default the intermediate one, the "
                         "flip); not for the top")
    animate.add_argument("--duration", type=float, metavar="S",
                         help="seconds of motion shown (default: a body's two flips, one "
                         "turn of the top's precession)")
    animate.add_argument("--fps", type=float, default=20.0, metavar="N",
                         help="frames per second (default 20)")
    animate.add_argument("--speed", type=float, metavar="X",
                         help="seconds of motion per second shown (default 1 for a body, "
                         "0.25 for the top)")
    animate.add_argument("--size", type=_positive_int, default=320, metavar="PX",
                         help="width and height in pixels (default 320); the text grows with it")
    animate.set_defaults(func=_cmd_animate)
    return parser


def main(argv=None) -> int:
    """Entry point of the ``stability`` console script; returns the exit status."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, or a usage error (already printed)
        return exc.code if isinstance(exc.code, int) else 0
    if args.command is None:
        parser.print_help()
        return EXIT_USAGE
    args.argv = list(sys.argv[1:] if argv is None else argv)
    terminated = _terminate_as_interrupt()
    try:
        check_threads_variable()
        return args.func(args) or 0
    except KeyboardInterrupt as exc:
        if args.debug:
            raise
        what = "SIGTERM" if terminated.is_set() else "Ctrl-C"
        text = str(exc) or "interrupted; nothing was published"
        print(f"stability {args.command}: {what}: {text}", file=sys.stderr, flush=True)
        # Objects torn half-way (a compilation in LLVM) may complain when collected at exit;
        # the line above is the whole story.
        sys.unraisablehook = lambda unraisable: None
        return EXIT_TERMINATED if terminated.is_set() else EXIT_INTERRUPTED
    except BrokenPipeError:  # output piped into e.g. `head`, which stopped reading
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 1
    except (ValueError, OSError) as exc:  # user errors: bad file, bad value, existing output
        if args.debug:
            raise
        print(_one_line(exc, args.command), file=sys.stderr)
        return EXIT_USAGE


def console() -> int:
    """The ``stability`` console script (and ``python -m stability``): :func:`main`, with the
    garbage collector tuned for one command in a short-lived process.

    numba, xarray and matplotlib hold about 250,000 objects, which every full collection walks
    (0.07 s each). The youngest generation is collected every 10,000 allocations instead of
    700, so that the imports and the run set off no full collection (0.43 s of collections in
    the tennis study, 0.18 s now); at the end the objects are frozen out of the collector
    (:func:`gc.freeze`), so that the interpreter's passes on the way out skip them (0.5 s).
    """
    import gc

    gc.set_threshold(10_000, 10, 10)
    status = main()
    gc.freeze()
    return status


def _terminate_as_interrupt():
    """Make SIGTERM stop a run as Ctrl-C does (cleanly); return the event it sets."""
    import signal
    import threading

    terminated = threading.Event()
    if threading.current_thread() is not threading.main_thread():
        return terminated

    def handler(signum, frame):
        from ..util.interrupts import request_stop

        terminated.set()
        if request_stop():  # a run in progress ends after its chunk in flight
            return
        if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:  # started as a background job
            raise KeyboardInterrupt
        signal.raise_signal(signal.SIGINT)  # whatever handles Ctrl-C now handles this too

    signal.signal(signal.SIGTERM, handler)
    return terminated


def _one_line(exc: BaseException, command: str) -> str:
    from ..study import ConfigError

    if isinstance(exc, ConfigError):
        text = str(exc)
    elif isinstance(exc, OSError) and exc.filename is not None:
        text = f"stability {command}: error: {exc.strerror or exc}: {exc.filename}"
    else:
        text = f"stability {command}: error: {exc}"
    return " ".join(text.split())


def _cmd_animate(args) -> int:
    from ..free_body.animation import animate_flip
    from ..heavy_top.animation import animate_top

    if (args.moments is None) == (args.what == "body"):
        raise ValueError("--moments I1 I2 I3 goes with WHAT = body: give both, or name a "
                         "preset (racket, top, " + ", ".join(_animated()[2:-1]) + ")")
    options = {"duration": args.duration, "fps": args.fps, "size": args.size}
    if args.speed is not None:
        options["speed"] = args.speed
    if args.spin is not None:
        options["spin"] = args.spin
    if args.what == "top":
        given = [f"--{name}" for name in ("epsilon", "axis") if getattr(args, name) is not None]
        if given:
            raise ValueError(f"{' and '.join(given)} is for a flipping body, not the top: drop "
                             "it (the top takes --spin)")
        path = animate_top(path=args.out, **options)
    else:
        if args.what == "body":
            try:
                body = RigidBody(*args.moments, name="body")
            except ValueError as exc:  # physical=False is no option here
                text = str(exc).replace(", or pass physical=False for a mathematical body", "")
                raise ValueError(f"--{text}") from None
        else:
            body = RigidBody.preset("tennis_racket" if args.what == "racket" else args.what)
        if args.epsilon is not None:
            options["epsilon"] = args.epsilon
        path = animate_flip(body, path=args.out, axis=args.axis, **options)
    print(f"wrote {path} ({path.stat().st_size / 1024:.0f} KiB)")
    return 0


def _cmd_run(args) -> int:
    from ..study import load_study, quick_notes, run_study

    overrides = list(args.overrides)
    kind, config, source = load_study(
        args.study, overrides=overrides, members=args.members, quick=args.quick
    )
    if args.dry_run:
        from ..study import to_toml

        sys.stdout.write(to_toml(config))
        return 0
    history = "stability " + shlex.join(args.argv)  # the Dataset's history line adds the time
    summary = run_study(
        config,
        out_dir=args.out,
        threads=args.threads,
        overwrite=args.overwrite,
        resume=args.resume,
        scheduler=args.scheduler,
        progress=False if args.no_progress else None,
        history=history,
        source=source,
    )
    if args.quick:
        from ..study.load import read

        summary.notes += quick_notes(kind, read(args.study), config)
    print(f"\nsummary of the {kind.name} study ({kind.title})")
    print(summary.table())
    print(f"\nwrote {len(summary.files)} files to {summary.out_dir}/:")
    for path in summary.files:
        print(f"  {path.name}")
    return 0


def _cmd_status(args) -> int:
    from pathlib import Path

    from ..output.lock import holder_of
    from ..output.store import find_stores, status_lines

    folder = Path(args.dir)
    if not folder.is_dir():
        raise ValueError(f"{folder} is not a folder; give the output folder of a run")
    holder = holder_of(folder)
    if holder is not None:
        print(f"{folder}: in use by a run ({holder})")
    stores = find_stores(folder)
    if not stores:
        if holder is None:
            print(f"{folder}: no run in progress or stopped (finished runs keep no chunks)")
        return 0
    for store in stores:
        print("\n".join(status_lines(store)))
    return 0


def _cmd_studies(args) -> int:
    from ..study import STUDIES, quick_notes, study_kind

    if args.kind is None:
        width = max(len(name) for name in STUDIES)
        for name, kind in STUDIES.items():
            print(f"{name:<{width}}  {kind.title}")
        print("\n`stability studies KIND` lists the keys of a kind's study files.")
        return 0
    kind = study_kind(args.kind)
    print(f'study = "{kind.name}"  # {kind.title}\n')
    print(kind.schema.describe())
    print("\n" + "\n".join(f"# {line}" for line in quick_notes(kind)))
    return 0


def _cmd_methods(args) -> int:
    from ..free_body.methods import METHODS

    print(methods_table(METHODS, references=args.references))
    return 0


def methods_table(methods, references: bool = False) -> str:
    """The registry as a plain-text table built from each spec's ``describe()``."""
    columns = [
        ("name", "name"),
        ("order", "order"),
        ("family", "family"),
        ("poisson", "Poisson"),
        ("preserves_casimir", "|L| kept"),
        ("preserves_energy", "E kept"),
        ("symmetric", "symmetric"),
        ("implicit", "implicit"),
        ("evaluations", "cost/step"),
        ("attitude", "attitude"),
        ("title", "method"),
    ]
    rows = []
    for spec in methods.values():
        facts = spec.describe()
        rows.append([_cell(facts.get(key, "")) for key, _ in columns])
    header = [title for _, title in columns]
    widths = [max(len(header[i]), *(len(r[i]) for r in rows)) for i in range(len(columns))]
    lines = ["  ".join(h.ljust(w) for h, w in zip(header, widths)).rstrip()]
    lines.append("  ".join("-" * w for w in widths))
    for row in rows:
        lines.append("  ".join(c.ljust(w) for c, w in zip(row, widths)).rstrip())
    lines.append("")
    lines.append(
        "order: global order of accuracy; Poisson: the step is a Poisson map (symplectic on the "
        "|L| sphere); |L| kept / E kept: to round-off (or solver tolerance); cost/step: "
        "right-hand-side evaluations or exact sub-flows per step."
    )
    if references:
        lines.append("")
        for spec in methods.values():
            facts = spec.describe()
            lines.append(f"{facts['name']}: {facts.get('reference', '')}")
    return "\n".join(lines)


def _cell(value) -> str:
    if isinstance(value, bool):
        return "yes" if value else "-"
    return str(value)


def _cmd_bench(args) -> int:
    from .bench import bench, format_report, format_top_report, top_work_precision
    from ..registry import SCENES

    log = lambda line: print(line, file=sys.stderr, flush=True)
    if args.scene in ("free_body", "all"):
        report = bench(
            members=args.members,
            steps=args.steps,
            threads=args.threads,
            methods=args.methods,
            scipy=not args.no_scipy,
            numpy=not args.no_numpy,
            repeat=args.repeat,
            log=log,
            engine=not args.no_engine,
            adaptive=not args.no_adaptive,
        )
        print(format_report(report))
    if args.scene in ("heavy_top", "all"):
        methods = args.methods
        if methods and args.scene == "all":
            methods = [name for name in methods if name in SCENES["heavy_top"].methods]
            if not methods:
                print("\nheavy top: none of the --methods runs it")
                return 0
        report = top_work_precision(
            members=args.top_members,
            methods=methods,
            threads=max(args.threads) if args.threads else None,
            repeat=args.repeat,
            log=log,
        )
        print(("\n" if args.scene == "all" else "") + format_top_report(report))
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
