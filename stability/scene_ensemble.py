"""Grouped runs of any scene, streamed to disk, resumable and distributed like the free body's.

A study of a scene (a heavy top, a struck bat, a rolling body ...) lays its members out in groups,
each group with its own parameter row, step and step count, and runs them with the one member
loop (:func:`stability.engine.propagate_groups`). :class:`GroupedRun` holds such a run;
:func:`propagate_stored` runs it, by default in this process exactly as before, and with a
``store`` folder chunk by chunk through the same machinery as the free body's streamed ensembles
(:mod:`stability.output.stream`): each finished chunk of members is kept at once, a stopped run
resumes with ``resume`` and only the missing chunks run, and the chunks run on dask.distributed
with ``scheduler``. The result is the same :class:`~stability.engine.Propagation`, bitwise,
however the run was cut or wherever it ran: members are independent, and a chunk that holds a
part of a group runs that part with the group's own row, step and step count.

A scene of the user's own (:func:`stability.define_scene`) runs the same way. A dask worker
finds it by reference: it imports the module that defines the scene, so that module must be
importable there (a local cluster's workers start with this process's ``sys.path``; put the
module's folder on remote workers' ``PYTHONPATH``), and it loads the compiled loop from the disk
cache when the workers share it (``STABILITY_CACHE_DIR``).
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import xarray as xr

from .util import conventions as cv
from .engine import propagate_groups
from .engine.run import Propagation
from .scenes import Scene
from .output.store import ChunkStore
from .output.stream import stream_chunks
from .version import __version__

#: Chunks a stored run is cut into by default (each one is kept as soon as it is finished) ...
DEFAULT_CHUNKS = 8
#: ... each of at least this many member-steps: a chunk costs a few tens of milliseconds of
#: files and launch, so short runs (many in a study, of a few members) stay whole.
MIN_CHUNK_WORK = 10**7

#: Dimension names of the chunk files.
COMPONENT = "component"
SAMPLE = "sample"


@dataclass(eq=False)
class GroupedRun:
    """Groups of members of one scene and method, as :func:`propagate_groups` takes them.

    The fields are the constructor's parameters and the instance's attributes.

    Parameters
    ----------
    scene : str or Scene
        A registered scene's name, or a scene (one of the user's own is pickled by reference:
        its module is imported where a chunk runs).
    method : str
        A method of the scene.
    x0 : ndarray, shape (N, n)
        Initial states, group after group.
    params : ndarray, shape (G, p)
        Each group's parameter row.
    sizes : ndarray of int, shape (G,)
        Members per group.
    h : ndarray, shape (G,)
        Each group's step.
    n_steps : ndarray of int, shape (G,)
        Each group's step count.
    save_every : int, default 0
        Keep the state every ``save_every`` steps (0: only the final state).
    axes, levels : ndarray, optional
        Tracking, as :func:`propagate_groups` takes it.
    label : str, optional
        The progress bar's label.
    device : {"cpu", "gpu"}, default "cpu"
        Where the member loop runs: ``"gpu"`` on a CUDA GPU
        (:func:`stability.gpu.propagate_groups_gpu`; the results agree with the CPU's to
        round-off, not bitwise, so the device is part of a stored run's identity).
    """

    scene: str | Scene
    method: str
    x0: np.ndarray
    params: np.ndarray
    sizes: np.ndarray
    h: np.ndarray
    n_steps: np.ndarray
    save_every: int = 0
    axes: np.ndarray | None = None
    levels: np.ndarray | None = None
    label: str | None = None
    device: str = "cpu"

    def __post_init__(self):
        if self.device not in ("cpu", "gpu"):
            raise ValueError(f"device must be 'cpu' or 'gpu', got {self.device!r}")
        self.x0 = np.ascontiguousarray(self.x0, dtype=float)
        self.params = np.ascontiguousarray(np.atleast_2d(self.params), dtype=float)
        self.sizes = np.asarray(self.sizes, dtype=np.int64).reshape(-1)
        groups = self.sizes.size
        self.h = np.broadcast_to(np.asarray(self.h, dtype=float), (groups,)).copy()
        self.n_steps = np.broadcast_to(np.asarray(self.n_steps, dtype=np.int64), (groups,)).copy()
        if self.axes is not None:
            self.axes = np.broadcast_to(np.asarray(self.axes, dtype=np.int64), (groups, 3)).copy()
        if self.levels is not None:
            levels = np.atleast_2d(np.asarray(self.levels, dtype=float))
            self.levels = np.broadcast_to(levels, (groups, levels.shape[-1])).copy()

    @property
    def members(self) -> int:
        return int(self.sizes.sum())

    @property
    def n_saved(self) -> int:
        """Samples kept per member in the whole run (NaN past a group's own last one)."""
        return int(self.n_steps.max()) // self.save_every if self.save_every > 0 else 0

    def identity(self) -> dict:
        """What makes the run what it is, for a store's fingerprint: names and array digests."""
        arrays = {name: getattr(self, name) for name in
                  ("x0", "params", "sizes", "h", "n_steps", "axes", "levels")}
        name, source = ((self.scene, "") if isinstance(self.scene, str)
                        else (self.scene.name, self.scene.source))
        return {"scene": name, **({"scene_source": source} if source else {}),  # user's code
                **({"device": self.device} if self.device != "cpu" else {}),
                "method": self.method, "save_every": self.save_every,
                "arrays": {name: None if a is None else _digest(a) for name, a in arrays.items()}}

    def part(self, lo: int, hi: int) -> "GroupedRun":
        """Members ``lo ... hi - 1``: the groups they fall in, each with its own row and step."""
        ends = np.cumsum(self.sizes)
        starts = ends - self.sizes
        sizes = np.clip(np.minimum(ends, hi) - np.maximum(starts, lo), 0, None)
        keep = sizes > 0
        pick = (lambda a: None if a is None else a[keep])
        return replace(self, x0=self.x0[lo:hi], params=self.params[keep], sizes=sizes[keep],
                       h=self.h[keep], n_steps=self.n_steps[keep], axes=pick(self.axes),
                       levels=pick(self.levels))

    def propagate(self, progress=None) -> Propagation:
        """The run in this process (:func:`propagate_groups`, or its GPU twin)."""
        propagator = propagate_groups
        if self.device == "gpu":
            from .gpu import propagate_groups_gpu as propagator  # numba-cuda: optional

        return propagator(self.scene, self.method, self.x0, self.params, self.sizes, self.h,
                          self.n_steps, save_every=self.save_every, axes=self.axes,
                          levels=self.levels, progress=progress, label=self.label)

    def __call__(self, lo: int, hi: int, progress, threads) -> xr.Dataset:
        """The chunk job (:func:`stability.output.stream.stream_chunks`): members ``lo ... hi - 1``
        as a Dataset, their saved states padded to the whole run's samples."""
        part = self.part(lo, hi)
        run = part.propagate(progress)
        data = {
            "x_final": ((cv.MEMBER, COMPONENT), run.x_final),
            "status": ((cv.MEMBER,), run.status),
            "fail_step": ((cv.MEMBER,), run.fail_step),
            "iterations": ((cv.MEMBER,), run.iterations),
            "steps_done": ((cv.MEMBER,), np.repeat(run.steps_done, part.sizes)),
        }
        if self.n_saved:  # no variable of a dimension of length 0 (netCDF's unlimited one)
            saved = np.full((hi - lo, self.n_saved, self.x0.shape[1]), np.nan)
            saved[:, :run.saved.shape[1]] = run.saved
            data["saved"] = ((cv.MEMBER, SAMPLE, COMPONENT), saved)
        for name, value in run.extras.items():
            dims = (cv.MEMBER,) + tuple(f"{name}_{d}" for d in range(1, value.ndim))
            data[f"extra_{name}"] = (dims, value)
        return xr.Dataset(data, coords={cv.MEMBER: np.arange(lo, hi)},
                          attrs={"wall_time": run.wall_time, "compile_time": run.compile_time})


def propagate_stored(run: GroupedRun, store=None, *, resume=False, scheduler=None,
                     chunk_members=None, threads=None, progress=None) -> Propagation:
    """Run ``run``: in this process, or chunk by chunk into the folder ``store``.

    Parameters
    ----------
    run : GroupedRun
    store : path-like, optional
        Folder of the chunk files (a :class:`~stability.output.store.ChunkStore`, created if
        missing). Without it the run is :func:`propagate_groups` in this process.
    resume : bool, default False
        Finish a run of the same members stopped earlier (only the missing chunks run).
    scheduler : str or distributed.Client, optional
        Run the chunks on dask.distributed (needs ``store``;
        :func:`stability.ensemble.run_streamed`).
    chunk_members : int, optional
        Members per chunk; default: the run in :data:`DEFAULT_CHUNKS` chunks, fewer where a
        chunk would hold less than :data:`MIN_CHUNK_WORK` member-steps.
    threads : int, optional
        Numba threads for chunks run in this process.
    progress : bool, optional
        Progress bar.

    Returns
    -------
    Propagation
        As :func:`propagate_groups` returns it; ``wall_time`` and ``compile_time`` are the
        sums over the chunks run.

    Raises
    ------
    stability.output.stream.RunInterrupted
        Ctrl-C or SIGTERM stopped a stored run; its finished chunks are kept.
    """
    if store is None:
        if scheduler is not None:
            raise ValueError("a run on a dask scheduler needs a store folder for its chunks")
        return run.propagate(progress)
    n = run.members
    if chunk_members is None:
        chunk_members = default_chunk_members(n, float(np.sum(run.sizes * run.n_steps)))
    identity = {"grouped_run": run.identity(), "software": f"stability {__version__}"}
    chunks = ChunkStore(store, identity, n, chunk_members, resume=resume)
    try:
        stream_chunks(run, chunks, scheduler=scheduler, threads=threads, progress=progress,
                      compress=False)
        parts = []
        for k in range(chunks.n_chunks):
            with xr.open_dataset(chunks.path(k), engine="netcdf4") as ds:
                parts.append(ds.load())
        chunks.complete({})
    finally:
        chunks.close()
    return _propagation(run, parts)


def default_chunk_members(members: int, member_steps: float) -> int:
    """Members per chunk of a stored run by default: at most :data:`DEFAULT_CHUNKS` chunks,
    fewer where a chunk would hold less than :data:`MIN_CHUNK_WORK` member-steps."""
    chunks = min(DEFAULT_CHUNKS, max(1, int(member_steps // MIN_CHUNK_WORK)))
    return max(1, math.ceil(members / chunks))


def sub_store(stored: dict | None, name: str) -> dict:
    """``stored`` (keyword arguments of :func:`propagate_stored`) for one of several runs of a
    study: its own store, the folder ``name`` inside the study's (nothing if there is none)."""
    stored = dict(stored or {})
    if stored.get("store") is not None:
        stored["store"] = Path(stored["store"]) / name
        if stored["store"].is_symlink():
            raise ValueError(f"{stored['store']} is a symbolic link; a run keeps its chunks "
                             "only in a real folder inside the output folder: remove the link")
    return stored


def _propagation(run: GroupedRun, parts: list) -> Propagation:
    """The :class:`Propagation` of a whole run from the Datasets of its chunks, in order."""
    ds = xr.concat(parts, cv.MEMBER)
    first = np.cumsum(run.sizes) - run.sizes
    steps = np.where(run.sizes > 0, ds.steps_done.values[np.minimum(first, run.members - 1)]
                     if run.members else 0, run.n_steps)
    extras = {name[len("extra_"):]: ds[name].values for name in ds.data_vars
              if name.startswith("extra_")}
    saved = (ds.saved.values if "saved" in ds
             else np.empty((run.members, 0, run.x0.shape[1])))
    return Propagation(
        x_final=ds.x_final.values, saved=saved, status=ds.status.values,
        fail_step=ds.fail_step.values, iterations=ds.iterations.values,
        steps_done=steps.astype(np.int64),
        wall_time=sum(float(p.attrs["wall_time"]) for p in parts),
        compile_time=sum(float(p.attrs["compile_time"]) for p in parts), extras=extras)


def _digest(a: np.ndarray) -> str:
    a = np.ascontiguousarray(a)
    h = hashlib.sha256(f"{a.dtype.str}{a.shape}".encode())
    h.update(a.tobytes())
    return h.hexdigest()
