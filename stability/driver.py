"""The one loop that repeats a step, for every integrator and every ensemble.

Layout of the hot path (``member_loop``): members are split into blocks of ``BLOCK``; blocks run
in parallel (``prange``); inside a block the time loop is outside and the loop over the block's
members is innermost, so the inlined step kernel vectorizes across members. The state is the body
angular momentum m in the canonical frame, advanced by the step's increment with Kahan
compensated summation (Hairer, Lubich & Wanner, GNI, VIII.5), so round-off does not accumulate
linearly over long runs. Kernels never raise: a member whose state stops being finite, or whose
implicit solve fails, gets a status code and the index of the step where it happened.

Optionally the loop *tracks* each member without storing its time series (summaries-only runs):
sign changes of the spin-axis component (flips) and of one perpendicular component
(oscillations), the largest perpendicular amplitude, and the first time the perpendicular
amplitude reaches each of a ladder of levels (growth rates).

``propagate`` is the Python side: it converts to the canonical frame, runs the loop in chunks
(progress bar, Ctrl-C ends the run cleanly after the chunk in flight and returns what was done),
and converts back.
"""

from __future__ import annotations

import contextlib
import functools
import signal
import threading
import time
from dataclasses import dataclass, field

import numpy as np
from numba import njit, prange

from .body import canonical_frame, from_canonical, to_canonical
from .conventions import STATUS_OK
from .integrators import method_spec
from .integrators.spec import P_INV1

#: Members per block: the vector loop's trip count (a multiple of the SIMD width).
BLOCK = 64
#: Steps between finiteness checks (a check every step costs RK4 ~20% of its speed). Inf and
#: NaN are absorbing, so a failure is caught at the next check: ``fail_step`` is the step
#: count at the first check that found the state non-finite, at most CHECK_EVERY - 1 steps late;
#: ``untrusted`` says which samples to mask.
CHECK_EVERY = 8

# Columns of the per-member tracking state (float64, carried between chunked calls).
T_PREV_A = 0  #: spin-axis component w_a at the previous step (rad/s)
T_PREV_B = 1  #: first perpendicular component w_b at the previous step
T_PREV_AMP = 2  #: perpendicular amplitude sqrt(w_b^2 + w_c^2) at the previous step
T_COUNT_A = 3  #: sign changes of w_a so far (flips)
T_FIRST_A = 4  #: time of the first sign change of w_a (s), NaN before
T_LAST_A = 5  #: time of the latest sign change of w_a (s)
T_COUNT_B = 6  #: sign changes of w_b
T_FIRST_B = 7
T_LAST_B = 8
T_MAX_AMP = 9  #: largest perpendicular amplitude so far
T_NEXT_LEVEL = 10  #: index of the next amplitude level to reach
N_TRACK = 11


@njit(inline="always")
def _kahan_add(x, c, j, d):
    """x[j] += d with the running compensation c[j] (Kahan 1965)."""
    y = d - c[j]
    t = x[j] + y
    c[j] = (t - x[j]) - y
    x[j] = t


@njit(inline="always")
def _commit(x1, x2, x3, c1, c2, c3, j, e1, e2, e3):
    """Add one step's increment to member j."""
    _kahan_add(x1, c1, j, e1)
    _kahan_add(x2, c2, j, e2)
    _kahan_add(x3, c3, j, e3)


@njit(inline="always")
def _check_finite(x1, x2, x3, j, n, bad, first_bad):
    """Note the first checked step at which member j is no longer finite (inf/NaN absorb)."""
    total = x1[j] + x2[j] + x3[j]
    now_bad = 1 if total - total != 0.0 else 0
    first_bad[j] = n if (now_bad == 1 and bad[j] == 0) else first_bad[j]
    bad[j] |= now_bad


@njit(inline="always")
def _component(x1, x2, x3, j, index):
    return x1[j] if index == 0 else (x2[j] if index == 1 else x3[j])


