"""The member loop as a CUDA kernel: one member per thread, its state in registers.

The GPU twin of :mod:`stability.engine.loop` for the free-body scene. Thread i advances member i
for ``n_steps`` steps with the method's own stage kernel (its device twin,
:mod:`stability.gpu.retarget`), commits each step with the same Kahan compensated sum, and
tracks what the CPU loop tracks, with the same definitions: sign changes of the spin-axis
component ``a`` (flips) and of the first perpendicular component ``b``, each with the first and
last time interpolated linearly within the step, the largest ``b^2 + c^2``, the first passage of
``sqrt(b^2 + c^2)`` through each level (interpolated in its logarithm), and a non-finite check
every ``CHECK_EVERY`` global steps. Everything a member carries between steps lives in
registers; global memory is read at the start and written at the end (and at saved samples
and level passages), so the memory traffic is independent of the number of steps.

Layout: structure of arrays, members along the last axis (``x[k, i]``, ``track[col, i]``,
``passage[level, i]``), so consecutive threads touch consecutive addresses (coalesced). A
member's group ``group[i]`` selects its parameter row, step, step count, tracking axes and
levels, as blocks of the CPU loop do.

This module imports ``numba.cuda``: import it only after
:func:`stability.gpu.device.cuda_module` has found a device or the simulator. (The kernel reads
``cuda`` as a module global, which is where the simulator swaps in its own.)
"""

from __future__ import annotations

import math

from numba import cuda

from ..conventions import STATUS_NONFINITE, STATUS_OK
from ..engine import loop as cpu_loop
from ..engine.loop import (
    CHECK_EVERY, T_COUNT_A, T_COUNT_B, T_FIRST_A, T_FIRST_B, T_LAST_A, T_LAST_B, T_MAX_AMP2,
    T_NEXT_LEVEL, T_PREV_A, T_PREV_AMP2, T_PREV_B,
)
from ..scenes.free_body import observe as cpu_observe
from .methods import gpu_method
from .retarget import device_twin

_KERNELS: dict = {}


def member_kernel(method, tracked=True):
    """The CUDA kernel advancing free-body members with ``method`` (made once per process).

    Parameters
    ----------
    method : str or MethodSpec
        One of :data:`GPU_METHODS`.
    tracked : bool
        Compile the tracking of flips, crossings, amplitudes and levels in (or leave it out).

    Returns
    -------
    CUDA kernel
        ``advance[blocks, threads](x, comp, params, group, hs, steps, step0, axes, track,
        thresholds, levels, passage, status, fail_step, saved, save_every, k0)``; shapes in
        :func:`stability.gpu.propagate.propagate_many_gpu`.
    """
    spec = gpu_method(method)
    key = (spec.name, bool(tracked))
    if key not in _KERNELS:
        _KERNELS[key] = _build(spec, bool(tracked))
    return _KERNELS[key]


