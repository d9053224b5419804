"""Perturbed ensembles about a steady spin: ``run_ensemble`` and its per-member summaries.

Member j starts at steady spin ``W`` about a principal axis plus a perturbation of size
``epsilon W`` perpendicular to it, in a random direction (or a fixed one, or from starts the
caller gives), and the members are one grouped run of the ensemble layer
(:mod:`stability.ensemble.chunks`, built by :func:`stability.free_body.propagate.loop_plan`),
advanced by the one parallel member loop. The result is an xarray Dataset (schema in
:mod:`stability.output.dataset`): the time series ``w`` (unless the summaries only are kept) and
per-member summaries: flips (sign changes of the spin-axis component), crossings of a
perpendicular component, the maximum perpendicular amplitude and the first passage of that
amplitude through given levels (all tracked at every step inside the member loop, so also
without a time series), the end-of-run relative errors of energy and |L|, and a status code. A
member whose state stops being finite, whose invariants leave ``divergence_tolerance``, whose
implicit solve fails or whose step angle ``h max|w|`` exceeds what the method resolves
(``MethodSpec.max_step_angle``) is flagged and all its numbers are NaN: status ok means the
member's numbers can be trusted.

Reproducibility: the random directions are drawn outside compiled code, from one
``numpy.random.SeedSequence`` child per :data:`RNG_CHUNK` members (child c draws the members
``RNG_CHUNK c ... RNG_CHUNK (c + 1) - 1``), and each member is advanced independently of the
others. So the Dataset is bitwise the same for any number of threads and any compute chunking,
and an ensemble of N members is the first N members of any larger one with the same seed.

Its parts: the start rule (:mod:`~stability.ensemble.starts`), the plan that checks and
resolves the arguments (:mod:`~stability.free_body.ensemble_plan`), from a propagation to the
Dataset (:mod:`~stability.free_body.results`), and the run streamed to a store
(:mod:`~stability.free_body.streamed`); here the runs in memory, one or many at once.
"""

from __future__ import annotations

import inspect
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, replace

import numpy as np

from ..core.quaternions import IDENTITY
from ..core.body import RigidBody
from .propagate import loop_plan
from ..ensemble.chunks import run_plan
from ..ensemble.options import RunOptions, run_options
from .keep import Keep, kept
from ..analysis.members import summary_members
from .timescales import (
    DEFAULT_EPSILON,
    DEFAULT_MEMBERS,
    default_timescales,
    nominal_start,
)
from ..util import conventions as cv
from ..util.checks import checked_progress, did_you_mean, positive_float, vectors3
from ..util.threads import checked_threads, numba_threads
from .ensemble_plan import NO_SPIN, NO_STARTS, EnsemblePlan, plan_ensemble
from ..core.axes import spin_axis
from .results import RunPart, finish_run, members_dataset
from ..ensemble.starts import axis_index, nonnegative_float
from .streamed import run_streamed