@njit(inline="always")
def _crossing(tr, j, col_prev, col_count, col_first, col_last, v, t_prev, h):
    """Record a sign change of v since the previous step (time by linear interpolation).

    Branch-free (selects only), so the tracking pass vectorizes across members; ``tr`` is the
    block's (N_TRACK, BLOCK) tracking state.
    """
    prev = tr[col_prev, j]
    crossed = (prev >= 0.0) != (v >= 0.0)
    t_cross = t_prev + h * prev / (prev - v)  # only used where crossed, so prev != v
    count = tr[col_count, j] + (1.0 if crossed else 0.0)
    tr[col_first, j] = t_cross if (crossed and count == 1.0) else tr[col_first, j]
    tr[col_last, j] = t_cross if crossed else tr[col_last, j]
    tr[col_count, j] = count
    tr[col_prev, j] = v


@functools.cache
def member_loop(step, staged=False):
    """Compile (once per process) the ensemble loop around the stage kernel ``step``.

    ``staged`` selects, at compile time, the loop for methods of several stages (increments
    summed per step) or the direct one for single-stage methods, so each kernel is inlined once.

    The returned function advances ``m`` (N, 3) in place by ``n_steps`` steps of size ``h``::

        advance(m, comp, p, h, n_stages, n_steps, save_every, saved, k0, status, fail_step,
                iterations, step0, axes, track, levels, passage)

    ``comp`` (N, 3) carries the Kahan compensation between calls; ``saved[:, k0 + k]`` receives
    the state after step ``(k + 1) * save_every`` of this call (``save_every = 0`` saves
    nothing); ``status`` (N,) int8, ``fail_step`` (N,) int64 and ``iterations`` (N,) int64
    are updated in place; ``step0`` is the global index of the first step. Tracking is on when
    ``axes[0] >= 0``: ``axes`` holds the canonical indices of the spin axis, the first and the
    second perpendicular axis; ``track`` (N, N_TRACK) and ``passage`` (N, len(levels)) are
    updated in place (passage times of the perpendicular amplitude through ``levels``).
    """

    @njit(parallel=True, error_model="numpy")
    def advance(
        m, comp, p, h, n_stages, n_steps, save_every, saved, k0, status, fail_step, iterations,
        step0, axes, track, levels, passage,
    ):
        n_members = m.shape[0]
        n_blocks = (n_members + BLOCK - 1) // BLOCK
        tracking = axes[0] >= 0
        ia, ib, ic = max(axes[0], 0), max(axes[1], 0), max(axes[2], 0)
        inv_a, inv_b, inv_c = p[P_INV1 + ia], p[P_INV1 + ib], p[P_INV1 + ic]
        n_levels = levels.shape[0]
        padded = np.full(n_levels + 1, np.inf)  # the sentinel keeps the gather in bounds
        padded[:n_levels] = levels
        for b in prange(n_blocks):
            lo = b * BLOCK
            size = min(BLOCK, n_members - lo)
            x1 = np.empty(BLOCK)
            x2 = np.empty(BLOCK)
            x3 = np.empty(BLOCK)
            c1 = np.empty(BLOCK)
            c2 = np.empty(BLOCK)
            c3 = np.empty(BLOCK)
            d1 = np.zeros(BLOCK)
            d2 = np.zeros(BLOCK)
            d3 = np.zeros(BLOCK)
            bad = np.zeros(BLOCK, dtype=np.int64)
            nonconv = np.zeros(BLOCK, dtype=np.int64)
            first_bad = np.full(BLOCK, -1, dtype=np.int64)
            first_nonconv = np.full(BLOCK, -1, dtype=np.int64)
            iters = np.zeros(BLOCK, dtype=np.int64)
            tr = np.zeros((N_TRACK, BLOCK))
            hit = np.zeros(BLOCK, dtype=np.int64)
            amp_now = np.zeros(BLOCK)
            if tracking:
                for col in range(N_TRACK):
                    for j in range(size):
                        tr[col, j] = track[lo + j, col]
            for j in range(size):
                x1[j] = m[lo + j, 0]
                x2[j] = m[lo + j, 1]
                x3[j] = m[lo + j, 2]
                c1[j] = comp[lo + j, 0]
                c2[j] = comp[lo + j, 1]
                c3[j] = comp[lo + j, 2]
            k = k0
            for n in range(n_steps):
                if not staged:  # a compile-time constant: Numba prunes the other branch
                    for j in range(size):
                        e1, e2, e3, it = step(x1[j], x2[j], x3[j], h, p, 0)
                        _commit(x1, x2, x3, c1, c2, c3, j, e1, e2, e3)
                        iters[j] += it if it > 0 else 0
                        first_nonconv[j] = n if (it < 0 and nonconv[j] == 0) else first_nonconv[j]
                        nonconv[j] |= 1 if it < 0 else 0
                else:
                    for j in range(size):
                        d1[j] = 0.0
                        d2[j] = 0.0
                        d3[j] = 0.0
                    for s in range(n_stages):
                        for j in range(size):
                            e1, e2, e3, it = step(
                                x1[j] + d1[j], x2[j] + d2[j], x3[j] + d3[j], h, p, s
                            )
                            d1[j] += e1
                            d2[j] += e2
                            d3[j] += e3
                            iters[j] += it if it > 0 else 0
                            first_nonconv[j] = (
                                n if (it < 0 and nonconv[j] == 0) else first_nonconv[j]
                            )
                            nonconv[j] |= 1 if it < 0 else 0
                    for j in range(size):
                        _commit(x1, x2, x3, c1, c2, c3, j, d1[j], d2[j], d3[j])
                if (n + 1) % CHECK_EVERY == 0 or n == n_steps - 1:
                    for j in range(size):
                        _check_finite(x1, x2, x3, j, n, bad, first_bad)
                if tracking:
                    t_prev = (step0 + n) * h
                    for j in range(size):
                        va = _component(x1, x2, x3, j, ia) * inv_a
                        vb = _component(x1, x2, x3, j, ib) * inv_b
                        vc = _component(x1, x2, x3, j, ic) * inv_c
                        _crossing(tr, j, T_PREV_A, T_COUNT_A, T_FIRST_A, T_LAST_A, va, t_prev, h)
                        _crossing(tr, j, T_PREV_B, T_COUNT_B, T_FIRST_B, T_LAST_B, vb, t_prev, h)
                        amp = np.sqrt(vb * vb + vc * vc)
                        tr[T_MAX_AMP, j] = max(tr[T_MAX_AMP, j], amp)
                        target = padded[int(tr[T_NEXT_LEVEL, j])]  # +inf past the last level
                        hit[j] = 1 if amp >= target else 0
                        amp_now[j] = amp
                    for j in range(size):
                        level = int(tr[T_NEXT_LEVEL, j])
                        while hit[j] == 1 and level < n_levels and amp_now[j] >= padded[level]:
                            # Interpolate ln(amplitude), which is linear in t during exponential
                            # growth (linear interpolation of the amplitude biases rates by
                            # ~(h lambda)^2 / 8); clamped to this step's interval.
                            prev_amp = tr[T_PREV_AMP, j]
                            if prev_amp > 0.0 and amp_now[j] > prev_amp:
                                frac = np.log(padded[level] / prev_amp) / np.log(
                                    amp_now[j] / prev_amp
                                )
                            else:
                                frac = (padded[level] - prev_amp) / (amp_now[j] - prev_amp)
                            passage[lo + j, level] = t_prev + h * min(max(frac, 0.0), 1.0)
                            level += 1
                        tr[T_NEXT_LEVEL, j] = level
                    for j in range(size):
                        tr[T_PREV_AMP, j] = amp_now[j]
                if save_every > 0 and (n + 1) % save_every == 0:
                    for j in range(size):
                        saved[lo + j, k, 0] = x1[j]
                        saved[lo + j, k, 1] = x2[j]
                        saved[lo + j, k, 2] = x3[j]
                    k += 1
            for j in range(size):
                m[lo + j, 0] = x1[j]
                m[lo + j, 1] = x2[j]
                m[lo + j, 2] = x3[j]
                comp[lo + j, 0] = c1[j]
                comp[lo + j, 1] = c2[j]
                comp[lo + j, 2] = c3[j]
                iterations[lo + j] += iters[j]
                if tracking:
                    for col in range(N_TRACK):
                        track[lo + j, col] = tr[col, j]
                if bad[j] != 0 and status[lo + j] == 0:
                    status[lo + j] = 1  # STATUS_NONFINITE
                    fail_step[lo + j] = step0 + first_bad[j] + 1
                elif nonconv[j] != 0 and status[lo + j] == 0:
                    status[lo + j] = 3  # STATUS_NOT_CONVERGED
                    fail_step[lo + j] = step0 + first_nonconv[j] + 1

    return advance


