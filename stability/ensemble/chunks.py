"""The one way every run goes: :func:`run_plan`, a :class:`~stability.ensemble.plan.Plan`
run in this process or chunk by chunk into a store, resumed, on dask.distributed, measured where
each chunk ran.

Every family's study, :func:`stability.run_scene` and :func:`stability.run_ensemble` hand a
plan (its scene and method, the members' starts, each group's parameter row, step and step
count, what the loop keeps) and their run options
(:class:`~stability.ensemble.options.RunOptions`) to :func:`run_plan`. By default the plan runs
in this process, with the member loop (:func:`stability.engine.propagate_groups`); with a
``store`` folder, chunk by chunk through the streaming machinery
(:mod:`stability.output.stream`): each finished chunk of members is kept at once, a stopped run
resumes with ``resume`` and only the missing chunks run, and the chunks run on dask.distributed
with ``scheduler``. The result is the same, bitwise, however the run was cut or wherever it
ran: members are independent, and a chunk that holds a part of a group runs that part with the
group's own row, step and step count.

A scene of the user's own (:func:`stability.define_scene`) runs the same way. A dask worker
finds it by reference: it imports the module that defines the scene, so that module must be
importable there (a local cluster's workers start with this process's ``sys.path``; put the
module's folder on remote workers' ``PYTHONPATH``), and it loads the compiled loop from the disk
cache when the workers share it (``STABILITY_CACHE_DIR``).

A stored run is cut into chunks, and each chunk is one job (:class:`ChunkJob`): its members
propagated, then *measured*. Without a measurement the chunk is the raw
:class:`~stability.engine.Propagation` and :func:`run_plan` gives the whole run's back (for a
family whose per-member results are small: final states and tracked events); with one
(``measure=``, a picklable ``measure(part, propagation, lo, hi, threads) -> xarray.Dataset``)
each chunk is kept as the measurement's Dataset of its members and the result is the
measurement's join of the chunks (``joiner``), or the Dataset over the chunk files: the
free body's :func:`stability.run_ensemble` with a store is that path, with its own start rule
and measurement, and so is :func:`stability.run_scene`, every scene's Dataset. The starts are
the plan's ``x0``, or a rule that makes any members' starts alone (``starts=``: the free body
draws each chunk's from its seed, so that memory is one chunk's).

Without a store, a raw run stays in this process, cut into chunks of members only when asked
(``chunk_members``, what bounds its memory), and Ctrl-C may keep what was done (``partial``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ..engine.driver import Propagation
from ..util.interrupts import deferred_interrupt
from ..util.ledger import book
from ..output.io import READ
from ..output.store import ChunkStore, read_manifest
from ..output.stream import sendable, stream_chunks
from ..output.untrusted import opened, read_dataset
from .options import run_options
from .plan import Plan
from ..util import conventions as cv
from ..util.checks import checked_progress, positive_int
from ..util.threads import checked_threads, numba_threads
from ..version import __version__

#: Chunks a stored run is cut into by default (each one is kept as soon as it is finished) ...
DEFAULT_CHUNKS = 8
#: ... each of at least this many member-steps: a chunk costs a few tens of milliseconds of
#: files and launch, so short runs (many in a study, of a few members) stay whole.
MIN_CHUNK_WORK = 10**7

#: Dimension names of the chunk files.
COMPONENT = "component"
SAMPLE = "sample"


@dataclass(eq=False)
class ChunkJob:
    """The chunk job of a stored run (:func:`stability.output.stream.stream_chunks`): members
    ``lo ... hi - 1`` of ``run`` propagated (:meth:`Plan.part`), then measured.

    Parameters
    ----------
    run : Plan
        The whole run.
    measure : callable, optional
        ``measure(part, propagation, lo, hi, threads) -> xarray.Dataset``: the chunk's Dataset
        from its part of the run (a :class:`Plan`) and that part's
        :class:`~stability.engine.Propagation`, members numbered from ``lo``; ``threads`` is
        what the chunk was asked to run with. Default: :class:`RawChunk`, the propagation as
        it is. A measurement with ``integrates = True`` runs its own loop on the part's starts
        (:mod:`stability.ensemble.adaptive_run`) and is given None for the propagation.
    """

    run: Plan
    measure: object = None

    def __post_init__(self):
        if self.measure is None:
            self.measure = RawChunk(self.run.n_saved)

    def __call__(self, lo: int, hi: int, progress, threads) -> xr.Dataset:
        part = self.run.part(lo, hi)
        if getattr(self.measure, "integrates", False):  # its own loop (adaptive steps)
            return self.measure(part, None, lo, hi, threads)
        return self.measure(part, part.propagate(progress), lo, hi, threads)


@dataclass(frozen=True)
class RawChunk:
    """The measurement that keeps a chunk raw: its members' :class:`Propagation` as a Dataset,
    which :func:`run_plan` reads back into the whole run's.

    Parameters
    ----------
    n_saved : int
        Samples per member of the whole run (:attr:`Plan.n_saved`): a chunk's saved
        states are padded with NaN to them, whichever groups it holds.
    """

    n_saved: int

    def __call__(self, part: Plan, run: Propagation, lo: int, hi: int,
                 threads=None) -> xr.Dataset:
        data = {
            "x_final": ((cv.MEMBER, COMPONENT), run.x_final),
            "status": ((cv.MEMBER,), run.status),
            "fail_step": ((cv.MEMBER,), run.fail_step),
            "iterations": ((cv.MEMBER,), run.iterations),
            "steps_done": ((cv.MEMBER,), np.repeat(run.steps_done, part.sizes)),
        }
        if self.n_saved:  # no variable of a dimension of length 0 (netCDF's unlimited one)
            saved = np.full((hi - lo, self.n_saved, part.width), np.nan)
            saved[:, :run.saved.shape[1]] = run.saved
            data["saved"] = ((cv.MEMBER, SAMPLE, COMPONENT), saved)
        for name, value in run.extras.items():
            dims = (cv.MEMBER,) + tuple(f"{name}_{d}" for d in range(1, value.ndim))
            data[f"extra_{name}"] = (dims, value)
        return xr.Dataset(data, coords={cv.MEMBER: np.arange(lo, hi)},
                          attrs={"wall_time": run.wall_time, "compile_time": run.compile_time})


def run_plan(plan: Plan, options=None, *, measure=None, compress=None, partial=False):
    """Run ``plan``: in this process, or chunk by chunk into the folder ``options.store``.

    Parameters
    ----------
    plan : Plan
    options : RunOptions, optional
        How and where it runs (:class:`~stability.ensemble.options.RunOptions`): ``store``, the
        folder of the chunk files (a :class:`~stability.output.store.ChunkStore`, created if
        missing; without it the run is :func:`propagate_groups` in this process); ``resume``,
        finish a run of the same members stopped earlier (only the missing chunks run);
        ``scheduler``, run the chunks on dask.distributed (needs ``store``);
        ``chunk_members``, members per chunk (default: the run in :data:`DEFAULT_CHUNKS`
        chunks, fewer where a chunk would hold less than :data:`MIN_CHUNK_WORK` member-steps;
        without a store and a measurement the run is cut into chunks only when this is given,
        each run in turn: what bounds the memory of a run kept in memory); ``threads``, Numba
        threads for chunks run in this process; ``progress``, the progress bar. Its
        ``chunk_steps`` and ``device`` are the plan's own.
    measure : callable, optional
        The measurement each chunk is kept as (:class:`ChunkJob`); the result is then the
        measured Dataset. It may also have ``joiner(members)``, a
        :class:`~stability.ensemble.combine.ChunkJoin` that joins the chunks into the whole run
        in memory as they come (:func:`measured_whole`);
        ``identity(run) -> dict``, what makes the run what it is for the store's fingerprint
        (default: the run's :meth:`Plan.identity` and the measurement's class); and
        ``whole_attrs(chunks, todo, elapsed, chunk_attrs=None) -> dict``, the attributes of
        the whole Dataset from the store, the chunks this call ran and the seconds they took
        (``chunk_attrs``: the chunks' attributes where they were joined; default
        :func:`summed_attrs`).
    compress : bool, optional
        zlib-compress the chunk files; default: only a measured run's (a raw run's are read
        back at once).
    partial : bool, default False
        Without a store or a measurement: if Ctrl-C stops the run, return what was done
        (``interrupted`` True) instead of raising: the chunks finished before it (the result
        then has fewer members than the run), or, if it stopped the first chunk, the steps
        that chunk did.

    Returns
    -------
    Propagation or xarray.Dataset
        Without ``measure``, the :class:`Propagation` :func:`propagate_groups` returns;
        ``wall_time`` and ``compile_time`` are the sums over the chunks run. With it, the
        measurement's Dataset of the whole run: with a store, over the chunk files, its time
        series dask arrays and the rest loaded (:func:`small_loaded`); in memory without.

    Raises
    ------
    stability.output.stream.RunInterrupted
        Ctrl-C or SIGTERM stopped a stored run; its finished chunks are kept.
    """
    result = _run_plan(plan, run_options(options), measure, compress, partial)
    _book(result)
    return result


def _book(result) -> None:
    """Book a run's member loop, compilation and per-chunk measurement (a Propagation's
    times, or a measured Dataset's from its chunks) in the open time ledger."""
    if isinstance(result, Propagation):
        book("integration", result.wall_time)
        book("compile", result.compile_time)
        return
    attrs = result.attrs
    book("integration", float(attrs.get("chunk_time", attrs.get("wall_time", 0.0))))
    book("compile", float(attrs.get("compile_time", 0.0)))
    book("measuring", float(attrs.get("measure_time", 0.0)))


