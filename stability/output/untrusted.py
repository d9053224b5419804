"""Reading a netCDF file the package is handed, which may be hostile: :func:`read_dataset`.

A file given to :func:`stability.load`, or found in a run's chunk folder, is input like any
other, and the netCDF library trusts it: it follows an HDF5 external link to another file
(whose contents then come back as a variable; a link to a FIFO waits for good), reads a
variable's data from external files the file names, allocates whatever size a file declares
(a 6 kB file can declare 1e12 members), and reports a damaged chunk as "NetCDF: HDF error",
naming no file. So before the netCDF library opens a file: it must be a regular file (a FIFO,
a device or a folder is refused without being opened for reading; the check opens nothing
that blocks), and its HDF5 objects are walked (:mod:`stability.output.hdf5_links`, without
following any link) for external links, user-defined links, external storage and virtual
datasets, each refused. Then the declared size of its variables is checked against the memory
limit before any is read, and every read error names the file. Each refusal is one line: what is wrong and what to do.
"""

from __future__ import annotations

import contextlib
import math
import os
import stat
from pathlib import Path

import xarray as xr
from xarray.backends import NetCDF4DataStore

from ..ensemble.memory import DEFAULT_MAX_MEMORY, memory_problem
from .hdf5_links import DamagedHDF5, outside

#: Bytes a string element of a variable is counted in memory (a Python str of a short label).
STRING_BYTES = 64

#: How the line for a file that reaches outside itself ends.
NOT_OURS = ("and stability reads nothing outside the file it is given; use a file written by "
            "stability.save (which has none)")


def regular_file(path) -> Path:
    """``path`` if it is a regular file (or a link to one), else one line saying what it is.

    Checked with ``stat`` before any open, then again on a descriptor opened with
    ``O_NONBLOCK`` (so a FIFO put in its place meanwhile never blocks the open).

    Raises
    ------
    FileNotFoundError
        If nothing is there.
    ValueError
        If it is a folder, a FIFO, a device or a socket.
    PermissionError
        If it cannot be read.
    """
    path = Path(path)
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        raise FileNotFoundError(f"no such file: {path}") from None
    except OSError as exc:  # a loop of links, a name too long ...
        raise ValueError(f"{path} cannot be read as a file ({exc.strerror})") from None
    if stat.S_ISREG(mode):
        flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
        fd = os.open(path, flags | getattr(os, "O_CLOEXEC", 0))
        try:
            mode = os.fstat(fd).st_mode
        finally:
            os.close(fd)
    if stat.S_ISDIR(mode):
        raise ValueError(f"{path} is a folder; give a .nc file written by stability.save (the "
                         "folder of a stored run opens with stability.output.store.open_store)")
    if not stat.S_ISREG(mode):
        raise ValueError(f"{path} is {_kind(mode)}, not a regular file; a netCDF file is read "
                         "from a regular file only: copy it to one first")
    return path


def check_links(path) -> None:
    """ValueError if the HDF5 file ``path`` reaches outside itself: an external or
    user-defined link, a variable with external storage, or a virtual dataset
    (:func:`stability.output.hdf5_links.outside`). A file that is not HDF5 (netCDF classic, or
    no netCDF file at all) passes: it has none of these."""
    path = Path(path)
    try:
        problem = outside(path)
    except DamagedHDF5 as exc:
        raise ValueError(f"{path} is a damaged HDF5 file ({exc}); give a .nc file written by "
                         "stability.save") from None
    if problem:
        raise ValueError(f"{path} {problem}, {NOT_OURS}")


def checked_file(path) -> Path:
    """:func:`regular_file` and :func:`check_links`: ``path`` if it may be given to netCDF."""
    path = regular_file(path)
    check_links(path)
    return path


def declared_bytes(path, indexes_only: bool = False, drop=()) -> int:
    """Bytes the variables of the netCDF file ``path`` (its root group, as xarray opens it)
    would take in memory, from their declared shapes; no data is read.

    With ``indexes_only``, those of the index coordinates alone (a 1-D variable named as its
    dimension), which xarray reads as it opens a file, lazily or not; ``drop``: names left
    out (xarray's ``drop_variables``).

    Raises
    ------
    ValueError
        If ``path`` is not a netCDF file (one line naming it).
    """
    with _store(path) as store:
        return _declared(store, indexes_only, drop)