@dataclass
class Propagation:
    """What ``propagate`` returns; all vectors in the *body* frame, m = I w in kg m^2 s^-1.

    Attributes
    ----------
    m_final : ndarray, shape (N, 3)
        Body angular momentum after the last completed step.
    saved : ndarray, shape (N, n_saved, 3)
        Body angular momentum after steps ``save_every, 2 save_every, ...`` (initial excluded).
    status, fail_step, iterations : ndarray, shape (N,)
        Per-member status code (``stability.conventions``), the step count at which the failure
        was detected (-1 if none; see ``untrusted``), and the nonlinear-solver iterations used.
    steps_done : int
        Steps completed (fewer than asked if the run was interrupted).
    interrupted : bool
        True if Ctrl-C ended the run early.
    wall_time : float
        Seconds spent in the loop, compilation excluded.
    compile_time : float
        Seconds spent compiling (first use of a method in the process).
    extras : dict of ndarray
        Tracking results when ``track_axis`` was given (see :func:`propagate`).
    """

    m_final: np.ndarray
    saved: np.ndarray
    status: np.ndarray
    fail_step: np.ndarray
    iterations: np.ndarray
    steps_done: int
    interrupted: bool = False
    wall_time: float = 0.0
    compile_time: float = 0.0
    extras: dict = field(default_factory=dict)


