"""The adaptive Dormand-Prince 5(4) member loop as a CUDA kernel: one member per thread.

The GPU twin of :mod:`stability.engine.adaptive`: thread i integrates member i to its own end time
with its own steps, the same PI control, first-step rule, error norm, events located on the
continuous extension by the CPU loop's regula falsi, and samples, in the same order of operations as
the CPU loop's lanes. The scene's vector field, the events' functions and the CPU module's helpers
(``_f``, ``_g``, ``_dense``, ``_root``) are their device twins
(:mod:`stability.engine.gpu.retarget`), so the GPU evaluates the scene's own formulas. Its arguments
are the CPU loop's (``integrate``), members as rows; a member's scratch (stages, the extension's
coefficients, the events' signs) is in thread-local arrays of the state's width.

This module imports ``numba.cuda``: import it only after
:func:`stability.engine.gpu.device.cuda_module` has found a device or the simulator.
"""

from __future__ import annotations

import linecache
import math
import time

import numpy as np
from numba import cuda, float64, int64

from ...util import conventions as cv
from .. import adaptive as cpu
from .device import cuda_module
from .support import THREADS_PER_BLOCK
from .retarget import device_twin

_KERNELS: dict = {}

_TEMPLATE = '''\
def integrate(x, rows, group, t_end, rtol, atol, max_steps, directions, stops, keep, samples,
              t_final, accepted, rejected, error, error_sum, h_last, status, counts, times,
              stop_event, x_sample):
    i = cuda.grid(1)
    if i >= x.shape[0]:
        return
    p = rows[group[i]]
    n = {n}
    m = directions.shape[0]
    y = cuda.local.array({n}, float64)
    z = cuda.local.array({n}, float64)
    c = cuda.local.array({n}, float64)
    cz = cuda.local.array({n}, float64)
    s = cuda.local.array({n}, float64)
    a1 = cuda.local.array({n}, float64)
    k1 = cuda.local.array({n}, float64)
    k2 = cuda.local.array({n}, float64)
    k3 = cuda.local.array({n}, float64)
    k4 = cuda.local.array({n}, float64)
    k5 = cuda.local.array({n}, float64)
    k6 = cuda.local.array({n}, float64)
    k7 = cuda.local.array({n}, float64)
    r = cuda.local.array(({five}, {n}), float64)
    g_old = cuda.local.array({m}, float64)
    g_new = cuda.local.array({m}, float64)
    t_hit = cuda.local.array({m}, float64)
    order = cuda.local.array({m}, int64)
    for j in range(n):
        y[j] = x[i, j]
        c[j] = 0.0
    tend = t_end[i]
    t = 0.0
    n_samples = samples.shape[0]
    si = 0
    while si < n_samples and samples[si] <= 0.0:
        for j in range(n):
            x_sample[i, si, j] = y[j]
        si += 1
    _f(y, p, k1)
    for k in range(m):
        g_old[k] = _g(k, y, 0.0, p)
    d0 = 0.0
    d1 = 0.0
    for j in range(n):
        a1[j] = atol + rtol * abs(y[j])
        d0 += (y[j] / a1[j]) ** 2
        d1 += (k1[j] / a1[j]) ** 2
    d0 = math.sqrt(d0 / n)
    d1 = math.sqrt(d1 / n)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    h0 = min(h0, tend)
    for j in range(n):
        s[j] = y[j] + h0 * k1[j]
    _f(s, p, k2)
    d2 = 0.0
    for j in range(n):
        d2 += ((k2[j] - k1[j]) / a1[j]) ** 2
    d2 = math.sqrt(d2 / n) / h0
    top = max(d1, d2)
    h1 = max(1e-6, 1e-3 * h0) if top <= 1e-15 else (0.01 / top) ** 0.2
    h = min(100.0 * h0, h1, tend)
    log_fac_old = LOG_FLOOR
    was_rejected = False
    bad = False
    nacc = 0
    nrej = 0
    err = math.nan
    esum = 0.0
    used = math.nan
    code = STATUS_OK
    stopped = -1
    while t < tend:
        if nacc + nrej >= max_steps:
            code = STATUS_MAX_STEPS
            break
        if not (t + h > t):
            code = STATUS_NONFINITE if bad else STATUS_STEP_TOO_SMALL
            break
        last = t + 1.01 * h >= tend
        if last:
            h = tend - t
        for j in range(n):
            s[j] = y[j] + h * A21 * k1[j]
        _f(s, p, k2)
        for j in range(n):
            s[j] = y[j] + h * (A31 * k1[j] + A32 * k2[j])
        _f(s, p, k3)
        for j in range(n):
            s[j] = y[j] + h * (A41 * k1[j] + A42 * k2[j] + A43 * k3[j])
        _f(s, p, k4)
        for j in range(n):
            s[j] = y[j] + h * (A51 * k1[j] + A52 * k2[j] + A53 * k3[j] + A54 * k4[j])
        _f(s, p, k5)
        for j in range(n):
            s[j] = y[j] + h * (A61 * k1[j] + A62 * k2[j] + A63 * k3[j] + A64 * k4[j]
                               + A65 * k5[j])
        _f(s, p, k6)
        for j in range(n):
            d = h * (B1 * k1[j] + B3 * k3[j] + B4 * k4[j] + B5 * k5[j] + B6 * k6[j]) + c[j]
            zj = y[j] + d
            back = zj - y[j]
            cz[j] = (y[j] - (zj - back)) + (d - back)
            z[j] = zj
        _f(z, p, k7)
        for j in range(n):
            s[j] = h * (E1 * k1[j] + E3 * k3[j] + E4 * k4[j] + E5 * k5[j] + E6 * k6[j]
                        + E7 * k7[j])
        total = 0.0
        for j in range(n):
            q = s[j] / (atol + rtol * max(abs(y[j]), abs(z[j])))
            total += q * q
        e = math.sqrt(total / n)
        if not (e < math.inf):
            bad = True
            nrej += 1
            h *= FAC_MIN
            was_rejected = True
            continue
        bad = False
        log_e = math.log(e)
        fac = max(1.0 / FAC_MAX, min(1.0 / FAC_MIN,
                                     math.exp(EXPO1 * log_e - BETA * log_fac_old) / SAFE))
        h_new = h / fac
        if e > 1.0:
            nrej += 1
            h = h / min(1.0 / FAC_MIN, math.exp(EXPO1 * log_e) / SAFE)
            was_rejected = True
            continue
        log_fac_old = log_e if e > 1e-4 else LOG_FLOOR
        if was_rejected:
            h_new = min(h_new, h)
        was_rejected = False
        nacc += 1
        err = e
        local = 0.0
        for j in range(n):
            local += s[j] * s[j]
        esum += math.sqrt(local)
        used = h
        t_new = tend if last else t + h
        hits = 0
        for k in range(m):
            g_new[k] = _g(k, z, t_new, p)
            up = g_old[k] < 0.0 and g_new[k] >= 0.0
            down = g_old[k] >= 0.0 and g_new[k] < 0.0
            if (up and directions[k] >= 0) or (down and directions[k] <= 0):
                order[hits] = k
                hits += 1
        if hits > 0 or (si < n_samples and samples[si] < t_new):
            for j in range(n):
                r[0, j] = y[j]
                r[1, j] = z[j] - y[j]
                r[2, j] = h * k1[j] - r[1, j]
                r[3, j] = r[1, j] - h * k7[j] - r[2, j]
                r[4, j] = h * (D1 * k1[j] + D3 * k3[j] + D4 * k4[j] + D5 * k5[j] + D6 * k6[j]
                               + D7 * k7[j])
        if hits > 0:
            for q in range(hits):
                k = order[q]
                t_hit[k] = _root(k, r, t, t_new - t, g_old[k], g_new[k], p, a1)
            for q in range(1, hits):
                k = order[q]
                w = q
                while w > 0 and t_hit[order[w - 1]] > t_hit[k]:
                    order[w] = order[w - 1]
                    w -= 1
                order[w] = k
            for q in range(hits):
                k = order[q]
                counts[i, k] += 1
                if counts[i, k] <= keep[k]:
                    times[i, k, counts[i, k] - 1] = t_hit[k]
                if stops[k] and counts[i, k] == keep[k]:
                    stopped = k
                    break
        t_upto = t_hit[stopped] if stopped >= 0 else t_new
        while si < n_samples and samples[si] <= t_upto:
            if samples[si] == t_new:
                for j in range(n):
                    x_sample[i, si, j] = z[j]
            else:
                _dense(r, (samples[si] - t) / (t_new - t), a1)
                for j in range(n):
                    x_sample[i, si, j] = a1[j]
            si += 1
        if stopped >= 0:
            _dense(r, (t_hit[stopped] - t) / (t_new - t), y)
            t = t_hit[stopped]
            break
        for j in range(n):
            y[j] = z[j]
            c[j] = cz[j]
            k1[j] = k7[j]
        for k in range(m):
            g_old[k] = g_new[k]
        t = t_new
        h = h_new
    for j in range(n):
        x[i, j] = y[j]
    t_final[i] = t
    accepted[i] = nacc
    rejected[i] = nrej
    error[i] = err
    error_sum[i] = esum
    h_last[i] = used
    status[i] = code
    stop_event[i] = stopped
'''


