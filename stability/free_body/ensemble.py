"""Perturbed ensembles about a steady spin: ``run_ensemble`` and its per-member summaries.

Member j starts at steady spin ``W`` about a principal axis plus a perturbation of size
``epsilon W`` perpendicular to it, in a random direction (or a fixed one, or from starts the
caller gives), and every member is advanced by the one parallel member loop of
:mod:`stability.free_body.propagate`. The result is an xarray Dataset (schema in :mod:`stability.output.dataset`):
the time series ``w`` (unless ``summaries_only``) and per-member summaries: flips (sign changes
of the spin-axis component), crossings of a perpendicular component, the maximum perpendicular
amplitude and the first passage of that amplitude through given levels (all tracked at every
step inside the member loop, so also without a time series), the end-of-run relative
errors of energy and |L|, and a status code. A member whose state stops being finite, whose
invariants leave ``divergence_tolerance``, whose implicit solve fails or whose step angle
``h max|w|`` exceeds what the method resolves (``MethodSpec.max_step_angle``) is flagged and all
its numbers are NaN: status ok means the member's numbers can be trusted.

Reproducibility: the random directions are drawn outside compiled code, from one
``numpy.random.SeedSequence`` child per :data:`RNG_CHUNK` members (child c draws the members
``RNG_CHUNK c ... RNG_CHUNK (c + 1) - 1``), and each member is advanced independently of the
others. So the Dataset is bitwise the same for any number of threads and any compute chunking,
and an ensemble of N members is the first N members of any larger one with the same seed.
"""

from __future__ import annotations

import logging
import math
import numbers
from dataclasses import dataclass, replace

import numba
import numpy as np

from .model import perpendicular_axes
from .attitude import IDENTITY, attitude_error, attitude_spec, carries_attitude
from ..core.body import RigidBody
from .propagate import CanonicalGroups, group_levels, propagate_many
from ..analysis.members import summary_members
from .exact_attitude import exact_attitudes
from ..integrators import method_spec
from ..ensemble.memory import DEFAULT_MAX_MEMORY
from ..output.dataset import (
    add_attitude, config_toml, ensemble_dataset, history_line, provenance_attrs, summary_bytes,
    threading_layer,
)
from ..output.store import ChunkStore, read_progress
from ..ensemble.chunks import GroupedRun, propagate_stored, summed_attrs
from .timescales import (
    DEFAULT_EPSILON,
    DEFAULT_MEMBERS,
    default_horizon,
    default_step,
    nominal_start,
)
from ..util import conventions as cv
from ..util.checks import (
    positive_float, positive_int, real_array, real_number, step_count, vectors3,
)
from ..util.formatting import format_bytes
from ..util.threads import checked_threads, numba_threads
from ..version import __version__

log = logging.getLogger(__name__)

#: Members per SeedSequence child. Fixed, so that the draws never depend on how the
#: computation is chunked; changing it changes every random ensemble.
RNG_CHUNK = 4096

#: Default members per chunk of a run streamed to disk (``store=``): a multiple of RNG_CHUNK.
STREAM_CHUNK_MEMBERS = 2**20

#: Default relative energy / |L| error at the end above which a member is "diverged".
DEFAULT_DIVERGENCE_TOLERANCE = 1e-2

#: Runs whose stored data exceed this many bytes are announced with a logging warning.
LARGE_RUN_BYTES = 2**30

#: Default perpendicular-amplitude levels of ``passage_time``, as fractions of the spin:
#: half decades from 1e-6 to 1 (13 levels).
DEFAULT_LEVELS = 10.0 ** (np.arange(-12, 1) / 2.0)

#: Working copies of the time series a time-series run holds at its peak (the driver's buffer,
#: its conversion out of the canonical frame, and the Dataset's ``w``).
PEAK_COPIES = 3


def ensemble_memory(members: int, n_saved: int, n_levels: int = DEFAULT_LEVELS.size,
                    scene: str = "free_body") -> int:
    """Bytes of the Dataset ``run_ensemble`` returns.

    Parameters
    ----------
    members : int
        Number of members N.
    n_saved : int
        Saved samples per member after the start (``t_end / (h save_every)``); 0 for a
        summaries-only run.
    n_levels : int, optional
        Number of ``passage_time`` levels.
    scene : {"free_body", "free_body_attitude"}, default "free_body"
        With the attitude (``q``, ``q_norm_error``, ``attitude_error``): 6 more doubles
        a sample.

    Returns
    -------
    int
        ``N (n_saved + 1) 3 8`` bytes of time series (``w`` in float64, start included; none if
        ``n_saved`` is 0; 9 doubles a sample with the attitude) plus the per-member summaries. A
        time-series run needs about
        :data:`PEAK_COPIES` times the time series while it builds the Dataset.
    """
    members = positive_int("members", members)
    n_saved = positive_int("n_saved", n_saved, allow_zero=True)
    per_sample = 9 if carries_attitude(scene) else 3
    series = members * (n_saved + 1) * per_sample * 8 if n_saved > 0 else 0
    return series + members * summary_bytes(n_levels)


def max_angular_speed(moments, w0) -> np.ndarray:
    """The largest |w| the exact motion from each start reaches, in rad/s; shape (N,).

    The motion keeps the energy E and |L| = |m| (m = I w), so it stays on the set
    ``sum m_i^2 = |L|^2``, ``sum m_i^2 / I_i = 2E`` where ``|w|^2 = sum m_i^2 / I_i^2``; all three
    are linear in ``u_i = m_i^2 >= 0``, so the largest |w| on that set is reached where one
    ``u_i`` is 0 (a vertex of the segment), and is found from the three pairs in closed form.
    It is at least |w0| and at most |L| / min(I) (reached only by spins about the axis of the
    smallest moment); for a spin near a principal axis it is |w0| to first order.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments in kg m^2.
    w0 : array_like, shape (N, 3)
        Starts in rad/s.
    """
    I = np.asarray(moments, dtype=float)
    w0 = np.atleast_2d(np.asarray(w0, dtype=float))
    # The motion is the same for moments scaled alike, and scales with w0: both are brought to
    # order 1 first, so that the squares below neither overflow (a spin of 1e160 rad/s) nor
    # underflow (moments of 1e-160 kg m^2) into inf or nan.
    I = I / I.max()
    with np.errstate(invalid="ignore", over="ignore"):
        scale = np.max(np.abs(w0), axis=1)
        w0 = w0 / np.where(scale > 0.0, scale, 1.0)[:, None]
    m = w0 * I
    L2 = np.sum(m * m, axis=1)
    E2 = np.sum(m * w0, axis=1)  # 2E
    b, best = 1.0 / I, np.sum(w0 * w0, axis=1)  # |w0|^2: the start is on the set
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for i, j in ((0, 1), (0, 2), (1, 2)):
            if b[i] == b[j]:
                continue  # equal moments: |w| is fixed along this edge
            ui = (E2 - L2 * b[j]) / (b[i] - b[j])
            uj = L2 - ui
            inside = (ui >= 0.0) & (uj >= 0.0)
            best = np.where(inside, np.maximum(best, ui * b[i] ** 2 + uj * b[j] ** 2), best)
    return np.sqrt(best) * scale