def _run_plan(plan: Plan, options, measure, compress, partial):
    """:func:`run_plan` with its options checked."""
    run = plan
    n = run.members
    store, resume, scheduler = options.store, options.resume, options.scheduler
    chunk_members, threads = options.chunk_members, options.threads
    progress = checked_progress(options.progress)
    if chunk_members is not None:
        chunk_members = positive_int("chunk_members", chunk_members)
    if store is None:
        if scheduler is not None:
            raise ValueError("a run on a dask scheduler needs a store folder for its chunks")
        if measure is None:
            return _in_chunks(run, chunk_members, progress, partial)
        with numba_threads(checked_threads(threads)):
            return ChunkJob(run, measure)(0, n, progress, threads)
    if chunk_members is None:
        chunk_members = default_chunk_members(n, float(np.sum(run.sizes * run.n_steps)))
    if measure is not None and hasattr(measure, "identity"):
        identity = measure.identity(run)
    else:
        identity = {"grouped_run": run.identity(),
                    **({"measurement": type(measure).__qualname__} if measure is not None
                       else {}),
                    "software": f"stability {__version__}"}
    job = ChunkJob(run, measure)
    # pickled before the store is made (a scene in __main__ is refused first), and only once
    payload = sendable(job) if scheduler is not None else None
    chunks = ChunkStore(store, identity, n, chunk_members, resume=resume)
    try:
        join = measure.joiner(n) if hasattr(measure, "joiner") else None
        streamed = stream_chunks(job, chunks, scheduler=scheduler, threads=threads,
                                 progress=progress, payload=payload,
                                 compress=measure is not None if compress is None else compress,
                                 kept=None if join is None else join.add)
        if measure is not None:
            finished_before = not streamed.todo and read_manifest(chunks.dir)["complete"]
            return measured_whole(measure, chunks, None if finished_before else streamed, join)
        parts = []
        for k in range(chunks.n_chunks):
            # the run's own memory check came first: a chunk is held to the machine's
            parts.append(read_dataset(chunks.path(k), math.inf, engine="netcdf4"))
        chunks.complete({})
    finally:
        chunks.close()
    return _propagation(run, parts)