def untrusted(steps, fail_step):
    """Mask of samples that may be past a failure.

    Parameters
    ----------
    steps : ndarray of int, shape (n,)
        Step count of each sample (0 for the initial state).
    fail_step : ndarray of int, shape (N,)
        ``Propagation.fail_step``.

    Returns
    -------
    ndarray of bool, shape (N, n)
        True where the sample must be masked: at or after the last check that could have
        missed the failure (``CHECK_EVERY`` steps before its detection).
    """
    fail = np.asarray(fail_step)[:, None]
    return (fail >= 0) & (np.asarray(steps)[None, :] > fail - CHECK_EVERY)


_NO_AXES = np.full(3, -1, dtype=np.int64)
_NO_LEVELS = np.zeros(0)


def _compiled(advance, p):
    """Compile ``advance`` for the standard argument types; return the seconds it took."""
    t0 = time.perf_counter()
    if not advance.signatures:
        one = np.zeros((1, 3))
        advance(
            one.copy(), one.copy(), p, 0.0, 1, 0, 0, np.zeros((1, 0, 3)), 0, np.zeros(1, np.int8),
            np.full(1, -1, np.int64), np.zeros(1, np.int64), 0, _NO_AXES,
            np.zeros((1, N_TRACK)), _NO_LEVELS, np.zeros((1, 0)),
        )
    return time.perf_counter() - t0