def seed_sequence(seed) -> np.random.SeedSequence:
    """``seed`` (int >= 0, ``None`` for fresh entropy, or a SeedSequence) as a SeedSequence.

    Parameters
    ----------
    seed : int, None or numpy.random.SeedSequence
        The seed; a SeedSequence is returned as it is.

    Returns
    -------
    numpy.random.SeedSequence

    Raises
    ------
    ValueError
        If ``seed`` is not one of these (a bool or a negative integer included).
    """
    if isinstance(seed, np.random.SeedSequence):
        return seed
    if seed is None:
        return np.random.SeedSequence()
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or seed < 0:
        raise ValueError(
            f"seed must be an integer >= 0, None (fresh entropy, recorded in the Dataset) or a "
            f"numpy.random.SeedSequence, got {seed!r}"
        )
    return np.random.SeedSequence(int(seed))


def perturbed_starts(axis, spin, epsilon, members, seed=0, direction=None) -> np.ndarray:
    """Initial angular velocities: steady spin about ``axis`` plus a perpendicular perturbation.

    ``w0_j = spin e_a + epsilon spin (cos(phi_j) e_b + sin(phi_j) e_c)`` with b < c the other
    two axes and ``phi_j`` uniform in [0, 2 pi), drawn from one PCG64 stream per
    :data:`RNG_CHUNK` members (child c of ``SeedSequence(seed)``), so member j gets the same start
    whatever ``members`` is; or ``w0_j = spin e_a + epsilon spin d / |d|`` for a fixed direction d.

    Parameters
    ----------
    axis : int
        Principal axis 1, 2 or 3 of the spin.
    spin : float
        Spin rate W in rad/s, > 0.
    epsilon : float
        Size of the perturbation relative to the spin, >= 0.
    members : int
        Number of members N.
    seed : int, None or numpy.random.SeedSequence, default 0
    direction : array_like, shape (3,), optional
        A fixed perturbation direction, perpendicular to ``axis``.

    Returns
    -------
    ndarray, shape (N, 3)
        Body-frame angular velocities in rad/s; the component along ``axis`` is exactly
        ``spin`` and the perpendicular part has norm ``epsilon spin`` (to rounding).
    """
    a = _axis_index(axis)
    spin = positive_float("spin", spin, "rad/s")
    epsilon = _nonnegative_float("epsilon", epsilon)
    members = positive_int("members", members)
    if direction is not None:
        w0 = np.zeros((members, 3))
        w0[:, a] = spin
        w0 += epsilon * spin * _perpendicular_direction(direction, a)
        return w0
    return _random_starts(a, spin, epsilon, seed_sequence(seed), 0, members)


def _random_starts(a, spin, epsilon, ss, lo, hi) -> np.ndarray:
    """Members ``lo ... hi - 1`` of :func:`perturbed_starts` in random directions."""
    w0 = np.zeros((hi - lo, 3))
    w0[:, a] = spin
    phi = _random_angles(ss, lo, hi)
    b, c = (x - 1 for x in perpendicular_axes(a + 1))  # lowest first, as the tracking uses
    w0[:, b] = epsilon * spin * np.cos(phi)
    w0[:, c] = epsilon * spin * np.sin(phi)
    return w0


