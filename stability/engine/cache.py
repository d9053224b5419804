"""Where rendered member loops live, and when they are compiled again.

Each (scene, method) loop is rendered (:func:`stability.engine.loop.render`) into a module file
in the cache directory and run from the very bytes rendered (never from that file read again,
nor from a ``.pyc``); its ``advance`` is given Numba's disk cache (:class:`LoopCache`), which
keeps the machine code in ``__pycache__`` beside it, so the next process loads it instead of
compiling (about 0.1 s instead of 3 to 10 s). The file's *name* carries a digest of everything
the loop is made of (:mod:`stability.engine.sources`): an edit of any of it compiles again.

The cache may be shared (a cluster's shared folder, several users, many processes at once).
Numba's index and machine code are pickles, which run code when loaded, so nothing in the cache
is loaded unless it passes the trust rule (:mod:`stability.util.trust`): every component from
the cache root down to the file, looked at without following links, belongs to this user, to
root or to an owner named in ``$STABILITY_CACHE_OWNER``, and is writable by no one else (or by
the group named in ``$STABILITY_CACHE_GROUP``). A shared cache is therefore one prepared by one
account and read-only for the rest. A cache that fails the rule is a miss: the loop is kept in a
private cache (:func:`private_dirs`) instead, with one warning naming the reason.

- Files are created with mode 0644 and folders 0755 (less the umask), never writable by group
  or others (0775 for folders where a group is trusted), under a temporary name and then
  renamed, so no process ever sees half a file.
- A warm loop is only read: it needs no write access and takes no lock. A process that has to
  compile a loop takes the lock file beside it first (:func:`compiling`), so processes that need
  the same loop at once compile it once: the others wait, then load that compile. A wait of more
  than ``WAIT_NOTICE_S`` says so on stderr (naming the process holding the lock) and goes on.
  A lock file that is a link, a FIFO, another user's or cannot be opened is no lock: the loop is
  compiled without it; a lock file is never truncated.
- A folder where a loop cannot be written, or its file read, is replaced for that loop by a
  private one, with a one-line warning.
- A damaged entry (a truncated or garbled rendered file, Numba index or machine code) is
  discarded with a one-line warning naming the file, and rendered or compiled again.

The directory is ``$STABILITY_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/stability`` (by default
``~/.cache/stability``), with a ``loops`` folder inside; on a cluster, point
``STABILITY_CACHE_DIR`` at a folder prepared by one account so that workers compile nothing.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import logging
import os
import pickle
import secrets
import stat
import sys
import tempfile
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

from numba.core.caching import (CompileResultCacheImpl, FunctionCache, IndexDataCacheFile,
                                InTreeCacheLocator)
from numba.core.dispatcher import Dispatcher

from ..util.private import private_folder
from ..util.trust import (TrustRule, UntrustedPath, chain_problem, open_flags,
                          private_folder_problem, read_trusted)
from .sources import digest

try:  # POSIX; elsewhere each process compiles for itself
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None

log = logging.getLogger(__name__)

#: Environment variable naming the cache directory.
CACHE_ENV = "STABILITY_CACHE_DIR"
#: Name prefix of the imported loop modules (they are not part of the package).
MODULE_PREFIX = "stability_loop"
#: Seconds a process waits for another one's compile before it says so.
WAIT_NOTICE_S = 3.0
#: Global of a rendered module holding the SHA-256 of the bytes it was run from: Numba's
#: source stamp of its functions, taken from those bytes rather than the file read again.
STAMP = "__loop_sha256__"
#: Bytes of the holder's record in a lock file (written over, never truncated).
LOCK_RECORD = 128


def cache_root() -> Path:
    """The cache's root folder (links in the path given resolved: the user chose them)."""
    return Path(os.path.realpath(os.environ.get(CACHE_ENV) or _user_cache()))


def cache_dir() -> Path:
    """The directory of rendered loops (created on first use)."""
    return cache_root() / "loops"


