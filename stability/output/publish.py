"""The outputs of a run as one unit: staged in a hidden folder, published together or not at all.

A study writes its Dataset, configuration and figures into a :class:`Stage`, a hidden folder
``.stability-stage-<host>-<pid>-<tag>`` inside the output folder (so publishing is a rename
within one file system). Only when every file is complete does :meth:`Stage.publish` move them
to their final names: it first writes a journal (JSON: the list of names) into the stage, then
renames file after file, then removes the stage. A run killed before the journal leaves an
unpublished stage, which the next run in that folder removes; a run killed while publishing
leaves a journal, and the next run finishes the publication (every staged file was complete).
So an earlier result replaced with ``--overwrite`` stays intact until the new one is whole,
and no temporary file outlives the run that made it by more than the next run.

The output folder is a boundary, and what a run finds in it is untrusted: a leftover stage is
completed only if its name parses as this package's own, it is a real folder (not a symbolic
link), and its journal lists plain file names that the stage holds as regular files; every
rename is made relative to open descriptors of the two folders, so it never follows a link
and never leaves the output folder. Anything else is left untouched, with one line saying why.

Checks of the target come first (:func:`check_target`): output names are plain, visible,
distinct file names, the folder can be created and written, no output name is a folder,
nothing is replaced without ``overwrite`` (a dangling link at an output name counts as an
output), and the free space covers the expected size of the result when it is known. Errors of
the file system while writing (a full disk, a permission, a vanished folder) are
:class:`OSError` with the path and the cause, which the command line reports in one line with
exit status 2.
"""

from __future__ import annotations

import contextlib
import errno
import json
import logging
import os
import re
import shutil
import signal
import socket
import stat
import threading
import uuid
from pathlib import Path

from ..util.formatting import format_bytes
from .lock import process_alive

#: Name prefix of stage folders.
STAGE_PREFIX = ".stability-stage-"

#: File in a stage listing the names being published; its presence means "all complete".
JOURNAL = ".publishing"

#: What a journal says it is (its ``format`` field).
JOURNAL_FORMAT = "stability publishing journal 1"

#: Most bytes of a journal that are read back (names of a few dozen files).
JOURNAL_MOST = 2**20

#: A stage folder's name: prefix, host (no "-"), process id, 8 hex digits.
_STAGE_NAME = re.compile(r"\.stability-stage-([A-Za-z0-9_.]{1,255})-([0-9]{1,10})-([0-9a-f]{8})")

log = logging.getLogger(__name__)


#: Free space kept beyond the expected size of a result (bytes).
SPACE_MARGIN = 16 * 2**20


class UnsafeLeftover(ValueError):
    """A leftover in the output folder that is not as this package writes it: left untouched."""


class Stage:
    """A hidden folder in ``out_dir`` where a run writes its outputs before publishing them.

    Parameters
    ----------
    out_dir : path-like
        The output folder (created if missing).
    """

    def __init__(self, out_dir):
        self.out_dir = Path(out_dir)
        tag = f"{_host()}-{os.getpid()}-{uuid.uuid4().hex[:8]}"
        self.dir = self.out_dir / f"{STAGE_PREFIX}{tag}"
        made = False
        try:
            self.out_dir.mkdir(parents=True, exist_ok=True)
            self.dir.mkdir()
            made = True
            probe = self.dir / ".probe"
            probe.write_bytes(b"0")
            probe.unlink()
        except OSError as exc:
            if made:
                remove_folder(self.out_dir, self.dir.name)
            raise OSError(exc.errno, f"cannot write into the output folder "
                          f"({exc.strerror or exc})", str(self.out_dir)) from None
        self.published: list[Path] = []

    def path(self, name: str) -> Path:
        """Where to write the output ``name`` (a file name, no folder)."""
        return self.dir / name

    def names(self) -> list[str]:
        """The files written into the stage so far, sorted."""
        return sorted(p.name for p in self.dir.iterdir() if not p.name.startswith("."))

    def publish(self) -> list[Path]:
        """Move every staged file to its final name; return the final paths.

        The journal makes the publication finish even if this process dies half-way: the next
        :func:`clean_leftovers` in this folder completes it.
        """
        names = self.names()
        with _interrupts_held():  # a result is either the old one or the new one, whole
            _write_atomic(self.dir / JOURNAL, journal_text(names))
            _finish_publishing(self.out_dir, self.dir.name)
        self.published = [self.out_dir / name for name in names]
        return self.published

    def discard(self) -> None:
        """Remove the stage and everything in it (nothing published stays behind)."""
        remove_folder(self.out_dir, self.dir.name)