def _random_angles(ss: np.random.SeedSequence, lo: int, hi: int) -> np.ndarray:
    """Angles of members ``lo ... hi - 1``, uniform in [0, 2 pi).

    Block c of :data:`RNG_CHUNK` members is drawn in order from child c of ``ss``, so a
    member's angle does not depend on which members are drawn with it.
    """
    phi = np.empty(hi - lo)
    for c in range(lo // RNG_CHUNK, -(-hi // RNG_CHUNK)):
        # The c-th child of ss.spawn(...), built directly so that ss is not mutated.
        child = np.random.SeedSequence(
            ss.entropy, spawn_key=tuple(ss.spawn_key) + (c,), pool_size=ss.pool_size
        )
        rng = np.random.Generator(np.random.PCG64(child))
        first = c * RNG_CHUNK
        block = rng.uniform(0.0, 2.0 * math.pi, size=min(first + RNG_CHUNK, hi) - first)
        start = max(lo, first)
        phi[start - lo:first + block.size - lo] = block[start - first:]
    return phi


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
    save_every: int = 1,
    direction=None,
    starts=None,
    summaries_only: bool = False,
    scene: str = "free_body",
    levels=None,
    divergence_tolerance: float = DEFAULT_DIVERGENCE_TOLERANCE,
    max_memory: float = DEFAULT_MAX_MEMORY,
    threads: int | None = None,
    progress: bool | None = None,
    chunk_members: int | None = None,
    chunk_steps: int | None = None,
    config: dict | None = None,
    command: str | None = None,
    store=None,
    resume: bool = False,
    scheduler: str | None = None,
    device: str = "cpu",
):
    """Run an ensemble of perturbed steady spins and return it as a labelled Dataset.

    Every member is advanced by the parallel member loop
    (:func:`stability.free_body.propagate.propagate`) with the method ``method``; the members are
    independent, so the cost is ``members x t_end / h`` steps (of order 1e7 member-steps/s per core
    for ``lp2``, a few times more for ``rk4``). The result does not depend on ``threads``,
    ``chunk_members`` or ``chunk_steps``, bit for bit.

    Parameters
    ----------
    body : RigidBody
    axis : int
        Principal axis (1, 2 or 3, as the body numbers them) of the steady spin. Flips are sign
        changes of the component of w along it.
    spin : float
        Spin rate W in rad/s, > 0 (not with ``starts``).
    epsilon : float, default 1e-3
        Perturbation size relative to the spin, >= 0: member j starts at
        ``W e_axis + epsilon W u_j`` with ``u_j`` a unit vector perpendicular to the axis, in a
        random direction (see :func:`perturbed_starts`) or ``direction`` (not with ``starts``).
    members : int, default 100
        Number of members N (with ``starts``: optional, must equal ``len(starts)``).
    h : float, optional
        Step in s; for ``lp2`` about 0.01 / W to 0.05 / W, for ``rk4`` up to about 0.1 / W.
        A member whose step angle ``h max|w|`` (:func:`max_angular_speed`) exceeds the
        method's ``max_step_angle`` (``stability.METHODS[method].max_step_angle``, 0.3 to 3
        rad) is labelled ``step_too_large``; if every member would be, the run is refused.
        By default the step angle is 0.02 rad (:func:`stability.free_body.timescales.default_step`),
        and the Dataset says so in its ``h_rule`` attribute.
    t_end : float, optional
        Horizon in s: a whole number of steps, and of ``save_every`` steps. By default four flip
        intervals 2K/nu of the exact motion
        (:func:`stability.free_body.timescales.default_horizon`; the ``t_end_rule`` attribute).
    seed : int, None or numpy.random.SeedSequence, default 0
        Seed of the random directions; ``None`` draws fresh entropy. The entropy is recorded
        in the Dataset (``seed_entropy``), which is enough to repeat the run.
    method : str, default "lp2"
        A name from ``stability.METHODS``.
    save_every : int, default 1
        Keep w every ``save_every`` steps (time-series runs). The summaries do not depend on
        it: they are tracked at every step inside the member loop.
    direction : array_like, shape (3,), optional
        Fixed perturbation direction perpendicular to ``axis`` (all members start alike).
    starts : array_like, shape (N, 3), optional
        The initial angular velocities in rad/s, instead of ``spin``/``epsilon``/``direction``.
    summaries_only : bool, default False
        Keep only the per-member summaries (no ``w`` time series; memory about
        ``ensemble_memory(members, 0)``, ~250 bytes a member): for ensembles of 1e6
        members and more, and for many small ensembles. The summaries are bitwise those of the
        time-series run.
    scene : {"free_body", "free_body_attitude"}, default "free_body"
        What is integrated: w alone, or w and each member's attitude (a method of
        ``stability.free_body.attitude.attitude_methods()``, time series only, on the CPU; w is
        bitwise the same): every member starts at the identity (body axes along the space axes),
        and the Dataset gains ``q``, ``q_norm_error`` and ``attitude_error``, the angle to the
        exact attitude (:mod:`stability.free_body.exact_attitude`) at each saved time.
    levels : array_like, shape (n_levels,), optional
        Ascending perpendicular-amplitude levels in rad/s for ``passage_time``; default
        :data:`DEFAULT_LEVELS` times the spin (with ``starts``, times the median |w0|).
    divergence_tolerance : float, default 1e-2
        A member whose relative energy or |L| error at the end exceeds this is "diverged".
    max_memory : float, default 4 GiB
        Refuse a run whose Dataset (:func:`ensemble_memory`, with or without the time series)
        would exceed this many bytes.
    threads : int, optional
        Numba threads for this run (restored afterwards); default: Numba's current setting.
    progress : bool, optional
        Progress bar; by default shown for runs expected to take more than 2 s.
    chunk_members, chunk_steps : int, optional
        Members per driver call and steps per kernel call. They change memory use and the
        progress bar, never the result.
    config : dict, optional
        The caller's whole resolved configuration (e.g. a study file), stored as TOML in the
        ``config_toml`` attribute; by default the resolved arguments of this call.
    command : str, optional
        The command recorded as the first ``history`` line; default: this call.
    store : str or path-like, optional
        Stream the run to this folder, one netCDF file per chunk of ``chunk_members``
        (default 2**20) written as soon as it is done, and return the Dataset over those files
        (dask arrays): memory is one chunk's, and a stopped run can be resumed
        (:mod:`stability.output.stream`).
    resume : bool, default False
        With ``store``: finish a run stopped earlier (only the missing chunks are run; the
        result is bitwise that of an uninterrupted run). A store of a different run is refused.
    scheduler : str or distributed.Client, optional
        With ``store``: run the chunks on dask.distributed, ``"dask"`` for a local cluster, a
        scheduler address such as ``"tcp://host:8786"``, or a client.
    device : {"cpu", "gpu"}, default "cpu"
        ``"gpu"``: run the member loop on a CUDA GPU (:mod:`stability.engine.gpu`; methods
        ``stability.engine.gpu.GPU_METHODS``). Same members, agreeing with the CPU run to about
        1e-12 relative, not bitwise (fused multiply-adds, the device's libm).

    Returns
    -------
    xarray.Dataset
        Dims ``member``, ``time``, ``axis``, ``level``; variables ``w`` (member, time, axis)
        unless ``summaries_only``, ``w0``, ``status`` and the summaries (see
        :mod:`stability.output.dataset`). ``status`` is 0 (ok) only for a member whose numbers can
        be trusted; otherwise 1 non-finite, 2 diverged (energy or |L| left
        ``divergence_tolerance``), 3 not converged (implicit solve) or 4 step too large (the
        step angle exceeds the method's ``max_step_angle``), and the member's numbers are NaN.
        If Ctrl-C stopped the run, ``interrupted`` is 1 and the
        Dataset holds what was done (``steps_done``).

    Raises
    ------
    ValueError
        For any invalid argument, a run above ``max_memory``, or a step too large for the
        method at every member; before any compiled code runs.

    Examples
    --------
    >>> body = stability.RigidBody(1.0, 2.0, 3.0)
    >>> ds = stability.run_ensemble(body, axis=2, spin=1.0, epsilon=1e-3, members=1000,
    ...                             h=0.01, t_end=60.0, save_every=10)
    >>> float(ds.mean_flip_interval.median())  # doctest: +SKIP
    28.7
    >>> ds = stability.run_ensemble(body, axis=2, spin=1.0)  # the step and horizon by default
    """
    if starts is None:
        epsilon = DEFAULT_EPSILON if epsilon is None else epsilon
        members = DEFAULT_MEMBERS if members is None else members
    h, t_end, rules = _default_timescales(body, axis, spin, epsilon, starts, h, t_end, save_every)
    ds = _run_ensemble(
        body, axis, spin, epsilon, members, h=h, t_end=t_end, seed=seed, method=method,
        save_every=save_every, direction=direction, starts=starts,
        summaries_only=summaries_only, scene=scene, levels=levels,
        divergence_tolerance=divergence_tolerance, max_memory=max_memory, threads=threads,
        progress=progress, chunk_members=chunk_members, chunk_steps=chunk_steps, config=config,
        command=command, store=store, resume=resume, scheduler=scheduler, device=device,
    )
    ds.attrs.update(rules)
    return ds


_NO_SPIN = ("give spin, the spin rate in rad/s (epsilon and members have defaults), or "
            "starts=, the initial angular velocities")


def _default_timescales(body, axis, spin, epsilon, starts, h, t_end, save_every):
    """``h`` and ``t_end``, each chosen from the physics where it is None
    (:mod:`stability.free_body.timescales`), and the rules chosen, by attribute name. Arguments too
    wrong
    to choose from are left for :func:`_plan` to name."""
    if (h is not None and t_end is not None) or not isinstance(body, RigidBody):
        return h, t_end, {}
    a = _axis_index(axis)
    if starts is not None:
        w0 = vectors3("starts", starts, "rad/s")
        if w0.ndim != 2:
            return h, t_end, {}
    elif spin is None:
        raise ValueError(_NO_SPIN)
    else:
        spin = positive_float("spin", spin, "rad/s")
        w0 = nominal_start(a + 1, spin, _nonnegative_float("epsilon", epsilon))[None, :]
    rules = {}
    if h is None:
        h, rules["h_rule"] = default_step(float(np.max(max_angular_speed(body.moments, w0))))
    if t_end is None:
        t_end, rules["t_end_rule"] = default_horizon(
            body, w0, positive_float("h", h, "s"), positive_int("save_every", save_every))
    return h, t_end, rules