def run_ensemble(
    body: RigidBody,
    axis: int,
    spin: float | None = None,
    epsilon: float | None = None,
    members: int | None = None,
    *,
    h: float | None = None,
    t_end: float | None = None,
    seed=0,
    method: str = "lp2",
    starts=None,
    keep: Keep | None = None,
    options: RunOptions | None = None,
):
    """Run an ensemble of perturbed steady spins and return it as a labelled Dataset.

    Every member is advanced by the parallel member loop
    (:func:`stability.free_body.propagate.propagate`) with the method ``method``; the members are
    independent, so the cost is ``members x t_end / h`` steps (of order 1e7 member-steps/s per core
    for ``lp2``, a few times more for ``rk4``). The result does not depend on the run options
    (threads, chunks, a store, dask), bit for bit.

    Parameters
    ----------
    body : RigidBody
    axis : int or str
        Principal axis (1, 2 or 3, as the body numbers them) of the steady spin, or the name of
        its moment, ``"smallest"``, ``"intermediate"`` or ``"largest"``
        (:func:`~stability.core.axes.spin_axis`, as study files take it). Flips are sign
        changes of the component of w along it.
    spin : float
        Spin rate W in rad/s, > 0 (not with ``starts``).
    epsilon : float, default 1e-3
        Perturbation size relative to the spin, >= 0: member j starts at
        ``W e_axis + epsilon W u_j`` with ``u_j`` a unit vector perpendicular to the axis, in a
        random direction (see :func:`perturbed_starts`; not with ``starts``).
    members : int, default 100
        Number of members N (with ``starts``: optional, must equal ``len(starts)``).
    h : float, optional
        Step in s; for ``lp2`` about 0.01 / W to 0.05 / W, for ``rk4`` up to about 0.1 / W.
        A member whose step angle ``h max|w|`` (:func:`~stability.free_body.timescales.max_angular_speed`) exceeds the
        method's ``max_step_angle`` (``stability.METHODS[method].max_step_angle``, 0.3 to 3
        rad) is labelled ``step_too_large``; if every member would be, the run is refused.
        By default the step angle is 0.02 rad (:func:`stability.free_body.timescales.default_step`),
        or a little less, so that a ``t_end`` given is a whole number of saved steps; the
        Dataset says which in its ``h_rule`` attribute.
    t_end : float, optional
        Horizon in s: a whole number of steps, and of ``save_every`` steps. By default four flip
        intervals 2K/nu of the exact motion
        (:func:`stability.free_body.timescales.default_horizon`; the ``t_end_rule`` attribute).
    seed : int, None or numpy.random.SeedSequence, default 0
        Seed of the random directions; ``None`` draws fresh entropy. The entropy is recorded
        in the Dataset (``seed_entropy``), which is enough to repeat the run.
    method : str, default "lp2"
        A name from ``stability.METHODS``.
    starts : array_like, shape (N, 3), optional
        The initial angular velocities in rad/s, instead of ``spin``/``epsilon`` (one fixed
        perturbation direction for every member: ``perturbed_starts(..., direction=u)``).
    keep : Keep, optional
        What the Dataset keeps (:class:`~stability.free_body.keep.Keep`): the time series of w
        every ``save_every`` steps (default 1; 0: the per-member summaries only), the attitude,
        the amplitude levels of the passage times, and the divergence tolerance of a trusted
        member.
    options : RunOptions, optional
        How and where it runs (:class:`~stability.ensemble.options.RunOptions`), never what it
        computes: ``threads``; ``progress`` (by default shown for runs expected to take more
        than 2 s); ``chunk_members`` and ``chunk_steps`` (memory and the progress bar); a
        ``store`` folder, the run streamed to it one netCDF file per chunk of
        ``chunk_members`` (default 2**20) as soon as each is done and the Dataset over those
        files returned (memory one chunk's and the summaries'; the time series ``w`` dask
        arrays, ``ds.w.load()`` reads them; the summaries loaded, as in memory), which
        ``resume`` finishes after a stop (only the missing chunks run, bitwise an
        uninterrupted run; a store of a different run is refused) and whose chunks a
        ``scheduler`` runs on dask.distributed; ``device="gpu"`` runs the member loop on a CUDA
        GPU (:mod:`stability.engine.gpu`; methods
        ``stability.free_body.propagate_gpu.GPU_METHODS``; agreeing with the CPU run to about
        1e-12 relative, not bitwise); ``max_memory`` (4 GiB by default) refuses a run whose
        Dataset (:func:`ensemble_memory`) would exceed it.

    Returns
    -------
    xarray.Dataset
        Dims ``member``, ``time``, ``axis``, ``level``; variables ``w`` (member, time, axis)
        unless the summaries only are kept, ``w0``, ``status`` and the summaries (see
        :mod:`stability.output.dataset`). ``status`` is 0 (ok) only for a member whose numbers
        can be trusted; otherwise 1 non-finite, 2 diverged (energy or |L| left the divergence
        tolerance), 3 not converged (implicit solve) or 4 step too large (the step angle
        exceeds the method's ``max_step_angle``), and the member's numbers are NaN. If Ctrl-C
        stopped the run, ``interrupted`` is 1 and the Dataset holds what was done
        (``steps_done``).

    Raises
    ------
    ValueError
        For any invalid argument, a run above ``max_memory``, or a step too large for the
        method at every member; before any compiled code runs.

    Examples
    --------
    >>> body = stability.RigidBody(1.0, 2.0, 3.0)
    >>> ds = stability.run_ensemble(body, axis=2, spin=1.0, epsilon=1e-3, members=1000,
    ...                             h=0.01, t_end=60.0, keep=stability.Keep(save_every=10))
    >>> float(ds.mean_flip_interval.median())  # doctest: +SKIP
    28.7
    >>> ds = stability.run_ensemble(body, axis=2, spin=1.0)  # the step and horizon by default
    """
    keep, options = kept(keep), run_options(options)
    options = replace(options, progress=checked_progress(options.progress))
    axis = _named_axis(body, axis)
    epsilon, members, h, t_end, rules = _with_defaults(body, axis, spin, epsilon, members,
                                                       starts, h, t_end, keep.save_every or 1)
    ds = _run_ensemble(body, axis, spin, epsilon, members, h=h, t_end=t_end, seed=seed,
                       method=method, starts=starts, keep=keep, options=options)
    ds.attrs.update(rules)
    return ds


