"""The one member loop, for every scene and every method.

Layout of the hot path: members are split into blocks of at most ``BLOCK``; blocks run in parallel,
on threads that each run a share of them with the GIL released
(:func:`stability.engine.driver.run_blocks`), each a call of the block function ``_block``; inside a
block the time loop is outside and the loop over the block's members is innermost, in
structure-of-arrays form (one array per state component), so the inlined step kernel vectorizes
across members. Every step's increment is added with Kahan compensated summation (Hairer, Lubich &
Wanner, GNI, VIII.5), so round-off does not accumulate linearly over long runs. Kernels never
raise: a member whose state stops being finite, or whose implicit solve fails, gets a status code
and the step count at which it was found.

The loop is written once, as the template below, and rendered for each (scene, method) pair with
the state width, the kernel and the stage count written in: the step kernel is then an ordinary
global of a module-level function, which Numba inlines and caches on disk (a closure around a
kernel could not be cached). :mod:`stability.engine.cache` writes the rendered module, keyed by
a digest of every source it depends on, and gives its ``advance`` Numba's disk cache, so an
edited kernel is compiled again and an unchanged one is loaded from disk in the next process.

Inlining: the loop calls the kernels it is rendered with (a method's step, a scene's ``observe``),
which are ``njit(inline="always")``: Numba copies their code into the loop, which then
vectorizes across members (as plain ``@njit`` calls, LLVM left the larger kernels out of line and
those loops ran 3 to 14 times slower). The short helpers the kernels call in turn (rotations,
compensated sums, a scene's right-hand side, ``kahan`` and the other helpers here) are
``njit(forceinline=True, error_model="numpy")``: LLVM inlines them (``alwaysinline``), the same
arithmetic, but Numba compiles each once per process instead of copying and typing its code again
at every call site. Their error model is the loop's, written out: a function compiled on its own
keeps the error model of its first compilation, and a division by zero must give inf in the loop,
never raise, whoever called the helper first.
Helpers with a loop or a long body (the implicit solves, ``carried_rotation``) stay
``inline="always"``: as ``forceinline`` the midpoint rule and heavy_top lp4 ran 9-10 % slower.
Compiling the loops of every scene and method (43 loops, one process) took 2 min 39 s instead of
4 min 10 s, with bitwise the same results (546 arrays) and the same speed (one thread, best of 4
alternated runs: 0.97 to 1.18 of before on nine loops).

Groups: one call advances any number of independent ensembles ("groups"), each with its own
parameter row, step, step count and tracking axes; blocks never straddle two groups, so a
study of many small ensembles keeps every core busy in one call.

Tracking (summaries without time series): the scene's ``observe`` kernel gives each member's
spin-axis component ``a`` and two perpendicular components ``b, c`` every step; the loop counts
sign changes of ``a`` (flips) and of ``b`` (oscillations), keeps the largest amplitude
``sqrt(b^2 + c^2)`` and the first time it reaches each of a ladder of levels. The per-step pass
is branch-free and vectorized (sign tests, ``b^2 + c^2`` against the next level's threshold);
the rare members that crossed or reached a level are then finished by a scalar pass that
interpolates the time within the step.
"""

from __future__ import annotations

import importlib
import math

import numpy as np
from numba import njit

from .events import bracketed_root, scalar_form

#: Members per block: the vector loop's trip count (a multiple of the SIMD width).
BLOCK = 64
#: Steps between finiteness checks, counted from step 0 of the run (and once more after its
#: last step, by :func:`stability.engine.driver.propagate_groups`). Inf and NaN are absorbing, so a
#: failure is caught at the next check: ``fail_step`` is the step count at the first check that
#: found the state non-finite, at most CHECK_EVERY - 1 steps late
#: (``stability.engine.untrusted`` masks conservatively).
CHECK_EVERY = 8

# Columns of the per-member tracking state (float64, carried between chunked calls).
T_PREV_A = 0  #: spin-axis component a at the previous step
T_PREV_B = 1  #: first perpendicular component b at the previous step
T_PREV_AMP2 = 2  #: squared perpendicular amplitude b^2 + c^2 at the previous step
T_COUNT_A = 3  #: sign changes of a so far (flips)
T_FIRST_A = 4  #: time of the first sign change of a, NaN before
T_LAST_A = 5  #: time of the latest sign change of a
T_COUNT_B = 6  #: sign changes of b
T_FIRST_B = 7
T_LAST_B = 8
T_MAX_AMP2 = 9  #: largest squared perpendicular amplitude so far
T_NEXT_LEVEL = 10  #: index of the next amplitude level to reach
N_TRACK = 11


