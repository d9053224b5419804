"""Where rendered member loops live, and when they are compiled again.

Each (scene, method) loop is rendered (:func:`stability.engine.loop.render`) into a module file
in the cache directory and imported from there; its ``advance`` is given Numba's disk cache
(:class:`LoopCache`), which keeps the machine code in ``__pycache__`` beside it, so the next
process loads it instead of compiling (about 0.1 s instead of 3 to 10 s).

Numba checks only the file that defines a cached function, not the kernels it inlines from
other modules. So the file's *name* carries a digest of everything the loop is made of: the
rendered source and the text of every module it reaches (the kernel's module, the scene's, and
the package modules those refer to, followed through their globals). Editing any of them gives
a new name, hence a fresh compile; unchanged sources give the same name and a cache hit.

The cache may be shared (a cluster's shared folder, several users, many processes at once):

- Files are created like any other, with the mode the umask gives (0644 under umask 022, 0664
  under 002), under a temporary name and then renamed, so no process ever sees half a file.
- A warm loop is only read: it needs no write access and takes no lock. A process that has to
  compile a loop takes the lock file beside it first (:func:`compiling`), so processes that need
  the same loop at once compile it once: the others wait, then load that compile. A wait of more
  than ``WAIT_NOTICE_S`` says so on stderr (naming the process holding the lock) and goes on.
  A lock file that cannot be opened is no lock: the loop is compiled without it.
- A folder where a loop cannot be written, or its file read (another user's private file), is
  replaced for that loop by a private one (:func:`private_dirs`), with a one-line warning.
- A damaged entry (a truncated or garbled rendered file, Numba index or machine code) is
  discarded with a one-line warning naming the file, and rendered or compiled again.

The directory is ``$STABILITY_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/stability`` (by default
``~/.cache/stability``), with a ``loops`` folder inside; on a cluster, point
``STABILITY_CACHE_DIR`` at a shared folder so that workers compile nothing.
"""

from __future__ import annotations

import contextlib
import getpass
import hashlib
import importlib.util
import logging
import os
import secrets
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path
from types import CodeType, ModuleType

from numba.core.caching import (CompileResultCacheImpl, FunctionCache, IndexDataCacheFile,
                                InTreeCacheLocator)
from numba.core.dispatcher import Dispatcher

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


def cache_dir() -> Path:
    """The directory of rendered loops (created on first use)."""
    return Path(os.environ.get(CACHE_ENV) or _user_cache()) / "loops"


def _user_cache() -> str:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(Path.home(), ".cache")
    return os.path.join(base, "stability")


def private_dirs() -> Iterator[Path]:
    """Where a process keeps the loops :func:`cache_dir` cannot hold, in the order tried.

    The user's own cache (when ``$STABILITY_CACHE_DIR`` names another folder), then a folder of
    the user's own in the temporary directory (a home may be missing or read-only): created,
    mode 0700, only when reached, and skipped where it exists but belongs to someone else.
    """
    if (own := Path(_user_cache()) / "loops") != cache_dir():
        yield own
    user = os.getuid() if hasattr(os, "getuid") else getpass.getuser()
    temp = Path(tempfile.gettempdir()) / f"stability-{user}"
    try:
        temp.mkdir(mode=0o700, exist_ok=True)
        ours = not hasattr(os, "getuid") or temp.stat().st_uid == user
    except OSError:
        ours = False
    if ours:
        yield temp / "loops"


def source_files(*roots: str) -> list[str]:
    """Files of the modules ``roots`` and of every ``stability`` module they reach.

    A module reaches another when one of its globals is that module, or an object (function,
    dispatcher, class) defined there. The roots are followed whatever package they belong to
    (a user's own kernel module counts); beyond them only ``stability.*`` modules are.
    """
    seen: dict[str, str] = {}
    stack = list(roots)
    while stack:
        name = stack.pop()
        if name in seen:
            continue
        module = sys.modules.get(name)
        path = getattr(module, "__file__", None)
        if path is None:
            continue
        seen[name] = path
        for value in vars(module).values():
            other = value.__name__ if isinstance(value, ModuleType) else getattr(
                value, "__module__", None)
            if isinstance(other, str) and other not in seen and (
                    other == "stability" or other.startswith("stability.")):
                stack.append(other)
    return sorted(set(seen.values()))


def digest(source: str, roots, code=()) -> str:
    """SHA-256 of ``source``, of the text of :func:`source_files` of ``roots``, and of the
    compiled bytecode ``code`` (functions defined where no file says what they are: a
    notebook's kernel changes the digest when it is edited)."""
    h = hashlib.sha256(source.encode())
    for path in source_files(*roots):  # contents, not locations: checkouts share the cache
        h.update(Path(path).name.encode())
        h.update(Path(path).read_bytes())
    for function in code:
        h.update(code_fingerprint(function.__code__))
    return h.hexdigest()


def code_fingerprint(code: CodeType) -> bytes:
    """What compiled code says, the same in every process: bytecode, names and constants.

    Nested code objects are followed, and a frozenset's elements are sorted. Not
    ``marshal.dumps``: it marks an object shared when something else in the process refers to
    it too, so its bytes (and a digest of them) changed with what the process had run.
    """
    parts = [code.co_code, repr((code.co_names, code.co_varnames, code.co_freevars,
                                 code.co_cellvars, code.co_argcount, code.co_kwonlyargcount,
                                 code.co_flags)).encode()]
    parts += [_constant_fingerprint(const) for const in code.co_consts]
    return hashlib.sha256(b"\0".join(parts)).digest()