def _user_cache() -> str:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(Path.home(), ".cache")
    return os.path.join(base, "stability")


@dataclass(frozen=True)
class Place:
    """A cache root whose ``loops`` folder may hold rendered loops, and whom it trusts."""

    root: Path
    rule: TrustRule
    #: A folder of this user's alone: it and its ``loops`` made 0700 and held to that.
    private: bool = False
    #: The folder of rendered loops in the root ("": the root itself).
    loops: str = "loops"

    @property
    def folder(self) -> Path:
        return self.root / self.loops if self.loops else self.root

    def take(self, filename: str, text: bytes) -> Path:
        """The loop file ``filename`` holding ``text`` in :attr:`folder` (written if needed).

        OSError (:class:`~stability.util.trust.UntrustedPath` among them) where the folders
        cannot be made, the loop's entries fail the trust rule, or the file cannot be written.
        """
        mode = 0o700 if self.private else _folder_mode(self.rule)
        self.root.mkdir(mode=mode, parents=True, exist_ok=True)
        self.folder.mkdir(mode=mode, exist_ok=True)
        why = (self.private and (private_folder_problem(self.root)
                                 or private_folder_problem(self.folder))
               or chain_problem(self.root, self.folder, self.rule)
               or self._entries_problem(filename))
        if why is not None:
            raise UntrustedPath(why)
        return _rendered(self.folder / filename, text, self.rule)

    def _entries_problem(self, filename: str) -> str | None:
        """Why a file of the loop ``filename`` (its source, lock, ``__pycache__`` and Numba's
        files there) fails the trust rule, or None."""
        stem = filename.removesuffix(".py")
        machine_code = self.folder / "__pycache__"
        paths = [self.folder / filename, self.folder / f"{stem}.lock", machine_code]
        with contextlib.suppress(FileNotFoundError, NotADirectoryError):
            paths += [Path(entry.path) for entry in os.scandir(machine_code)
                      if entry.name.startswith(f"{stem}.")]
        for path in paths:
            try:
                st = os.lstat(path)
            except FileNotFoundError:
                continue
            why = self.rule.problem(st)
            if why is None and path == machine_code and not stat.S_ISDIR(st.st_mode):
                why = "is not a folder"
            if why is not None:
                return f"{path} {why}"
        return None


def places() -> Iterator[Place]:
    """Where a loop may be kept, in the order tried: the cache (:func:`cache_root`), whom
    ``$STABILITY_CACHE_OWNER`` and ``$STABILITY_CACHE_GROUP`` say to trust beside this user
    and root, then :func:`private_dirs`."""
    yield Place(cache_root(), TrustRule.from_environment())
    yield from private_dirs()


def private_dirs() -> Iterator[Place]:
    """Where a process keeps the loops :func:`cache_dir` cannot hold, in the order tried.

    The user's own cache (when ``$STABILITY_CACHE_DIR`` names another folder), then a folder of
    the user's own in the temporary directory (a home may be missing or read-only):
    :func:`stability.util.private.private_folder`, which passes over a folder there that is a
    link, another user's or open to others for a fresh one of this process.
    """
    own = Path(os.path.realpath(_user_cache()))
    if own != cache_root():
        yield Place(own, TrustRule.private())
    yield Place(private_folder("loops"), TrustRule.private(), private=True, loops="")


def _folder_mode(rule: TrustRule) -> int:
    """0755, or 0775 where a group is trusted to write (its members then share the cache)."""
    return 0o775 if rule.group is not None else 0o755