@njit(forceinline=True, error_model="numpy")
def kahan(x, c, d):
    """``x + d`` with the running compensation ``c`` (Kahan 1965): returns (x, c) updated."""
    y = d - c
    t = x + y
    return t, (t - x) - y


@njit(forceinline=True, error_model="numpy")
def not_finite(total):
    """1 if ``total`` is inf or NaN (a sum of the state's components), else 0."""
    return 1 if total - total != 0.0 else 0


@njit(forceinline=True, error_model="numpy")
def crossed(prev, v):
    """True if v has another sign than prev (zero counts as positive)."""
    return (prev >= 0.0) != (v >= 0.0)


@njit(forceinline=True, error_model="numpy")
def counted_crossing(count, first, last, prev, v, t_prev, h):
    """``(count, first, last)`` after a sign change of v since the previous step.

    Its time ``t_prev + h prev / (prev - v)`` by linear interpolation is the new ``last``, and
    ``first`` too when it is the first one; the CPU and the GPU loops both count with this.
    """
    t_cross = t_prev + h * prev / (prev - v)
    count += 1.0
    if count == 1.0:
        first = t_cross
    return count, first, t_cross


@njit(forceinline=True, error_model="numpy")
def passage_fraction(level, prev_amp, amp):
    """Where in the step the amplitude passed ``level``, in [0, 1]: ln(level / prev_amp) /
    ln(amp / prev_amp) (linear in t during exponential growth), the amplitude itself
    interpolated where the logarithms are undefined; the CPU and the GPU loops both use it."""
    if prev_amp > 0.0 and amp > prev_amp:
        frac = math.log(level / prev_amp) / math.log(amp / prev_amp)
    else:
        frac = (level - prev_amp) / (amp - prev_amp)
    return min(max(frac, 0.0), 1.0)


@njit
def record_crossing(tr, j, col_count, col_first, col_last, prev, v, t_prev, h):
    """Count a sign change of v since the previous step; its time by linear interpolation."""
    count, first, last = counted_crossing(tr[col_count, j], tr[col_first, j], tr[col_last, j],
                                          prev, v, t_prev, h)
    tr[col_count, j] = count
    tr[col_first, j] = first
    tr[col_last, j] = last


@njit
def record_events(tr, j, prev_a, prev_b, prev_amp2, va, vb, amp2, t_prev, h, levels, thresholds,
                  passage, member):
    """Finish the step of member j of a block: crossings of a and b, levels its amplitude passed.

    ``prev_*`` are the tracked values at the start of the step, ``va, vb, amp2`` at its end.
    ``levels`` are the amplitudes and ``thresholds`` the smallest squares whose square root
    reaches them (so ``amp2 >= thresholds[k]`` is exactly ``sqrt(amp2) >= levels[k]``). The time
    of a level passage interpolates ln(amplitude), which is linear in t during exponential
    growth (interpolating the amplitude itself biases rates by ~(h lambda)^2 / 8), clamped to
    this step.
    """
    if crossed(prev_a, va):
        record_crossing(tr, j, T_COUNT_A, T_FIRST_A, T_LAST_A, prev_a, va, t_prev, h)
    if crossed(prev_b, vb):
        record_crossing(tr, j, T_COUNT_B, T_FIRST_B, T_LAST_B, prev_b, vb, t_prev, h)
    level = int(tr[T_NEXT_LEVEL, j])
    n_levels = levels.shape[0]
    if level < n_levels and amp2 >= thresholds[level]:
        amp = math.sqrt(amp2)
        prev_amp = math.sqrt(prev_amp2)
        while level < n_levels and amp2 >= thresholds[level]:
            passage[member, level] = t_prev + h * passage_fraction(levels[level], prev_amp, amp)
            level += 1
        tr[T_NEXT_LEVEL, j] = level