@contextlib.contextmanager
def _store(path):
    """xarray's netCDF4 store of ``path``, open for the ``with`` block; an error while
    opening names the file. One handle serves a whole read: a netCDF handle of the file
    opened and closed beside another one open on it left the netCDF library (4.10 with HDF5
    2.2) to crash at the next open."""
    try:
        store = NetCDF4DataStore.open(str(path), mode="r")
    except PermissionError:
        raise
    except (OSError, RuntimeError, ValueError) as exc:  # "Unknown file format", HDF error ...
        raise not_netcdf(path, exc) from None
    try:
        yield store
    finally:
        store.close()


def _declared(store, indexes_only: bool = False, drop=()) -> int:
    """:func:`declared_bytes` of an open store."""
    total = 0
    for name, var in store.get_variables().items():
        if name in drop or (indexes_only and var.dims != (name,)):
            continue
        size = STRING_BYTES if var.dtype.kind in "OSU" else var.dtype.itemsize
        total += size * math.prod(var.shape)
    return total


def lazy_file(path, drop=(), max_memory: float = DEFAULT_MAX_MEMORY) -> Path:
    """``path`` if it may be opened lazily: a :func:`checked_file` whose index coordinates
    (all but ``drop``), which xarray reads on opening it, fit in ``max_memory``."""
    path = checked_file(path)
    problem = memory_problem(
        declared_bytes(path, indexes_only=True, drop=drop), f"the coordinates of {path}",
        "a file written by stability has small ones: use another file", max_memory,
        holder="opening a file")
    if problem is not None:
        raise ValueError(problem)
    return path


@contextlib.contextmanager
def opened(path, **kwargs):
    """``xr.open_dataset(path, **kwargs)`` of a :func:`checked_file`, lazily, closed at the
    end of the ``with`` block; an error while opening names the file."""
    path = checked_file(path)
    with _store(path) as store:
        with _dataset(path, store, kwargs) as ds:
            yield ds


def _dataset(path, store, kwargs) -> xr.Dataset:
    """The Dataset of an open store, as ``xr.open_dataset(path, **kwargs)`` opens it."""
    options = {k: v for k, v in kwargs.items() if k != "engine"}  # the store is the engine
    try:
        return xr.open_dataset(store, **options)
    except (OSError, RuntimeError, ValueError) as exc:
        raise not_netcdf(path, exc) from None


def read_dataset(path, max_memory: float = DEFAULT_MAX_MEMORY, **kwargs) -> xr.Dataset:
    """The netCDF file ``path`` in memory, read as ``xr.open_dataset(path, **kwargs)`` reads
    it, once checked (:func:`checked_file`) and its declared size within ``max_memory``.

    Raises
    ------
    FileNotFoundError, PermissionError
        If nothing is there, or it cannot be read.
    ValueError
        One line naming the file: not a regular file, a link or storage outside it, larger in
        memory than ``max_memory`` (or the machine's memory), not netCDF, or damaged.
    """
    path = checked_file(path)
    with _store(path) as store:
        problem = memory_problem(
            _declared(store), f"the variables of {path}",
            "open it lazily instead, a variable at a time (xarray.open_dataset(path, "
            "engine='netcdf4'); a stored run's folder: stability.output.store.open_store), or "
            "raise max_memory", max_memory, holder="a file read into memory")
        if problem is not None:
            raise ValueError(problem)
        with _dataset(path, store, kwargs) as ds:
            for name, var in ds.variables.items():
                try:
                    var.load()
                except MemoryError:
                    raise
                except (OSError, RuntimeError, ValueError) as exc:  # "NetCDF: HDF error" ...
                    raise ValueError(
                        f"{path} is damaged: its variable {name!r} cannot be read "
                        f"({first_line(exc)}); write it again, or use an intact copy") from None
            return ds.load()


def not_netcdf(path, exc: BaseException) -> ValueError:
    """The line for a file that the netCDF library does not open."""
    return ValueError(f"{path} is not a netCDF file stability can read ({first_line(exc)}); "
                      "give a .nc file written by stability.save")


def first_line(exc: BaseException) -> str:
    """The first line of an exception's message, for the middle of a one-line refusal."""
    text = str(exc).strip().splitlines()
    return (text[0] if text else type(exc).__name__)[:160]


def _kind(mode: int) -> str:
    return ("a FIFO (named pipe)" if stat.S_ISFIFO(mode) else "a character device"
            if stat.S_ISCHR(mode) else "a block device" if stat.S_ISBLK(mode)
            else "a socket" if stat.S_ISSOCK(mode) else "not a regular file")