def load_module(stem: str, source: str, roots, code=()) -> ModuleType:
    """Write ``source`` as ``<stem>__<digest>.py`` in the cache (once) and run it as a module.

    The text ``{digest}`` in ``source`` is replaced by the digest
    (:func:`stability.engine.sources.digest`). The file goes to the first of :func:`places`
    that takes it (a warning, once a process, where the first does not), and the module is run
    from the bytes rendered here: the file is there for Numba's cache beside it, never read
    back to be run. Every ``@njit`` function the module defines gets the disk cache
    :class:`LoopCache`, but its helpers (names starting with ``_``): they are compiled into
    the functions that call them, whose machine code on disk holds theirs.
    """
    key = digest(source, roots, code)[:20]
    name = f"{MODULE_PREFIX}__{stem}__{key}"
    if name in sys.modules:
        return sys.modules[name]
    text = source.replace("{digest}", key).encode()
    module = _run(name, _placed(f"{stem}__{key}.py", text), text)
    for value in vars(module).values():
        if (isinstance(value, Dispatcher) and value.py_func.__module__ == name
                and not value.py_func.__name__.startswith("_")):
            value._cache = LoopCache(value.py_func)  # what njit(cache=True) would set
    return module


def _run(name: str, path: Path, text: bytes) -> ModuleType:
    """The module ``name`` run from ``text`` (labelled with the file ``path`` it was put in)."""
    module = ModuleType(name)
    module.__file__ = str(path)
    module.__dict__[STAMP] = hashlib.sha256(text).digest()
    code = compile(text, str(path), "exec", dont_inherit=True)
    sys.modules[name] = module
    try:
        exec(code, module.__dict__)
    except BaseException:
        del sys.modules[name]
        raise
    return module


#: Cache folders this process could not use (each is warned about once).
_UNUSABLE: set[Path] = set()


def _placed(filename: str, text: bytes) -> Path:
    """The loop file in the first of :func:`places` that takes it; one warning a process for
    the cache where it could not go. The first refusal is raised if none takes it."""
    refused: tuple[Place, OSError] | None = None
    for place in places():
        try:
            path = place.take(filename, text)
        except OSError as exc:
            refused = refused or (place, exc)
            continue
        if refused is not None and refused[0].folder not in _UNUSABLE:
            _UNUSABLE.add(refused[0].folder)
            reason = refused[1]
            log.warning("stability: cannot use the compiled-loop cache %s (%s); using %s",
                        refused[0].folder, reason.strerror or reason, place.folder)
        return path
    raise refused[1]


def _rendered(path: Path, text: bytes, rule: TrustRule) -> Path:
    """``path``, holding ``text``: only read when it does, else written (again, if damaged).

    OSError if it can be neither read nor written. Written under a temporary name (never
    through a link), then renamed; created with mode 0644 less the umask.
    """
    try:
        if read_trusted(path, rule) == text:
            return path
        log.warning("stability: discarded the damaged compiled-loop file %s: written again",
                    path)
    except FileNotFoundError:
        pass
    _write_new(path, text)
    return path


def _write_new(path: Path, data: bytes) -> None:
    """``data`` as the file ``path`` (:func:`_new_file`)."""
    with _new_file(path) as f:
        f.write(data)