def _constant_fingerprint(const) -> bytes:
    if isinstance(const, CodeType):
        return code_fingerprint(const)
    if isinstance(const, (tuple, frozenset)):
        items = [_constant_fingerprint(item) for item in const]
        return (b"(" if isinstance(const, tuple) else b"{") + b",".join(
            items if isinstance(const, tuple) else sorted(items)) + b")"
    return repr((type(const).__name__, const)).encode()


def load_module(stem: str, source: str, roots, code=()) -> ModuleType:
    """Write ``source`` as ``<stem>__<digest>.py`` in :func:`cache_dir` (once) and import it.

    The text ``{digest}`` in ``source`` is replaced by the digest (a label in the docstring).
    Where the file cannot be written or read there, it goes to the first of
    :func:`private_dirs` that takes it (one warning a process). Every ``@njit`` function the
    module defines gets the disk cache :class:`LoopCache`, but its helpers (names starting with
    ``_``): they are compiled into the functions that call them, whose machine code on disk
    holds theirs, so a process that loads those never compiles or loads a helper.
    """
    key = digest(source, roots, code)[:20]
    name = f"{MODULE_PREFIX}__{stem}__{key}"
    if name in sys.modules:
        return sys.modules[name]
    text = source.replace("{digest}", key).encode()
    filename = f"{stem}__{key}.py"
    try:
        path = _rendered(cache_dir() / filename, text)
    except OSError as exc:
        path = _rendered_privately(filename, text, exc)
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[name]
        raise
    for value in vars(module).values():
        if (isinstance(value, Dispatcher) and value.py_func.__module__ == name
                and not value.py_func.__name__.startswith("_")):
            value._cache = LoopCache(value.py_func)  # what njit(cache=True) would set
    return module


def _rendered(path: Path, text: bytes) -> Path:
    """``path``, holding ``text``: only read when it does, else written (again, if damaged).

    OSError if it can be neither read nor written. Written under a temporary name, then
    renamed; created with mode 0666 less the umask, as any file.
    """
    try:
        if path.read_bytes() == text:
            return path
        log.warning("stability: discarded the damaged compiled-loop file %s: written again",
                    path)
    except FileNotFoundError:
        pass
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{secrets.token_hex(6)}.tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path


#: Cache folders this process could not use (each is warned about once).
_UNUSABLE: set[Path] = set()


def _rendered_privately(filename: str, text: bytes, reason: OSError) -> Path:
    """:func:`_rendered` in the first of :func:`private_dirs` that takes it; ``reason`` is why
    :func:`cache_dir` did not (it is raised if none does)."""
    for folder in private_dirs():
        try:
            path = _rendered(folder / filename, text)
        except OSError:
            continue
        if cache_dir() not in _UNUSABLE:
            _UNUSABLE.add(cache_dir())
            log.warning("stability: cannot use the compiled-loop cache %s (%s); using %s",
                        cache_dir(), reason.strerror or reason, folder)
        return path
    raise reason


class _LoopLocator(InTreeCacheLocator):
    """``__pycache__`` beside the loop's file, even where it cannot be written: Numba's own
    locator then goes elsewhere, and every user of a shared cache but its owner compiled
    again."""

    @classmethod
    def from_function(cls, py_func, py_file):
        return cls(py_func, py_file)


class _LoopCacheImpl(CompileResultCacheImpl):
    _locator_classes = [_LoopLocator]


class _DamagedEntry(Exception):
    """A cache file that exists but cannot be loaded."""

    def __init__(self, path):
        super().__init__(path)
        self.path = path


class _LoopCacheFile(IndexDataCacheFile):
    """Numba's index and machine-code files, a file that cannot be loaded named in the error."""

    def _load_index(self):
        try:
            return super()._load_index()
        except Exception as exc:
            raise _DamagedEntry(self._index_path) from exc

    def _load_data(self, name):
        try:
            return super()._load_data(name)
        except FileNotFoundError:
            raise  # a miss
        except Exception as exc:
            raise _DamagedEntry(self._data_path(name)) from exc


class LoopCache(FunctionCache):
    """Numba's disk cache of a rendered loop, for a cache others share and may damage.

    Loads from a ``__pycache__`` it cannot write (:class:`_LoopLocator`); takes the loop's
    compile lock on a miss, when :func:`compiling` has armed it, and loads again once it has it;
    discards a damaged entry with a warning (a miss: compiled again), and warns where the
    machine code cannot be saved rather than failing the run.
    """

    _impl_class = _LoopCacheImpl

    def __init__(self, py_func):
        super().__init__(py_func)
        self._cache_file = _LoopCacheFile(self._cache_path, self._impl.filename_base,
                                          self._impl.locator.get_source_stamp())
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
        a file system without locks): the loop is then compiled without it.
        """
        if fcntl is None or self.fd is not None:
            return False
        try:
            fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o666)
        except OSError:
            try:
                fd = os.open(self.path, os.O_RDONLY)  # flock needs no write access
            except OSError:
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
                                    self._holder(), self.path.stem, self.path)
                        notice = None
                    time.sleep(0.05)
        except OSError:
            os.close(fd)
            return False
        except BaseException:
            os.close(fd)
            raise
        with contextlib.suppress(OSError):  # who holds it, for the processes waiting
            os.ftruncate(fd, 0)
            os.pwrite(fd, f"{os.getpid()} on {os.uname().nodename}".encode(), 0)
        self.fd = fd
        return True

    def _holder(self) -> str:
        with contextlib.suppress(OSError, UnicodeDecodeError):
            holder = self.path.read_text().strip()
            if holder:
                return f"process {holder}"
        return "another process"

    def release(self):
        if self.fd is not None:
            with contextlib.suppress(OSError):
                os.ftruncate(self.fd, 0)
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
