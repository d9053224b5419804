"""A run on disk, chunk by chunk: one netCDF file per chunk of members, opened lazily as one.

A :class:`ChunkStore` is a folder::

    manifest.json          what run this is (its fingerprint), how it is chunked, and, once
                           every chunk is done, the attributes of the whole Dataset
    chunk-000000.nc        members 0 ... C - 1, written atomically (temporary name, rename)
    chunk-000000.nc.sha256 its checksum and the store's fingerprint, written (atomically)
                           after it
    progress.json          chunks done, members/s, time left: for ``stability status DIR``
    .lock                  held by the process writing the store (:mod:`stability.output.lock`)

A chunk counts as done only when its file and its checksum are both there and agree, and the
checksum names this store's fingerprint, so a run killed at any point (while compiling,
integrating or writing, or by a full disk) leaves only whole chunks, a chunk whose file was
damaged later is found and recomputed, and a chunk copied from another run (its own valid
checksum, another seed) is never taken for one of this run. Resuming runs
the chunks that are not done; every member is computed independently of the others, so the
result is bitwise that of an uninterrupted run. A store refuses to resume a different run (its
fingerprint: the resolved arguments and the package version) with a message saying what
differs, and a store that another live process holds (its lock) with that process's id.

:meth:`ChunkStore.open` returns the Dataset over all chunks with dask arrays (xarray's
``open_mfdataset``), so a run of 1e8 members is read a chunk at a time.
"""

from __future__ import annotations

import hashlib
import json
import logging
import math
import os
import socket
import stat
import time
from pathlib import Path

import netCDF4
import numpy as np
import pandas as pd
import xarray as xr
from xarray.indexes import PandasIndex

from ..util import conventions as cv
from ..util.checks import folder_path
from .dataset import variable_attrs
from .io import READ, save
from ..ensemble.schema import held_order
from .lock import FolderLock
from .publish import read_plain_file, write_text
from .untrusted import first_line, lazy_file

MANIFEST = "manifest.json"
PROGRESS = "progress.json"

log = logging.getLogger(__name__)

#: Version of the store layout; a store of another layout is not resumed.
LAYOUT = 2

#: The lock file of a store, held by the process writing it.
LOCK = ".lock"


class StoreMismatch(ValueError):
    """The folder holds chunks of another run."""