def level_thresholds(levels) -> np.ndarray:
    """The smallest double x with ``sqrt(x) >= level``, for each level (``inf`` pads the end).

    ``sqrt`` is correctly rounded and monotone, so comparing squares against these is exactly
    the comparison of amplitudes against the levels, without a square root per step.
    """
    levels = np.asarray(levels, dtype=float)
    unique, where = np.unique(levels, return_inverse=True)
    out = np.empty(unique.shape)
    for index, level in enumerate(unique):
        if not level > 0.0:  # every amplitude reaches it
            out[index] = 0.0
            continue
        x = level * level
        while x > 0.0 and math.sqrt(np.nextafter(x, 0.0)) >= level:
            x = np.nextafter(x, 0.0)
        while math.sqrt(x) < level:
            x = np.nextafter(x, np.inf)
        out[index] = x
    return out[where].reshape(levels.shape)


# --- the template ---------------------------------------------------------------------------
#
# Every per-member number of a block lives in one flat array ``w`` (rows of BLOCK), addressed as
# ``w[ROW + j]`` with ROW a compile-time constant: LLVM then knows that no two rows overlap and
# vectorizes the member loops without runtime alias checks (separate arrays per row defeat it
# once a loop touches more than a handful of them). Integers live in ``iw`` the same way.
#
# A call of ``advance`` runs the blocks it is given (``blocks``, indices into the block table),
# one after the other, with the GIL released: :func:`stability.engine.driver.run_blocks` gives
# each of its threads a share of the blocks. The loop has no parallel region of Numba's
# own (``prange``): Numba's parallel passes and the kernel they build cost 2 s of the 4 to 6 s
# a loop takes to compile (free_body rk4 5.75 s as a prange loop, 4.0 s as this; heavy_top lp2
# 7.8 and 5.9 s), for bitwise the same results. The block number is int64 (an index of the
# block table).

