"""An ensemble's plan: :func:`stability.run_ensemble`'s arguments checked and resolved
(method, steps, levels, memory, chunks, starts) before anything is compiled or run."""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, replace

import numpy as np

from .attitude import FREE_BODY_SCENES, attitude_spec, carries_attitude
from ..core.body import RigidBody
from .keep import DEFAULT_DIVERGENCE_TOLERANCE
from .methods import method_spec
from ..ensemble.memory import DEFAULT_MAX_MEMORY, limit_words, machine_memory
from ..output.dataset import config_toml, summary_bytes
from ..util.checks import positive_float, positive_int, real_array, step_count, vectors3
from ..util.formatting import format_bytes
from ..ensemble.starts import (
    RNG_CHUNK, axis_index, nonnegative_float, perpendicular_direction, perturbed_starts,
    random_starts, seed_sequence,
)
from .timescales import max_angular_speed

__all__ = ["ensemble_memory"]

log = logging.getLogger(__name__)

#: Default members per chunk of a run streamed to disk (``RunOptions(store=...)``): a multiple of RNG_CHUNK.
STREAM_CHUNK_MEMBERS = 2**20


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


NO_STARTS = "starts has no rows: give one start w0 (3 numbers, rad/s) per member"
NO_SPIN = ("give spin, the spin rate in rad/s (epsilon and members have defaults), or "
            "starts=, the initial angular velocities")


@dataclass
class EnsemblePlan:
    """One validated ensemble: everything :func:`run_ensemble` resolved before running."""

    body: RigidBody
    spec: object
    a: int
    members: int
    w0: np.ndarray | None  # None: drawn per chunk (chunk_plan)
    h: float
    t_end: float
    n_steps: int
    save_every: int
    summaries_only: bool
    levels: np.ndarray
    tolerance: float
    step_angle: np.ndarray | None  # None: worked out per chunk (chunk_plan)
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
    nbytes: int = 0  # of the whole ensemble's Dataset (ensemble_memory)