def propagate(
    method, moments, m0, h, n_steps, save_every=0, progress=None, chunk_steps=None,
    track_axis=None, levels=None,
):
    """Advance an ensemble of body angular momenta with a registered method.

    Parameters
    ----------
    method : str or MethodSpec
        Registry name (see ``stability.METHODS``).
    moments : array_like, shape (3,)
        Principal moments (I1, I2, I3) in kg m^2, any order.
    m0 : array_like, shape (N, 3)
        Initial body angular momenta m = I w, body frame.
    h : float
        Step in s, > 0.
    n_steps : int
        Number of steps.
    save_every : int, default 0
        Store the state every ``save_every`` steps; 0 stores nothing but the final state.
    progress : bool or None
        Show a progress bar; ``None`` shows one when the run is expected to take > 2 s.
    chunk_steps : int, optional
        Steps per kernel call (rounded to a multiple of ``save_every``); by default chosen so a
        call takes about 0.25 s.
    track_axis : int, optional
        Body axis (0-based) of the spin; turns on tracking, returned in ``extras``:
        ``axis_crossings``, ``first_axis_crossing``, ``last_axis_crossing`` (sign changes of
        w_a: count, and times in s by linear interpolation, NaN if none); ``perp_crossings``,
        ``first_perp_crossing``, ``last_perp_crossing`` (the same for the first perpendicular
        component, the lowest body axis other than ``track_axis``); ``max_perp_amplitude``
        (rad/s, the start included); ``passage_time`` (N, len(levels)): first time
        sqrt(w_b^2 + w_c^2) reaches each level (0 for levels the start reaches, NaN if never).
    levels : array_like, optional
        Ascending perpendicular-amplitude levels in rad/s for ``passage_time``.

    Returns
    -------
    Propagation
    """
    spec = method_spec(method)
    moments = np.asarray(moments, dtype=float)
    perm, signs = canonical_frame(moments)
    p = spec.params(moments[perm], h)
    m = np.ascontiguousarray(to_canonical(np.atleast_2d(m0), perm, signs))
    n_members = m.shape[0]
    comp = np.zeros_like(m)
    status = np.full(n_members, STATUS_OK, dtype=np.int8)
    fail_step = np.full(n_members, -1, dtype=np.int64)
    iterations = np.zeros(n_members, dtype=np.int64)
    n_saved = n_steps // save_every if save_every > 0 else 0
    saved = np.empty((n_members, n_saved, 3))

    if track_axis is None:
        axes, track = _NO_AXES, np.zeros((0, N_TRACK))
        levels, passage = _NO_LEVELS, np.zeros((0, 0))
    else:
        axes, track, levels, passage = _tracking_state(
            m, moments[perm], perm, int(track_axis), levels
        )

    advance = member_loop(spec.step, spec.stages > 1)
    compile_time = _compiled(advance, p)

    def run_chunk(steps_this, done, k_saved):
        advance(
            m, comp, p, h, spec.stages, steps_this, save_every, saved, k_saved, status, fail_step,
            iterations, done, axes, track, levels, passage,
        )

    done, k_saved, wall, interrupted = run_in_chunks(
        run_chunk, n_steps, save_every, chunk_steps, progress, spec.name
    )

    extras = {} if track_axis is None else _tracking_results(track, passage)
    return Propagation(
        m_final=from_canonical(m, perm, signs),
        saved=from_canonical(saved[:, :k_saved], perm, signs),
        status=status,
        fail_step=fail_step,
        iterations=iterations,
        steps_done=done,
        interrupted=interrupted,
        wall_time=wall,
        compile_time=compile_time,
        extras=extras,
    )