_TEMPLATE = '''\
"""Member loop of scene {scene!r} with method {method!r}{variant_note}.

Rendered from the template in stability/engine/loop.py; do not edit (sources {{digest}}).
"""

import numpy as np
from numba import njit

from stability.util.conventions import STATUS_NONFINITE, STATUS_NOT_CONVERGED, STATUS_OK
from stability.engine.loop import (
    BLOCK, N_TRACK, T_MAX_AMP2, T_NEXT_LEVEL, T_PREV_A, T_PREV_AMP2, T_PREV_B, CHECK_EVERY,
    crossed, kahan, not_finite, record_events,
)
from {step_module} import {step_name} as step
from {observe_module} import {observe_name} as observe
{event_header}
# Rows of the block's float work array w (state x, compensation c, stage sums d, tracking) and
# of its integer array iw.
{rows}


@njit(nogil=True, error_model="numpy")
def _block(
    b, x, comp, params, block_lo, block_size, block_group, hs, steps, step0, save_every, saved,
    k0, status, fail_step, iterations, axes, track, levels, thresholds, passage,{event_args}
):
    tracking = track.shape[0] > 0
    lo = block_lo[b]
    size = block_size[b]
    g = block_group[b]
    p = params[g]
    h = hs[g]
    n_steps = steps[g]
    first_step = step0[g]
    ia = axes[g, 0]
    ib = axes[g, 1]
    ic = axes[g, 2]
    lv = levels[g]
    th = thresholds[g]
    w = np.zeros(N_ROWS * BLOCK)
    iw = np.zeros(N_IROWS * BLOCK, dtype=np.int64)
    tr = np.zeros((N_TRACK, BLOCK))
    for j in range(size):
{load}
        iw[FIRST_BAD + j] = -1
        iw[FIRST_NONCONV + j] = -1
    if tracking:
        for col in range(N_TRACK):
            for j in range(size):
                tr[col, j] = track[lo + j, col]
        for j in range(size):
            w[MAX_AMP2 + j] = tr[T_MAX_AMP2, j]
            w[NEXT_THRESHOLD + j] = th[int(tr[T_NEXT_LEVEL, j])]
{event_load}    k = k0[g]
    for n in range(n_steps):
{stages}
{event_before}        if tracking:
            any_event = 0
            for j in range(size):
{advance_tracked}
            if any_event != 0:
                t_prev = (first_step + n) * h
                for j in range(size):
                    if w[EVENT + j] == 0.0:
                        continue
                    va, vb, vc = observe({state}, p, ia, ib, ic)
                    amp2 = vb * vb + vc * vc
                    if first_step + n == 0:  # the start's own values (as the caller set)
                        pa, pb, pamp2 = tr[T_PREV_A, j], tr[T_PREV_B, j], tr[T_PREV_AMP2, j]
                    else:
                        pa, pb = w[OLD_A + j], w[OLD_B + j]
                        pamp2 = pb * pb + w[OLD_C + j] * w[OLD_C + j]
                    record_events(
                        tr, j, pa, pb, pamp2, va, vb, amp2, t_prev, h, lv, th, passage, lo + j
                    )
                    w[NEXT_THRESHOLD + j] = th[int(tr[T_NEXT_LEVEL, j])]
        else:
            for j in range(size):
{advance_plain}
{event_pass}        if (first_step + n + 1) % CHECK_EVERY == 0:  # global steps: chunking changes nothing
            for j in range(size):
                now_bad = not_finite({total})
                first = now_bad == 1 and iw[BAD + j] == 0
                iw[FIRST_BAD + j] = n if first else iw[FIRST_BAD + j]
                iw[BAD + j] |= now_bad
        if save_every > 0 and (n + 1) % save_every == 0:
            for j in range(size):
{save}
            k += 1
    for j in range(size):
{store}
        iterations[lo + j] += iw[ITERS + j]
        # The earlier failure wins (a non-finite state found at a check, or a failed solve),
        # so the status does not depend on where chunks end.
        bad = first_step + iw[FIRST_BAD + j] + 1 if iw[BAD + j] != 0 else -1
        nonconv = first_step + iw[FIRST_NONCONV + j] + 1 if iw[NONCONV + j] != 0 else -1
        ok = status[lo + j] == STATUS_OK
        if ok and bad >= 0 and (nonconv < 0 or bad <= nonconv):
            status[lo + j] = STATUS_NONFINITE
            fail_step[lo + j] = bad
        elif ok and nonconv >= 0:
            status[lo + j] = STATUS_NOT_CONVERGED
            fail_step[lo + j] = nonconv
    if tracking:
        for j in range(size):
            va, vb, vc = observe({state}, p, ia, ib, ic)
            tr[T_PREV_A, j] = va
            tr[T_PREV_B, j] = vb
            tr[T_PREV_AMP2, j] = vb * vb + vc * vc
            tr[T_MAX_AMP2, j] = w[MAX_AMP2 + j]
        for col in range(N_TRACK):
            for j in range(size):
                track[lo + j, col] = tr[col, j]
{event_store}


@njit(nogil=True, error_model="numpy")
def advance(
    blocks, x, comp, params, block_lo, block_size, block_group, hs, steps, step0, save_every,
    saved, k0, status, fail_step, iterations, axes, track, levels, thresholds, passage,{event_args}
):
    for k in range(blocks.shape[0]):
        _block(
            blocks[k], x, comp, params, block_lo, block_size, block_group, hs, steps, step0,
            save_every, saved, k0, status, fail_step, iterations, axes, track, levels,
            thresholds, passage,{event_args}
        )
'''


#: The event arguments the loop takes with events: per event its direction code, whether it
#: stops, times kept; per member (carried between calls) each g at the current state, the
#: crossings counted, the times kept, and where and when a stop event ended the member.
EVENT_ARGS = ("ev_dir", "ev_stop", "ev_keep", "ev_prev", "ev_count", "ev_time", "stop_x",
              "stop_t", "stop_event")

_EVENT_HELPERS = '''

@njit(forceinline=True, error_model="numpy")
def _g(k, y, t, p):
{g_calls}
    return 0.0


@njit(error_model="numpy")
def _flow(y, tau, p, out):
    """The method's own step of length tau from y, its stages as the loop takes them: the
    continuous extension an event is located on (the exact flow, for an exact method)."""
{d_zero}
    for s in range({stages}):
        {es}, it = step({shifted}, tau, p, s)
{d_add}
{out_set}


{root}

@njit(error_model="numpy")
def _step_events(i, y, t0, h, p, gp, gn, ev_dir, ev_stop, ev_keep, ev_count, ev_time, stop_x,
                 stop_t, stop_event, t_hit, order, out):
    """Member i's crossings in the step from y at t0: located, taken in the order of their
    times (then of the events), counted and kept; a stop event's last one ends the member
    there (its state and time kept in stop_x, stop_t)."""
    hits = 0
    for k in range(gn.shape[0]):
        up = gp[k] < 0.0 and gn[k] >= 0.0
        down = gp[k] >= 0.0 and gn[k] < 0.0
        if (up and ev_dir[k] >= 0) or (down and ev_dir[k] <= 0):
            order[hits] = k
            hits += 1
    for q in range(hits):
        k = order[q]
        t_hit[k] = _root(k, y, t0, h, gp[k], gn[k], p, out)
    k = taken_in_order(order, hits, t_hit, ev_count[i], ev_time[i], ev_keep, ev_stop)
    if k >= 0:
        _flow(y, t_hit[k] - t0, p, out)
        for c in range(out.shape[0]):
            stop_x[i, c] = out[c]
        stop_t[i] = t_hit[k]
        stop_event[i] = k
'''


