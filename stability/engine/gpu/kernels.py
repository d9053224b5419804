"""The member loop as a CUDA kernel: one member per thread, its state in registers.

The GPU twin of :mod:`stability.engine.loop`, for any scene. Like the CPU loop it is written once,
as the template below, and rendered for each (scene, method) with the state's width, the stage
count and the solver's bookkeeping written in; the scene's stage kernel and ``observe`` are
their device twins (:mod:`stability.engine.gpu.retarget`), so the GPU runs the scene's own formulas.

Thread i advances member i for ``n_steps`` steps, commits each step with the same Kahan
compensated sum, and tracks what the CPU loop tracks, with the same definitions: sign changes of
the spin-axis component ``a`` (flips) and of the first perpendicular component ``b``, each with
the first and last time interpolated linearly within the step, the largest ``b^2 + c^2``, the
first passage of ``sqrt(b^2 + c^2)`` through each level (interpolated in its logarithm), a
non-finite check every ``CHECK_EVERY`` global steps, and for implicit methods the solver's
iterations and its first failure. Everything a member carries between steps lives in registers;
global memory is read at the start and written at the end (and at saved samples and level
passages), so the memory traffic is independent of the number of steps.

Layout: structure of arrays, members along the last axis (``x[k, i]``, ``track[col, i]``,
``passage[level, i]``, ``saved[sample, k, i]``), so consecutive threads touch consecutive
addresses (coalesced). A member's group ``group[i]`` selects its parameter row, step, step count,
tracking axes and levels, as blocks of the CPU loop do.

This module imports ``numba.cuda``: import it only after
:func:`stability.engine.gpu.device.cuda_module` has found a device or the simulator. (The kernel reads
``cuda`` as a global of its namespace, which is where the simulator swaps in its own.)
"""

from __future__ import annotations

import linecache
import math

from numba import cuda, float64, int64

from ...util.conventions import STATUS_NONFINITE, STATUS_NOT_CONVERGED, STATUS_OK
from .. import loop as cpu_loop
from ..events import located
from ..loop import EVENT_ARGS
from ..driver import compiled_loop
from .retarget import device_twin

_KERNELS: dict = {}

#: Kernel arguments, in order (shapes in :func:`stability.engine.gpu.driver.propagate_groups_gpu`).
ARGUMENTS = ("x", "comp", "params", "group", "hs", "steps", "step0", "axes", "track",
             "thresholds", "levels", "passage", "status", "fail_step", "iterations", "saved",
             "save_every", "k0")

_TEMPLATE = '''\
def advance({arguments}{event_arguments}):
    i = cuda.grid(1)
    if i >= x.shape[1]:
        return
    g = group[i]
    n_steps = steps[g]
    if n_steps == 0:  # a group already done (the CPU loop gives it no blocks)
        return
    p = params[g]
    h = hs[g]
    first_step = step0[g]
{load}
    bad = 0
    first_bad = -1
    nonconv = 0
    first_nonconv = -1
    iters = 0
    k = k0[g]
{track_load}
{event_load}
    for n in range(n_steps):
{stages}
{commit}
{track_step}
{event_step}
        if (first_step + n + 1) % CHECK_EVERY == 0:  # global steps, as on the CPU
            now_bad = not_finite({total})
            if now_bad == 1 and bad == 0:
                first_bad = n
            bad |= now_bad
        if save_every > 0 and (n + 1) % save_every == 0:
{save}
            k += 1
{store}
    iterations[i] += iters
    # The earlier failure wins, so the status does not depend on where launches end.
    failed_at = first_step + first_bad + 1 if bad != 0 else -1
    stuck_at = first_step + first_nonconv + 1 if nonconv != 0 else -1
    ok = status[i] == STATUS_OK
    if ok and failed_at >= 0 and (stuck_at < 0 or failed_at <= stuck_at):
        status[i] = STATUS_NONFINITE
        fail_step[i] = failed_at
    elif ok and stuck_at >= 0:
        status[i] = STATUS_NOT_CONVERGED
        fail_step[i] = stuck_at
{track_store}
{event_store}
'''