def measured_whole(measure, chunks: ChunkStore, streamed=None, join=None) -> xr.Dataset:
    """The Dataset of a measured store whose chunks are all done, its whole attributes
    recorded (the measurement's ``whole_attrs``, else :func:`summed_attrs`) unless a call
    before finished it (``streamed`` None: its attributes then).

    With ``join`` (the measurement's ``joiner(members)``, a
    :class:`~stability.ensemble.combine.ChunkJoin` given the chunks this call ran as they
    came), the chunks joined in memory, the others read from their files once; else the
    Dataset over the chunk files (:func:`small_loaded`)."""
    ds = chunk_attrs = None
    if join is not None:
        for k in range(chunks.n_chunks):
            lo = chunks.bounds(k)[0]
            if not join.holds(lo):
                join.add_file(lo, chunks.path(k))
        ds, chunk_attrs = join.result()
    if streamed is not None:
        whole = getattr(measure, "whole_attrs", None)
        chunks.complete(
            whole(chunks, streamed.todo, streamed.elapsed, chunk_attrs=chunk_attrs)
            if whole is not None else summed_attrs(chunks, streamed.elapsed, chunk_attrs))
    if ds is None:
        return small_loaded(chunks.open())
    ds.attrs = dict(read_manifest(chunks.dir)["attrs"])
    return ds