def scalar_events(events, width) -> bool:
    """Whether every g of ``events`` (module, name, compiled) has a scalar form
    (:func:`stability.engine.events.scalar_form`), so the commit loop tests them on the numbers
    it holds, the member's state before and after the step, with no view of the state."""
    return bool(events) and all(
        scalar_form(getattr(importlib.import_module(module), name), width) is not None
        for module, name, _ in events)


def event_source(width, stages, events, scalar=False) -> dict:
    """The template's event parts: the loop without events has none of them (the same source
    as before events existed); with events, each step evaluates every g at the new state of
    every member, and the members where one changed sign (and that are not stopped) are
    finished by ``_step_events``, which locates each crossing on the method's own step from
    the state before (``_flow``) by regula falsi (:func:`~.events.bracketed_root`). Time is
    the loop's, ``steps x h`` from 0. The commit keeps the state before the step in the rows
    ``XO``.

    The pass that evaluates g is a reduction, whether any g of the block changed sign, as lean
    as it can be; which members crossed, and whether they are stopped, is asked again only in a
    step where one did. With ``scalar`` (every g has a scalar form, :func:`scalar_events`),
    the reduction is part of the commit loop itself (``event_commit``), on the numbers the
    commit has at hand, the state before the step and after it: no pass of its own, and no g
    carried from step to step. Without it, a pass after the commit evaluates each g on a
    strided view of each member's row and carries it to the next step."""
    keys = ("event_header", "event_args", "event_load", "event_before", "event_commit",
            "event_pass", "event_store")
    if not events:
        return {**dict.fromkeys(keys, ""), "event_commit": []}
    m = len(events)
    header = ["from stability.engine.events import scalar_form, taken_in_order"]
    for k, (module, name, compiled) in enumerate(events):
        header.append(f"from {module} import {name} as user_g{k}")
        python = f"user_g{k}.py_func" if compiled else f"user_g{k}"  # inlined into the loop
        header.append(f'g{k} = njit(inline="always", error_model="numpy")({python})')
        if scalar:
            header.append(f'sg{k} = njit(inline="always", error_model="numpy")'
                          f"(scalar_form({python}, {width}))")
    ds = [f"d{i}" for i in range(width)]
    helpers = _EVENT_HELPERS.format(
        g_calls="\n".join(f"    if k == {k}:\n        return float(g{k}(y, t, p))"
                          for k in range(m)),
        stages=stages, es=", ".join(f"e{i}" for i in range(width)),
        shifted=", ".join(f"y[{i}] + d{i}" for i in range(width)),
        d_zero=_indent([f"{d} = 0.0" for d in ds], 1),
        d_add=_indent([f"d{i} += e{i}" for i in range(width)], 2),
        out_set=_indent([f"out[{i}] = y[{i}] + d{i}" for i in range(width)], 1),
        root=bracketed_root("y", "out", "_flow(y, c - t0, p, out)", "g along _flow"))
    load = ["yo = np.empty(NW)", "out = np.empty(NW)",
            "gp = np.empty(NE)", "gn = np.empty(NE)", "t_hit = np.empty(NE)",
            "order = np.empty(NE, dtype=np.int64)",
            "for j in range(size):",
            "    w[STOPPED + j] = 1.0 if stop_event[lo + j] >= 0 else 0.0"]
    if scalar:
        before = ["t_old = (first_step + n) * h", "t_new = (first_step + n + 1) * h",
                  "any_hit = 0"]
        commit, after, store = _scalar_reduction(width, m), _scalar_pass(width, m), \
            _scalar_store(width, m)
    else:
        load, before, commit, (after, store) = load + _view_load(m), [], [], _view_pass(width, m)
    return {"event_header": "\n".join(header) + f"\n\nNW = {width}\nNE = {m}\n" + helpers,
            "event_args": " " + ", ".join(EVENT_ARGS) + ",",
            "event_load": _indent(load, 1) + "\n",
            "event_before": _indent(before, 2) + "\n" if before else "",
            "event_commit": commit,
            "event_pass": _indent(after, 2) + "\n" if after else "",
            "event_store": _indent(store, 1) + "\n"}