# Events (the CPU loop's, stability.engine.loop.event_source): each g at the start or carried,
# then after every step at the new state; where one changed sign, the CPU module's own
# _step_events (its device twin) locates the crossings on the method's step and takes them.
_EVENT_LOAD = '''\
xs = cuda.local.array({width}, float64)
yo = cuda.local.array({width}, float64)
out = cuda.local.array({width}, float64)
gp = cuda.local.array({m}, float64)
gn = cuda.local.array({m}, float64)
t_hit = cuda.local.array({m}, float64)
order = cuda.local.array({m}, int64)
stopped = stop_event[i] >= 0
{fill}
for q in range({m}):
    gp[q] = _g(q, xs, 0.0, p) if first_step == 0 else ev_prev[i, q]'''

_EVENT_STEP = '''\
if not stopped:
    t_new = (first_step + n + 1) * h
{fill}
    hit = False
    for q in range({m}):
        gn[q] = _g(q, xs, t_new, p)
        hit = hit or crossed(gp[q], gn[q])
    if hit:
{old}
        _step_events(i, yo, t_new - h, h, p, gp, gn, ev_dir, ev_stop, ev_keep, ev_count,
                     ev_time, stop_x, stop_t, stop_event, t_hit, order, out)
        stopped = stop_event[i] >= 0
    for q in range({m}):
        gp[q] = gn[q]'''

_EVENT_STORE = '''\
for q in range({m}):
    ev_prev[i, q] = gp[q]'''

_TRACK_LOAD = '''\
ia = axes[g, 0]
ib = axes[g, 1]
ic = axes[g, 2]
th = thresholds[g]
lv = levels[g]
n_levels = lv.shape[0]
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
next_th = th[level]'''

# The events of one step: the scalar pass of the CPU loop (record_events), rare.
_TRACK_STEP = '''\
a0, b0, cc0 = observe({old}, p, ia, ib, ic)
va, vb, vc = observe({state}, p, ia, ib, ic)
amp2 = vb * vb + vc * vc
hit = crossed(a0, va) or crossed(b0, vb) or amp2 >= next_th
max_amp2 = max(max_amp2, amp2)
if hit:
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
        count_a, first_a, last_a = counted_crossing(count_a, first_a, last_a, pa, va, t_prev, h)
    if crossed(pb, vb):
        count_b, first_b, last_b = counted_crossing(count_b, first_b, last_b, pb, vb, t_prev, h)
    if level < n_levels and amp2 >= th[level]:
        amp = math.sqrt(amp2)
        prev_amp = math.sqrt(pamp2)
        while level < n_levels and amp2 >= th[level]:
            passage[level, i] = t_prev + h * passage_fraction(lv[level], prev_amp, amp)
            level += 1
    next_th = th[level]'''

_TRACK_STORE = '''\
va, vb, vc = observe({state}, p, ia, ib, ic)
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
track[T_NEXT_LEVEL, i] = level'''


def _indent(text, depth):
    return "\n".join("    " * depth + line if line else line for line in text.splitlines())


def render(width, stages, implicit, tracked, events=0) -> str:
    """Source of the CUDA member loop for a state of ``width`` numbers.

    Parameters
    ----------
    width : int
        Numbers per member in the state.
    stages : int
        Kernel calls per step, each from the state plus the earlier stages' increments.
    implicit : bool
        Count the kernel's solver iterations and its first failure (``it < 0``).
    tracked : bool
        Compile the tracking of flips, crossings, amplitudes and levels in.
    events : int, default 0
        Events the loop locates (its namespace then holds the CPU event loop's ``_g`` and
        ``_step_events``); the kernel takes :data:`stability.engine.loop.EVENT_ARGS` too.
    """
    xs = [f"x{k}" for k in range(width)]
    state = ", ".join(xs)
    es = ", ".join(f"e{k}" for k in range(width))
    solver = ["iters += it if it > 0 else 0",
              "if it < 0 and nonconv == 0:",
              "    first_nonconv = n",
              "    nonconv = 1"] if implicit else []
    if stages == 1:
        stage = [f"{es}, it = step({state}, h, p, 0)"]
        stage += [f"d{k} = e{k}" for k in range(width)] + solver
    else:
        stage = [f"d{k} = 0.0" for k in range(width)]
        shifted = ", ".join(f"x{k} + d{k}" for k in range(width))
        stage += [f"for s in range({stages}):", f"    {es}, it = step({shifted}, h, p, s)"]
        stage += [f"    d{k} += e{k}" for k in range(width)]
        stage += ["    " + line for line in solver]
    commit = [f"o{k} = x{k}" for k in range(width)] if tracked or events else []
    commit += [f"x{k}, c{k} = kahan(x{k}, c{k}, d{k})" for k in range(width)]
    load = [f"x{k} = x[{k}, i]" for k in range(width)]
    load += [f"c{k} = comp[{k}, i]" for k in range(width)]
    store = [f"x[{k}, i] = x{k}" for k in range(width)]
    store += [f"comp[{k}, i] = c{k}" for k in range(width)]
    old = ", ".join(f"o{k}" for k in range(width))
    return _TEMPLATE.format(
        arguments=", ".join(ARGUMENTS),
        load=_indent("\n".join(load), 1),
        track_load=_indent(_TRACK_LOAD, 1) if tracked else "",
        stages=_indent("\n".join(stage), 2),
        commit=_indent("\n".join(commit), 2),
        track_step=_indent(_TRACK_STEP.format(old=old, state=state), 2) if tracked else "",
        total=" + ".join(xs),
        save=_indent("\n".join(f"saved[k, {j}, i] = x{j}" for j in range(width)), 3),
        store=_indent("\n".join(store), 1),
        track_store=_indent(_TRACK_STORE.format(state=state), 1) if tracked else "",
        event_arguments=(", " + ", ".join(EVENT_ARGS)) if events else "",
        **_event_parts(width, events),
    )


