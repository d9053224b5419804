"""The outputs of a run as one unit: staged in a hidden folder, published together or not at all.

A study writes its Dataset, configuration and figures into a :class:`Stage`, a hidden folder
``.stability-stage-<host>-<pid>-<tag>`` inside the output folder (so publishing is a rename
within one file system). Only when every file is complete does :meth:`Stage.publish` move them
to their final names: it first writes a journal (the list of names) into the stage, then
renames file after file, then removes the stage. A run killed before the journal leaves an
unpublished stage, which the next run in that folder removes; a run killed while publishing
leaves a journal, and the next run finishes the publication (every staged file was complete).
So an earlier result replaced with ``--overwrite`` stays intact until the new one is whole,
and no temporary file outlives the run that made it by more than the next run.

Checks of the target come first (:func:`check_target`): the folder can be created and written,
no output name is a folder, nothing is replaced without ``overwrite``, and the free space
covers the expected size of the result when it is known. Errors of the file system while
writing (a full disk, a permission, a vanished folder) are :class:`OSError` with the path and
the cause, which the command line reports in one line with exit status 2.
"""

from __future__ import annotations

import contextlib
import errno
import os
import shutil
import signal
import socket
import threading
import uuid
from pathlib import Path

#: Name prefix of stage folders.
STAGE_PREFIX = ".stability-stage-"

#: File in a stage listing the names being published; its presence means "all complete".
JOURNAL = ".publishing"

#: Free space kept beyond the expected size of a result (bytes).
SPACE_MARGIN = 16 * 2**20


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
        try:
            self.out_dir.mkdir(parents=True, exist_ok=True)
            self.dir.mkdir()
            probe = self.dir / ".probe"
            probe.write_bytes(b"0")
            probe.unlink()
        except OSError as exc:
            shutil.rmtree(self.dir, ignore_errors=True)
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
            _write_atomic(self.dir / JOURNAL, "\n".join(names) + "\n")
            _finish_publishing(self.dir, self.out_dir)
        self.published = [self.out_dir / name for name in names]
        return self.published

    def discard(self) -> None:
        """Remove the stage and everything in it (nothing published stays behind)."""
        shutil.rmtree(self.dir, ignore_errors=True)


@contextlib.contextmanager
def staged(out_dir):
    """A :class:`Stage` that is discarded when the block raises (Ctrl-C included).

    Leftovers of killed runs in ``out_dir`` are cleaned up first. The caller publishes.
    """
    clean_leftovers(out_dir)
    stage = Stage(out_dir)
    try:
        yield stage
    finally:
        if (stage.dir / JOURNAL).exists():  # stopped while publishing: finish it
            _finish_publishing(stage.dir, stage.out_dir)
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
        An output name that is empty, has a folder part or is a folder; an existing output
        without ``overwrite``; an output folder that is a file.
    OSError
        A folder that cannot be written (``EACCES``/``EROFS``), too little space (``ENOSPC``).
    """
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise ValueError(f"output folder {out} exists and is not a folder; choose another --out")
    for name in names:
        if not name or Path(name).name != name or name in (".", ".."):
            raise ValueError(f"output file name {name!r} must be a plain file name (no folder "
                             "part, not empty), e.g. 'run.nc'")
        if (out / name).is_dir():
            raise ValueError(f"{out / name} is a folder, where the output file {name!r} goes; "
                             "rename one of them")
    existing = [out / name for name in names if (out / name).exists()]
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
                f"not enough free space: the result needs about {_size(expected_bytes)}, "
                f"{_size(free)} free on the file system of",
                str(parent),
            )


def clean_leftovers(out_dir) -> list[str]:
    """Finish or remove what killed runs left in ``out_dir``; return what was done, per stage.

    A stage with a journal was being published: its publication is completed. A stage without
    one, of a process on this host that no longer runs, is removed. Stages of other hosts
    (a shared file system) and of running processes are left alone.
    """
    out = Path(out_dir)
    done = []
    if not out.is_dir():
        return done
    for stage in sorted(out.glob(STAGE_PREFIX + "*")):
        if not stage.is_dir():
            continue
        if (stage / JOURNAL).exists():
            _finish_publishing(stage, out)
            done.append(f"completed the publication of {stage.name}")
            continue
        host, pid = _owner(stage.name)
        if host != _host() or (pid is not None and process_alive(pid)):
            continue
        shutil.rmtree(stage, ignore_errors=True)
        done.append(f"removed the unfinished {stage.name}")
    return done


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


def _finish_publishing(stage: Path, out: Path) -> None:
    names = (stage / JOURNAL).read_text(encoding="utf-8").split()
    for name in names:
        staged_file = stage / name
        if staged_file.exists():
            os.replace(staged_file, out / name)
    _fsync_dir(out)
    shutil.rmtree(stage, ignore_errors=True)


def _write_atomic(path: Path, text: str) -> None:
    partial = path.with_name(f".{path.name}.{os.getpid()}.part")
    try:
        with open(partial, "w", encoding="utf-8") as f:
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
    return socket.gethostname().replace("-", "_") or "host"


def _owner(name: str):
    """(host, pid) of a stage folder's name, or (None, None) if it is not one of ours."""
    parts = name[len(STAGE_PREFIX):].split("-")
    if len(parts) != 3 or not parts[1].isdigit():
        return None, None
    return parts[0], int(parts[1])


def process_alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _read_only(folder: Path) -> bool:
    """Whether ``folder`` is on a file system mounted read-only (root ignores mode bits)."""
    try:
        return bool(os.statvfs(folder).f_flag & os.ST_RDONLY)
    except OSError:
        return False


def _size(n: float) -> str:
    from .ensemble import format_bytes

    return format_bytes(n)