#: A member's state as a strided view of its row of the block.
_VIEW = "xv = w[j:j + NW * BLOCK:BLOCK]  # member j's state: X0 ... are rows 0 ..."
#: Locate, take and count member j's crossings of the step ending at t_new, the state before it
#: in yo and each g before and after in gp, gn (the start as t_new - h on both passes: the
#: same number, bitwise, whichever pass runs).
_STEP_EVENTS = ["        _step_events(lo + j, yo, t_new - h, h, p, gp, gn, ev_dir, ev_stop, "
                "ev_keep, ev_count, ev_time, stop_x, stop_t, stop_event, t_hit, order, out)",
                "        w[STOPPED + j] = 1.0 if stop_event[lo + j] >= 0 else 0.0"]


def _view_load(m):
    """Each g at the start of the call, into GP: at the run's start from the state, later the
    value carried from the call before (``ev_prev``)."""
    return (["    if first_step == 0:  # each g at the start", "        " + _VIEW]
            + [f"        w[GP{k} + j] = _g({k}, xv, 0.0, p)" for k in range(m)]
            + ["    else:"] + [f"        w[GP{k} + j] = ev_prev[lo + j, {k}]" for k in range(m)])


def _view_pass(width, m):
    """The pass after the commit where some g has no scalar form: each g on a view of the
    member's row into GN, the state before the step kept by the commit in XO; then GN moved to
    GP. Returns (the pass, the store of GP into ``ev_prev`` at the end of the call)."""
    found = ["t_new = (first_step + n + 1) * h", "any_hit = 0", "for j in range(size):",
             "    " + _VIEW]
    for k in range(m):
        found += [f"    gv = _g({k}, xv, t_new, p)",
                  f"    any_hit |= 1 if crossed(w[GP{k} + j], gv) else 0",
                  f"    w[GN{k} + j] = gv"]
    changed = " or ".join(f"crossed(w[GP{k} + j], w[GN{k} + j])" for k in range(m))
    found += ["if any_hit != 0:",
              "    for j in range(size):",
              f"        if w[STOPPED + j] != 0.0 or not ({changed}):",
              "            continue"]
    found += [f"        yo[{i}] = w[XO{i} + j]" for i in range(width)]
    found += [f"        gp[{k}] = w[GP{k} + j]" for k in range(m)]
    found += [f"        gn[{k}] = w[GN{k} + j]" for k in range(m)] + _STEP_EVENTS
    found += ["for j in range(size):"] + [f"    w[GP{k} + j] = w[GN{k} + j]" for k in range(m)]
    store = ["for j in range(size):"] + [f"    ev_prev[lo + j, {k}] = w[GP{k} + j]"
                                         for k in range(m)]
    return found, store


def _scalar_g(k, rows, width, t):
    """g of event k by its scalar form at time t, on the numbers of member j's rows ``rows``
    (``"X"``: the state, ``"XO"``: the state before the step)."""
    numbers = ", ".join(f"w[{rows}{i} + j]" for i in range(width))
    return f"float(sg{k}({numbers}, {t}, p))"