def plan_arguments(keep: Keep, options: RunOptions) -> dict:
    """What :func:`stability.free_body.ensemble_plan.plan_ensemble` takes of an ensemble's choices.

    Parameters
    ----------
    keep : Keep
        What the ensemble keeps.
    options : RunOptions
        How it runs: of these, what shapes the plan (its memory limit, chunks and device).

    Returns
    -------
    dict
        Keyword arguments of :func:`~stability.free_body.ensemble_plan.plan_ensemble`.
    """
    return {**keep.plan_arguments(), "max_memory": options.max_memory,
            "chunk_members": options.chunk_members, "chunk_steps": options.chunk_steps,
            "device": options.device}


def _named_axis(body, axis):
    """``axis`` named by its moment as its label (:func:`spin_axis`), for a RigidBody."""
    return spin_axis(body, axis) if isinstance(body, RigidBody) else axis


def _with_defaults(body, axis, spin, epsilon, members, starts, h, t_end, save_every):
    """``(epsilon, members, h, t_end, rules)``: the arguments of :func:`run_ensemble` that are
    None given their defaults, and the rules of a default step and horizon."""
    if starts is None:
        epsilon = DEFAULT_EPSILON if epsilon is None else epsilon
        members = DEFAULT_MEMBERS if members is None else members
    h, t_end, rules = _default_timescales(body, axis, spin, epsilon, starts, h, t_end, save_every)
    return epsilon, members, h, t_end, rules


def _default_timescales(body, axis, spin, epsilon, starts, h, t_end, save_every):
    """``h`` and ``t_end``, each chosen from the physics where it is None
    (:func:`stability.free_body.timescales.default_timescales`), and the rules chosen, by
    attribute name. Arguments too wrong to choose from are left for :func:`plan_ensemble` to
    name."""
    if (h is not None and t_end is not None) or not isinstance(body, RigidBody):
        return h, t_end, {}
    a = axis_index(axis)
    if starts is not None:
        w0 = vectors3("starts", starts, "rad/s")
        if w0.ndim != 2:
            return h, t_end, {}
        if w0.shape[0] == 0:
            raise ValueError(NO_STARTS)
    elif spin is None:
        raise ValueError(NO_SPIN)
    else:
        spin = positive_float("spin", spin, "rad/s")
        w0 = nominal_start(a + 1, spin, nonnegative_float("epsilon", epsilon))[None, :]
    return default_timescales(body, w0, h, t_end, save_every)


def _run_ensemble(body, axis, spin, epsilon, members, *, h, t_end, seed, method, starts,
                  keep, options):
    """:func:`run_ensemble` once its step and horizon are known."""
    kwargs = dict(body=body, axis=axis, spin=spin, epsilon=epsilon, members=members, h=h,
                  t_end=t_end, seed=seed, method=method, starts=starts,
                  **plan_arguments(keep, options))
    if options.store is not None:
        return run_streamed(kwargs, options)
    if options.resume or options.scheduler is not None:
        raise ValueError("resume and scheduler need a store: RunOptions(store=...), the folder "
                         "the chunks go to")
    plan = plan_ensemble(**kwargs)
    with numba_threads(checked_threads(options.threads)):
        (run,) = _run([plan], options.progress)
        return members_dataset(plan, run, options.threads)