def run_in_chunks(run_chunk, n_steps, save_every, chunk_steps, progress, label):
    """Call ``run_chunk(steps, done, k_saved)`` until ``n_steps`` steps are done.

    Chunks are whole numbers of save intervals; without ``chunk_steps`` the first call is short
    (64 steps) and calibrates chunks of about 0.25 s. A progress bar appears when the rest is
    expected to take more than 2 s (or when ``progress`` is True); Ctrl-C sets a flag that ends
    the run after the chunk in flight, so the state always matches the steps done.

    Returns
    -------
    done, k_saved : int
        Steps completed and samples saved.
    wall : float
        Seconds spent in ``run_chunk``.
    interrupted : bool
    """
    unit = save_every if save_every > 0 else 1
    done = 0
    k_saved = 0
    wall = 0.0
    bar = None
    chunk = chunk_steps
    with _deferred_interrupt() as interrupt:
        while done < n_steps and not interrupt.requested:
            wanted = 64 if chunk is None else int(chunk)
            this = min(n_steps - done, max(unit, (wanted // unit) * unit))
            t0 = time.perf_counter()
            run_chunk(this, done, k_saved)
            dt = time.perf_counter() - t0
            wall += dt
            done += this
            k_saved += this // save_every if save_every > 0 else 0
            if chunk_steps is None:
                rate = this / max(dt, 1e-9)
                chunk = max(unit, int(0.25 * rate))
                if bar is None and progress is not False:
                    if progress or (n_steps - done) / rate > 2.0:
                        bar = _progress_bar(n_steps, done, label)  # counts this chunk
                        continue
            if bar is not None:
                bar.update(this)
        interrupted = interrupt.requested
    if bar is not None:
        bar.close()
    return done, k_saved, wall, interrupted


def _tracking_state(m, canonical_moments, perm, track_axis, levels):
    """Canonical axis indices and initial tracking arrays for spin about body ``track_axis``."""
    if track_axis not in (0, 1, 2):
        raise ValueError(f"track_axis must be 0, 1 or 2 (a body axis), got {track_axis}")
    others = [a for a in (0, 1, 2) if a != track_axis]
    where = {int(body_axis): i for i, body_axis in enumerate(perm)}  # body axis -> canonical
    axes = np.array([where[track_axis], where[others[0]], where[others[1]]], dtype=np.int64)
    levels = _NO_LEVELS if levels is None else np.asarray(levels, dtype=float)
    if levels.ndim != 1 or np.any(np.diff(levels) <= 0) or np.any(~np.isfinite(levels)):
        raise ValueError("levels must be a 1-D array of finite, strictly ascending amplitudes")
    w = m / canonical_moments
    amplitude0 = np.hypot(w[:, axes[1]], w[:, axes[2]])
    track = np.zeros((m.shape[0], N_TRACK))
    track[:, T_PREV_A] = w[:, axes[0]]
    track[:, T_PREV_B] = w[:, axes[1]]
    track[:, T_PREV_AMP] = amplitude0
    track[:, T_MAX_AMP] = amplitude0
    for col in (T_FIRST_A, T_LAST_A, T_FIRST_B, T_LAST_B):
        track[:, col] = np.nan
    # Levels the start already reaches are passed at t = 0.
    passage = np.full((m.shape[0], levels.size), np.nan)
    reached = levels[None, :] <= amplitude0[:, None]
    passage[reached] = 0.0
    track[:, T_NEXT_LEVEL] = reached.sum(axis=1)
    return axes, track, np.ascontiguousarray(levels), passage


def _tracking_results(track, passage):
    return {
        "axis_crossings": track[:, T_COUNT_A].astype(np.int64),
        "first_axis_crossing": track[:, T_FIRST_A].copy(),
        "last_axis_crossing": track[:, T_LAST_A].copy(),
        "perp_crossings": track[:, T_COUNT_B].astype(np.int64),
        "first_perp_crossing": track[:, T_FIRST_B].copy(),
        "last_perp_crossing": track[:, T_LAST_B].copy(),
        "max_perp_amplitude": track[:, T_MAX_AMP].copy(),
        "passage_time": passage,
    }


class _Interrupt:
    requested = False


@contextlib.contextmanager
def _deferred_interrupt():
    """Turn Ctrl-C into a flag checked between chunks, so no half-finished chunk is lost."""
    flag = _Interrupt()
    if threading.current_thread() is not threading.main_thread():
        yield flag
        return

    def handler(signum, frame):
        flag.requested = True

    previous = signal.signal(signal.SIGINT, handler)
    try:
        yield flag
    finally:
        signal.signal(signal.SIGINT, previous)


def _progress_bar(total, initial, label):
    from tqdm.auto import tqdm

    return tqdm(total=total, initial=initial, unit="step", desc=label, leave=False)