def _run_ensemble(body, axis, spin, epsilon, members, *, h, t_end, seed, method, save_every,
                  direction, starts, summaries_only, scene, levels, divergence_tolerance,
                  max_memory, threads, progress, chunk_members, chunk_steps, config, command,
                  store, resume, scheduler, device):
    """:func:`run_ensemble` once its step and horizon are known."""
    if store is not None:
        kwargs = dict(
            body=body, axis=axis, spin=spin, epsilon=epsilon, members=members, h=h,
            t_end=t_end, seed=seed, method=method, save_every=save_every, direction=direction,
            starts=starts, summaries_only=summaries_only, levels=levels,
            divergence_tolerance=divergence_tolerance, max_memory=max_memory,
            chunk_members=chunk_members, chunk_steps=chunk_steps, config=config,
            command=command, device=device, scene=scene,
        )
        return run_streamed(kwargs, store, resume=resume, scheduler=scheduler, threads=threads,
                            progress=progress)
    if resume or scheduler is not None:
        raise ValueError("resume and scheduler need store= (the folder the chunks go to)")
    plan = _plan(
        body, axis, spin, epsilon, members, h=h, t_end=t_end, seed=seed, method=method,
        save_every=save_every, direction=direction, starts=starts, summaries_only=summaries_only,
        levels=levels, divergence_tolerance=divergence_tolerance, max_memory=max_memory,
        chunk_members=chunk_members, chunk_steps=chunk_steps, config=config, command=command,
        device=device, scene=scene,
    )
    with numba_threads(checked_threads(threads)):
        (run,) = _run([plan], progress)
        return _dataset(plan, run, threads)


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
        ``spin``, ... ; not ``threads``, ``progress``, ``chunk_members``, ``chunk_steps``).
        Summaries-only ensembles of one method run together; time-series ones one at a time.
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
    plans = []
    for k, call in enumerate(calls):
        call = dict(call)
        bad = {"threads", "progress", "chunk_members", "chunk_steps"} & set(call)
        if bad:
            raise ValueError(f"calls[{k}]: {sorted(bad)[0]} is set for the whole batch, not per "
                             "ensemble; pass it to run_ensembles")
        plans.append(_plan(**call))
        if not (datasets or plans[-1].summaries_only):
            raise ValueError(f"calls[{k}]: datasets=False needs summaries_only=True")
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
        return [_dataset(plan, run, threads) for plan, run in zip(plans, runs)]


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


def _summary(plan: _Plan, run) -> EnsembleSummary:
    """The :class:`EnsembleSummary` of one summaries-only ensemble, from its plan and run."""
    spin = abs(float(plan.spin)) if plan.start_kind != "given" else None  # None: from w0
    members = summary_members(run.summaries, plan.levels, plan.a + 1, spin, w0=run.w0,
                              ok=np.asarray(run.status) == cv.STATUS_OK)
    return EnsembleSummary(members, np.asarray(run.status, dtype=np.int8),
                           np.asarray(run.summaries["energy_error"], dtype=float),
                           run.members * run.steps_done, run.wall_time, run.interrupted)


# --- a run streamed to a store, chunk by chunk (stability.output.stream)
# -----------------------------


def run_streamed(kwargs: dict, store, *, resume=False, scheduler=None, threads=None,
                 progress=None, compress=True):
    """Run the ensemble ``run_ensemble(**kwargs)`` chunk by chunk into the folder ``store``.

    Returns the Dataset over the chunk files (dask arrays). See :func:`stability.run_ensemble`
    for ``kwargs``; ``chunk_members`` there is the members per chunk file here
    (default :data:`STREAM_CHUNK_MEMBERS`).

    Parameters
    ----------
    kwargs : dict
        Keyword arguments of :func:`stability.run_ensemble` (without ``threads``,
        ``progress``, ``store``, ``resume`` and ``scheduler``).
    store : str or path-like
        Folder of the chunk files; created if missing.
    resume : bool, default False
        Finish a run of the same arguments stopped earlier: only the chunks not on disk are
        run. Without it, a store that already has chunks done is refused.
    scheduler : str or distributed.Client, optional
        Run the chunks on dask.distributed: ``"dask"`` for a local cluster, a scheduler
        address such as ``"tcp://host:8786"``, or a client. By default they run in this
        process.
    threads : int, optional
        Numba threads when the chunks run in this process; default: Numba's current setting.
        Dask workers use their own threads.
    progress : bool, optional
        Progress bar: over members when several chunks are run, else the chunk's own;
        ``False`` shows none.
    compress : bool, default True
        zlib-compress the chunk files (:func:`stability.output.io.save`).

    Returns
    -------
    xarray.Dataset
        The whole run over the chunk files (dask arrays).

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
    plan = _plan(**kwargs, defer_starts=True)
    kwargs["chunk_members"] = plan.chunk_members
    ensemble = EnsembleChunks(kwargs, plan)
    return propagate_stored(ensemble.grouped_run(), store, measure=ensemble, resume=resume,
                            scheduler=scheduler, chunk_members=plan.chunk_members,
                            threads=threads, progress=progress, compress=compress)


class EnsembleChunks:
    """A free-body ensemble as a stored grouped run (:mod:`stability.ensemble.chunks`): its
    start rule and its measurement.

    :meth:`grouped_run` is the run, one group, whose starts come from :meth:`starts`: members
    ``lo ... hi - 1`` of :func:`stability.run_ensemble` drawn for those members alone, in each
    body's canonical frame. Called as a measurement, the object turns a chunk's propagation
    into the Dataset ``run_ensemble`` gives those members, numbered from ``lo``
    (:func:`_finish` and :func:`_dataset`). :meth:`identity` and :meth:`whole_attrs` are the
    store's fingerprint and the whole Dataset's attributes.

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
    def plan(self) -> _Plan:
        if self._plan is None:
            self._plan = _plan(**self.kwargs, defer_starts=True)
        return self._plan

    def grouped_run(self):
        """The ensemble as a :class:`~stability.ensemble.chunks.GroupedRun`: the arguments
        :func:`stability.free_body.propagate.propagate_many` gives the member loop for it."""
        plan = self.plan
        groups = self._groups(plan.members)
        return GroupedRun(
            "free_body_attitude" if plan.attitude else "free_body", plan.spec.name, None,
            groups.params, [plan.members], plan.h, plan.n_steps,
            save_every=0 if plan.summaries_only else plan.save_every,
            axes=groups.tracking_axes([plan.a]), levels=group_levels([plan.levels], 1),
            device=plan.device, chunk_steps=plan.chunk_steps, starts=self.starts)

    def starts(self, lo: int, hi: int) -> np.ndarray:
        """The start rule: the initial states (canonical m, and q) of members lo to hi - 1."""
        sub = _chunk_plan(self.plan, lo, hi)
        self._drawn[lo, hi] = sub  # for the measurement of the same chunk: drawn once
        groups = self._groups(hi - lo)
        x0 = groups.to_canonical(sub.w0 * sub.body.moments)
        if sub.attitude:
            x0 = np.concatenate([x0, groups.attitudes(np.tile(IDENTITY, (hi - lo, 1)),
                                                      to_canonical=True)], axis=1)
        return x0

    def __call__(self, part, run, lo: int, hi: int, threads):
        """The measurement: the Dataset of members lo to hi - 1 from their propagation."""
        sub = self._drawn.pop((lo, hi), None) or _chunk_plan(self.plan, lo, hi)
        n = hi - lo
        groups = self._groups(n)
        run.x_final = groups.from_canonical_state(run.x_final)
        run.saved = groups.from_canonical_state(run.saved)
        measured = _finish(sub, [_Part(run, slice(0, n), slice(0, n), int(run.steps_done[0]))],
                           n, sub.n_steps, False)
        ds = _dataset(sub, measured, threads)
        member = ds[cv.MEMBER]
        return ds.assign_coords({cv.MEMBER: (cv.MEMBER, np.arange(lo, lo + member.size),
                                             member.attrs)})

    def identity(self, run) -> dict:
        """What decides the members' numbers, for the store's fingerprint (not the caller's
        configuration, which may differ in keys that do not, such as the figures of a study)."""
        return {"run_ensemble": {k: v for k, v in self.plan.resolved.items() if k != "threads"},
                "software": f"stability {__version__}"}

    def whole_attrs(self, chunks: ChunkStore, todo) -> dict:
        """The whole Dataset's attributes, with a ``history`` line for this call."""
        attrs = _whole_attrs(chunks)
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