def run_ensembles(calls, *, threads=None, progress=None, datasets=True) -> list:
    """Run many ensembles together, each exactly as :func:`run_ensemble` runs it alone.

    The ensembles that share a method (and the kind of output) are advanced in one parallel call
    of the member loop, so many small ensembles (a map over body shapes, a sweep of steps) keep
    every core busy, where one after another each would use one block of members on one core.
    Each Dataset is bitwise the one :func:`run_ensemble` returns for the same arguments.

    Parameters
    ----------
    calls : sequence of dict
        Keyword arguments of :func:`run_ensemble`, one dict per ensemble (``body``, ``axis``,
        ``spin``, ``keep``, ... ; its ``options`` may set ``max_memory`` and ``device``, the
        batch's ``threads``, ``progress``, ``chunk_members``, ``chunk_steps`` not).
        Summaries-only ensembles of one method run together; time-series ones one at a time.
        The batch holds every ensemble at once, so each call's ``max_memory`` (4 GiB by
        default; the machine's memory where that is less) bounds its ensemble together with
        those before it: the whole batch is checked before any start is drawn.
    threads : int, optional
        Numba threads for the whole batch.
    progress : bool, optional
        Progress bar per call of the loop.
    datasets : bool, default True
        False: each summaries-only ensemble comes back as an :class:`EnsembleSummary` (what the
        estimators need) instead of its Dataset, about 1 ms less per ensemble, for maps of
        thousands of small ensembles.

    Returns
    -------
    list of xarray.Dataset or EnsembleSummary
        In the order of ``calls``. If Ctrl-C stopped the batch, the Datasets of the ensembles it
        stopped say so (``interrupted``), as :func:`run_ensemble`'s do.
    """
    if isinstance(calls, (Mapping, str, bytes)) or not isinstance(calls, Iterable):
        raise ValueError("calls must be a list of dicts, each the keyword arguments of "
                         f"run_ensemble for one ensemble; got a {type(calls).__name__}")
    progress = checked_progress(progress)
    plans, rules = [], []
    held = 0  # bytes of the calls planned so far
    for k, call in enumerate(calls):
        if not isinstance(call, Mapping):
            raise ValueError(f"calls[{k}] must be a dict of run_ensemble's keyword arguments, "
                             f"got a {type(call).__name__}")
        call = dict(call)
        _check_call_keys(k, call)
        try:  # the batch's memory so far counts, checked before this call's starts are drawn
            plan, rule = _planned(call, held=held)
        except ValueError as exc:
            raise ValueError(f"calls[{k}]: {exc}") from None
        held += plan.nbytes
        plans.append(plan)
        rules.append(rule)
        if not (datasets or plan.summaries_only):
            raise ValueError(f"calls[{k}]: datasets=False needs the summaries only: "
                             "keep=Keep(save_every=0)")
    batches: dict = {}
    for k, plan in enumerate(plans):
        # Time series run one ensemble at a time, so each stays within its max_memory.
        key = ((plan.spec.name, plan.levels.size, plan.device) if plan.summaries_only
               else ("alone", k))
        batches.setdefault(key, []).append(k)
    runs = [None] * len(plans)
    with numba_threads(checked_threads(threads)):
        for indices in batches.values():
            for k, run in zip(indices, _run([plans[k] for k in indices], progress)):
                runs[k] = run
        if not datasets:
            return [_summary(plan, run) for plan, run in zip(plans, runs)]
        out = []
        for plan, run, rule in zip(plans, runs, rules):
            ds = members_dataset(plan, run, threads)
            ds.attrs.update(rule)
            out.append(ds)
        return out


#: The arguments :func:`run_ensemble` takes, by name.
_ARGUMENTS = tuple(inspect.signature(run_ensemble).parameters)
#: Run options that are the whole batch's in :func:`run_ensembles`.
_BATCH_OPTIONS = ("threads", "progress", "chunk_members", "chunk_steps")
#: Run options of a streamed run, which :func:`run_ensembles` (in memory) has not.
_STREAM_OPTIONS = ("store", "resume", "scheduler")


def _check_call_keys(k, call) -> None:
    """ValueError naming ``calls[k]`` for a key :func:`run_ensembles` cannot take."""
    for name in call:
        if name not in _ARGUMENTS:
            raise ValueError(f"calls[{k}]: unknown argument {name!r} of run_ensemble"
                             f"{did_you_mean(name, _ARGUMENTS)}")
    try:
        options = run_options(call.get("options"))
    except ValueError as exc:
        raise ValueError(f"calls[{k}]: {exc}") from None
    default = RunOptions()
    for name in _BATCH_OPTIONS:
        if getattr(options, name) != getattr(default, name):
            raise ValueError(f"calls[{k}]: {name} is set for the whole batch, not per "
                             "ensemble; pass it to run_ensembles")
    for name in _STREAM_OPTIONS:
        if getattr(options, name) not in (None, False):
            raise ValueError(f"calls[{k}]: {name} is for a streamed run of run_ensemble; "
                             "run_ensembles runs in memory: call run_ensemble with "
                             "RunOptions(store=...) for each ensemble instead")
    for name in ("body", "axis"):
        if name not in call:
            raise ValueError(f"calls[{k}]: give {name}, as run_ensemble needs it")


def _planned(call, held=0):
    """The plan of one call of :func:`run_ensembles` and the rules of its default step and
    horizon, with the defaults :func:`run_ensemble` applies; ``held``: bytes of the calls
    before it (:func:`~stability.free_body.ensemble_plan.plan_ensemble`)."""
    call = dict(call)
    keep, options = kept(call.pop("keep", None)), run_options(call.pop("options", None))
    call["axis"] = _named_axis(call["body"], call["axis"])
    call["epsilon"], call["members"], call["h"], call["t_end"], rules = _with_defaults(
        call["body"], call["axis"], call.get("spin"), call.get("epsilon"), call.get("members"),
        call.get("starts"), call.get("h"), call.get("t_end"), keep.save_every or 1)
    return plan_ensemble(**call, **plan_arguments(keep, options), held=held), rules