class ChunkStore:
    """The chunk files of one run in ``directory``.

    The store holds its folder's lock (:class:`~stability.output.lock.FolderLock`) from here until
    :meth:`close` (or the end of the process): a second process is refused, naming the first.

    Parameters
    ----------
    directory : path-like
        Created if missing.
    identity : dict
        What makes the run what it is (JSON-able): resolved arguments and software version.
        Its hash is the store's fingerprint.
    members : int
        Members of the whole run.
    chunk_members : int
        Members per chunk (the last chunk may be shorter).
    resume : bool
        Continue a store of the same run that has chunks done; otherwise such a store is
        refused (``ValueError`` telling to pass ``resume``), so no finished work is lost.
    unit : str, default "members"
        What ``members`` counts (the stability map keeps one ensemble batch per chunk).
    """

    def __init__(self, directory, identity: dict, members: int, chunk_members: int,
                 resume: bool = False, unit: str = "members"):
        self.dir = folder_path("store", directory)
        self.unit = unit
        self.members = int(members)
        self.chunk_members = int(chunk_members)
        self.n_chunks = -(-self.members // self.chunk_members)
        self.identity = _jsonable(identity)
        self.fingerprint = _fingerprint(
            {"identity": self.identity, "members": self.members,
             "chunk_members": self.chunk_members, "layout": LAYOUT})
        manifest = self.dir / MANIFEST
        if self.dir.exists() and not self.dir.is_dir():
            raise ValueError(f"{self.dir} is a file; a run's chunks need a folder there")
        self.dir.mkdir(parents=True, exist_ok=True)
        self._lock = FolderLock(self.dir, LOCK, "chunk folder").acquire()
        try:
            self._open(manifest, resume)
        except BaseException:
            self.close()
            raise

    def _open(self, manifest: Path, resume: bool) -> None:
        if manifest.exists():
            earlier = read_manifest(self.dir)
            if earlier["fingerprint"] != self.fingerprint:
                raise StoreMismatch(
                    f"the settings changed since the run kept in {self.dir} was started: "
                    f"{_difference(earlier, self)}; give the settings it had to finish it "
                    "(--resume), or start afresh (stability run: --overwrite without --resume; "
                    "run_ensemble: another folder, or remove this one)"
                )
            for partial in [*self.dir.glob(".*.tmp"), *self.dir.glob(".*.part")]:
                partial.unlink(missing_ok=True)  # what a killed run was writing
            self.finished = self.done()
            done = len(self.finished)
            if done and not resume and earlier["complete"]:
                raise ValueError(
                    f"{self.dir} already holds this run, complete; open it with "
                    "stability.output.store.open_store, or pass --resume (resume=True) to reuse it"
                )
            if done and not resume:
                raise ValueError(
                    f"{self.dir} holds {done} of {self.n_chunks} finished chunks of this run; "
                    "pass --resume (resume=True) to finish it, or remove the folder to start "
                    "afresh"
                )
        else:
            self._write_manifest(complete=False, attrs=None)
            self.finished = []

    def close(self) -> None:
        """Give the folder's lock back (the chunks stay)."""
        self._lock.release()

    # --- chunks ---------------------------------------------------------------------------

    def bounds(self, k: int) -> tuple[int, int]:
        """Members ``lo, hi`` (``lo`` included, ``hi`` not) of chunk ``k``."""
        lo = k * self.chunk_members
        return lo, min(lo + self.chunk_members, self.members)

    def path(self, k: int) -> Path:
        return self.dir / chunk_name(k)

    def done(self) -> list[int]:
        """Chunks whose file is whole (its checksum agrees); damaged ones are removed."""
        finished = []
        for k in range(self.n_chunks):
            if self.verify(k):
                finished.append(k)
        return finished

    def missing(self) -> list[int]:
        """Chunks that were not done when the store was opened (each file is read once)."""
        done = set(self.finished)
        return [k for k in range(self.n_chunks) if k not in done]

    def verify(self, k: int) -> bool:
        """Whether chunk ``k`` is done; a file that does not match its checksum is removed."""
        return self.verify_path(self.dir, k, self.fingerprint)

    @staticmethod
    def verify_path(directory, k: int, fingerprint: str, remove: bool = True) -> bool:
        """Whether chunk ``k`` of the store in ``directory`` (of ``fingerprint``) is done.

        Done: the chunk file and its checksum file are plain files (not links), the file's
        SHA-256 is the one recorded, and the record names ``fingerprint``. Otherwise, with
        ``remove``, both files are removed (the chunk is run again), with a warning when
        there was a chunk file.
        """
        path = Path(directory) / chunk_name(k)
        check = _checksum_path(path)
        kinds = [_file_kind(path), _file_kind(check)]
        if "other" in kinds:
            raise ValueError(f"{path if kinds[0] == 'other' else check} is not a file, where a "
                             "run keeps a chunk; remove it")
        if kinds != ["file", "file"]:
            if remove and "link" in kinds:
                _discard(path, check, "or its checksum is a symbolic link")
            return False
        try:
            record = read_plain_file(check, 4096).decode("utf-8", "replace").split()
        except OSError:
            record = []
        if len(record) == 2 and record[1] == fingerprint and file_checksum(path) == record[0]:
            return True
        if remove:
            _discard(path, check, "does not match its checksum" if len(record) == 2 and (
                record[1] == fingerprint) else "is not a chunk of this run (its checksum names "
                "another run)")
        return False

    def write(self, k: int, ds: xr.Dataset, compress: bool = True) -> Path:
        """Write chunk ``k`` (atomically), then its checksum."""
        write_chunk(ds, self.path(k), compress, self.fingerprint)
        return self.path(k)

    # --- the whole ------------------------------------------------------------------------

    def complete(self, attrs: dict) -> None:
        """Record that every chunk is done, with the attributes of the whole Dataset."""
        self._write_manifest(complete=True, attrs=attrs)

    def open(self) -> xr.Dataset:
        """The run as one Dataset over its chunk files (dask arrays; nothing read yet)."""
        return open_store(self.dir)

    def report(self, state: str, chunks_done: int, members_done: int, rate: float,
               started: float) -> None:
        """Write ``progress.json`` (for ``stability status``)."""
        left = self.members - members_done
        write_text(self.dir / PROGRESS, json.dumps({
            "state": state,
            "chunks_done": chunks_done,
            "chunks": self.n_chunks,
            "members_done": members_done,
            "members": self.members,
            "members_per_second": rate,
            "seconds_left": left / rate if rate > 0 else None,
            "elapsed_seconds": time.time() - started,
            "updated": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
            "host": socket.gethostname(),
            "pid": os.getpid(),
        }, indent=1) + "\n")

    def _write_manifest(self, complete: bool, attrs) -> None:
        write_text(self.dir / MANIFEST, json.dumps({
            "layout": LAYOUT,
            "fingerprint": self.fingerprint,
            "identity": self.identity,
            "members": self.members,
            "chunk_members": self.chunk_members,
            "chunks": self.n_chunks,
            "unit": self.unit,
            "complete": complete,
            "attrs": _jsonable(attrs) if attrs is not None else None,
        }, indent=1) + "\n")


def chunk_name(k: int) -> str:
    """File name of chunk ``k``."""
    return f"chunk-{k:06d}.nc"


def write_chunk(ds: xr.Dataset, path, compress: bool, fingerprint: str) -> None:
    """Write one chunk file atomically, then its checksum beside it, bound to the store's
    ``fingerprint`` (so that the chunk counts only in the store of that run)."""
    path = Path(path)
    save(ds, path, overwrite=True, compress=compress)
    write_text(_checksum_path(path), f"{file_checksum(path)} {fingerprint}\n")


def find_stores(folder) -> list[Path]:
    """The stores in ``folder``, sorted: itself if it is one, else the stores among its
    folders and anywhere inside its work folders (``.stability-work-*``: a study that makes
    several runs keeps a store per run there). Links are not followed."""
    folder = Path(folder)
    if (folder / MANIFEST).is_file():
        return [folder]
    found = []
    for sub in _real_folders(folder):
        if (sub / MANIFEST).is_file():
            found.append(sub)
        elif sub.name.startswith(".stability-work-"):
            for top, folders, files in os.walk(sub):  # os.walk follows no link
                folders.sort()
                if MANIFEST in files:
                    found.append(Path(top))
    return found


def _real_folders(folder: Path) -> list[Path]:
    try:
        return [p for p in sorted(folder.iterdir()) if not p.is_symlink() and p.is_dir()]
    except OSError:
        return []


def read_manifest(directory) -> dict:
    """The manifest of the store in ``directory``, its fields checked.

    The file is input like any other (a disk, a copy or a hand may have damaged it): every
    field the store reads is checked here, once, so that no reader meets a list, a string or a
    negative count where it expects a number.

    Raises
    ------
    ValueError
        One line naming the file: there is none, or it is not JSON, or a field is missing or of
        the wrong type or range.
    """
    path = Path(directory) / MANIFEST
    try:
        manifest = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ValueError(f"{directory} is not a run's chunk folder (no {MANIFEST})") from None
    except (ValueError, RecursionError) as exc:  # not JSON, not UTF-8, absurd numbers or depth
        raise _damaged(path, f"{exc.__class__.__name__}: {exc}") from None
    layout = manifest.get("layout") if isinstance(manifest, dict) else None
    if isinstance(layout, int) and not isinstance(layout, bool) and layout != LAYOUT:
        raise ValueError(f"{path} is of store layout {layout}, written by another version of "
                         f"stability (this one reads layout {LAYOUT}); remove its folder to "
                         "start afresh")
    problem = _manifest_problem(manifest)
    if problem:
        raise _damaged(path, problem)
    return manifest


def _manifest_problem(manifest) -> str:
    """What is wrong with a parsed manifest, in words; "" if nothing."""
    if not isinstance(manifest, dict):
        return f"it holds {_shown(manifest)}, not an object"
    fields = {"layout": int, "fingerprint": str, "identity": dict, "members": int,
              "chunk_members": int, "chunks": int, "unit": str, "complete": bool,
              "attrs": (dict, type(None))}
    for name, kind in fields.items():
        if name not in manifest:
            return f"no {name!r}"
        value = manifest[name]
        if not isinstance(value, kind) or (kind is int and isinstance(value, bool)):
            return f"{name!r} is {_shown(value)}"
    members, per_chunk = manifest["members"], manifest["chunk_members"]
    if members < 0:
        return f"'members' is {members}, below 0"
    if per_chunk < 1:
        return f"'chunk_members' is {per_chunk}, below 1"
    if manifest["chunks"] != -(-members // per_chunk):
        return (f"'chunks' is {manifest['chunks']}, but {members} members in chunks of "
                f"{per_chunk} make {-(-members // per_chunk)}")
    if not _displayable(manifest["unit"]):
        return f"'unit' is {_shown(manifest['unit'])}, not a short line of text"
    if manifest["complete"] and manifest["attrs"] is None:
        return "complete, but no 'attrs'"
    return ""


def _damaged(path: Path, problem: str) -> ValueError:
    return ValueError(f"{path} is damaged ({problem}); remove its folder to start afresh")


#: The fields of ``progress.json`` and their types (a number: int or float).
_PROGRESS_FIELDS = {"state": str, "chunks_done": int, "chunks": int, "members_done": int,
                    "members": int, "members_per_second": float, "seconds_left": float,
                    "elapsed_seconds": float, "updated": str, "host": str, "pid": int}


def read_progress(directory) -> dict | None:
    """``progress.json`` of a store, or None if it has none or it cannot be read.

    Only for display and for telling whether a run is alive: the fields of the right type
    and range are returned and the others left out (callers use ``.get``), so a damaged file
    never stops a command.
    """
    return _progress(directory)[0]


def _progress(directory) -> tuple[dict | None, bool]:
    """:func:`read_progress`, and whether the file is there but damaged (some field left out)."""
    try:
        progress = json.loads((Path(directory) / PROGRESS).read_text(encoding="utf-8"))
    except FileNotFoundError:
        return None, False
    except (OSError, ValueError, RecursionError):
        return None, True
    if not isinstance(progress, dict):
        return None, True
    kept = {}
    for name, kind in _PROGRESS_FIELDS.items():
        value = progress.get(name)
        if kind is str:
            ok = _displayable(value)
        elif kind is int:
            ok = (isinstance(value, int) and not isinstance(value, bool)
                  and 0 <= value < 2**53 and (name != "pid" or 0 < value < 2**31))
        else:
            ok = (isinstance(value, (int, float)) and not isinstance(value, bool)
                  and math.isfinite(value) and value >= 0)
        if ok or (name == "seconds_left" and name in progress and value is None):
            kept[name] = value
    return kept, len(kept) < len(_PROGRESS_FIELDS)


def _displayable(value) -> bool:
    """A short string without control characters (safe to print on one line)."""
    return isinstance(value, str) and len(value) <= 200 and value.isprintable()


def _shown(value) -> str:
    """A value of a damaged file for a message: short, on one line, with its JSON type."""
    kind = {dict: "an object", list: "a list", str: "a string", bool: "a boolean",
            int: "a number", float: "a number", type(None): "null"}.get(type(value), "a value")
    if isinstance(value, (dict, list)) or value is None:
        return kind
    text = json.dumps(value)
    return f"{text if len(text) <= 40 else text[:37] + '...'} ({kind})"


def open_store(directory) -> xr.Dataset:
    """The Dataset of a complete store, lazily over its chunk files (dask arrays).

    Each chunk file is checked before it is opened, as :func:`stability.load` checks a file
    (:func:`stability.output.untrusted.lazy_file`): a regular file, nothing reaching outside
    it, coordinates of a size that fits in memory.

    Raises
    ------
    ValueError
        If the folder is not a store, not every chunk is done, or a chunk file is refused or
        does not open (one line naming it).
    """
    directory = Path(directory)
    manifest = read_manifest(directory)
    if not manifest.get("complete"):
        raise ValueError(f"{directory} holds an unfinished run; finish it with --resume "
                         "(resume=True) first")
    paths = [lazy_file(directory / chunk_name(k), drop=(cv.MEMBER,))
             for k in range(manifest["chunks"])]
    # No HDF5 chunk cache for these files: dask reads each on-disk chunk once, and a cache per
    # variable per open file would keep the whole run in memory as it is read (64 files of
    # 32768 members: 0.24 GiB more after reading one variable each).
    previous = netCDF4.get_chunk_cache()
    netCDF4.set_chunk_cache(0, 0, previous[2])
    try:
        ds = xr.open_mfdataset(
            paths, combine="nested", concat_dim=cv.MEMBER, data_vars="minimal",
            coords="minimal", compat="override", join="override", combine_attrs="override",
            **READ, chunks={}, parallel=False,
            drop_variables=[cv.MEMBER],
        )
    except (OSError, RuntimeError, ValueError) as exc:  # a damaged coordinate, chunks that differ
        raise _unopened(directory, paths, exc) from None
    finally:
        netCDF4.set_chunk_cache(*previous)
    # Members are numbered by position: a pandas RangeIndex, not 8 bytes a member in memory
    # (0.8 GB for 1e8 members, read from every file and concatenated). xarray's own RangeIndex
    # did that too, but a Dataset holding it could not be printed (xarray 2026.9: its
    # coordinate has no nbytes, which the repr sums).
    numbers = xr.Coordinates.from_xindex(
        PandasIndex(pd.RangeIndex(manifest["members"], name=cv.MEMBER), cv.MEMBER))
    ds = ds.assign_coords(numbers)
    ds[cv.MEMBER].attrs.update(variable_attrs(cv.MEMBER))
    ds.attrs = dict(manifest["attrs"])
    return held_order(ds)


def _unopened(directory: Path, paths, exc: BaseException) -> ValueError:
    """The line for chunk files that did not open as one: the first that does not open alone
    named, or that they do not fit together."""
    for path in paths:
        try:
            xr.open_dataset(path, **READ, drop_variables=[cv.MEMBER]).close()
        except (OSError, RuntimeError, ValueError) as alone:
            return ValueError(f"{path} is damaged ({first_line(alone)}); remove its folder and "
                              "run again")
    return ValueError(f"the chunk files in {directory} do not fit together as one "
                      f"run ({first_line(exc)}); remove the folder and run again")


def file_checksum(path) -> str:
    """SHA-256 of a file's bytes, hex."""
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(2**22), b""):
            digest.update(block)
    return digest.hexdigest()


def status_lines(directory) -> list[str]:
    """A run's state in a few lines, from its manifest and progress file.

    ValueError (naming the file) if the manifest is missing or damaged; a damaged progress
    file is said in place of the chunks done, and its fields that are sound are shown.
    """
    manifest = read_manifest(directory)
    progress, damaged = _progress(directory)
    progress = progress or {}
    store_chunks = manifest["chunks"]
    done = progress.get("chunks_done", 0)
    unit = manifest["unit"]
    lines = [f"{directory}: {manifest['members']} {unit} in {store_chunks} chunks of "
             f"{manifest['chunk_members']}"]
    if manifest["complete"]:
        lines.append("complete: every chunk is done")
    elif damaged:
        lines.append(f"chunks done unknown: {Path(directory) / PROGRESS} is damaged (it is "
                     "written afresh when the run goes on)")
    else:
        state = progress.get("state", "not started")
        lines.append(f"{state}: {done} of {store_chunks} chunks done "
                     f"({progress.get('members_done', 0)} {unit})")
    rate = progress.get("members_per_second")
    if rate:
        left = progress.get("seconds_left")
        lines.append(f"{rate:.3g} {unit}/s" + (
            f", about {_duration(left)} left" if left and not manifest["complete"] else ""))
    if progress.get("updated"):
        lines.append(f"last update {progress['updated']} by pid {progress.get('pid')} on "
                     f"{progress.get('host')}")
    return lines


# --- helpers ----------------------------------------------------------------------------------


def _checksum_path(path: Path) -> Path:
    return path.with_name(path.name + ".sha256")


def _file_kind(path: Path) -> str:
    """"file", "link", "missing" or "other" (a folder, a FIFO ...), never following a link."""
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return "missing"
    return "file" if stat.S_ISREG(mode) else "link" if stat.S_ISLNK(mode) else "other"


def _discard(path: Path, check: Path, why: str) -> None:
    """Remove a chunk file and its checksum that do not count (the links themselves, if so)."""
    log.warning("chunk file %s %s: it is run again", path, why)
    path.unlink(missing_ok=True)
    check.unlink(missing_ok=True)


def _fingerprint(value) -> str:
    return hashlib.sha256(json.dumps(value, sort_keys=True).encode()).hexdigest()


def _jsonable(value):
    """``value`` with NumPy scalars and arrays as plain numbers and lists (JSON-able)."""
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return _jsonable(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, float) and not np.isfinite(value):
        return repr(value)
    return value


def _difference(earlier: dict, store: ChunkStore) -> str:
    """What differs between the run in a store and this one, the changed settings first.

    Settings of one value (a spin, a step, a seed) lead, with both values; lists (such as the
    amplitude levels that follow from the spin) are named after them, so the line says what
    was changed rather than quoting long lists.
    """
    old, new = _flat(earlier["identity"]), _flat(store.identity)
    old.update({"members": earlier["members"], "chunk_members": earlier["chunk_members"]})
    new.update({"members": store.members, "chunk_members": store.chunk_members})
    keys = [k for k in sorted(set(old) | set(new)) if old.get(k, _ABSENT) != new.get(k, _ABSENT)]
    if not keys:
        return "the same settings, another fingerprint (another version of the store)"
    scalar = [k for k in keys
              if not isinstance(old.get(k), (list, dict)) and not isinstance(new.get(k), list)]
    lead = (scalar or keys)[:3]
    text = "; ".join(f"{k} {_brief(old.get(k, _ABSENT))} there, {_brief(new.get(k, _ABSENT))} "
                     "here" for k in lead)
    rest = [k for k in keys if k not in lead]
    if rest:
        named = ", ".join(rest[:3]) + (f" and {len(rest) - 3} more" if len(rest) > 3 else "")
        text += f"; {named} differ{'s' if len(rest) == 1 else ''} too"
    return text


#: A setting one run has and the other has not.
_ABSENT = object()


def _brief(value) -> str:
    """A setting's value for a message: on one line, at most about 40 characters."""
    if value is _ABSENT:
        return "(unset)"
    text = " ".join(repr(value).split())
    return text if len(text) <= 40 else text[:36] + " ...]" if text[0] == "[" else text[:37] + "..."


def _flat(value, prefix="") -> dict:
    if isinstance(value, dict):
        out = {}
        for k, v in value.items():
            out.update(_flat(v, f"{prefix}{k}."))
        return out
    return {prefix[:-1]: value}


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"