def _whole_attrs(chunks: ChunkStore) -> dict:
    """The attributes of the whole run from those of its chunks."""
    attrs = summed_attrs(chunks)
    wall = attrs["wall_time"]
    n = chunks.members
    title = attrs.get("title", "")
    if "-member ensemble" in title:
        attrs["title"] = f"{n}-member ensemble" + title.split("-member ensemble", 1)[1]
    steps = float(attrs.get("steps_done", 0))
    attrs.update({
        "members": n,
        "members_requested": n,
        "member_steps_per_second": n * steps / wall if wall > 0 else 0.0,
        "chunks": chunks.n_chunks,
        "chunk_members": chunks.chunk_members,
    })
    return attrs


# --- the plan ---------------------------------------------------------------------------------


@dataclass
class _Plan:
    """One validated ensemble: everything :func:`run_ensemble` resolved before running."""

    body: RigidBody
    spec: object
    a: int
    members: int
    w0: np.ndarray | None  # None: drawn per chunk (_chunk_plan)
    h: float
    t_end: float
    n_steps: int
    save_every: int
    summaries_only: bool
    levels: np.ndarray
    tolerance: float
    step_angle: np.ndarray | None  # None: worked out per chunk (_chunk_plan)
    chunk_members: int
    chunk_steps: int | None
    resolved: dict
    start_kind: str
    spin: float | None
    epsilon: float | None
    direction: np.ndarray | None
    ss: np.random.SeedSequence
    config_text: str | None
    command: str | None
    device: str = "cpu"
    attitude: bool = False


def _plan(body, axis, spin=None, epsilon=None, members=None, *, h, t_end, seed=0, method="lp2",
          save_every=1, direction=None, starts=None, summaries_only=False, levels=None,
          divergence_tolerance=DEFAULT_DIVERGENCE_TOLERANCE, max_memory=DEFAULT_MAX_MEMORY,
          chunk_members=None, chunk_steps=None, config=None, command=None, device="cpu",
          defer_starts=False, scene="free_body") -> _Plan:
    """Validate the arguments of :func:`run_ensemble` and draw the starts; ValueError if bad.

    With ``defer_starts`` random starts are not drawn: :func:`_chunk_plan` draws each chunk's.
    """
    if not isinstance(body, RigidBody):
        raise ValueError(f"body must be a stability.RigidBody, got {type(body).__name__}")
    a = _axis_index(axis)
    spec = method_spec(method)
    if device not in ("cpu", "gpu"):
        raise ValueError(f"device must be 'cpu' or 'gpu', got {device!r}")
    if device == "gpu":
        from ..engine.gpu import NoGPUError, gpu_method
        from ..engine.gpu.device import cuda_module

        gpu_method(spec.name, scene)  # ValueError naming the methods the GPU has
        try:
            cuda_module()
        except NoGPUError as exc:  # before anything runs, as a user's error
            raise ValueError(f"device = 'gpu': {exc}") from None
    h = positive_float("h", h, "s")
    t_end = positive_float("t_end", t_end, "s")
    n_steps = step_count(t_end, h)
    save_every = positive_int("save_every", save_every)
    if not isinstance(summaries_only, (bool, np.bool_)):
        raise ValueError(f"summaries_only must be True or False, got {summaries_only!r}")
    attitude = carries_attitude(scene)
    if attitude:
        attitude_spec(spec)
    if attitude and summaries_only:
        raise ValueError("scene 'free_body_attitude' needs the time series: leave "
                         "summaries_only False")
    if n_steps % save_every and not summaries_only:
        raise ValueError(
            f"t_end / h = {n_steps} steps is not a multiple of save_every = {save_every}; "
            "choose save_every dividing the number of steps"
        )
    ss = seed_sequence(seed)
    if starts is not None:
        if spin is not None or epsilon is not None or direction is not None:
            raise ValueError(
                "starts= gives the initial angular velocities itself; leave spin, epsilon "
                "and direction out (None) when you pass it"
            )
        w0 = vectors3("starts", starts, "rad/s")
        if w0.ndim != 2:
            raise ValueError(f"starts must have shape (members, 3), got {w0.shape}")
        if members is not None and positive_int("members", members) != w0.shape[0]:
            raise ValueError(
                f"members = {members} but starts has {w0.shape[0]} rows; leave members out "
                "or make them agree"
            )
        if np.any(np.all(w0 == 0.0, axis=1)):
            raise ValueError("starts has a row w0 = 0 (a body at rest); every member must spin")
        start_kind = "given"
        spin_ref = float(np.median(np.linalg.norm(w0, axis=1)))
    else:
        if spin is None or epsilon is None or members is None:
            raise ValueError(_NO_SPIN if spin is None else "give spin, epsilon and members "
                             "(or starts=)")
        spin = positive_float("spin", spin, "rad/s")
        epsilon = _nonnegative_float("epsilon", epsilon)
        members = positive_int("members", members)
        if direction is not None:
            direction = _perpendicular_direction(direction, a)
        start_kind = "random_perpendicular" if direction is None else "fixed_direction"
        spin_ref = spin
        w0 = None
    n_members = w0.shape[0] if w0 is not None else members
    levels = _levels(levels, spin_ref)
    divergence_tolerance = positive_float("divergence_tolerance", divergence_tolerance)
    max_memory = positive_float("max_memory", max_memory, "bytes")
    if chunk_members is not None:
        chunk_members = positive_int("chunk_members", chunk_members)
    if chunk_steps is not None:
        chunk_steps = positive_int("chunk_steps", chunk_steps)
    config_text = config_toml(config) if config is not None else None

    # --- memory -----------------------------------------------------------------------------
    n_saved = n_steps // save_every
    n_time = n_saved + 1
    if defer_starts:  # streamed to disk: a chunk at a time in memory
        chunk_members = min(chunk_members or STREAM_CHUNK_MEMBERS, n_members)
    held = chunk_members if defer_starts else n_members
    stored = ensemble_memory(held, 0 if summaries_only else n_saved, levels.size,
                             scene=scene)
    if not summaries_only and stored > max_memory:
        raise ValueError(
            f"the time series of {held} members x {n_time} samples x "
            f"{9 if attitude else 3} doubles would "
            f"take {format_bytes(stored)} (about {PEAK_COPIES}x that while the run builds it), "
            f"above max_memory = {format_bytes(max_memory)}; raise save_every, use fewer "
            "members, pass summaries_only=True (per-member summaries only), or raise max_memory"
        )
    if summaries_only and stored > max_memory:
        raise ValueError(
            f"the summaries of {held} members would take {format_bytes(stored)} "
            f"({format_bytes(stored / held)} a member), above max_memory = "
            f"{format_bytes(max_memory)}; use fewer members, stream the run to disk "
            "(store=, a chunk at a time in memory), or raise max_memory"
        )
    chunk_members = min(chunk_members or n_members, n_members)
    level = logging.WARNING if stored > LARGE_RUN_BYTES else logging.INFO
    log.log(
        level,
        "run_ensemble: %d members x %d steps of %s (%.3g member-steps); Dataset %s "
        "(%s per member)%s",
        n_members, n_steps, spec.name, float(n_members) * n_steps, format_bytes(stored),
        format_bytes(stored / held),
        "" if summaries_only else f", about {PEAK_COPIES}x that at the peak",
    )

    # --- starts -----------------------------------------------------------------------------
    if w0 is None and (direction is not None or not defer_starts):
        w0 = perturbed_starts(axis, spin, epsilon, members, ss, direction)
    if starts is not None:
        given = (f"starts of up to {np.abs(w0).max():.3g} rad/s", "smaller starts")
    elif epsilon <= 1:
        given = (f"spin = {spin:.3g} rad/s", "a smaller spin")
    else:
        given = (f"epsilon = {epsilon:.3g} (of spin = {spin:.3g} rad/s)", "a smaller epsilon")
    if w0 is not None:
        step_angle = _step_angles(body, spec, w0, h, t_end, given)
    else:  # drawn per chunk; refuse up front if the first block of starts is hopeless
        _step_angles(body, spec, _random_starts(a, spin, epsilon, ss, 0,
                                                min(n_members, RNG_CHUNK)), h, t_end, given)
        step_angle = None

    resolved = {
        "body": {"name": body.name, "I1": body.I1, "I2": body.I2, "I3": body.I3,
                 "physical": body.physical},
        "axis": a + 1,
        "spin": spin,
        "epsilon": epsilon,
        "members": n_members,
        "start_kind": start_kind,
        "direction": direction,
        "seed": ss.entropy,
        "seed_spawn_key": list(ss.spawn_key),
        "method": spec.name,
        "h": h,
        "t_end": t_end,
        "save_every": save_every,
        "summaries_only": bool(summaries_only),
        "scene": scene,
        "levels": levels,
        "divergence_tolerance": divergence_tolerance,
        "threads": None,
        "device": device,
    }
    return _Plan(
        body=body, spec=spec, a=a, members=n_members, w0=w0, h=h, t_end=t_end, n_steps=n_steps,
        save_every=save_every, summaries_only=bool(summaries_only), levels=levels,
        tolerance=divergence_tolerance, step_angle=step_angle, chunk_members=chunk_members,
        chunk_steps=chunk_steps,
        resolved=resolved, start_kind=start_kind, spin=spin, epsilon=epsilon,
        direction=direction, ss=ss, config_text=config_text, command=command, device=device,
        attitude=bool(attitude),
    )


