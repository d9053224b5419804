"""From a propagation of an ensemble's members to their Dataset: status, summaries and
time series per member (:func:`finish_run`), then the labelled Dataset
(:func:`members_dataset`)."""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from ..core.body import canonical_m_to_w
from ..core.quaternions import IDENTITY, attitude_error
from .exact_attitude import exact_attitudes
from ..output.dataset import (
    add_attitude, config_toml, ensemble_dataset, provenance_attrs, threading_layer,
)
from ..util import conventions as cv
from .ensemble_plan import EnsemblePlan
from ..ensemble.starts import RNG_CHUNK

def members_dataset(plan: EnsemblePlan, run, threads):
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
        add_attitude(ds, *carried_attitude(body.moments, run.w0, run.time, run.q))
    return ds


def carried_attitude(moments, w0, time, q):
    """The attitudes ``q`` (N, T, 4) an ensemble carried, normalised; their norm error
    ``|q| - 1``; and their angle from the exact attitude of each start ``w0`` (N, 3) at
    ``time`` (T,) from the identity (:func:`~stability.core.quaternions.attitude_error`)."""
    norm = np.linalg.norm(q, axis=-1)
    unit = q / norm[..., None]
    return unit, norm - 1.0, attitude_error(unit, exact_attitudes(moments, w0, time, IDENTITY))


@dataclass
class MemberRun:
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


@dataclass
class RunPart:
    """Members ``rows`` of a propagation that are the plan's members ``mine``.

    ``share`` is the fraction of the propagation's time that counts for them (their share of
    the member-steps of a batch).
    """

    prop: object
    rows: slice
    mine: slice
    steps_done: int
    share: float = 1.0
    #: ``(perm, signs)`` when the saved states are still in that canonical frame
    #: (:func:`stability.core.body.canonical_frame`): converted as they are copied into ``w``.
    frame: tuple | None = None


def finish_run(plan, parts, done, steps_done, interrupted) -> MemberRun:
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
            saved = prop.saved[rows, : n_kept_time - 1, :3]
            if part.frame is None:
                np.divide(saved, moments, out=w[:, 1:])
            else:  # one pass: from the canonical frame (from_canonical) and divided
                canonical_to_w(saved, part.frame, moments, w[:, 1:])
            w[bad] = np.nan
        if q_all is not None:
            q = q_all[mine]
            q[:, 0] = IDENTITY
            q[:, 1:] = prop.saved[rows, : n_kept_time - 1, 3:]
            q[bad] = np.nan
        status[mine] = chunk_status
        fail_time[mine] = chunk_fail
    return MemberRun(
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


def canonical_to_w(m, frame, moments, out) -> None:
    """Canonical angular momenta ``m`` (N, T, 3) in ``frame = (perm, signs)`` to body-frame w
    into ``out`` (N, T, 3), in one compiled pass (:func:`_canonical_to_w`)."""
    perm, signs = frame
    _canonical_to_w(m, np.asarray(perm, dtype=np.int64), np.asarray(signs, dtype=float),
                    np.asarray(moments, dtype=float), out)


@numba.njit(cache=True, parallel=True)
def _canonical_to_w(m, perm, signs, moments, out):
    """:func:`stability.core.body.canonical_m_to_w` of each member, members on Numba's
    threads."""
    for j in numba.prange(m.shape[0]):
        canonical_m_to_w(m[j], perm, signs, moments, out[j])


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


def _call_repr(body, resolved) -> str:
    """The call that made the Dataset, for its first ``history`` line."""
    keys = ("axis", "spin", "epsilon", "members", "seed", "method", "h", "t_end")
    args = ", ".join(f"{k}={resolved[k]!r}" for k in keys if resolved[k] is not None)
    if resolved["start_kind"] != "random_perpendicular":
        args += ", starts=<given>"
    every = 0 if resolved["summaries_only"] else resolved["save_every"]
    attitude = ", attitude=True" if resolved["scene"] == "free_body_attitude" else ""
    if every != 1 or attitude:
        args += f", keep=Keep(save_every={every}{attitude})"
    return f"stability.run_ensemble({body!r}, {args})"
