"""Datasets to netCDF4 files and back: ``save(ds, path)`` and ``load(path)``.

``save`` writes netCDF4 through xarray with zlib compression (level 1, byte shuffle; or zstd,
or none: :data:`COMPRESSIONS`) and chunks along ``member``, to a temporary file in the target's
directory that is renamed over the target only when complete (``os.replace`` is atomic on one
filesystem), so an interrupted write never leaves a broken file; it refuses to replace an
existing file unless asked. ``load`` reads the file back into memory and returns a Dataset
identical (``xarray.testing.assert_identical``) to the one saved; it refuses, in one line, a
file that is not a regular one, that reaches outside itself (HDF5 external links, external
storage) or that declares more than fits in memory
(:mod:`stability.output.untrusted`). Time coordinates are float numbers with CF time units
counted from a nominal date (``"s since 1970-01-01 00:00:00"``,
:data:`stability.util.conventions.TIME_ORIGIN`): ``load`` passes ``decode_times=False`` (and
``decode_timedelta=False``) so that they stay numbers; other readers may do the same, or let
xarray decode them to dates from that origin.
"""

from __future__ import annotations

import contextlib
import os
import uuid
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import netCDF4
import numpy as np
import xarray as xr

from ..util import conventions as cv
from .dataset import check_storable
from .publish import disk_error
from .untrusted import read_dataset
from ..ensemble.memory import DEFAULT_MAX_MEMORY
from ..ensemble.schema import file_order, held_order

#: The compressions :func:`save` offers (``[output] compression``), each as netCDF4 encodes it,
#: read back by xarray and the CF checker; zlib after the shuffle filter (netCDF4 applies
#: shuffle with zlib alone). On the summaries of a million-member ensemble (260 MB, two cores):
#: zlib level 1 writes 66 MB/s into 143 MB (level 4: 59 MB/s, 140 MB; without shuffle 72 MB/s,
#: 160 MB), zstd level 1 511 MB/s into 158 MB (level 3: 247 MB/s, 155 MB), none 338 MB/s into
#: 269 MB; blosc refuses such data ("buffer is uncompressible").
#: zlib is the default: every netCDF-4 reader has it, where zstd needs netCDF-C 4.9 with its
#: plugins (netCDF4-python's wheels and conda's builds have them).
COMPRESSIONS = {
    "zlib": {"zlib": True, "complevel": 1, "shuffle": True},
    "zstd": {"compression": "zstd", "complevel": 1},
    "none": {"zlib": False},
}

#: Target size of one netCDF chunk in bytes (a chunk holds whole members).
CHUNK_BYTES = 4 * 2**20

#: How the package opens the files it wrote: as numbers, the way they were saved.
READ = {"engine": "netcdf4", "decode_times": False, "decode_timedelta": False}


@contextlib.contextmanager
def saving(ds: xr.Dataset, path, overwrite: bool = False, compress=True):
    """:func:`save` in a background thread while the ``with`` block runs (figures, say).

    The netCDF library compresses and writes without holding the interpreter lock, so a study
    draws its figures meanwhile (the tennis-racket study: 1.2 s of writing and 2.4 s of drawing
    took 2.3 s together). The write is complete, or its error raised, when the block ends.

    Parameters
    ----------
    ds : xarray.Dataset
        The Dataset to write, as for :func:`save`; leave it unchanged inside the block.
    path : str or path-like
        Target file, conventionally ``*.nc``. Its directory must exist.
    overwrite : bool, default False
        Replace an existing file.
    compress : bool or str, default True
        As for :func:`save`.

    Raises
    ------
    FileExistsError, ValueError, OSError
        As :func:`save`, when the block ends.
    """
    with ThreadPoolExecutor(max_workers=1) as pool:
        written = pool.submit(save, ds, path, overwrite, compress)
        yield
        written.result()


def save(ds: xr.Dataset, path, overwrite: bool = False, compress=True) -> Path:
    """Write ``ds`` to the netCDF4 file ``path``, atomically.

    The netCDF library is driven from a worker thread, so Ctrl-C in the main thread never
    stops it half-way inside HDF5 (which then waits for good on its own lock): the write ends,
    the partial file is removed and the interrupt goes on.

    Parameters
    ----------
    ds : xarray.Dataset
        Attributes must be str, numbers or 1-D numeric arrays (no bool, no None).
    path : str or path-like
        Target file, conventionally ``*.nc``. Its directory must exist.
    overwrite : bool, default False
        Replace an existing file.
    compress : bool or str, default True
        How the variables are compressed: a name of :data:`COMPRESSIONS` (``"zlib"``,
        ``"zstd"``, ``"none"``); True is ``"zlib"``, False ``"none"`` (scratch files read back
        soon).

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    FileExistsError
        If ``path`` exists and ``overwrite`` is False.
    ValueError
        If ``path`` is a folder, or an attribute or variable cannot be stored in netCDF
        (nothing is written).
    OSError
        If the file system refuses the write (no space, permission, a vanished folder): the
        path and the cause, and nothing left behind.
    """
    path = Path(path)
    if not isinstance(ds, xr.Dataset):
        raise ValueError(f"save() writes an xarray.Dataset, got {type(ds).__name__}")
    if path.is_dir():  # before the advice to overwrite, which cannot replace a folder
        raise ValueError(
            f"{path} is a folder, and a Dataset is saved to a file: give a file name such as "
            f"{path / 'run.nc'} (a folder is never replaced, not even with overwrite=True)"
        )
    if path.exists() and not overwrite:
        raise FileExistsError(
            f"{path} already exists; pass overwrite=True (stability run: --overwrite) to "
            "replace it, or choose another path"
        )
    if not path.parent.is_dir():
        raise ValueError(f"directory {path.parent} does not exist; create it first")
    codec = _compression(compress)
    check_storable(ds)
    ds = file_order(ds)
    encoding = _encoding(ds, codec)
    temporary = path.with_name(f".{path.name}.{os.getpid()}.{uuid.uuid4().hex[:8]}.tmp")
    try:
        _write_in_thread(ds, temporary, encoding)
        os.replace(temporary, path)
    except (OSError, RuntimeError) as exc:  # netCDF reports a full disk as "HDF error"
        temporary.unlink(missing_ok=True)
        raise disk_error(exc, path) from exc
    except BaseException:  # including KeyboardInterrupt: never leave the partial file
        temporary.unlink(missing_ok=True)
        raise
    return path