@contextlib.contextmanager
def staged(out_dir):
    """A :class:`Stage` that is discarded when the block raises (Ctrl-C included).

    The caller cleans up leftovers first (:func:`clean_leftovers`, holding the folder's lock)
    and publishes.
    """
    stage = Stage(out_dir)
    try:
        yield stage
    finally:
        if (stage.dir / JOURNAL).exists():  # stopped while publishing: finish it
            _finish_publishing(stage.out_dir, stage.dir.name)
        stage.discard()  # published files are no longer in it


def check_target(out_dir, names, *, overwrite: bool, expected_bytes: int | None = None) -> None:
    """Refuse, before any computation, an output that cannot or must not be written.

    Parameters
    ----------
    out_dir : path-like
        The output folder; it or its nearest existing parent must be a writable folder.
    names : sequence of str
        The files the run will publish.
    overwrite : bool
        Whether existing files may be replaced.
    expected_bytes : int, optional
        Size of the result when it can be known; refused if the file system has less free.

    Raises
    ------
    ValueError
        An output name that is not a plain visible file name (:func:`name_problem`), two
        outputs of one name, an output name that is a folder; an existing output (a dangling
        link included) without ``overwrite``; an output folder that is a file.
    OSError
        A folder that cannot be written (``EACCES``/``EROFS``), too little space (``ENOSPC``).
    """
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise ValueError(f"output folder {out} exists and is not a folder; choose another --out")
    seen = {}
    for name in names:
        problem = name_problem(name)
        if problem:
            raise ValueError(f"output file name {name!r} must be a plain file name ({problem}), "
                             "e.g. 'run.nc'")
        if name.casefold() in seen:
            raise ValueError(f"two outputs of this run are named {seen[name.casefold()]!r} and "
                             f"{name!r}; give the Dataset or the figures another name")
        seen[name.casefold()] = name
        if (out / name).is_dir() and not (out / name).is_symlink():
            raise ValueError(f"{out / name} is a folder, where the output file {name!r} goes; "
                             "rename one of them")
    existing = [out / name for name in names if os.path.lexists(out / name)]
    if existing and not overwrite:
        shown = ", ".join(str(p) for p in existing[:2]) + (" ..." if len(existing) > 2 else "")
        raise ValueError(f"{shown} already exists; pass --overwrite to replace it, "
                         "or --out DIR for another folder")
    parent = out
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir():
        raise ValueError(f"{parent} is not a folder, so {out} cannot be created")
    if not os.access(parent, os.W_OK | os.X_OK) or _read_only(parent):
        raise OSError(errno.EACCES, "output folder is not writable", str(parent))
    if expected_bytes is not None:
        free = shutil.disk_usage(parent).free
        if free < expected_bytes + SPACE_MARGIN:
            raise OSError(
                errno.ENOSPC,
                "not enough free space: the result needs about "
                f"{format_bytes(expected_bytes)}, {format_bytes(free)} free on the file "
                "system of",
                str(parent),
            )