def _event_parts(width, m) -> dict:
    if not m:
        return {"event_load": "", "event_step": "", "event_store": ""}
    fill = "\n".join(f"xs[{k}] = x{k}" for k in range(width))
    return {
        "event_load": _indent(_EVENT_LOAD.format(width=width, m=m, fill=fill), 1),
        "event_step": _indent(_EVENT_STEP.format(
            m=m, fill=_indent(fill, 1),
            old=_indent("\n".join(f"yo[{k}] = o{k}" for k in range(width)), 2)), 2),
        "event_store": _indent(_EVENT_STORE.format(m=m), 1)}


def member_kernel(scene, spec, tracked=True, events=()):
    """The CUDA kernel advancing members of ``scene`` with ``spec`` (made once per process).

    Parameters
    ----------
    scene : Scene
        The scene (registered or the user's own).
    spec : MethodSpec
        One of its methods (:func:`stability.engine.gpu.support.gpu_method`).
    tracked : bool
        Compile the tracking of flips, crossings, amplitudes and levels in (or leave it out).
    events : tuple of Event, optional
        Events the kernel locates, as the CPU loop does (its helpers' device twins).

    Returns
    -------
    CUDA kernel
        ``advance[blocks, threads](*ARGUMENTS)``; shapes in
        :func:`stability.engine.gpu.driver.propagate_groups_gpu`.
    """
    kernel = scene.kernel(spec)
    key = (scene.name, scene.source, spec.name, kernel, scene.observe, bool(tracked),
           tuple(located(event.g) for event in events))
    if key not in _KERNELS:
        _KERNELS[key] = _build(scene, spec, kernel, bool(tracked), tuple(events))
    return _KERNELS[key]


def _build(scene, spec, kernel, tracked, events):
    source = render(scene.width, spec.stages, spec.implicit, tracked, len(events))
    filename = f"<stability.engine.gpu member loop: {scene.name}, {spec.name}>"
    linecache.cache[filename] = (len(source), None, source.splitlines(True), filename)
    namespace = {
        "cuda": cuda, "math": math,
        "step": device_twin(cuda, kernel), "observe": device_twin(cuda, scene.observe),
        "kahan": device_twin(cuda, cpu_loop.kahan),
        "crossed": device_twin(cuda, cpu_loop.crossed),
        "counted_crossing": device_twin(cuda, cpu_loop.counted_crossing),
        "passage_fraction": device_twin(cuda, cpu_loop.passage_fraction),
        "not_finite": device_twin(cuda, cpu_loop.not_finite),
        "CHECK_EVERY": cpu_loop.CHECK_EVERY, "STATUS_OK": STATUS_OK,
        "STATUS_NONFINITE": STATUS_NONFINITE, "STATUS_NOT_CONVERGED": STATUS_NOT_CONVERGED,
    }
    namespace.update({name: getattr(cpu_loop, name) for name in dir(cpu_loop)
                      if name.startswith("T_")})
    if events:  # the CPU event loop's helpers, as device twins
        helpers = compiled_loop(scene, spec, True, events).py_func.__globals__
        namespace.update({name: device_twin(cuda, helpers[name])
                          for name in ("_g", "_step_events")})
        namespace.update(float64=float64, int64=int64)
    exec(compile(source, filename, "exec"), namespace)
    return cuda.jit(namespace["advance"])
