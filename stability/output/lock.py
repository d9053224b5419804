"""A folder held by one run at a time: an OS lock that dies with the process that holds it.

A run takes :class:`FolderLock` on its output folder (the file ``.stability-lock`` inside it) for
its whole life, and a chunk store on its own folder (``.lock``). The lock is ``fcntl.flock`` on
that file: the kernel releases it when the process ends, however it ends (``kill -9``
included), so a lock is never stale. A second run that finds the lock held is refused at once,
with the holder's process id and host (written into the lock file by the holder), and touches
nothing: it neither waits nor cleans up what the holder owns.

The lock file is removed when the lock is given back. A process that opened the file just
before it was removed would hold a lock on a file no longer in the folder, so after locking,
the file's identity is checked against the name in the folder and the lock is taken again on
a mismatch (the usual protocol for lock files that are removed). The file is opened relative to
the folder's descriptor and never through a symbolic link. Without ``fcntl`` (Windows) nothing
is held.
"""

from __future__ import annotations

import contextlib
import json
import os
import socket
import stat
import time
from pathlib import Path

try:  # POSIX
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None

#: The lock of an output folder, held by the run that writes into it.
OUTPUT_LOCK = ".stability-lock"

#: Most bytes read from a lock file written by another process (it holds one short line).
_MOST = 4096


class FolderBusy(ValueError):
    """Another live process holds the folder."""