def integrate_adaptive_gpu(scene, x0, rows, group, t_end, *, rtol, atol, events=(),
                           max_steps=cpu.MAX_STEPS, samples=None,
                           threads_per_block=THREADS_PER_BLOCK) -> cpu.AdaptiveRun:
    """:func:`stability.engine.adaptive.integrate_adaptive` on a CUDA GPU (or the simulator):
    the same parameters and checks, and results that agree with the CPU's to round-off (the
    device contracts products into fused multiply-adds, and its ``log`` and ``exp`` are not
    glibc's: a step can then differ in its last bits).

    Parameters
    ----------
    scene, x0, rows, group, t_end, rtol, atol, events, max_steps, samples
        As :func:`~stability.engine.adaptive.integrate_adaptive`.
    threads_per_block : int, optional
        CUDA threads per block.

    Returns
    -------
    AdaptiveRun
        Its ``wall_time`` includes compiling the kernel, at its first launch in a process.

    Raises
    ------
    NoGPUError
        One line, where there is neither a CUDA GPU nor the simulator.
    """
    cuda_module()  # NoGPUError, one line, where there is neither a GPU nor the simulator
    events, out, arguments = cpu.prepared_run(scene, x0, rows, group, t_end, rtol=rtol,
                                              atol=atol, events=events, max_steps=max_steps,
                                              samples=samples)
    kernel = adaptive_kernel(scene, tuple((e.g, e.name) for e in events))
    arrays = (out.x_final,) + arguments
    on_device = [cuda.to_device(a) if isinstance(a, np.ndarray) else a for a in arrays]
    members = out.x_final.shape[0]
    blocks = max(1, -(-members // threads_per_block))
    t0 = time.perf_counter()
    kernel[blocks, threads_per_block](*on_device)
    cuda.synchronize()
    out.wall_time = time.perf_counter() - t0
    filled = {id(a) for a in vars(out).values() if isinstance(a, np.ndarray)}  # the results
    for host, device in zip(arrays, on_device):
        if id(host) in filled:
            device.copy_to_host(host)
    return out


def adaptive_kernel(scene, events=()):
    """The CUDA kernel of :func:`stability.engine.adaptive.adaptive_loop` for ``scene`` and the
    events ``((g, name), ...)`` (made once a process); launched as
    ``integrate[blocks, threads](...)`` with the CPU loop's arguments, on device arrays.

    Parameters
    ----------
    scene : Scene
        A scene with a vector field.
    events : tuple of (function, str), optional
        The events' functions and names, as :func:`~stability.engine.adaptive.adaptive_loop`
        takes them.

    Returns
    -------
    CUDA kernel
    """
    key = (scene, tuple(g for g, _ in events))
    if key not in _KERNELS:
        helpers = cpu.adaptive_loop(scene, events).py_func.__globals__
        source = _TEMPLATE.format(n=scene.width, m=max(len(events), 1), five=5)
        filename = f"<stability.engine.gpu adaptive loop: {scene.name}, {len(events)} event(s)>"
        linecache.cache[filename] = (len(source), None, source.splitlines(True), filename)
        namespace = {"cuda": cuda, "math": math, "float64": float64, "int64": int64,
                     "STATUS_OK": cv.STATUS_OK, "STATUS_NONFINITE": cv.STATUS_NONFINITE,
                     "STATUS_MAX_STEPS": cv.STATUS_MAX_STEPS,
                     "STATUS_STEP_TOO_SMALL": cv.STATUS_STEP_TOO_SMALL}
        namespace.update({name: getattr(cpu, name) for name in _CONSTANTS})
        namespace.update({name: device_twin(cuda, helpers[name])
                          for name in ("_f", "_g", "_dense", "_root")})
        exec(compile(source, filename, "exec"), namespace)  # noqa: S102 (our own template)
        _KERNELS[key] = cuda.jit(namespace["integrate"])
    return _KERNELS[key]


#: The method's constants the kernel reads (:mod:`stability.engine.adaptive`).
_CONSTANTS = ("A21", "A31", "A32", "A41", "A42", "A43", "A51", "A52", "A53", "A54", "A61", "A62",
              "A63", "A64", "A65", "B1", "B3", "B4", "B5", "B6", "D1", "D3", "D4", "D5", "D6",
              "D7", "E1", "E3", "E4", "E5", "E6", "E7", "BETA", "EXPO1", "SAFE", "FAC_MIN",
              "FAC_MAX", "LOG_FLOOR")

__all__ = ["adaptive_kernel", "integrate_adaptive_gpu"]