def _chunk_plan(plan: _Plan, lo: int, hi: int) -> _Plan:
    """The plan of members ``lo ... hi - 1`` of ``plan`` alone (a chunk of a streamed run)."""
    if plan.w0 is not None:
        w0 = plan.w0[lo:hi]
    else:
        w0 = _random_starts(plan.a, plan.spin, plan.epsilon, plan.ss, lo, hi)
    angle = (plan.step_angle[lo:hi] if plan.step_angle is not None
             else plan.h * max_angular_speed(plan.body.moments, w0))
    return replace(plan, members=hi - lo, w0=w0, step_angle=angle,
                   chunk_members=min(plan.chunk_members, hi - lo))


#: Most steps a run can take: beyond 2^53 the times t = n h of its steps are no longer
#: distinct doubles. A step bound that asks for more means the spin is out of range.
MAX_STEPS = 2**53


def _step_angles(body, spec, w0, h, t_end, given) -> np.ndarray:
    """Each member's step angle ``h max|w|`` in rad; ValueError if all exceed the bound.

    ``given`` is what set the starts and what to change, ``("spin = 1e+30 rad/s", "a smaller
    spin")``, for the message when no step could do: the spin is then out of range, and the
    step it would need is no advice.
    """
    angle = h * max_angular_speed(body.moments, w0)
    bound = spec.max_step_angle
    if bound is not None and angle.size and not np.any(angle <= bound):
        smallest = float(np.nanmin(angle)) if not np.isnan(angle).all() else math.inf
        if not smallest * t_end / (h * bound) <= MAX_STEPS:  # inf or nan included
            moments = ", ".join(f"{I:.3g}" for I in body.moments)
            raise ValueError(
                f"{given[0]} is out of range: {spec.name} needs h max|w| <= {bound:g} rad, so "
                f"more than 2^53 steps (the most a run can count) to t_end = {t_end:g} s; use "
                f"{given[1]}" + ("" if np.isfinite(angle).any() else
                                  f", or moments closer together than ({moments}) kg m^2")
            )
        raise ValueError(
            f"h = {h:g} s is too large for {spec.name} at these spins: every member would turn "
            f"by {smallest:.3g} rad or more per step (h max|w|), above the {bound:g} rad up to "
            f"which {spec.name}'s results can be trusted; choose h <= {h * bound / smallest:.3g} s"
        )
    return angle