def _build(spec, tracked):
    step = device_twin(cuda, spec.step)
    observe = device_twin(cuda, cpu_observe)
    kahan = device_twin(cuda, cpu_loop.kahan)
    crossed = device_twin(cuda, cpu_loop.crossed)
    not_finite = device_twin(cuda, cpu_loop.not_finite)
    stages = spec.stages
    ok = STATUS_OK
    nonfinite = STATUS_NONFINITE
    check_every = CHECK_EVERY

    @cuda.jit
    def advance(x, comp, params, group, hs, steps, step0, axes, track, thresholds, levels,
                passage, status, fail_step, saved, save_every, k0):
        i = cuda.grid(1)
        if i >= x.shape[1]:
            return
        g = group[i]
        p = params[g]
        h = hs[g]
        n_steps = steps[g]
        if n_steps == 0:  # a group already done (the CPU loop gives it no blocks)
            return
        first_step = step0[g]
        ia = axes[g, 0]
        ib = axes[g, 1]
        ic = axes[g, 2]
        th = thresholds[g]
        lv = levels[g]
        n_levels = lv.shape[0]
        x1 = x[0, i]
        x2 = x[1, i]
        x3 = x[2, i]
        c1 = comp[0, i]
        c2 = comp[1, i]
        c3 = comp[2, i]
        # Tracking state (columns of stability.engine.loop), in registers.
        start_a = 0.0
        start_b = 0.0
        start_amp2 = 0.0
        count_a = 0.0
        first_a = 0.0
        last_a = 0.0
        count_b = 0.0
        first_b = 0.0
        last_b = 0.0
        max_amp2 = 0.0
        level = 0
        next_th = 0.0
        if tracked:
            start_a = track[T_PREV_A, i]
            start_b = track[T_PREV_B, i]
            start_amp2 = track[T_PREV_AMP2, i]
            count_a = track[T_COUNT_A, i]
            first_a = track[T_FIRST_A, i]
            last_a = track[T_LAST_A, i]
            count_b = track[T_COUNT_B, i]
            first_b = track[T_FIRST_B, i]
            last_b = track[T_LAST_B, i]
            max_amp2 = track[T_MAX_AMP2, i]
            level = int(track[T_NEXT_LEVEL, i])
            next_th = th[level]
        bad = 0
        first_bad = -1
        k = k0[g]
        for n in range(n_steps):
            if stages == 1:
                d1, d2, d3, it = step(x1, x2, x3, h, p, 0)
            else:  # each stage from the state plus the earlier stages' increments
                d1 = 0.0
                d2 = 0.0
                d3 = 0.0
                for s in range(stages):
                    e1, e2, e3, it = step(x1 + d1, x2 + d2, x3 + d3, h, p, s)
                    d1 += e1
                    d2 += e2
                    d3 += e3
            o1 = x1
            o2 = x2
            o3 = x3
            x1, c1 = kahan(x1, c1, d1)
            x2, c2 = kahan(x2, c2, d2)
            x3, c3 = kahan(x3, c3, d3)
            if tracked:
                a0, b0, cc0 = observe(o1, o2, o3, p, ia, ib, ic)
                va, vb, vc = observe(x1, x2, x3, p, ia, ib, ic)
                amp2 = vb * vb + vc * vc
                hit = crossed(a0, va) or crossed(b0, vb) or amp2 >= next_th
                max_amp2 = max(max_amp2, amp2)
                if hit:  # rare: the scalar pass of the CPU loop (record_events)
                    t_prev = (first_step + n) * h
                    if first_step + n == 0:  # the start's own values (as the caller set)
                        pa = start_a
                        pb = start_b
                        pamp2 = start_amp2
                    else:
                        pa = a0
                        pb = b0
                        pamp2 = pb * pb + cc0 * cc0
                    if crossed(pa, va):
                        t_cross = t_prev + h * pa / (pa - va)
                        count_a += 1.0
                        if count_a == 1.0:
                            first_a = t_cross
                        last_a = t_cross
                    if crossed(pb, vb):
                        t_cross = t_prev + h * pb / (pb - vb)
                        count_b += 1.0
                        if count_b == 1.0:
                            first_b = t_cross
                        last_b = t_cross
                    if level < n_levels and amp2 >= th[level]:
                        amp = math.sqrt(amp2)
                        prev_amp = math.sqrt(pamp2)
                        while level < n_levels and amp2 >= th[level]:
                            if prev_amp > 0.0 and amp > prev_amp:
                                frac = math.log(lv[level] / prev_amp) / math.log(amp / prev_amp)
                            else:
                                frac = (lv[level] - prev_amp) / (amp - prev_amp)
                            passage[level, i] = t_prev + h * min(max(frac, 0.0), 1.0)
                            level += 1
                    next_th = th[level]
            if (first_step + n + 1) % check_every == 0:  # global steps, as on the CPU
                now_bad = not_finite(x1 + x2 + x3)
                if now_bad == 1 and bad == 0:
                    first_bad = n
                bad |= now_bad
            if save_every > 0 and (n + 1) % save_every == 0:
                saved[k, 0, i] = x1
                saved[k, 1, i] = x2
                saved[k, 2, i] = x3
                k += 1
        x[0, i] = x1
        x[1, i] = x2
        x[2, i] = x3
        comp[0, i] = c1
        comp[1, i] = c2
        comp[2, i] = c3
        if bad != 0 and status[i] == ok:
            status[i] = nonfinite
            fail_step[i] = first_step + first_bad + 1
        if tracked:
            va, vb, vc = observe(x1, x2, x3, p, ia, ib, ic)
            track[T_PREV_A, i] = va
            track[T_PREV_B, i] = vb
            track[T_PREV_AMP2, i] = vb * vb + vc * vc
            track[T_COUNT_A, i] = count_a
            track[T_FIRST_A, i] = first_a
            track[T_LAST_A, i] = last_a
            track[T_COUNT_B, i] = count_b
            track[T_FIRST_B, i] = first_b
            track[T_LAST_B, i] = last_b
            track[T_MAX_AMP2, i] = max_amp2
            track[T_NEXT_LEVEL, i] = level

    return advance