@contextlib.contextmanager
def _new_file(path: Path):
    """A file to write ``path`` through: a new temporary file beside it (created exclusively,
    mode 0644, never through a link), renamed over ``path`` once the block ends, and removed
    if it fails."""
    tmp = path.with_name(f".{path.name}.{secrets.token_hex(6)}.tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | open_flags(), 0o644)
    try:
        with os.fdopen(fd, "wb") as f:
            yield f
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


class _LoopLocator(InTreeCacheLocator):
    """``__pycache__`` beside the loop's file, even where it cannot be written (Numba's own
    locator then goes elsewhere, and every user of a shared cache but its owner compiled
    again); the source stamp is the digest of the bytes the module was run from, and the
    folder is made with the cache's mode."""

    def __init__(self, py_func, py_file):
        super().__init__(py_func, py_file)
        self._stamp = py_func.__globals__.get(STAMP)

    @classmethod
    def from_function(cls, py_func, py_file):
        return cls(py_func, py_file)

    def get_source_stamp(self):
        return self._stamp if self._stamp is not None else super().get_source_stamp()

    def ensure_cache_path(self):
        with contextlib.suppress(FileExistsError):
            os.mkdir(self._cache_path, _folder_mode(TrustRule.from_environment()))
        tempfile.TemporaryFile(dir=self._cache_path).close()


class _LoopCacheImpl(CompileResultCacheImpl):
    _locator_classes = [_LoopLocator]


class _DamagedEntry(Exception):
    """A cache file that exists but cannot be loaded."""

    def __init__(self, path):
        super().__init__(path)
        self.path = path


class _UntrustedEntry(_DamagedEntry):
    """A cache file that fails the trust rule: never unpickled, never removed."""


class _LoopCacheFile(IndexDataCacheFile):
    """Numba's index and machine-code files, each read through one checked descriptor
    (:func:`~stability.util.trust.read_trusted`) before it is unpickled, and written without
    following links; a file that cannot be loaded is named in the error."""

    def __init__(self, cache_path, filename_base, source_stamp, rule: TrustRule):
        super().__init__(cache_path, filename_base, source_stamp)
        self._rule = rule

    def _read(self, path):
        try:
            return read_trusted(Path(path), self._rule)
        except FileNotFoundError:
            raise
        except UntrustedPath as exc:
            raise _UntrustedEntry(path) from exc
        except OSError as exc:
            raise _DamagedEntry(path) from exc

    def _load_index(self):
        try:
            stream = io.BytesIO(self._read(self._index_path))
        except FileNotFoundError:
            return {}
        try:
            if pickle.load(stream) != self._version:
                return {}  # another version of Numba's: its entries are not ours to read
            stamp, overloads = pickle.loads(stream.read())
        except Exception as exc:
            raise _DamagedEntry(self._index_path) from exc
        return overloads if stamp == self._source_stamp else {}

    def _load_data(self, name):
        data = self._read(self._data_path(name))  # FileNotFoundError: a miss
        try:
            return pickle.loads(data)
        except Exception as exc:
            raise _DamagedEntry(self._data_path(name)) from exc

    def _open_for_write(self, filepath):
        return _new_file(Path(filepath))


class LoopCache(FunctionCache):
    """Numba's disk cache of a rendered loop, for a cache others share and may damage.

    Loads from a ``__pycache__`` it cannot write (:class:`_LoopLocator`), only files that pass
    the trust rule; takes the loop's compile lock on a miss, when :func:`compiling` has armed
    it, and loads again once it has it; discards a damaged entry with a warning (a miss:
    compiled again), passes over an untrusted one with a warning, and warns where the machine
    code cannot be saved rather than failing the run.
    """

    _impl_class = _LoopCacheImpl

    def __init__(self, py_func):
        super().__init__(py_func)
        self._cache_file = _LoopCacheFile(self._cache_path, self._impl.filename_base,
                                          self._impl.locator.get_source_stamp(),
                                          TrustRule.from_environment())
        self.lock: _CompileLock | None = None

    def load_overload(self, sig, target_context):
        found = self._load_or_discard(sig, target_context)
        if found is None and self.lock is not None and self.lock.acquire():
            found = self._load_or_discard(sig, target_context)  # the holder's compile
        return found

    def _load_or_discard(self, sig, target_context):
        try:
            return super().load_overload(sig, target_context)
        except Exception as exc:
            path = getattr(exc, "path", self._cache_file._index_path)
            cause = exc.__cause__ or exc
            if isinstance(exc, _UntrustedEntry):
                log.warning("stability: not loading the compiled-loop file %s (%s): compiled "
                            "again", path, cause)
                return None
            if isinstance(cause, PermissionError):  # another user's: not ours to remove
                log.warning("stability: cannot read the compiled-loop file %s: compiled again",
                            path)
                return None
            log.warning("stability: discarded the damaged compiled-loop file %s (%s: %s): "
                        "compiled again", path, type(cause).__name__, cause)
            with contextlib.suppress(OSError):
                os.unlink(path)
            return None

    def save_overload(self, sig, data):
        try:
            super().save_overload(sig, data)
        except Exception as exc:
            cause = exc.__cause__ or exc
            log.warning("stability: cannot save the compiled loop in %s (%s: %s): the next run "
                        "compiles it again", self._cache_path, type(cause).__name__, cause)


class _CompileLock:
    """The lock file ``path``, held by the one process compiling the loop beside it."""

    def __init__(self, path: Path):
        self.path = path
        self.fd: int | None = None

    def acquire(self) -> bool:
        """Take the lock, waiting for its holder (saying so after :data:`WAIT_NOTICE_S`).

        False, and nothing held, where the file cannot be opened or locked (a read-only folder,
        a file system without locks) or is no lock of a trusted owner (:meth:`_open`): the loop
        is then compiled without it.
        """
        if fcntl is None or self.fd is not None:
            return False
        fd = self._open()
        if fd is None:
            return False
        try:
            notice = time.monotonic() + WAIT_NOTICE_S
            while True:
                try:
                    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                    break
                except BlockingIOError:
                    if notice is not None and time.monotonic() >= notice:
                        log.warning("stability: waiting for %s compiling %s (lock %s)",
                                    self._holder(fd), self.path.stem, self.path)
                        notice = None
                    time.sleep(0.05)
        except OSError:
            os.close(fd)
            return False
        except BaseException:
            os.close(fd)
            raise
        self._record(fd, f"{os.getpid()} on {os.uname().nodename}")
        self.fd = fd
        return True

    def _open(self) -> int | None:
        """A descriptor of the lock file: created here, or an existing regular file of a
        trusted owner with one link, opened without following a link and without blocking
        (a FIFO at its name is refused at once). None where there is no such file."""
        flags = open_flags()
        try:
            return os.open(self.path, os.O_RDWR | os.O_CREAT | os.O_EXCL | flags, 0o644)
        except FileExistsError:
            pass
        except OSError:
            return None
        for access in (os.O_RDWR, os.O_RDONLY):  # flock needs no write access
            try:
                fd = os.open(self.path, access | flags)
                break
            except OSError:
                continue
        else:
            return None
        st = os.fstat(fd)
        if TrustRule.from_environment().problem(st) is not None:
            os.close(fd)
            return None
        return fd

    @staticmethod
    def _record(fd: int, text: str) -> None:
        """Write the holder's record over the first :data:`LOCK_RECORD` bytes (no truncation:
        the file may be another process's)."""
        with contextlib.suppress(OSError):
            os.pwrite(fd, text.encode()[:LOCK_RECORD].ljust(LOCK_RECORD), 0)

    @staticmethod
    def _holder(fd: int) -> str:
        with contextlib.suppress(OSError, UnicodeDecodeError):
            holder = os.pread(fd, LOCK_RECORD, 0).decode().strip()
            if holder:
                return f"process {holder}"
        return "another process"

    def release(self):
        if self.fd is not None:
            self._record(self.fd, "")
            os.close(self.fd)  # releases the lock
            self.fd = None


@contextlib.contextmanager
def compiling(function):
    """Within this block, a call of ``function`` that finds no machine code on disk takes the
    lock file ``<module>.lock`` beside its file before compiling, then loads again (the holder
    may have just compiled it); released at the end of the block.

    So processes that need a loop at once compile it once, and a warm loop takes no lock. A
    function without :class:`LoopCache` takes none.
    """
    cache = getattr(function, "_cache", None)
    if not isinstance(cache, LoopCache):
        yield
        return
    lock = cache.lock = _CompileLock(
        Path(function.py_func.__code__.co_filename).with_suffix(".lock"))
    try:
        yield
    finally:
        lock.release()
        if cache.lock is lock:
            cache.lock = None