def _dataset(plan: _Plan, run, threads):
    """The Dataset of one ensemble from its plan and its run."""
    body, spec, a, h = plan.body, plan.spec, plan.a, plan.h
    spin, epsilon, start_kind, direction = plan.spin, plan.epsilon, plan.start_kind, plan.direction
    ss, t_end, save_every, levels = plan.ss, plan.t_end, plan.save_every, plan.levels
    n_members, n_steps = plan.w0.shape[0], plan.n_steps
    summaries_only, divergence_tolerance = plan.summaries_only, plan.tolerance
    layer = threading_layer()
    used_threads = numba.get_num_threads()
    resolved = dict(plan.resolved, threads=threads)
    command = plan.command
    if command is None:
        command = _call_repr(body, resolved)
    title = (
        f"{run.members}-member ensemble: {body.name} {body.moments.tolist()} kg m2, "
        + (f"spin {spin:g} rad/s about axis {a + 1}, perturbation {epsilon:g} of the spin"
           if start_kind != "given" else f"given starts, spin axis {a + 1}")
        + f", {spec.name}, h = {h:g} s"
        + (" (partial: interrupted)" if run.interrupted else "")
    )
    attrs = provenance_attrs(title, body, spec, h, command)
    attrs.update(
        {
            "scene": plan.resolved["scene"],
            "axis": a + 1,
            "start_kind": start_kind,
            **({"spin": spin, "epsilon": epsilon} if start_kind != "given" else {}),
            **({"direction": direction} if direction is not None else {}),
            "members": run.members,
            "members_requested": n_members,
            "seed_entropy": str(ss.entropy),
            "seed_spawn_key": str(tuple(ss.spawn_key)),
            "seed_spawn_scheme": (
                f"member j uses child j // {RNG_CHUNK} of numpy.random.SeedSequence("
                "seed_entropy, spawn_key=seed_spawn_key) (SeedSequence.spawn), a "
                "numpy.random.Generator(PCG64) drawing the angles of its "
                f"{RNG_CHUNK} members in order from uniform(0, 2 pi)"
            ),
            "rng_chunk_members": RNG_CHUNK,
            "t_end": t_end,
            "save_every": save_every,
            "steps": n_steps,
            "steps_done": run.steps_done,
            "interrupted": int(run.interrupted),
            "time_series": int(not summaries_only),
            "summary_tracking": (
                "flips, crossings, the largest amplitude and level passages tracked at every "
                "step inside the member loop, times linearly interpolated within the step; "
                "the start counts (levels it reaches are passed at time 0)"
            ),
            "divergence_tolerance": divergence_tolerance,
            "numba_threading_layer": layer,
            "numba_num_threads": used_threads,
            "wall_time": run.wall_time,
            "compile_time": run.compile_time,
            "member_steps_per_second": (
                run.members * run.steps_done / run.wall_time if run.wall_time > 0 else 0.0
            ),
            "config_toml": plan.config_text if plan.config_text is not None else config_toml(
                {"run_ensemble": resolved}),
        }
    )
    ds = ensemble_dataset(
        run.w0, run.status, run.fail_time, run.summaries, levels, attrs,
        time=run.time, w=run.w,
    )
    if run.q is not None:
        norm = np.linalg.norm(run.q, axis=-1)
        q = run.q / norm[..., None]
        exact = exact_attitudes(body.moments, run.w0, run.time, IDENTITY)
        add_attitude(ds, q, norm - 1.0, attitude_error(q, exact))
    return ds


# --- the run ----------------------------------------------------------------------------------


@dataclass
class _Run:
    """Everything ``_run`` measured, for the members that completed."""

    members: int
    w0: np.ndarray
    status: np.ndarray
    fail_time: np.ndarray
    summaries: dict
    time: np.ndarray | None
    w: np.ndarray | None
    steps_done: int
    interrupted: bool
    wall_time: float
    compile_time: float
    q: np.ndarray | None = None  # (N, n_time, 4) carried attitudes, scene free_body_attitude


def _run(plans, progress) -> list:
    """Propagate the members of ``plans`` (one method), tracking their summaries.

    One plan runs in chunks of its ``chunk_members``; several plans run together, one group
    each, in one call of the member loop. If Ctrl-C stops a single plan's chunk, the result
    holds the chunks completed before it; if it stopped the first chunk, that chunk up to the
    steps it completed. A stopped batch keeps the steps every ensemble completed.
    """
    if len(plans) == 1:
        return [_run_chunked(plans[0], progress)]
    prop = _propagate_tracked(plans, progress, None)
    work = np.array([plan.w0.shape[0] * plan.n_steps for plan in plans], dtype=float)
    runs, lo = [], 0
    for g, plan in enumerate(plans):
        n = plan.w0.shape[0]
        steps = int(prop.steps_done[g])
        part = _Part(prop, slice(lo, lo + n), slice(0, n), steps, work[g] / work.sum())
        runs.append(_finish(plan, [part], n, steps, prop.interrupted and steps < plan.n_steps))
        lo += n
    return runs


@dataclass
class _Part:
    """Members ``rows`` of a propagation that are the plan's members ``mine``.

    ``share`` is the fraction of the propagation's time that counts for them (their share of
    the member-steps of a batch).
    """

    prop: object
    rows: slice
    mine: slice
    steps_done: int
    share: float = 1.0


def _run_chunked(plan, progress) -> _Run:
    """One plan, ``chunk_members`` members per call."""
    n = plan.w0.shape[0]
    parts = []
    steps_done, interrupted, done = plan.n_steps, False, 0
    for lo in range(0, n, plan.chunk_members):
        hi = min(lo + plan.chunk_members, n)
        prop = _propagate_tracked([plan], progress, slice(lo, hi))
        if prop.interrupted and lo > 0:  # keep the chunks that completed
            interrupted = True
            break
        parts.append(_Part(prop, slice(0, hi - lo), slice(lo, hi), int(prop.steps_done[0])))
        done = hi
        if prop.interrupted:  # the first chunk: keep the steps it completed
            interrupted, steps_done = True, int(prop.steps_done[0])
            break
    return _finish(plan, parts, done, steps_done, interrupted)


def _finish(plan, parts, done, steps_done, interrupted) -> _Run:
    """Status, summaries and time series of the plan's members ``0:done`` from ``parts``."""
    moments, h = plan.body.moments, plan.h
    w0 = plan.w0[:done]
    n_kept_time = steps_done // plan.save_every + 1
    w_all = None if plan.summaries_only else np.empty((done, n_kept_time, 3))
    q_all = np.empty((done, n_kept_time, 4)) if plan.attitude else None
    status = np.empty(done, dtype=np.int8)
    fail_time = np.empty(done)
    summaries = {}
    wall = compile_time = 0.0
    for part in parts:
        prop, rows, mine = part.prop, part.rows, part.mine
        wall += part.share * prop.wall_time
        compile_time += part.share * prop.compile_time
        chunk_status, chunk_fail, errors = _member_status(
            prop.status[rows], prop.fail_step[rows], prop.x_final[rows, :3], w0[mine], moments, h,
            plan.tolerance, part.steps_done, plan.step_angle[mine], plan.spec.max_step_angle,
        )
        chunk = _summaries({name: value[rows] for name, value in prop.extras.items()}, errors)
        bad = chunk_status != cv.STATUS_OK
        for value in chunk.values():
            value[bad] = np.nan
        for name, value in chunk.items():
            if len(parts) == 1:  # one part: no copy
                summaries[name] = value
                continue
            if name not in summaries:
                summaries[name] = np.empty((done,) + value.shape[1:])
            summaries[name][mine] = value
        if w_all is not None:
            w = w_all[mine]
            w[:, 0] = w0[mine]
            np.divide(prop.saved[rows, : n_kept_time - 1, :3], moments, out=w[:, 1:])
            w[bad] = np.nan
        if q_all is not None:
            q = q_all[mine]
            q[:, 0] = IDENTITY
            q[:, 1:] = prop.saved[rows, : n_kept_time - 1, 3:]
            q[bad] = np.nan
        status[mine] = chunk_status
        fail_time[mine] = chunk_fail
    return _Run(
        members=done,
        w0=w0,
        status=status,
        fail_time=fail_time,
        summaries=summaries,
        time=None if plan.summaries_only else np.arange(n_kept_time) * plan.save_every * h,
        w=w_all,
        q=q_all,
        steps_done=steps_done,
        interrupted=interrupted,
        wall_time=wall,
        compile_time=compile_time,
    )