def clean_leftovers(out_dir) -> list[str]:
    """Finish or remove what killed runs left in ``out_dir``; return what was done, per stage.

    A stage with a journal was being published: its publication is completed. A stage without
    one, of a process on this host that no longer runs, is removed. Stages of other hosts
    (a shared file system) and of running processes are left alone, and so is anything not as
    this package writes it (a name that does not parse, a link, a journal naming anything but
    plain files of the stage), with one warning line each.
    """
    out = Path(out_dir)
    done = []
    if not out.is_dir():
        return done
    for entry in sorted(os.scandir(out), key=lambda e: e.name):
        if not entry.name.startswith(STAGE_PREFIX):
            continue
        owner = _owner(entry.name)
        try:
            if owner is None:
                raise UnsafeLeftover("its name is not that of a stage of this package")
            if not entry.is_dir(follow_symlinks=False):
                raise UnsafeLeftover("it is not a folder (a link or a file)")
            if os.path.lexists(os.path.join(entry.path, JOURNAL)):
                _finish_publishing(out, entry.name)
                done.append(f"completed the publication of {entry.name}")
                continue
        except UnsafeLeftover as exc:
            log.warning("left %s untouched: %s; remove it if no run of yours made it",
                        entry.path, exc)
            continue
        host, pid = owner
        if host != _host() or process_alive(pid):
            continue
        remove_folder(out, entry.name)
        done.append(f"removed the unfinished {entry.name}")
    return done


def name_problem(name) -> str | None:
    """What keeps ``name`` from being an output's file name, in words; None if nothing.

    An output is a plain file of the output folder: no folder part, not hidden (a leading dot:
    the package's own working files are hidden), no white space or control characters (so that
    a listing or a shell shows it as it is), at most 255 bytes.
    """
    if not isinstance(name, str) or not name:
        return "not empty"
    if "/" in name or "\\" in name or name in (".", ".."):
        return "no folder part"
    if name.startswith("."):
        return "not hidden: no leading dot"
    if any(c.isspace() for c in name) or not name.isprintable():
        return "no white space or control characters"
    if len(name.encode("utf-8", "surrogatepass")) > 255:
        return "at most 255 bytes"
    return None


def journal_text(names) -> str:
    """The journal of a publication of the files ``names`` (JSON)."""
    return json.dumps({"format": JOURNAL_FORMAT, "names": list(names)}, indent=1) + "\n"


def write_text(path, text: str) -> Path:
    """Write ``text`` to ``path`` under a temporary name, then rename (never a partial file)."""
    _write_atomic(Path(path), text)
    return Path(path)


def disk_error(exc: BaseException, path) -> OSError:
    """An error raised while writing ``path`` as an :class:`OSError` naming the cause.

    Libraries report a full disk in their own words (netCDF: "HDF error"); when the file
    system of ``path`` has (almost) no space left, that is the cause given.
    """
    path = Path(path)
    if isinstance(exc, OSError) and exc.errno is not None:
        return OSError(exc.errno, f"{exc.strerror} while writing", str(path))
    folder = path.parent if path.parent.exists() else None
    if folder is None:
        return OSError(errno.ENOENT, "the folder vanished while writing", str(path))
    if shutil.disk_usage(folder).free < SPACE_MARGIN:
        return OSError(errno.ENOSPC, "no space left on device while writing", str(path))
    return OSError(errno.EIO, f"could not write ({exc})", str(path))


# --- helpers ----------------------------------------------------------------------------------


