"""Running a study: :func:`run_study` checks the output folder before any work, holds its lock,
runs the kind into a hidden stage with its options (:class:`~.kind.StudyRun`), publishes the
outputs together, and keeps or removes the work folder a resumable run leaves."""

from __future__ import annotations

import contextlib
import errno
import os
import stat
import time
from pathlib import Path

import numba

from ..ensemble.options import RunOptions
from ..output.lock import FolderLock
from ..output.publish import check_target, clean_leftovers, remove_folder, staged
from ..output.store import ChunkStore, find_stores, read_manifest
from ..output.stream import RunInterrupted
from ..util.ledger import time_ledger
from .kind import STUDY_KEY, StudyRun, StudySummary, quick_notes, study_kind
from .load import load_study, read
from .timing import add_time_table


def run_study(
    study,
    out_dir=None,
    *,
    members=None,
    threads=None,
    overwrite=False,
    resume=False,
    scheduler=None,
    quick=False,
    progress=None,
    overrides=(),
    history=None,
    source=None,
) -> StudySummary:
    """Run a study and publish its outputs together; return its summary.

    Everything about the output folder is checked before any computation (the output names
    are plain and distinct, it can be written, nothing is replaced without ``overwrite``, the
    free space suffices where the size is known). The run holds the folder's lock
    (:mod:`stability.output.lock`) from then on, so a second run into the same folder is refused
    while this one lives, ``overwrite`` included. The outputs are written into a hidden stage
    and published only when all are complete (:mod:`stability.output.publish`), then checked to be
    there: a stopped run publishes nothing and leaves an earlier result intact. What a
    resumable study has finished (the chunks of its ensemble) is kept in a work folder beside
    the outputs until the run is published; a run that fails removes that folder only if it
    made it and nothing there can be resumed.

    Parameters
    ----------
    study : str, Path or dict
        A study file, or a configuration already resolved by :func:`load_study`.
    out_dir : str or Path, optional
        Output folder; default ``[output] dir`` of the configuration.
    members, quick, overrides
        As in :func:`load_study` (only when ``study`` is a file).
    threads : int, optional
        Numba threads for the run (default: all that Numba was started with).
    overwrite : bool
        Replace output files that exist (and the finished parts of a stopped earlier run);
        otherwise refuse before running anything.
    resume : bool
        Finish a stopped run of the same study: only its missing parts are computed.
    scheduler : str, optional
        ``"dask"`` (a local dask.distributed cluster) or a scheduler address: run the parts
        there (resumable kinds; default: the file's ``[run] scheduler``, else this machine).
    progress : bool, optional
        Progress bar; by default shown for runs expected to take more than a few seconds.
    history : str, optional
        The command line, appended to the Dataset's ``history`` attribute.

    Returns
    -------
    StudySummary
        ``files`` are the published paths.

    Raises
    ------
    ValueError, OSError
        Bad configuration or output folder (before computing); a failed write (after).
    stability.output.stream.RunInterrupted
        Ctrl-C or SIGTERM; its message says what was kept and how to continue.
    """

    if isinstance(study, dict):
        kind = study_kind(study.get(STUDY_KEY))
        source = source or "<config>"
        config = kind.resolve(study, source)  # a resolved configuration resolves to itself
    else:
        kind, config, source = load_study(
            study, overrides=overrides, members=members, quick=quick
        )
    if threads is not None:
        threads = _check_threads(threads)
    if scheduler is not None and not hasattr(scheduler, "submit") and not (
            isinstance(scheduler, str) and (scheduler == "dask" or "://" in scheduler)):
        raise ValueError(f"scheduler must be 'dask' (a local cluster), a scheduler address such "
                         f"as 'tcp://host:8786' or a distributed.Client, got {scheduler!r}; "
                         "None runs on this machine")
    if (resume or scheduler is not None) and not kind.resumable:
        option = "--resume" if resume else "--scheduler"
        raise ValueError(f"study kind {kind.name!r} runs in one piece; drop {option}")
    out = Path(out_dir if out_dir is not None else config["output"]["dir"])
    names = kind.outputs(config)
    expected = kind.expected_bytes(config) if kind.expected_bytes is not None else None
    work = out / f".stability-work-{Path(names[0]).stem}"
    if resume:
        _check_something_to_resume(out, work, kind.name, None if overwrite else names[0])
    check_target(out, names, overwrite=overwrite, expected_bytes=expected)  # before writing
    created = not out.exists()
    made_work = False
    lock = FolderLock(out, what="output folder")
    try:
        _make_folder(out)
        lock.acquire()  # from here on, no other run writes into out
        clean_leftovers(out)  # it may complete the publication of a killed run ...
        check_target(out, names, overwrite=overwrite, expected_bytes=expected)  # ... so again
        if kind.resumable:
            _check_work_folder(work)
            if overwrite and not resume and work.exists():
                remove_folder(out, work.name)  # the user asked to start afresh
            made_work = not work.exists()
        options = StudyRun(RunOptions(store=work if kind.resumable else None, resume=resume,
                                      scheduler=scheduler, threads=threads, progress=progress),
                           overwrite=True, history=history)  # the stage is new: overwrite
        with staged(out) as stage, time_ledger() as spent:
            started = time.perf_counter()
            summary = kind.run(config, stage.dir, options)
            add_time_table(summary, time.perf_counter() - started, spent)
            _check_outputs(stage.dir, names, "wrote")
            stage.publish()
        _check_outputs(out, names, "published")
    except BaseException as exc:
        kept = _kept(work) if kind.resumable and lock.held else None
        if made_work and kept is not None and kept[0] == 0:
            remove_folder(out, work.name)  # made by this run, nothing there to resume
        lock.release()
        if created and out.is_dir() and not any(out.iterdir()):
            with contextlib.suppress(OSError):  # another run may have just begun in it
                out.rmdir()  # a folder this run made and left empty
        if isinstance(exc, KeyboardInterrupt):
            raise RunInterrupted(_interrupted(out, work, kept)) from None
        raise
    if kind.resumable:
        remove_folder(out, work.name)
    lock.release()
    summary.out_dir = out
    summary.files = [out / Path(p).name for p in summary.files]
    if quick and not isinstance(study, dict):
        summary.notes += quick_notes(kind, read(study), config)
    return summary