def _in_chunks(run: Plan, chunk_members, progress, partial) -> Propagation:
    """``run`` in this process, ``chunk_members`` members at a time (all at once by default);
    see :func:`run_plan`'s ``partial`` for Ctrl-C."""
    n = run.members
    if chunk_members is None or chunk_members >= n:
        return run.propagate(progress, partial)
    done = []
    with deferred_interrupt() as between:  # Ctrl-C between two chunks
        for lo in range(0, n, chunk_members):
            if between.requested and done:
                break
            prop = run.part(lo, min(lo + chunk_members, n)).propagate(progress, partial)
            if prop.interrupted and done:  # keep the chunks that finished
                break
            done.append(prop)
            if prop.interrupted:  # the first chunk: the steps it did
                break
    if between.requested and not partial:
        raise KeyboardInterrupt
    members = sum(p.x_final.shape[0] for p in done)
    ends = np.cumsum(run.sizes)
    first = ends - run.sizes
    steps = np.where(first < members, run.n_steps, 0)
    if done[0].interrupted:  # the groups of the first chunk, each the steps it did
        covered = np.minimum(ends, members) - first > 0
        steps = np.zeros_like(run.n_steps)
        steps[covered] = done[0].steps_done
    steps = np.where(run.sizes > 0, steps, run.n_steps)
    saved = np.full((members, max(p.saved.shape[1] for p in done), run.width), np.nan)
    lo = 0
    for p in done:
        saved[lo:lo + p.saved.shape[0], :p.saved.shape[1]] = p.saved
        lo += p.saved.shape[0]
    return Propagation(
        x_final=np.concatenate([p.x_final for p in done]), saved=saved,
        status=np.concatenate([p.status for p in done]),
        fail_step=np.concatenate([p.fail_step for p in done]),
        iterations=np.concatenate([p.iterations for p in done]),
        steps_done=steps.astype(np.int64), interrupted=members < n or done[0].interrupted,
        wall_time=sum(p.wall_time for p in done),
        compile_time=sum(p.compile_time for p in done),
        extras={name: np.concatenate([p.extras[name] for p in done]) for name in done[0].extras})


#: A stored run's variables without a time axis (per-member summaries, per-group numbers)
#: come back loaded when together they hold at most this many bytes.
LOADED_BYTES = 2**30


def small_loaded(ds: xr.Dataset) -> xr.Dataset:
    """``ds`` over its chunk files with its variables that have no ``time`` axis loaded into
    memory (NumPy: ``.median()`` and the like work on them), when they hold at most
    :data:`LOADED_BYTES`; the time series stay dask arrays, read as they are used."""
    small = [v for v in ds.variables.values() if cv.TIME not in v.dims]
    if sum(v.nbytes for v in small) <= LOADED_BYTES:
        for variable in small:
            variable.load()
    return ds


def summed_attrs(chunks: ChunkStore, elapsed: float, chunk_attrs=None) -> dict:
    """The attributes of a whole stored run from its chunks': the first chunk's, with
    ``wall_time`` the ``elapsed`` seconds of the call that finished it, ``chunk_time`` the
    chunks' own ``wall_time`` summed over every chunk (more than the elapsed time where chunks
    ran side by side), ``compile_time`` summed too, and ``measure_time`` (the seconds each
    chunk's measurement took where it ran) where the chunks record it. ``chunk_attrs``: the
    chunks' attributes in order, when they were read already (else they are read here)."""
    wall = compile_time = measure_time = 0.0
    first = None
    for k in range(chunks.n_chunks):
        if chunk_attrs is not None:
            attrs = chunk_attrs[k]
        else:
            with opened(chunks.path(k), **READ) as ds:
                attrs = dict(ds.attrs)
        wall += float(attrs.get("wall_time", 0.0))
        compile_time += float(attrs.get("compile_time", 0.0))
        measure_time += float(attrs.get("measure_time", 0.0))
        if first is None:
            first = attrs
    return {**first, "wall_time": float(elapsed), "chunk_time": wall,
            "compile_time": compile_time,
            **({"measure_time": measure_time} if "measure_time" in first else {})}


def default_chunk_members(members: int, member_steps: float) -> int:
    """Members per chunk of a stored run by default: at most :data:`DEFAULT_CHUNKS` chunks,
    fewer where a chunk would hold less than :data:`MIN_CHUNK_WORK` member-steps."""
    chunks = min(DEFAULT_CHUNKS, max(1, int(member_steps // MIN_CHUNK_WORK)))
    return max(1, math.ceil(members / chunks))


def _propagation(run: Plan, parts: list) -> Propagation:
    """The :class:`Propagation` of a whole run from the Datasets of its chunks, in order."""
    ds = xr.concat(parts, cv.MEMBER)
    first = np.cumsum(run.sizes) - run.sizes
    steps = np.where(run.sizes > 0, ds.steps_done.values[np.minimum(first, run.members - 1)]
                     if run.members else 0, run.n_steps)
    extras = {name[len("extra_"):]: ds[name].values for name in ds.data_vars
              if name.startswith("extra_")}
    saved = (ds.saved.values if "saved" in ds
             else np.empty((run.members, 0, run.width)))
    return Propagation(
        x_final=ds.x_final.values, saved=saved, status=ds.status.values,
        fail_step=ds.fail_step.values, iterations=ds.iterations.values,
        steps_done=steps.astype(np.int64),
        wall_time=sum(float(p.attrs["wall_time"]) for p in parts),
        compile_time=sum(float(p.attrs["compile_time"]) for p in parts), extras=extras)