@contextlib.contextmanager
def _interrupts_held():
    """Ctrl-C (and SIGTERM, which the command line turns into it) waits until the block ends.

    Publishing takes milliseconds; a signal in the middle would leave new files beside old
    ones. A run whose publication completed has finished, so the held signal is dropped.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, lambda signum, frame: None)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def _finish_publishing(out: Path, stage_name: str) -> None:
    """Move the files the journal of stage ``stage_name`` lists from it into ``out``.

    Every check comes before the first rename, so a journal that fails one moves nothing
    (:class:`UnsafeLeftover`). Renames are relative to descriptors of the two folders, opened
    without following links, so no name can lead out of ``out``.
    """
    out_fd = os.open(out, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    try:
        try:
            stage_fd = os.open(stage_name, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW
                               | os.O_CLOEXEC, dir_fd=out_fd)
        except OSError:
            raise UnsafeLeftover("it is not a folder (a link or a file)") from None
        try:
            moves = []
            for name in _read_journal(stage_fd):
                try:
                    staged_file = os.stat(name, dir_fd=stage_fd, follow_symlinks=False)
                except FileNotFoundError:
                    continue  # renamed into place before the run was killed
                if not stat.S_ISREG(staged_file.st_mode):
                    raise UnsafeLeftover(f"its journal names {name!r}, which is not a plain "
                                         "file of the stage")
                with contextlib.suppress(FileNotFoundError):
                    target = os.stat(name, dir_fd=out_fd, follow_symlinks=False)
                    if stat.S_ISDIR(target.st_mode):
                        raise UnsafeLeftover(f"its journal names {name!r}, a folder of "
                                             f"{out}")
                moves.append(name)
            for name in moves:
                os.replace(name, name, src_dir_fd=stage_fd, dst_dir_fd=out_fd)
        finally:
            os.close(stage_fd)
        with contextlib.suppress(OSError):
            os.fsync(out_fd)
        shutil.rmtree(stage_name, dir_fd=out_fd, ignore_errors=True)
    finally:
        os.close(out_fd)


def read_plain_file(path, most: int, dir_fd: int | None = None) -> bytes:
    """At most ``most + 1`` bytes of the regular file ``path`` (relative to ``dir_fd``), opened
    without following a link or waiting on a FIFO; OSError for anything else. Files a run finds
    in its folders are untrusted: one byte more than ``most`` says the file is too large."""
    fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC,
                 dir_fd=dir_fd)
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise OSError(errno.EINVAL, "not a plain file", str(path))
        return os.read(fd, most + 1)
    finally:
        os.close(fd)


def _read_journal(stage_fd: int) -> list[str]:
    """The names of a stage's journal, each checked to be an output's plain file name."""
    try:
        data = read_plain_file(JOURNAL, JOURNAL_MOST, dir_fd=stage_fd)
    except OSError:
        raise UnsafeLeftover("its journal is not a plain file") from None
    try:
        journal = json.loads(data.decode("utf-8")) if len(data) <= JOURNAL_MOST else None
    except (UnicodeDecodeError, ValueError):
        journal = None
    if not isinstance(journal, dict) or journal.get("format") != JOURNAL_FORMAT or not (
            isinstance(journal.get("names"), list)):
        raise UnsafeLeftover("its journal is not one this version of the package writes")
    for name in journal["names"]:
        if name_problem(name):
            raise UnsafeLeftover(f"its journal names {name!r}, which is not a plain file name")
    return journal["names"]


def remove_folder(out, name: str) -> None:
    """Remove the folder ``name`` of ``out`` and what it holds, never through a link (a link
    at ``name`` is left as it is)."""
    with contextlib.suppress(OSError):
        out_fd = os.open(out, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
        try:
            shutil.rmtree(name, dir_fd=out_fd, ignore_errors=True)
        finally:
            os.close(out_fd)


def _write_atomic(path: Path, text: str) -> None:
    """Write ``text`` to a new file of an unguessable name (never through a link planted at
    it), then rename it to ``path``."""
    partial = path.with_name(f".{path.name}.{os.getpid()}.{uuid.uuid4().hex[:8]}.part")
    try:
        fd = os.open(partial, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC,
                     0o666)
        with open(fd, "w", encoding="utf-8") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(partial, path)
    except BaseException:
        partial.unlink(missing_ok=True)
        raise


def _fsync_dir(folder: Path) -> None:
    with contextlib.suppress(OSError):
        fd = os.open(folder, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def _host() -> str:
    return re.sub(r"[^A-Za-z0-9_.]", "_", socket.gethostname())[:255] or "host"


def _owner(name: str):
    """(host, pid) of a stage folder's name, or None if it is not the name of one of ours."""
    match = _STAGE_NAME.fullmatch(name)
    if match is None:
        return None
    return match.group(1), int(match.group(2))


def _read_only(folder: Path) -> bool:
    """Whether ``folder`` is on a file system mounted read-only (root ignores mode bits)."""
    try:
        return bool(os.statvfs(folder).f_flag & os.ST_RDONLY)
    except OSError:
        return False
