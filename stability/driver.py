"""The one loop that repeats a step, for every integrator and every ensemble.

Layout of the hot path (``member_loop``): members are split into blocks of ``BLOCK``; blocks run
in parallel (``prange``); inside a block the time loop is outside and the loop over the block's
members is innermost, so the inlined step kernel vectorizes across members. The state is the body
angular momentum m in the canonical frame, advanced by the step's increment with Kahan
compensated summation (Hairer, Lubich & Wanner, GNI, VIII.5), so round-off does not accumulate
linearly over long runs. Kernels never raise: a member whose state stops being finite, or whose
implicit solve fails, gets a status code and the index of the step where it happened.

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
from .conventions import STATUS_NONFINITE, STATUS_NOT_CONVERGED, STATUS_OK
from .integrators import method_spec

#: Members per block: the vector loop's trip count (a multiple of the SIMD width).
BLOCK = 64


@njit(inline="always")
def _kahan_add(x, c, j, d):
    """x[j] += d with the running compensation c[j] (Kahan 1965)."""
    y = d - c[j]
    t = x[j] + y
    c[j] = (t - x[j]) - y
    x[j] = t


@njit(inline="always")
def _commit(x1, x2, x3, c1, c2, c3, j, e1, e2, e3, n, bad, first_bad):
    """Add one step's increment to member j and note the first step where it went non-finite."""
    _kahan_add(x1, c1, j, e1)
    _kahan_add(x2, c2, j, e2)
    _kahan_add(x3, c3, j, e3)
    total = x1[j] + x2[j] + x3[j]
    now_bad = 1 if total - total != 0.0 else 0  # inf or NaN somewhere
    first_bad[j] = n if (now_bad == 1 and bad[j] == 0) else first_bad[j]
    bad[j] |= now_bad


@functools.cache
def member_loop(step):
    """Compile (once per process) the ensemble loop around the stage kernel ``step``.

    The returned function advances ``m`` (N, 3) in place by ``n_steps`` steps of size ``h``::

        advance(m, comp, p, h, n_stages, n_steps, save_every, saved,
                status, fail_step, iterations, step0)

    ``comp`` (N, 3) carries the Kahan compensation between calls; ``saved`` (N, n_steps //
    save_every, 3) receives the state after every ``save_every``-th step (``save_every = 0``
    saves nothing); ``status`` (N,) int8, ``fail_step`` (N,) int64 and ``iterations`` (N,) int64
    are updated in place; ``step0`` is the global index of the first step (for ``fail_step``).
    """

    @njit(parallel=True, error_model="numpy")
    def advance(
        m, comp, p, h, n_stages, n_steps, save_every, saved, status, fail_step, iterations, step0
    ):
        n_members = m.shape[0]
        n_blocks = (n_members + BLOCK - 1) // BLOCK
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
            iters = np.zeros(BLOCK, dtype=np.int64)
            for j in range(size):
                x1[j] = m[lo + j, 0]
                x2[j] = m[lo + j, 1]
                x3[j] = m[lo + j, 2]
                c1[j] = comp[lo + j, 0]
                c2[j] = comp[lo + j, 1]
                c3[j] = comp[lo + j, 2]
            k = 0
            for n in range(n_steps):
                if n_stages == 1:
                    for j in range(size):
                        e1, e2, e3, it = step(x1[j], x2[j], x3[j], h, p, 0)
                        _commit(x1, x2, x3, c1, c2, c3, j, e1, e2, e3, n, bad, first_bad)
                        iters[j] += it if it > 0 else 0
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
                            nonconv[j] |= 1 if it < 0 else 0
                    for j in range(size):
                        _commit(x1, x2, x3, c1, c2, c3, j, d1[j], d2[j], d3[j], n, bad, first_bad)
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
                if bad[j] != 0 and status[lo + j] == 0:
                    status[lo + j] = 1  # STATUS_NONFINITE
                    fail_step[lo + j] = step0 + first_bad[j]
                elif nonconv[j] != 0 and status[lo + j] == 0:
                    status[lo + j] = 3  # STATUS_NOT_CONVERGED
                    fail_step[lo + j] = step0

    return advance


@dataclass
class Propagation:
    """What ``propagate`` returns; all vectors in the *body* frame, m = I w in kg m^2 s^-1.

    Attributes
    ----------
    m_final : ndarray, shape (N, 3)
        Body angular momentum after the last completed step.
    saved : ndarray, shape (N, n_saved, 3)
        Body angular momentum at steps ``save_every, 2 save_every, ...`` (initial state excluded).
    status, fail_step, iterations : ndarray, shape (N,)
        Per-member status code, global step index of the failure (-1 if none), and the number
        of nonlinear-solver iterations used.
    steps_done : int
        Steps completed (fewer than asked if the run was interrupted).
    interrupted : bool
        True if Ctrl-C ended the run early.
    wall_time : float
        Seconds spent in the loop, compilation excluded.
    compile_time : float
        Seconds spent compiling (first use of a method in the process).
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


def _compiled(advance, p):
    """Compile ``advance`` for the standard argument types, return the seconds it took."""
    t0 = time.perf_counter()
    if not advance.signatures:
        dummy = np.zeros((1, 3))
        advance(
            dummy.copy(), dummy.copy(), p, 0.0, 1, 0, 0, np.zeros((1, 0, 3)),
            np.zeros(1, np.int8), np.full(1, -1, np.int64), np.zeros(1, np.int64), 0,
        )
    return time.perf_counter() - t0


def propagate(method, moments, m0, h, n_steps, save_every=0, progress=None, chunk_steps=None):
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
    saved = np.full((n_members, n_saved, 3), np.nan)

    advance = member_loop(spec.step)
    compile_time = _compiled(advance, p)

    # Calibrate the chunk length on a short first call unless the caller fixed it.
    unit = save_every if save_every > 0 else 1
    done = 0
    k_saved = 0
    wall = 0.0
    interrupted = False
    bar = None
    chunk = chunk_steps
    with _deferred_interrupt() as interrupt:
        while done < n_steps and not interrupt.requested:
            if chunk is None:
                this = min(n_steps - done, max(unit, (64 // unit) * unit))
            else:
                this = min(n_steps - done, max(unit, (int(chunk) // unit) * unit))
            k_this = this // save_every if save_every > 0 else 0
            out = saved[:, k_saved : k_saved + k_this, :]
            buffer = np.empty((n_members, k_this, 3)) if k_this else np.empty((n_members, 0, 3))
            t0 = time.perf_counter()
            advance(
                m, comp, p, h, spec.stages, this, save_every, buffer,
                status, fail_step, iterations, done,
            )
            dt = time.perf_counter() - t0
            wall += dt
            out[...] = buffer
            done += this
            k_saved += k_this
            if chunk_steps is None:
                rate = this / max(dt, 1e-9)
                chunk = max(unit, int(0.25 * rate))
                if bar is None and progress is not False:
                    expected = (n_steps - done) / rate
                    if progress or expected > 2.0:
                        bar = _progress_bar(n_steps, done, spec.name)
            if bar is not None:
                bar.update(this)
        interrupted = interrupt.requested
    if bar is not None:
        bar.close()

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
    )


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

    return tqdm(total=total, initial=initial, unit="step", desc=f"{label}", leave=False)