class FolderLock:
    """An exclusive lock on ``folder`` held through the file ``name`` in it.

    Parameters
    ----------
    folder : path-like
        An existing folder. The path itself may be a link chosen by the user; the lock file
        in it is never followed.
    name : str
        The lock file's name.
    what : str
        How the refusal names the folder ("output folder", "chunk folder").
    """

    def __init__(self, folder, name: str = OUTPUT_LOCK, what: str = "folder"):
        self.folder = Path(folder)
        self.name = name
        self.what = what
        self._fd = None
        self._dir_fd = None

    def acquire(self) -> "FolderLock":
        """Take the lock, or raise :class:`FolderBusy` naming the process that holds it."""
        if fcntl is None or self._fd is not None:
            return self
        dir_fd = os.open(self.folder, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
        try:
            for _ in range(100):  # each retry means the file was removed under us: rare
                fd = _open_lock_file(self.name, dir_fd, self.folder)
                try:
                    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                except BlockingIOError:
                    holder = _read_holder(fd)
                    os.close(fd)
                    raise FolderBusy(f"{self.folder} is in use by another run ({holder}); wait "
                                     f"for it to end (stability status {self.folder}) or stop "
                                     "it, or choose another folder") from None
                except BaseException:
                    os.close(fd)
                    raise
                if _same_file(fd, self.name, dir_fd):
                    break
                os.close(fd)
            else:  # pragma: no cover - another process keeps removing the file
                raise FolderBusy(f"{self.folder}: its lock file {self.name} keeps vanishing")
            _write_holder(fd)
        except BaseException:
            os.close(dir_fd)
            raise
        self._fd, self._dir_fd = fd, dir_fd
        return self

    def release(self) -> None:
        """Remove the lock file and give the lock back (a no-op if not held)."""
        if self._fd is None:
            return
        fd, dir_fd, self._fd, self._dir_fd = self._fd, self._dir_fd, None, None
        try:
            if _same_file(fd, self.name, dir_fd):
                with contextlib.suppress(OSError):
                    os.unlink(self.name, dir_fd=dir_fd)
        finally:
            os.close(fd)
            os.close(dir_fd)

    @property
    def held(self) -> bool:
        return self._fd is not None

    def __del__(self):  # a lock nobody refers to any more is given back, as at exit
        try:
            self.release()
        except Exception:  # noqa: BLE001 - the interpreter may be shutting down
            pass

    def __enter__(self):
        return self.acquire()

    def __exit__(self, *exc):
        self.release()


def holder_of(folder, name: str = OUTPUT_LOCK) -> str | None:
    """Who holds ``folder``'s lock ("process 12 on host h, since ..."), or None if nobody."""
    if fcntl is None:
        return None
    try:
        dir_fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    except OSError:
        return None
    try:
        fd = os.open(name, os.O_RDONLY | os.O_NOFOLLOW | os.O_CLOEXEC | os.O_NONBLOCK,
                     dir_fd=dir_fd)
    except OSError:
        return None
    finally:
        os.close(dir_fd)
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            return None
        try:  # a shared lock is granted only when no exclusive one is held
            fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
        except BlockingIOError:
            return _read_holder(fd)
        fcntl.flock(fd, fcntl.LOCK_UN)
        return None
    finally:
        os.close(fd)


def process_alive(pid: int) -> bool:
    """Whether the process ``pid`` of this host runs (one of another user counts)."""
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


# --- helpers ----------------------------------------------------------------------------------


def _open_lock_file(name: str, dir_fd: int, folder: Path) -> int:
    """The lock file, created if missing (mode 0666 less the umask), never through a link.

    One that this user may not write (left by another user's killed run) is opened to read:
    ``flock`` needs no more, only the holder's note is then not written.
    """
    flags = os.O_CREAT | os.O_NOFOLLOW | os.O_CLOEXEC | os.O_NONBLOCK
    try:
        try:
            fd = os.open(name, os.O_RDWR | flags, 0o666, dir_fd=dir_fd)
        except PermissionError:
            fd = os.open(name, os.O_RDONLY | flags, 0o666, dir_fd=dir_fd)
    except OSError as exc:
        if exc.errno == getattr(os, "ELOOP", None) or os.path.islink(folder / name):
            raise ValueError(f"{folder / name} is a symbolic link; a run's lock file must be "
                             "a plain file: remove the link") from None
        raise OSError(exc.errno, f"cannot take the lock of the {folder} ({exc.strerror})",
                      str(folder / name)) from None
    st = os.fstat(fd)
    if not stat.S_ISREG(st.st_mode) or st.st_nlink != 1:
        os.close(fd)
        kind = "not a plain file" if not stat.S_ISREG(st.st_mode) else (
            f"a file with {st.st_nlink} names (a hard link)")
        raise ValueError(f"{folder / name} is {kind}; a run's lock file must be a plain file "
                         "of its own: remove it")
    return fd


def _same_file(fd: int, name: str, dir_fd: int) -> bool:
    try:
        there = os.stat(name, dir_fd=dir_fd, follow_symlinks=False)
    except OSError:
        return False
    here = os.fstat(fd)
    return (there.st_dev, there.st_ino) == (here.st_dev, here.st_ino)


def _write_holder(fd: int) -> None:
    """The holder's note, written over the file's start and padded with blanks to the length
    it had (at most :data:`_MOST`): the file is never truncated, as it may not be ours."""
    text = json.dumps({"pid": os.getpid(), "host": socket.gethostname(),
                       "since": time.strftime("%Y-%m-%dT%H:%M:%S%z")}) + "\n"
    with contextlib.suppress(OSError):  # the lock holds without the note
        size = min(os.fstat(fd).st_size, _MOST)
        os.pwrite(fd, text.encode().ljust(size), 0)


def _read_holder(fd: int) -> str:
    """The holder's note from an open lock file, as words; untrusted, so checked."""
    try:
        note = json.loads(os.pread(fd, _MOST, 0).decode("utf-8"))
    except (OSError, ValueError):
        note = None
    if not isinstance(note, dict):
        return "a process that left no note"
    pid, host, since = note.get("pid"), note.get("host"), note.get("since")
    if not isinstance(pid, int) or isinstance(pid, bool) or pid <= 0 or (
            host == socket.gethostname() and not process_alive(pid)):
        return "a process that left no note"  # a note of a process that ended is stale
    words = f"process {pid}"
    if isinstance(host, str) and host.isprintable() and len(host) <= 255:
        words += f" on host {host}"
    if isinstance(since, str) and since.isprintable() and len(since) <= 40:
        words += f", since {since}"
    return words
