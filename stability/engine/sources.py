"""What a compiled loop is made of, as one digest: the name under which it is cached.

Numba checks only the file that defines a cached function, not the kernels it inlines from
other modules, and it reads global variables as constants frozen into the machine code. So a
loop's digest (:func:`digest`) covers

- the rendered source;
- the text of every module the loop reaches (:func:`source_files`): its roots (the kernel's
  module, the scene's, a user's module), the package modules those refer to, and, from a user's
  module, every other module of the user's it refers to (a helper module the right-hand side
  imports), but not the standard library or installed packages;
- the compiled code of the functions given (a notebook's kernel has no file saying what it is);
- the values of the plain globals those functions read, and the functions they call read
  (:func:`globals_fingerprint`): a number set from the environment or a configuration file at
  start-up changes the digest as an edit does.

Editing any of them gives a new name, hence a fresh compile; unchanged ones give the same name
and a cache hit, in any process (the digest depends on nothing else the process holds).
"""

from __future__ import annotations

import functools
import hashlib
import site
import sys
import sysconfig
from collections.abc import Callable, Iterable
from pathlib import Path
from types import CodeType, FunctionType, ModuleType

import numpy as np


def digest(source: str, roots, code=()) -> str:
    """SHA-256 of ``source``, of the text of :func:`source_files` of ``roots``, and of the
    compiled code ``code`` and the plain globals it reads (:func:`globals_fingerprint`)."""
    h = hashlib.sha256(source.encode())
    for path in source_files(*roots):  # contents, not locations: checkouts share the cache
        h.update(Path(path).name.encode())
        h.update(Path(path).read_bytes())
    for function in code:
        h.update(code_fingerprint(function.__code__))
    h.update(globals_fingerprint(code))
    return h.hexdigest()


def source_files(*roots: str) -> list[str]:
    """Files of the modules ``roots`` and of every module they reach that may change.

    A module reaches another when one of its globals is that module, or an object (function,
    dispatcher, class) defined there. The roots are followed whatever package they belong to;
    beyond them, ``stability`` modules are followed, and, from a module of the user's (neither
    the package, nor the standard library, nor an installed package), the user's other modules.
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
        users = _is_users(module)
        for value in vars(module).values():
            other = value.__name__ if isinstance(value, ModuleType) else getattr(
                value, "__module__", None)
            if isinstance(other, str) and other not in seen and (
                    _is_package(other) or users and _is_users(sys.modules.get(other))):
                stack.append(other)
    return sorted(set(seen.values()))


def globals_fingerprint(functions: Iterable[Callable]) -> bytes:
    """SHA-256 of the plain globals (numbers, strings, arrays, tuples of them) that
    ``functions`` read, and those read by the package's and the user's functions they call.

    A global read as ``module.NAME`` counts too. Numba compiles such values into the machine
    code as constants, so they are part of what a loop is.
    """
    h = hashlib.sha256()
    seen: set[int] = set()
    stack = [getattr(f, "py_func", f) for f in functions]
    while stack:
        function = stack.pop()
        if not isinstance(function, FunctionType) or id(function) in seen:
            continue
        seen.add(id(function))
        names = _names(function.__code__)
        space = function.__globals__
        values = [(name, space[name]) for name in names if name in space]
        values += [(f"{value.__name__}.{name}", getattr(value, name))
                   for _, value in list(values) if isinstance(value, ModuleType)
                   for name in names if hasattr(value, name)]
        cells = function.__closure__ or ()
        values += [(f"<cell {k}>", cell.cell_contents) for k, cell in enumerate(cells)
                   if _filled(cell)]
        for name, value in sorted(values, key=lambda item: item[0]):
            plain = _plain(value)
            if plain is not None:
                h.update(f"{function.__module__}.{function.__qualname__}:{name}=".encode())
                h.update(plain)
                continue
            inner = getattr(value, "py_func", value)
            home = getattr(inner, "__module__", None)
            if isinstance(inner, FunctionType) and isinstance(home, str) and (
                    _is_package(home) or _is_users(sys.modules.get(home))):
                stack.append(inner)
    return h.digest()


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


def _names(code: CodeType) -> list[str]:
    """The global and attribute names ``code`` and the code nested in it use, sorted."""
    names = set(code.co_names)
    for const in code.co_consts:
        if isinstance(const, CodeType):
            names.update(_names(const))
    return sorted(names)


def _filled(cell) -> bool:
    try:
        cell.cell_contents
    except ValueError:  # an empty cell
        return False
    return True


def _plain(value) -> bytes | None:
    """The bytes of a value Numba would freeze as a constant, or None for anything else."""
    if value is None or isinstance(value, (bool, int, float, complex, str, bytes)):
        return repr((type(value).__name__, value)).encode()
    if isinstance(value, np.generic):
        return repr((value.dtype.str, value.item())).encode()
    if isinstance(value, np.ndarray) and value.dtype.kind in "biufcSU":
        return repr((value.dtype.str, value.shape)).encode() + np.ascontiguousarray(
            value).tobytes()
    if isinstance(value, tuple):
        items = [_plain(item) for item in value]
        if all(item is not None for item in items):
            return b"(" + b",".join(items) + b")"
    return None


def _is_package(name: str) -> bool:
    return name == "stability" or name.startswith("stability.")


def _is_users(module) -> bool:
    """Whether ``module`` is the user's own code: a source file outside the package, the
    standard library and every site-packages folder."""
    path = getattr(module, "__file__", None)
    if not isinstance(path, str) or not path.endswith(".py"):
        return False
    name = getattr(module, "__name__", "")
    if _is_package(name):
        return False
    resolved = str(Path(path).resolve())
    return not any(resolved.startswith(prefix) for prefix in _installed())


@functools.cache
def _installed() -> tuple[str, ...]:
    """Folders of the standard library and of installed packages."""
    paths = sysconfig.get_paths()
    folders = [paths[key] for key in ("stdlib", "platstdlib", "purelib", "platlib")
               if key in paths]
    folders += getattr(site, "getsitepackages", list)()
    folders.append(site.getusersitepackages())
    folders += [sys.base_prefix, sys.base_exec_prefix]
    return tuple(sorted({str(Path(f).resolve()) + "/" for f in folders if f}))


__all__ = ["code_fingerprint", "digest", "globals_fingerprint", "source_files"]