def _write_in_thread(ds: xr.Dataset, path: Path, encoding: dict) -> None:
    """:func:`_write` in a worker thread; on Ctrl-C, let it end, then raise the interrupt.

    The shutdown waits for the write whenever the interrupt comes, even while ``submit`` is
    still starting the thread, so the caller's clean-up never runs before the file is closed.
    """
    pool = ThreadPoolExecutor(max_workers=1)
    try:
        pool.submit(_write, ds, path, encoding).result()
    finally:
        pool.shutdown(wait=True)


def load(path, max_memory: float = DEFAULT_MAX_MEMORY) -> xr.Dataset:
    """Read a file written by :func:`save` into memory.

    The file is checked first, as any file handed in may be hostile
    (:mod:`stability.output.untrusted`): a regular file only, nothing that reaches outside
    it (HDF5 external links, external storage), and its declared size within ``max_memory``
    before anything is read.

    Parameters
    ----------
    path : str or path-like
    max_memory : float, default 4 GiB
        Refuse a file whose variables would take more than this many bytes in memory (or more
        than the machine has); open such a file lazily with ``xarray.open_dataset``.

    Returns
    -------
    xarray.Dataset
        Identical to the Dataset saved; time coordinates stay numbers (``decode_times`` and
        ``decode_timedelta`` off). The file is closed on return.

    Raises
    ------
    FileNotFoundError
        If ``path`` does not exist.
    ValueError
        One line naming the file: a folder, a FIFO or a device; not a netCDF file; links or
        storage outside it; too large for memory; or damaged (a variable cannot be read).
    """
    return held_order(read_dataset(path, max_memory, **READ))


#: Bytes of HDF5's chunk cache per variable while a file is written: a variable is written
#: whole, in chunks of :data:`CHUNK_BYTES`, so a cache only holds written chunks until the
#: file closes (netCDF's default of 64 MiB a variable held a second copy of every variable
#: up to that size: 0.27 GB more for the 0.27 GB of a million-member ensemble, 0.05 GB with
#: this).
WRITE_CHUNK_CACHE = 2**20


def _write(ds: xr.Dataset, path: Path, encoding: dict) -> None:
    """The write itself (one function, so tests can make it fail), with the chunk cache of
    :data:`WRITE_CHUNK_CACHE` for the file it creates."""
    size, elements, preemption = netCDF4.get_chunk_cache()
    netCDF4.set_chunk_cache(WRITE_CHUNK_CACHE, elements, preemption)
    try:
        ds.to_netcdf(path, mode="w", format="NETCDF4", engine="netcdf4", encoding=encoding)
    finally:
        netCDF4.set_chunk_cache(size, elements, preemption)


def _compression(compress) -> str:
    """The name in :data:`COMPRESSIONS` of ``compress`` (a name, or True for zlib and False for
    none); ValueError naming the choices for anything else."""
    if compress is True or compress is False:
        return "zlib" if compress else "none"
    if compress not in COMPRESSIONS:
        raise ValueError(f"compression must be one of {', '.join(COMPRESSIONS)}, "
                         f"got {compress!r}")
    return compress


def _encoding(ds: xr.Dataset, codec: str = "zlib") -> dict:
    """Compression ``codec`` (:data:`COMPRESSIONS`) and member-aligned chunks for every numeric
    variable.

    Chunks hold whole members (all times and axes) and about :data:`CHUNK_BYTES`; coordinates
    get no fill value (they are never missing), so reading adds no attributes.
    """
    encoding = {}
    for name, var in ds.variables.items():
        dtype = np.dtype(var.dtype)  # a range index reports its dtype as a name
        if dtype.kind not in "iuf" or var.ndim == 0:
            continue
        enc = {**COMPRESSIONS[codec], "dtype": dtype}
        if name in ds.coords:
            enc["_FillValue"] = None
        shape = var.shape
        if cv.MEMBER in var.dims:
            i = var.dims.index(cv.MEMBER)
            per_member = dtype.itemsize * int(np.prod(shape)) // max(shape[i], 1)
            chunk = list(shape)
            chunk[i] = max(1, min(shape[i], CHUNK_BYTES // max(per_member, 1)))
            enc["chunksizes"] = tuple(max(1, c) for c in chunk)
        encoding[name] = enc
    return encoding