def _propagate_tracked(plans, progress, rows):
    """One call of the member loop over ``plans`` (members ``rows`` of a single plan)."""
    starts = [plan.w0 if rows is None else plan.w0[rows] for plan in plans]
    first = plans[0]
    gpu = {}
    if first.device == "gpu":
        from ..engine.gpu import propagate_groups_gpu  # numba-cuda: an optional dependency

        gpu = {"propagator": propagate_groups_gpu}
    return propagate_many(
        first.spec, [plan.body.moments for plan in plans],
        np.concatenate([w * plan.body.moments for w, plan in zip(starts, plans)]),
        [w.shape[0] for w in starts], [plan.h for plan in plans],
        [plan.n_steps for plan in plans], 0 if first.summaries_only else first.save_every,
        progress, first.chunk_steps if len(plans) == 1 else None,
        track_axes=[plan.a for plan in plans], levels=[plan.levels for plan in plans],
        q0=np.tile(IDENTITY, (sum(w.shape[0] for w in starts), 1)) if first.attitude else None,
        partial=True,  # Ctrl-C: the chunks done are kept, the Dataset marked interrupted
        **gpu,
    )


def _member_status(loop_status, fail_step, m, w0, moments, h, tolerance, steps_done,
                   step_angle=None, max_step_angle=None):
    """Per-member status, failure time and end-of-run invariant errors.

    The loop reports non-finite states and solver failures; here members whose relative
    energy or |L| error at the end exceeds ``tolerance`` become ``STATUS_DIVERGED``, and
    members that are still ok but whose ``step_angle`` exceeds ``max_step_angle`` become
    ``STATUS_STEP_TOO_LARGE`` (failure time 0: it is known from the start). The invariants
    alone cannot tell: a Lie-Poisson splitting keeps |L| exactly and its energy bounded at
    any step, with w wrong by O(1).
    """
    m0 = w0 * moments
    energy0 = 0.5 * np.sum(m0 * w0, axis=1)  # E = w . I w / 2
    energy = 0.5 * np.sum(m * m / moments, axis=1)
    momentum0 = np.linalg.norm(m0, axis=1)
    momentum = np.linalg.norm(m, axis=1)
    with np.errstate(invalid="ignore", over="ignore"):
        energy_error = (energy - energy0) / energy0
        momentum_error = (momentum - momentum0) / momentum0
        worst = np.maximum(np.abs(energy_error), np.abs(momentum_error))
    status = loop_status.copy()
    fail_time = np.where(status != cv.STATUS_OK, fail_step * h, np.nan)
    # "not (worst <= tolerance)" also catches a NaN error the driver did not see.
    diverged = (status == cv.STATUS_OK) & ~(worst <= tolerance)
    status[diverged] = cv.STATUS_DIVERGED
    fail_time[diverged] = steps_done * h
    if step_angle is not None and max_step_angle is not None:
        too_large = (status == cv.STATUS_OK) & ~(step_angle <= max_step_angle)
        status[too_large] = cv.STATUS_STEP_TOO_LARGE
        fail_time[too_large] = 0.0
    return status, fail_time, {
        "energy_error": energy_error, "angular_momentum_error": momentum_error,
    }


def _summaries(track: dict, errors: dict) -> dict:
    """The Dataset's summary variables from the tracked events and the invariant errors."""
    count = track["axis_crossings"].astype(float)
    first = track["first_axis_crossing"]
    last = track["last_axis_crossing"]
    with np.errstate(invalid="ignore", divide="ignore"):
        interval = np.where(count >= 2, (last - first) / (count - 1.0), np.nan)
    return {
        "flip_count": count,
        "first_flip_time": np.array(first, dtype=float),
        "last_flip_time": np.array(last, dtype=float),
        "mean_flip_interval": interval,
        "perp_crossing_count": track["perp_crossings"].astype(float),
        "first_perp_crossing": np.array(track["first_perp_crossing"], dtype=float),
        "last_perp_crossing": np.array(track["last_perp_crossing"], dtype=float),
        "max_perp_amplitude": np.array(track["max_perp_amplitude"], dtype=float),
        "passage_time": np.array(track["passage_time"], dtype=float),
        "energy_error": np.array(errors["energy_error"], dtype=float),
        "angular_momentum_error": np.array(errors["angular_momentum_error"], dtype=float),
    }


# --- input helpers ----------------------------------------------------------------------------


def _axis_index(axis) -> int:
    """Principal axis 1, 2 or 3 as a 0-based index, else ValueError."""
    if isinstance(axis, bool) or not isinstance(axis, numbers.Integral) or axis not in (1, 2, 3):
        raise ValueError(f"axis must be the principal axis 1, 2 or 3, got {axis!r}")
    return int(axis) - 1


def _nonnegative_float(name, value) -> float:
    x = real_number(name, value)
    if not math.isfinite(x) or x < 0.0:
        raise ValueError(f"{name} must be finite and >= 0, got {value!r}")
    return x


def _perpendicular_direction(direction, a) -> np.ndarray:
    """``direction`` as a unit vector; ValueError unless it is perpendicular to axis a."""
    d = vectors3("direction", direction)
    if d.ndim != 1:
        raise ValueError(f"direction must have shape (3,), got {d.shape}")
    norm = float(np.linalg.norm(d))
    if norm == 0.0:
        raise ValueError("direction must be a nonzero vector perpendicular to the spin axis")
    if abs(d[a]) > 1e-12 * norm:
        raise ValueError(
            f"direction {d.tolist()} is not perpendicular to axis {a + 1}: its component "
            f"along that axis is {d[a]!r}; set it to 0"
        )
    d = d.copy()
    d[a] = 0.0
    return d / norm


def _levels(levels, spin_ref) -> np.ndarray:
    """Validated ascending amplitude levels in rad/s (default: DEFAULT_LEVELS x spin)."""
    if levels is None:
        return DEFAULT_LEVELS * spin_ref
    x = real_array("levels", levels, "rad/s")
    if x.ndim != 1 or x.size < 1:
        raise ValueError(f"levels must be a 1-D list of amplitudes in rad/s, got {levels!r}")
    if not np.all(np.isfinite(x)) or np.any(x <= 0.0) or np.any(np.diff(x) <= 0.0):
        raise ValueError(f"levels must be finite, > 0 and strictly ascending, got {levels!r}")
    return x


def _call_repr(body, resolved) -> str:
    """The call that made the Dataset, for its first ``history`` line."""
    keys = ("axis", "spin", "epsilon", "members", "seed", "method", "h", "t_end", "save_every",
            "summaries_only")
    args = ", ".join(f"{k}={resolved[k]!r}" for k in keys if resolved[k] is not None)
    if resolved["start_kind"] == "given":
        args += ", starts=<given>"
    if resolved["direction"] is not None:
        args += f", direction={list(resolved['direction'])}"
    return f"stability.run_ensemble({body!r}, {args})"