def _make_folder(out: Path) -> None:
    """Create the output folder (and its parents) if missing, as an OSError naming it."""
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OSError(exc.errno, f"cannot create the output folder ({exc.strerror or exc})",
                      str(out)) from None


def _check_something_to_resume(out: Path, work: Path, kind: str, dataset) -> None:
    """Refuse ``--resume`` into a folder that holds no stopped run of this study but its
    finished ``dataset`` (None: not asked, as with ``--overwrite``), or another study's stopped
    run (a mistaken study file or ``--out``); with nothing there at all, the run starts afresh,
    as a job that always passes ``--resume`` expects on its first start."""
    if os.path.lexists(work) or not out.is_dir() or out.is_symlink():
        return
    if dataset is not None and os.path.lexists(out / dataset):
        raise ValueError(
            f"nothing of study {kind!r} to resume in {out}: its run there is finished "
            f"({dataset} exists); drop --resume and pass --overwrite to run it again, or "
            "choose another --out")
    others = sorted(p.name for p in out.iterdir() if p.name.startswith(".stability-work-"))
    if others:
        raise ValueError(
            f"nothing of study {kind!r} to resume in {out}: it holds the stopped run of "
            f"another ({', '.join(others)}, not {work.name}); check the study file and --out, "
            "or drop --resume to start afresh")


def _check_work_folder(work: Path) -> None:
    """Refuse a work folder that is a link or not a folder: a run writes only inside ``out``."""
    if work.is_symlink():
        raise ValueError(f"{work} is a symbolic link; a run keeps its finished parts only in a "
                         "real folder inside the output folder: remove the link")
    if os.path.lexists(work) and not work.is_dir():
        raise ValueError(f"{work} is not a folder, where a run keeps its finished parts; "
                         "remove it")


def _check_outputs(folder: Path, names, done: str) -> None:
    """OSError naming the first of ``names`` that is not a plain file of ``folder``."""
    for name in names:
        try:
            plain = stat.S_ISREG(os.lstat(folder / name).st_mode)
        except FileNotFoundError:
            plain = False
        if not plain:
            raise OSError(errno.EIO, f"the run {done} no file {name!r}, one of its outputs",
                          str(folder / name))


def _kept(work: Path):
    """``(finished chunks, manifest)`` of a work folder (summed over the stores in it, one per
    run of the study); None if absent or unreadable.

    Nothing there is changed (the folder may be another run's), and only the chunk files
    there are checked (a manifest may claim any number of chunks).
    """

    if work.is_symlink() or not work.is_dir():
        return None
    done, total = 0, {"chunks": 0}
    for store in find_stores(work):
        try:
            manifest = read_manifest(store)
        except (ValueError, OSError):
            return None
        numbers = (path.name[len("chunk-"):-len(".nc")] for path in store.glob("chunk-*.nc"))
        chunks = {int(k) for k in numbers if k.isdigit()}
        done += sum(ChunkStore.verify_path(store, k, manifest["fingerprint"], remove=False)
                    for k in chunks if k < manifest["chunks"])
        total = {**manifest, "chunks": total["chunks"] + manifest["chunks"]}
    return done, total


def _interrupted(out: Path, work: Path, kept) -> str:
    """One line: the run stopped, what was kept (``_kept(work)``), how to continue."""
    text = "interrupted; nothing was published"
    if out.is_dir() and any(not p.name.startswith(".") for p in out.iterdir()):
        text += f" (what {out} held is unchanged)"
    if kept is not None and kept[0]:
        done, manifest = kept
        text += (f"; {done} of {manifest['chunks']} finished chunks "
                 f"({manifest.get('unit', 'members')}) are kept in {work}: run the same "
                 "command with --resume to continue")
    return text


def _check_threads(threads) -> int:
    """``threads`` if a whole number from 1 to the threads Numba started with; else ValueError."""
    most = numba.config.NUMBA_NUM_THREADS
    if isinstance(threads, bool) or not isinstance(threads, int) or not 1 <= threads <= most:
        raise ValueError(
            f"threads must be a whole number from 1 to {most} (the cores Numba started with; "
            f"set NUMBA_NUM_THREADS to change that), got {threads!r}"
        )
    return threads