def plan_ensemble(body, axis, spin=None, epsilon=None, members=None, *, h, t_end, seed=0,
                  method="lp2", save_every=1, direction=None, starts=None, summaries_only=False,
                  levels=None, divergence_tolerance=DEFAULT_DIVERGENCE_TOLERANCE,
                  max_memory=DEFAULT_MAX_MEMORY, chunk_members=None, chunk_steps=None,
                  config=None, command=None, device="cpu", defer_starts=False,
                  scene="free_body", held=0) -> EnsemblePlan:
    """Validate the arguments of :func:`run_ensemble` and draw the starts; ValueError if bad.

    With ``defer_starts`` random starts are not drawn: :func:`chunk_plan` draws each chunk's.
    ``held``: bytes that the ensembles before this one in a batch hold
    (:func:`stability.run_ensembles`), counted with it against ``max_memory``. The memory is
    checked before any start is drawn, against ``max_memory`` or the machine's
    memory where that is less.
    """
    if not isinstance(body, RigidBody):
        raise ValueError(f"body must be a stability.RigidBody, got {type(body).__name__}")
    a = axis_index(axis)
    spec = method_spec(method)
    if device not in ("cpu", "gpu"):
        raise ValueError(f"device must be 'cpu' or 'gpu', got {device!r}")
    if device == "gpu":
        from ..engine.gpu import NoGPUError, cuda_module, gpu_method

        gpu_method(spec.name, FREE_BODY_SCENES[scene])  # ValueError naming the GPU's methods
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
                "starts= gives the initial angular velocities itself; leave spin and "
                "epsilon out (None) when you pass it"
            )
        w0 = vectors3("starts", starts, "rad/s")
        if w0.ndim != 2:
            raise ValueError(f"starts must have shape (members, 3), got {w0.shape}")
        if w0.shape[0] == 0:
            raise ValueError(NO_STARTS)
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
            raise ValueError(NO_SPIN if spin is None else "give spin, epsilon and members "
                             "(or starts=)")
        spin = positive_float("spin", spin, "rad/s")
        epsilon = nonnegative_float("epsilon", epsilon)
        members = positive_int("members", members)
        if direction is not None:
            direction = perpendicular_direction(direction, a)
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
    members_held = chunk_members if defer_starts else n_members
    stored = ensemble_memory(members_held, 0 if summaries_only else n_saved, levels.size,
                             scene=scene)
    limit = min(max_memory, machine_memory() or max_memory)
    beside = (f", with the {format_bytes(held)} of the ensembles before it in the batch"
              if held else "")
    more = ", or raise max_memory" if limit == max_memory else ""
    if not summaries_only and stored + held > limit:
        raise ValueError(
            f"the time series of {members_held} members x {n_time} samples x "
            f"{9 if attitude else 3} doubles would "
            f"take {format_bytes(stored)} (about {PEAK_COPIES}x that while the run builds it)"
            f"{beside}, above {limit_words(max_memory)}; raise save_every, use fewer "
            f"members, keep the per-member summaries only (Keep(save_every=0)){more}"
        )
    if summaries_only and stored + held > limit:
        raise ValueError(
            f"the summaries of {members_held} members would take {format_bytes(stored)} "
            f"({format_bytes(stored / members_held)} a member){beside}, above "
            f"{limit_words(max_memory)}; use fewer members, stream the run to disk "
            f"(RunOptions(store=...), a chunk at a time in memory){more}"
        )
    chunk_members = min(chunk_members or n_members, n_members)
    level = logging.WARNING if stored > LARGE_RUN_BYTES else logging.INFO
    log.log(
        level,
        "run_ensemble: %d members x %d steps of %s (%.3g member-steps); Dataset %s "
        "(%s per member)%s",
        n_members, n_steps, spec.name, float(n_members) * n_steps, format_bytes(stored),
        format_bytes(stored / members_held),
        "" if summaries_only else f", about {PEAK_COPIES}x that at the peak",
    )

    # --- starts -----------------------------------------------------------------------------
    if w0 is None and (direction is not None or not defer_starts):
        w0 = perturbed_starts(axis, spin, epsilon, members, ss, direction)
    given = _given(w0 if starts is not None else None, spin, epsilon)
    if w0 is not None:
        step_angle = _step_angles(body, spec, w0, h, t_end, given)
    else:  # drawn per chunk; refuse up front if the first block of starts is hopeless
        _step_angles(body, spec, random_starts(a, spin, epsilon, ss, 0,
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
    return EnsemblePlan(
        body=body, spec=spec, a=a, members=n_members, w0=w0, h=h, t_end=t_end, n_steps=n_steps,
        save_every=save_every, summaries_only=bool(summaries_only), levels=levels,
        tolerance=divergence_tolerance, step_angle=step_angle, chunk_members=chunk_members,
        chunk_steps=chunk_steps,
        resolved=resolved, start_kind=start_kind, spin=spin, epsilon=epsilon,
        direction=direction, ss=ss, config_text=config_text, command=command, device=device,
        attitude=bool(attitude), nbytes=stored,
    )


def chunk_plan(plan: EnsemblePlan, lo: int, hi: int) -> EnsemblePlan:
    """The plan of members ``lo ... hi - 1`` of ``plan`` alone (a chunk of a streamed run)."""
    if plan.w0 is not None:
        w0 = plan.w0[lo:hi]
    else:
        w0 = random_starts(plan.a, plan.spin, plan.epsilon, plan.ss, lo, hi)
    angle = (plan.step_angle[lo:hi] if plan.step_angle is not None
             else plan.h * max_angular_speed(plan.body.moments, w0))
    return replace(plan, members=hi - lo, w0=w0, step_angle=angle,
                   chunk_members=min(plan.chunk_members, hi - lo))


#: Most steps a run can take: beyond 2^53 the times t = n h of its steps are no longer
#: distinct doubles. A step bound that asks for more means the spin is out of range.
MAX_STEPS = 2**53


class OutOfRange(ValueError):
    """Starts that no step can follow to ``t_end``, or a step too large for every start:
    ``argument`` (``"spin"``, ``"epsilon"``, ``"starts"`` or ``"h"``) is out of range;
    ``reason`` says why, without the value."""

    def __init__(self, message: str, argument: str, reason: str):
        super().__init__(message)
        self.argument = argument
        self.reason = reason


def check_random_starts(body, axis, spin, epsilon, members, *, h, t_end, seed=0,
                        method="lp2") -> None:
    """Refuse, as :func:`plan_ensemble` does, random starts that no step of ``method`` can
    follow to ``t_end`` (:class:`OutOfRange`), for values already checked one by one (a study
    file's), drawing only the first block of starts."""
    a = axis_index(axis)
    starts = random_starts(a, spin, epsilon, seed_sequence(seed), 0, min(members, RNG_CHUNK))
    _step_angles(body, method_spec(method), starts, h, t_end, _given(None, spin, epsilon))


def _given(starts, spin, epsilon) -> tuple[str, str, str]:
    """What set the starts, what to change and the argument that is at fault, for the message
    of :func:`_step_angles` (``starts`` given, or None for random ones)."""
    if starts is not None:
        return f"starts of up to {np.abs(starts).max():.3g} rad/s", "smaller starts", "starts"
    if epsilon <= 1:
        return f"spin = {spin:.3g} rad/s", "a smaller spin", "spin"
    return (f"epsilon = {epsilon:.3g} (of spin = {spin:.3g} rad/s)", "a smaller epsilon",
            "epsilon")


def _step_angles(body, spec, w0, h, t_end, given) -> np.ndarray:
    """Each member's step angle ``h max|w|`` in rad; ValueError if all exceed the bound.

    ``given`` is what set the starts, what to change and the argument (:func:`_given`), for the
    message when no step could do: that argument is then out of range (:class:`OutOfRange`),
    and the step it would need is no advice.
    """
    angle = h * max_angular_speed(body.moments, w0)
    bound = spec.max_step_angle
    if bound is not None and angle.size and not np.any(angle <= bound):
        smallest = float(np.nanmin(angle)) if not np.isnan(angle).all() else math.inf
        if not smallest * t_end / (h * bound) <= MAX_STEPS:  # inf or nan included
            moments = ", ".join(f"{I:.3g}" for I in body.moments)
            reason = (f"{spec.name} needs h max|w| <= {bound:g} rad, so more than 2^53 steps "
                      f"(the most a run can count) to t_end = {t_end:g} s")
            raise OutOfRange(
                f"{given[0]} is out of range: {reason}; use {given[1]}"
                + ("" if np.isfinite(angle).any() else
                   f", or moments closer together than ({moments}) kg m^2"), given[2], reason)
        reason = (f"too large for {spec.name} at these spins: every member would turn by "
                  f"{smallest:.3g} rad or more per step (h max|w|), above the {bound:g} rad up "
                  f"to which {spec.name}'s results can be trusted; choose h <= "
                  f"{h * bound / smallest:.3g} s")
        raise OutOfRange(f"h = {h:g} s is {reason}", "h", reason)
    return angle


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
