"""A free-body ensemble streamed to a store chunk by chunk
(:mod:`stability.ensemble.chunks`): resumable, and on dask.distributed."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .attitude import FREE_BODY_SCENES
from ..core.quaternions import IDENTITY
from .propagate import CanonicalGroups, group_levels
from ..output.dataset import history_line
from ..output.store import ChunkStore, read_progress
from ..ensemble.chunks import run_plan, summed_attrs
from ..ensemble.plan import Plan
from ..util import conventions as cv
from ..version import __version__
from .ensemble_plan import EnsemblePlan, chunk_plan, plan_ensemble
from .results import RunPart, finish_run, members_dataset

__all__ = ["run_streamed", "EnsembleChunks"]

def run_streamed(kwargs: dict, options, *, compress=True, measurement=None):
    """Run the ensemble ``run_ensemble(**kwargs)`` chunk by chunk into ``options.store``.

    Returns the Dataset over the chunk files, its time series dask arrays. See :func:`stability.run_ensemble`
    for ``kwargs``; ``chunk_members`` there is the members per chunk file here
    (default :data:`stability.free_body.ensemble_plan.STREAM_CHUNK_MEMBERS`).

    Parameters
    ----------
    kwargs : dict
        Keyword arguments of :func:`stability.free_body.ensemble_plan.plan_ensemble` for the
        whole run.
    options : RunOptions
        Where the chunks go and run (:class:`~stability.ensemble.options.RunOptions`): its
        ``store``, the folder of the chunk files (created if missing); ``resume``, finish a run
        of the same arguments stopped earlier (only the chunks not on disk are run; without
        it, a store that already has chunks done is refused); ``scheduler``, dask.distributed
        (by default the chunks run in this process); ``threads``, Numba threads when the
        chunks run in this process (dask workers use their own); ``progress``, the bar.
    compress : bool, default True
        zlib-compress the chunk files (:func:`stability.output.io.save`).
    measurement : callable, optional
        ``measurement(kwargs, plan) -> EnsembleChunks``: a study's own measurement of each
        chunk (a subclass of :class:`EnsembleChunks`; the tennis-racket study's keeps summaries
        and a sample, and combines its chunks in memory). Default :class:`EnsembleChunks`.

    Returns
    -------
    xarray.Dataset
        The whole run over the chunk files: the time series dask arrays, the summaries
        loaded (:func:`~stability.ensemble.chunks.small_loaded`); or the measurement's
        ``combine`` of them, in memory.

    Raises
    ------
    stability.output.stream.RunInterrupted
        If Ctrl-C or SIGTERM stopped the run; the finished chunks are kept.
    ValueError
        For invalid arguments, or a store with chunks done and no ``resume``.
    OSError
        If the dask scheduler cannot be reached, or a chunk written by a worker is not
        readable here.
    """
    kwargs = dict(kwargs)
    plan = plan_ensemble(**kwargs, defer_starts=True)
    kwargs["chunk_members"] = plan.chunk_members
    ensemble = (measurement or EnsembleChunks)(kwargs, plan)
    return run_plan(ensemble.loop_plan(), replace(options, chunk_members=plan.chunk_members),
                    measure=ensemble, compress=compress)


class EnsembleChunks:
    """A free-body ensemble as a stored grouped run (:mod:`stability.ensemble.chunks`): its
    start rule and its measurement.

    :meth:`loop_plan` is the run, one group, whose starts come from :meth:`starts`: members
    ``lo ... hi - 1`` of :func:`stability.run_ensemble` drawn for those members alone, in each
    body's canonical frame. Called as a measurement, the object turns a chunk's propagation
    into the Dataset ``run_ensemble`` gives those members, numbered from ``lo``
    (:func:`stability.free_body.results.finish_run` and
    :func:`stability.free_body.results.members_dataset`). :meth:`identity` and
    :meth:`whole_attrs` are the store's fingerprint and the whole Dataset's attributes.

    Parameters
    ----------
    kwargs : dict
        Keyword arguments of :func:`stability.run_ensemble` for the whole run (with
        ``chunk_members`` resolved).
    plan : optional
        The run's plan, when the caller has it (it is made again where the job is unpickled).
    """

    def __init__(self, kwargs: dict, plan=None):
        self.kwargs = kwargs
        self._plan = plan
        self._drawn = {}

    def __getstate__(self):
        return {"kwargs": self.kwargs, "_plan": None, "_drawn": {}}

    @property
    def plan(self) -> EnsemblePlan:
        if self._plan is None:
            self._plan = plan_ensemble(**self.kwargs, defer_starts=True)
        return self._plan

    def loop_plan(self) -> Plan:
        """The ensemble as the member loop's :class:`~stability.ensemble.plan.Plan`: the arguments
        :func:`stability.free_body.propagate.propagate_many` gives the member loop for it."""
        plan = self.plan
        groups = self._groups(plan.members)
        return Plan(
            FREE_BODY_SCENES["free_body_attitude" if plan.attitude else "free_body"],
            plan.spec.name, None,
            groups.params, [plan.members], plan.h, plan.n_steps,
            save_every=0 if plan.summaries_only else plan.save_every,
            axes=groups.tracking_axes([plan.a]), levels=group_levels([plan.levels], 1),
            device=plan.device, chunk_steps=plan.chunk_steps, starts=self.starts)

    def starts(self, lo: int, hi: int) -> np.ndarray:
        """The start rule: the initial states (canonical m, and q) of members lo to hi - 1."""
        sub = chunk_plan(self.plan, lo, hi)
        self._drawn[lo, hi] = sub  # for the measurement of the same chunk: drawn once
        groups = self._groups(hi - lo)
        x0 = groups.to_canonical(sub.w0 * sub.body.moments)
        if sub.attitude:
            x0 = np.concatenate([x0, groups.attitudes(np.tile(IDENTITY, (hi - lo, 1)),
                                                      to_canonical=True)], axis=1)
        return x0

    def __call__(self, part, run, lo: int, hi: int, threads):
        """The measurement: the Dataset of members lo to hi - 1 from their propagation."""
        sub, measured = self.member_run(run, lo, hi)
        return numbered(members_dataset(sub, measured, threads), lo)

    def member_run(self, run, lo: int, hi: int, series: bool = True):
        """The plan of members lo to hi - 1 and their :class:`~stability.free_body.results.MemberRun`
        (status, summaries and time series in the body frame) from their propagation.

        ``series=False`` (w alone, not the attitude): the MemberRun without ``w``, its ``time``
        set; the series stay in ``run.saved`` as the loop left them, canonical angular momenta
        in the frame :meth:`frame` (for a measurement that reads them so, and builds the w of
        the members it keeps)."""
        sub = self._drawn.pop((lo, hi), None) or chunk_plan(self.plan, lo, hi)
        n = hi - lo
        groups = self._groups(n)
        run.x_final = groups.from_canonical_state(run.x_final)
        frame = None
        if sub.attitude:
            run.saved = groups.from_canonical_state(run.saved)
        else:  # w alone: converted out of the canonical frame as it is copied (one pass)
            frame = groups.frames[0]
        steps = int(run.steps_done[0])
        part = RunPart(run, slice(0, n), slice(0, n), steps, frame=frame)
        if series or sub.attitude:
            return sub, finish_run(sub, [part], n, sub.n_steps, False)
        members = finish_run(replace(sub, summaries_only=True), [part], n, sub.n_steps, False)
        members.time = np.arange(steps // sub.save_every + 1) * sub.save_every * sub.h
        return sub, members

    def frame(self):
        """The canonical frame ``(perm, signs)`` the member loop ran the body in."""
        return self._groups(1).frames[0]

    def identity(self, run) -> dict:
        """What decides the members' numbers, for the store's fingerprint (not the caller's
        configuration, which may differ in keys that do not, such as the figures of a study)."""
        return {"run_ensemble": {k: v for k, v in self.plan.resolved.items() if k != "threads"},
                "software": f"stability {__version__}"}

    def whole_attrs(self, chunks: ChunkStore, todo, elapsed, chunk_attrs=None) -> dict:
        """The whole Dataset's attributes, with a ``history`` line for this call
        (``chunk_attrs``: the chunks' own, where they were read)."""
        attrs = _whole_attrs(chunks, todo, elapsed, chunk_attrs)
        progress = read_progress(chunks.dir) or {}
        attrs["history"] = attrs.get("history", "") + "\n" + history_line(
            f"streamed to {chunks.dir}: {chunks.n_chunks} chunks of {chunks.chunk_members} "
            f"members ({len(todo)} run by this call), "
            f"{progress.get('members_per_second', 0):.3g} members/s, "
            f"{progress.get('elapsed_seconds', 0):.1f} s")
        return attrs

    def _groups(self, members: int) -> CanonicalGroups:
        plan = self.plan
        return CanonicalGroups(plan.spec, plan.body.moments[None, :], np.array([members]),
                               np.array([plan.h]))


def numbered(ds, lo: int):
    """A chunk's Dataset with its members numbered from ``lo``."""
    member = ds[cv.MEMBER]
    return ds.assign_coords({cv.MEMBER: (cv.MEMBER, np.arange(lo, lo + member.size),
                                         member.attrs)})


def _whole_attrs(chunks: ChunkStore, todo, elapsed, chunk_attrs=None) -> dict:
    """The attributes of the whole run from those of its chunks (:func:`summed_attrs`), its
    rate that of the chunks ``todo`` this call ran in ``elapsed`` seconds."""
    attrs = summed_attrs(chunks, elapsed, chunk_attrs)
    n = chunks.members
    ran = sum(hi - lo for lo, hi in map(chunks.bounds, todo))
    title = attrs.get("title", "")
    if "-member ensemble" in title:
        attrs["title"] = f"{n}-member ensemble" + title.split("-member ensemble", 1)[1]
    steps = float(attrs.get("steps_done", 0))
    attrs.update({
        "members": n,
        "members_requested": n,
        "member_steps_per_second": ran * steps / elapsed if elapsed > 0 else 0.0,
        "chunks": chunks.n_chunks,
        "chunk_members": chunks.chunk_members,
    })
    return attrs