def _scalar_reduction(width, m):
    """The lines the commit loop ends with where every g has a scalar form: whether some g may
    have changed sign in the step, from the state before it (``XO``, which the commit has just
    written) and after it (``X``), numbers the loop holds in registers. g before the step is
    the number the previous step found after it (the same numbers, time and arithmetic), so
    none is carried from step to step. The test is ``not (g_old g_new > 0)`` with
    ``g_old != g_new``, true wherever :func:`crossed` is (and where the product is 0 or NaN, but
    for a g that stays at 0, which would send every step to the pass): a multiply and two
    compares a member, where ``crossed`` took two compares and their exclusive or (the pass
    after it asks ``crossed`` of each member, so the crossings are the same). With an event
    that never crosses (20,000 free-body members, 2,000 RK4 steps, one thread) the run costs
    +5 to +6 % over the one without it, against +7 to +9 % with ``crossed`` itself."""
    lines = []
    for k in range(m):
        lines += [f"g_before{k} = {_scalar_g(k, 'XO', width, 't_old')}",
                  f"g_after{k} = {_scalar_g(k, 'X', width, 't_new')}",
                  f"any_hit |= 1 if not (g_before{k} * g_after{k} > 0.0) "
                  f"and g_before{k} != g_after{k} else 0"]
    return lines


def _scalar_pass(width, m):
    """The pass after the commit in a step where some g may have changed sign
    (:func:`_scalar_reduction`): each member's g before and after the step again, and those
    that crossed located."""
    found = ["if any_hit != 0:",
             "    for j in range(size):",
             "        if w[STOPPED + j] != 0.0:",
             "            continue"]
    found += [f"        gp[{k}] = {_scalar_g(k, 'XO', width, 't_old')}" for k in range(m)]
    found += [f"        gn[{k}] = {_scalar_g(k, 'X', width, 't_new')}" for k in range(m)]
    changed = " or ".join(f"crossed(gp[{k}], gn[{k}])" for k in range(m))
    found += [f"        if not ({changed}):", "            continue"]
    found += [f"        yo[{i}] = w[XO{i} + j]" for i in range(width)]
    return found + _STEP_EVENTS


def _scalar_store(width, m):
    """Each g at the state the call ends on, into ``ev_prev``, once."""
    return ["t_now = (first_step + n_steps) * h", "for j in range(size):"] + [
        f"    ev_prev[lo + j, {k}] = {_scalar_g(k, 'X', width, 't_now')}" for k in range(m)]


def _indent(lines, depth):
    return "\n".join("    " * depth + line for line in lines)