@dataclass(frozen=True)
class EnsembleSummary:
    """A summaries-only ensemble without its Dataset (:func:`run_ensembles`, ``datasets=False``).

    The fields are the constructor's parameters and the instance's attributes.

    Parameters
    ----------
    members : stability.analysis.members.Members
        What the estimators take, as ``estimators.members`` gives it from the Dataset.
    status : ndarray of int8, shape (N,)
    energy_error : ndarray, shape (N,)
        Relative energy error at the end, per member (NaN for failed members).
    member_steps : int
        Members times the steps done.
    wall_time : float
        Seconds in compiled code.
    interrupted : bool
        Ctrl-C stopped the ensemble before its end.
    """

    members: object
    status: np.ndarray
    energy_error: np.ndarray
    member_steps: int
    wall_time: float
    interrupted: bool


def completed(*runs) -> None:
    """Raise KeyboardInterrupt if Ctrl-C stopped any of ``runs``: Datasets of
    :func:`run_ensemble` or :func:`stability.integrate` (``interrupted`` 1: the part done), or
    :class:`EnsembleSummary`. A function that builds on runs calls it, so it never passes a
    partial run on as a whole one."""
    for run in runs:
        if run.interrupted if isinstance(run, EnsembleSummary) else run.attrs["interrupted"]:
            raise KeyboardInterrupt


def _summary(plan: EnsemblePlan, run) -> EnsembleSummary:
    """The :class:`EnsembleSummary` of one summaries-only ensemble, from its plan and run."""
    spin = abs(float(plan.spin)) if plan.start_kind != "given" else None  # None: from w0
    members = summary_members(run.summaries, plan.levels, plan.a + 1, spin, w0=run.w0,
                              ok=np.asarray(run.status) == cv.STATUS_OK)
    return EnsembleSummary(members, np.asarray(run.status, dtype=np.int8),
                           np.asarray(run.summaries["energy_error"], dtype=float),
                           run.members * run.steps_done, run.wall_time, run.interrupted)


def _run(plans, progress) -> list:
    """Propagate the members of ``plans`` (one method), tracking their summaries.

    The plans are one plan of the ensemble layer (:func:`loop_plan`), run in this process by
    :func:`stability.ensemble.chunks.run_plan`: one plan in chunks of its
    ``chunk_members``; several plans together, one group each, in one call of the member loop.
    If Ctrl-C stops a single plan's chunk, the result holds the chunks completed before it; if
    it stopped the first chunk, that chunk up to the steps it completed. A stopped batch keeps
    the steps every ensemble completed.
    """
    first = plans[0]
    run, groups = loop_plan(
        first.spec, [plan.body.moments for plan in plans],
        np.concatenate([plan.w0 * plan.body.moments for plan in plans]),
        [plan.w0.shape[0] for plan in plans], [plan.h for plan in plans],
        [plan.n_steps for plan in plans], 0 if first.summaries_only else first.save_every,
        first.chunk_steps if len(plans) == 1 else None,
        track_axes=[plan.a for plan in plans], levels=[plan.levels for plan in plans],
        q0=(np.tile(IDENTITY, (sum(plan.w0.shape[0] for plan in plans), 1))
            if first.attitude else None),
        device=first.device,
    )
    prop = groups.from_kernels(run_plan(
        run, RunOptions(chunk_members=first.chunk_members if len(plans) == 1 else None,
                        progress=progress),
        partial=True,  # Ctrl-C: the chunks done are kept, the Dataset marked interrupted
    ))
    if len(plans) == 1:
        done, steps = prop.x_final.shape[0], int(prop.steps_done[0])
        return [finish_run(first, [RunPart(prop, slice(0, done), slice(0, done), steps)], done,
                           steps, prop.interrupted)]
    work = np.array([plan.w0.shape[0] * plan.n_steps for plan in plans], dtype=float)
    runs, lo = [], 0
    for g, plan in enumerate(plans):
        n = plan.w0.shape[0]
        steps = int(prop.steps_done[g])
        part = RunPart(prop, slice(lo, lo + n), slice(0, n), steps, work[g] / work.sum())
        runs.append(finish_run(plan, [part], n, steps, prop.interrupted and steps < plan.n_steps))
        lo += n
    return runs
