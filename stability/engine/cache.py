"""Where rendered member loops live, and when they are compiled again.

Each (scene, method) loop is rendered (:func:`stability.engine.loop.render`) into a module file
in the cache directory and imported from there; its ``advance`` is ``njit(cache=True)``, so Numba
keeps the machine code in ``__pycache__`` beside it and the next process loads it instead of
compiling (about 0.1 s instead of 5 to 20 s).

Numba checks only the timestamp of the file that defines a cached function, not of the kernels
it inlines from other modules. So the file's *name* carries a digest of everything the loop is
made of: the rendered source and the text of every module it reaches (the kernel's module, the
scene's, and the package modules those refer to, followed through their globals). Editing any of
them gives a new name, hence a fresh compile; unchanged sources give the same name and a cache
hit. Files are written atomically (a temporary name, then ``os.replace``), so processes that
render the same loop at once (dask workers, a crashed run) never see half a file, and the first
compile of a loop holds a lock file beside it (:func:`compiling`), so processes that need the
same loop at once (test workers, dask workers on one machine) compile it once: the others wait,
then load it from disk.

The directory is ``$STABILITY_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/stability`` (by default
``~/.cache/stability``), with a ``loops`` folder inside; on a cluster, point
``STABILITY_CACHE_DIR`` at a shared folder so that workers compile nothing.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import os
import sys
import tempfile
from pathlib import Path
from types import CodeType, ModuleType

try:  # POSIX; elsewhere each process compiles for itself
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None

#: Environment variable naming the cache directory.
CACHE_ENV = "STABILITY_CACHE_DIR"
#: Name prefix of the imported loop modules (they are not part of the package).
MODULE_PREFIX = "stability_loop"


def cache_dir() -> Path:
    """The directory of rendered loops (created on first use)."""
    root = os.environ.get(CACHE_ENV)
    if not root:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(Path.home(), ".cache")
        root = os.path.join(base, "stability")
    return Path(root) / "loops"


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
    """
    key = digest(source, roots, code)[:20]
    name = f"{MODULE_PREFIX}__{stem}__{key}"
    if name in sys.modules:
        return sys.modules[name]
    folder = cache_dir()
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{stem}__{key}.py"
    text = source.replace("{digest}", key)
    if not path.exists() or path.read_text() != text:
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{stem}.", suffix=".tmp")
        try:
            with os.fdopen(fd, "w") as f:
                f.write(text)
            os.replace(tmp, path)
        except BaseException:
            Path(tmp).unlink(missing_ok=True)
            raise
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        del sys.modules[name]
        raise
    return module


@contextlib.contextmanager
def compiling(function):
    """Hold an exclusive lock on ``<module>.lock`` beside the file defining ``function``.

    Numba looks for the function's machine code on disk when it is called without it, so a
    process that waited here for another one's compile of the same loop loads that compile
    instead of repeating it. Without ``fcntl`` (Windows) or a writable folder, nothing is held.
    """
    path = Path(function.py_func.__code__.co_filename).with_suffix(".lock")
    try:
        handle = open(path, "a") if fcntl is not None else None
    except OSError:
        handle = None
    if handle is None:
        yield
        return
    with handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)