def render(scene_name, method_name, width, stages, implicit, step, observe,
           compensated=True, events=()) -> str:
    """Source of the member loop for one (scene, method) pair; see the module docstring.

    Parameters
    ----------
    scene_name, method_name : str
        Registry names (written into the module docstring).
    width : int
        Numbers per member in the state.
    stages : int
        Kernel calls per step (s = 0 .. stages - 1), each applied to the state plus the
        increments of the earlier stages.
    implicit : bool
        The kernel reports solver iterations (negative: failed); explicit kernels' are ignored.
    step, observe : numba dispatchers
        The stage kernel ``step(x_0, ..., x_{width-1}, h, p, s) -> (d_0, ..., d_{width-1}, it)``
        and the tracking kernel ``observe(x_0, ..., x_{width-1}, p, ia, ib, ic) -> (a, b, c)``.
    compensated : bool
        Kahan-compensated update (the default), or the plain ``x += d`` (for benchmarks).
    events : sequence of (str, str, bool)
        Each event's ``g`` as (module, name, whether it is already ``@njit``): the loop then
        takes the event arrays too (:func:`event_source`).

    The kernel's increments go to the stage sums ``D`` in one loop and are committed in
    another, with or without tracking: the kernel is inlined once (compile time), and the
    tracked commit loop stays small enough to vectorize (it ran 7% faster than a loop that
    also called the kernel, and the bare loop 13% slower; measured with rk4 on one core).
    """
    rows = [f"X{i}" for i in range(width)] + [f"C{i}" for i in range(width)]
    rows += [f"D{i}" for i in range(width)]
    rows += ["OLD_A", "OLD_B", "OLD_C", "MAX_AMP2", "NEXT_THRESHOLD", "EVENT"]
    scalar = scalar_events(events, width)
    if events:  # the state before the step (kept by the commit), a stopped flag, and where g
        # has no scalar form each event's g before and after the step
        rows += [f"XO{i}" for i in range(width)] + ["STOPPED"]
        if not scalar:
            rows += [f"GP{k}" for k in range(len(events))]
            rows += [f"GN{k}" for k in range(len(events))]
    irows = ["BAD", "FIRST_BAD", "NONCONV", "FIRST_NONCONV", "ITERS"]
    row_lines = [f"{name} = {k} * BLOCK" for k, name in enumerate(rows)]
    row_lines += [f"N_ROWS = {len(rows)}", ""]
    row_lines += [f"{name} = {k} * BLOCK" for k, name in enumerate(irows)]
    row_lines += [f"N_IROWS = {len(irows)}"]

    def xs(i):
        return f"w[X{i} + j]"

    def cs(i):
        return f"w[C{i} + j]"

    def ds(i):
        return f"w[D{i} + j]"

    state = ", ".join(xs(i) for i in range(width))
    old = ", ".join(f"x_old{i}" for i in range(width))
    load = [f"{xs(i)} = x[lo + j, {i}]" for i in range(width)]
    load += [f"{cs(i)} = comp[lo + j, {i}]" for i in range(width)]
    store = [f"x[lo + j, {i}] = {xs(i)}" for i in range(width)]
    store += [f"comp[lo + j, {i}] = {cs(i)}" for i in range(width)]
    save = [f"saved[lo + j, k, {i}] = {xs(i)}" for i in range(width)]
    es = ", ".join(f"e{i}" for i in range(width))

    def commit(source):
        if compensated:
            return [f"{xs(i)}, {cs(i)} = kahan({xs(i)}, {cs(i)}, {source(i)})"
                    for i in range(width)]
        return [f"{xs(i)} += {source(i)}" for i in range(width)]

    solver = [
        "iw[ITERS + j] += it if it > 0 else 0",
        "first = it < 0 and iw[NONCONV + j] == 0",
        "iw[FIRST_NONCONV + j] = n if first else iw[FIRST_NONCONV + j]",
        "iw[NONCONV + j] |= 1 if it < 0 else 0",
    ] if implicit else []
    if stages == 1:  # the kernel's increment, kept for the commit loop
        stage_loops = ["for j in range(size):",
                       f"    {es}, it = step({state}, h, p, 0)"]
        stage_loops += [f"    {ds(i)} = e{i}" for i in range(width)]
    else:  # the sum of the stages' increments, each stage from the state plus the sum
        shifted = ", ".join(f"{xs(i)} + {ds(i)}" for i in range(width))
        stage_loops = ["for j in range(size):"] + [f"    {ds(i)} = 0.0" for i in range(width)]
        stage_loops += [f"for s in range({stages}):",
                        "    for j in range(size):",
                        f"        {es}, it = step({shifted}, h, p, s)"]
        stage_loops += [f"        {ds(i)} += e{i}" for i in range(width)]
    stage_loops += ["    " * (1 if stages == 1 else 2) + line for line in solver]
    update = commit(ds)
    # Tracked: the state before the update, the update, and the events of the step.
    tracked = [f"x_old{i} = {xs(i)}" for i in range(width)]
    kept_old = [f"w[XO{i} + j] = {xs(i)}" for i in range(width)] if events else []
    sources = event_source(width, stages, events, scalar)
    event_commit = sources.pop("event_commit")
    tracked += kept_old + update + event_commit
    tracked += [
        f"a0, b0, c0 = observe({old}, p, ia, ib, ic)",
        f"va, vb, vc = observe({state}, p, ia, ib, ic)",
        "amp2 = vb * vb + vc * vc",
        "hit = crossed(a0, va) | crossed(b0, vb) | (amp2 >= w[NEXT_THRESHOLD + j])",
        "any_event |= 1 if hit else 0",
        "w[EVENT + j] = 1.0 if hit else 0.0",
        "w[MAX_AMP2 + j] = max(w[MAX_AMP2 + j], amp2)",
        "w[OLD_A + j] = a0",
        "w[OLD_B + j] = b0",
        "w[OLD_C + j] = c0",
    ]
    return _TEMPLATE.format(
        scene=scene_name,
        method=method_name,
        variant_note="" if compensated else " (uncompensated update, for benchmarks)",
        step_module=step.py_func.__module__,
        step_name=step.py_func.__name__,
        observe_module=observe.py_func.__module__,
        observe_name=observe.py_func.__name__,
        rows="\n".join(row_lines),
        load=_indent(load, 2),
        stages=_indent(stage_loops, 2),
        advance_tracked=_indent(tracked, 4),
        advance_plain=_indent(kept_old + update + event_commit, 4),
        total=" + ".join(xs(i) for i in range(width)),
        state=state,
        save=_indent(save, 4),
        store=_indent(store, 2),
        **sources,
    )
