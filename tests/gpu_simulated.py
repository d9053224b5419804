"""The GPU kernels under the CUDA simulator, against the CPU engine; prints one JSON object.

Run by the ``simulated`` fixture of ``tests/conftest.py`` (for the GPU tests in
``tests/engine/gpu/`` and ``tests/free_body/test_propagate_gpu.py``) in a subprocess with
``NUMBA_ENABLE_CUDASIM=1`` (or without it, with ``--no-device``, to see the error when there is
no GPU), so the simulator never leaks into the other test modules of a pytest-xdist worker. Not
a test module itself (no ``test_`` prefix).
"""

import json
import sys
import time

import numpy as np

import stability
from stability.free_body.propagate import propagate
from stability.free_body.exact import exact_omega_of_starts
from stability.free_body.propagate_gpu import GPU_METHODS

#: A body in non-canonical axis order (body axis 0 is the intermediate one), spun about it.
MOMENTS = np.array([2.0, 1.0, 3.0])
AXIS = 0
SPIN = 3.0
EPSILON = 0.1
MEMBERS = 16
H = 0.04
STEPS = 200
SAVE = 50
LEVELS = [0.05, 0.5, 1.5]


def starts():
    """MEMBERS angular velocities: spin about AXIS plus EPSILON SPIN across it."""
    rng = np.random.default_rng(11)
    w0 = np.zeros((MEMBERS, 3))
    w0[:, AXIS] = SPIN
    angle = rng.uniform(0.0, 2.0 * np.pi, MEMBERS)
    w0[:, 1] = EPSILON * SPIN * np.cos(angle)
    w0[:, 2] = EPSILON * SPIN * np.sin(angle)
    return w0


def relative(a, b):
    """max over members of |a - b| / |b| (rows), or of |a - b| / scale for 1-D."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    if a.ndim == 2:
        scale = np.maximum(np.linalg.norm(b, axis=1), 1e-300)
        return float(np.max(np.linalg.norm(a - b, axis=1) / scale))
    both = np.isfinite(a) & np.isfinite(b)
    return float(np.max(np.abs(a[both] - b[both]), initial=0.0))


def compare(method):
    """GPU against CPU for one method: final states, tracked summaries, saved samples."""
    from stability.free_body.propagate_gpu import propagate_gpu

    m0 = starts() * MOMENTS
    t0 = time.perf_counter()
    gpu = propagate_gpu(method, MOMENTS, m0, H, STEPS, AXIS, levels=LEVELS, save_every=SAVE)
    seconds = time.perf_counter() - t0
    cpu = propagate(method, MOMENTS, m0, H, STEPS, save_every=SAVE, progress=False,
                    track_axis=AXIS, levels=LEVELS)
    g, c = gpu.extras, cpu.extras
    out = {
        "seconds": seconds,
        "final": relative(gpu.m_final, cpu.m_final),
        "bitwise": bool(np.array_equal(gpu.m_final, cpu.m_final)),
        "saved_shape": [list(gpu.saved.shape), list(cpu.saved.shape)],
        "saved": relative(gpu.saved.reshape(-1, 3), cpu.saved.reshape(-1, 3)),
        "status_equal": bool(np.array_equal(gpu.status, cpu.status)),
        "steps_done": [gpu.steps_done, cpu.steps_done],
        "flips_gpu": g["axis_crossings"].tolist(),
        "flips_cpu": c["axis_crossings"].tolist(),
        "perp_equal": bool(np.array_equal(g["perp_crossings"], c["perp_crossings"])),
        "nan_equal": all(bool(np.array_equal(np.isnan(g[k]), np.isnan(c[k])))
                         for k in g if g[k].dtype.kind == "f"),
        "max_amplitude": relative(g["max_perp_amplitude"][:, None],
                                  c["max_perp_amplitude"][:, None]),
    }
    # Event times, relative to the run's length.
    for key in ("first_axis_crossing", "last_axis_crossing", "first_perp_crossing",
                "last_perp_crossing", "passage_time"):
        out[key] = relative(g[key], c[key]) / (H * STEPS)
    return out


def exact_against_elliptic():
    """GPU ``exact`` (1 step of T, and 50 steps of T/50) against stability.free_body.exact at T."""
    from stability.free_body.propagate_gpu import propagate_gpu

    w0 = starts()
    body = stability.RigidBody(*MOMENTS, physical=False)
    t_end = H * STEPS
    reference = exact_omega_of_starts(body, w0, t_end) * MOMENTS
    one = propagate_gpu("exact", MOMENTS, w0 * MOMENTS, t_end, 1).m_final
    many = propagate_gpu("exact", MOMENTS, w0 * MOMENTS, t_end / 50, 50).m_final
    return {"one_step": relative(one, reference), "fifty_steps": relative(many, reference)}


def chunks_and_groups():
    """Chunked launches and grouped ensembles give bitwise the one-launch, one-group result."""
    from stability.free_body.propagate_gpu import propagate_gpu, propagate_many_gpu

    m0 = starts() * MOMENTS
    whole = propagate_gpu("rk4", MOMENTS, m0, H, STEPS, AXIS, levels=LEVELS)
    chunked = propagate_gpu("rk4", MOMENTS, m0, H, STEPS, AXIS, levels=LEVELS, chunk_steps=64)
    other = np.array([1.0, 2.0, 3.0])
    many = propagate_many_gpu("rk4", [MOMENTS, other], np.concatenate([m0, m0[:5]]), [16, 5],
                              [H, 0.01], [STEPS, 100], track_axes=[AXIS, 1],
                              levels=[LEVELS, LEVELS])
    alone = propagate_gpu("rk4", other, m0[:5], 0.01, 100, 1, levels=LEVELS)

    def same(a, b):
        return bool(np.array_equal(a.m_final, b.m_final)) and all(
            np.array_equal(a.extras[k], b.extras[k], equal_nan=True) for k in a.extras)

    head = many.__class__(**{**many.__dict__})
    head.x_final, head.extras = many.x_final[:16], {k: v[:16] for k, v in many.extras.items()}
    tail = many.__class__(**{**many.__dict__})
    tail.x_final, tail.extras = many.x_final[16:], {k: v[16:] for k, v in many.extras.items()}
    return {"chunked": same(chunked, whole), "group0": same(head, whole),
            "group1": same(tail, alone), "steps_done": many.steps_done.tolist()}


#: Every scene and method: members of two groups (two parameter sets of ``scene.example``),
#: steps of each, the step, a sample every SCENE_SAVE steps, and chunks of SCENE_CHUNK steps.
SCENE_MEMBERS = (5, 3)
SCENE_STEPS = (24, 16)
SCENE_H = 0.01
SCENE_SAVE = 4
SCENE_CHUNK = 8
SCENE_LEVELS = [1e-3, 1e-2, 1e-1]


def scene_case(scene, method, propagator, **options):
    """Run ``method`` on ``scene``'s example (two groups, tracked, saved) with ``propagator``
    (:func:`stability.engine.propagate_groups` or its GPU twin)."""
    x0, sets = scene.example(SCENE_MEMBERS[0], seed=3)
    sets = (list(sets) * 2)[:2]
    spec = scene.method(method)
    params = np.array([spec.params(s, SCENE_H) for s in sets])
    x = np.concatenate([x0, x0[:SCENE_MEMBERS[1]]])
    axes = [(1, 0, 2), (2, 0, 1)]
    return propagator(scene, spec, x, params, list(SCENE_MEMBERS), SCENE_H, list(SCENE_STEPS),
                      save_every=SCENE_SAVE, axes=axes, levels=[SCENE_LEVELS] * 2,
                      progress=False, **options)


def scene_differences(gpu, cpu):
    """Largest relative difference of states and tracked times, and what must be equal."""
    def rel(a, b):
        a, b = a.reshape(-1, a.shape[-1]), b.reshape(-1, b.shape[-1])
        ok = np.all(np.isfinite(b), axis=1)
        scale = np.maximum(np.linalg.norm(b[ok], axis=1), 1e-300)
        return float(np.max(np.linalg.norm(a[ok] - b[ok], axis=1) / scale, initial=0.0))

    times = [k for k in cpu.extras if cpu.extras[k].dtype.kind == "f"]
    counts = [k for k in cpu.extras if cpu.extras[k].dtype.kind != "f"]
    return {
        "bitwise": bool(np.array_equal(gpu.x_final, cpu.x_final, equal_nan=True)
                        and np.array_equal(gpu.saved, cpu.saved, equal_nan=True)
                        and all(np.array_equal(gpu.extras[k], cpu.extras[k], equal_nan=True)
                                for k in cpu.extras)),
        "final": rel(gpu.x_final, cpu.x_final),
        "saved": rel(gpu.saved, cpu.saved) if cpu.saved.size else 0.0,
        "shapes": gpu.saved.shape == cpu.saved.shape,
        "times": max((relative(gpu.extras[k], cpu.extras[k]) for k in times), default=0.0)
        / (SCENE_H * max(SCENE_STEPS)),
        "counts_equal": all(np.array_equal(gpu.extras[k], cpu.extras[k]) for k in counts),
        "status_equal": bool(np.array_equal(gpu.status, cpu.status)),
        "iterations_equal": bool(np.array_equal(gpu.iterations, cpu.iterations)),
        "steps_done": [gpu.steps_done.tolist(), cpu.steps_done.tolist()],
    }


def every_scene():
    """Every scene's every GPU method against the CPU loop, in chunked launches."""
    from stability.engine import propagate_groups
    from stability.engine.gpu import gpu_methods, propagate_groups_gpu
    from stability.registry import SCENES

    from tests.gpu_user_scene import DAMPED_BODY

    out = {}
    for scene in (*SCENES.values(), DAMPED_BODY):
        for method in gpu_methods(scene):
            cpu = scene_case(scene, method, propagate_groups)
            gpu = scene_case(scene, method, propagate_groups_gpu, chunk_steps=SCENE_CHUNK)
            out[f"{scene.name}/{method}"] = scene_differences(gpu, cpu)
    return out


#: The scenes whose tangent scenes run on the simulated GPU (the gyrostat's, of 30 numbers,
#: compiles for half a minute and adds no other path).
TANGENT_SCENES = ("free_body", "heavy_top", "sphere_damper")


def tangents_on_gpu():
    """The tangent scenes (state and two tangents, RK4 of the variational equations) of
    :data:`TANGENT_SCENES`, on the GPU against the CPU loop, in chunked launches: the
    tangents, the state-transition matrix's columns, are carried there too."""
    from stability.engine import propagate_groups
    from stability.engine.gpu import gpu_methods, propagate_groups_gpu
    from stability.engine.tangent import tangent_scene
    from stability.registry import SCENES

    out = {}
    for name in TANGENT_SCENES:
        base = SCENES[name]
        scene = tangent_scene(base, 2)
        x0, sets = base.example(SCENE_MEMBERS[0], seed=3)
        tangents = np.zeros((x0.shape[0], 2 * base.width))
        tangents[:, 0], tangents[:, base.width + 1] = 1.0, 1.0
        start = np.hstack([x0, tangents])
        x = np.concatenate([start, start[:SCENE_MEMBERS[1]]])
        for method in gpu_methods(scene):
            spec = scene.method(method)
            params = np.array([spec.params(s, SCENE_H) for s in (list(sets) * 2)[:2]])
            runs = [run(scene, spec, x, params, list(SCENE_MEMBERS), SCENE_H, list(SCENE_STEPS),
                        save_every=SCENE_SAVE, progress=False, **kw)
                    for run, kw in ((propagate_groups_gpu, {"chunk_steps": SCENE_CHUNK}),
                                    (propagate_groups, {}))]
            out[f"{scene.name}/{method}"] = scene_differences(*runs)
    return out


def tennis_on_gpu():
    """The tennis-racket study's measurement of chunks run on the GPU (the loop's canonical
    series read as they come back) against the same chunks on the CPU."""
    import tempfile

    from stability.free_body.streamed import run_streamed
    from stability.free_body.tennis_racket.measure import TennisChunks

    body = stability.RigidBody.preset("tennis_racket")
    from stability.free_body.spin_ensembles import plan_arguments

    run = dict(body=body, axis=2, spin=10.0, epsilon=1e-5, members=10, h=0.02, t_end=3.0,
               seed=2, method="rk4")
    measured = {}
    with tempfile.TemporaryDirectory() as folder:
        for device in ("cpu", "gpu"):
            measured[device] = run_streamed(
                {**run, **plan_arguments(stability.Keep(save_every=5),
                                         stability.RunOptions(chunk_members=4, device=device))},
                stability.RunOptions(store=f"{folder}/{device}", progress=False), compress=False,
                measurement=lambda kw, plan: TennisChunks(kw, (3.0, 0.1), 3,
                                                                          plan))
    cpu, gpu = measured["cpu"], measured["gpu"]
    names = ("member_growth_rate", "mean_flip_interval", "w", "perp_amplitude_count")
    worst = 0.0
    for name in names:
        a, b = cpu[name].values.astype(float), gpu[name].values.astype(float)
        if not np.array_equal(np.isnan(a), np.isnan(b)):
            return {"worst": float("inf"), "variable": name}
        ok = ~np.isnan(a)
        scale = np.maximum(np.abs(a[ok]), 1e-300)
        worst = max(worst, float(np.max(np.abs(a[ok] - b[ok]) / scale, initial=0.0)))
    return {"worst": worst, "rates": int(np.isfinite(cpu.member_growth_rate.values).sum()),
            "kept": int(gpu.sizes["series_member"])}


def stored_on_gpu():
    """A heavy-top run on the GPU streamed to a store in chunks, against the CPU in one piece."""
    import tempfile

    from stability import RunOptions
    from stability.ensemble.chunks import run_plan
    from stability.ensemble.plan import Plan
    from stability.registry import SCENES

    scene = SCENES["heavy_top"]
    x0, tops = scene.example(10, seed=4)
    spec = scene.method("lp2")
    run = Plan(scene, "lp2", x0, [spec.params(t, 0.01) for t in tops[:2]], [6, 4],
               0.01, [40, 30], save_every=10, axes=[2, 0, 1], levels=[0.3, 0.5])
    gpu = Plan(**{**run.__dict__, "device": "gpu"})
    cpu = run.propagate(progress=False)
    with tempfile.TemporaryDirectory() as folder:
        streamed = run_plan(gpu,
                            RunOptions(store=folder + "/store", chunk_members=3, threads=1,
                                       progress=False))
    return {
        "bitwise": bool(np.array_equal(streamed.x_final, cpu.x_final)
                        and np.array_equal(streamed.saved, cpu.saved, equal_nan=True)
                        and all(np.array_equal(streamed.extras[k], cpu.extras[k],
                                               equal_nan=True) for k in cpu.extras)),
        "identity_differs": gpu.identity() != run.identity(),
    }


def errors():
    """The ValueError for a method the scene does not have."""
    from stability.free_body.propagate_gpu import propagate_gpu

    try:
        propagate_gpu("no_such_method", MOMENTS, starts() * MOMENTS, H, 1)
    except ValueError as error:
        return str(error)
    return None


def no_device():
    """What propagate_gpu and run_adaptive say without a GPU and without the simulator."""
    from stability.engine.gpu import NoGPUError, real_gpu
    from stability.free_body.propagate_gpu import propagate_gpu

    if real_gpu():
        return {"real_gpu": True}
    out = {"real_gpu": False, "message": None, "adaptive_message": None}
    try:
        propagate_gpu("rk4", MOMENTS, starts() * MOMENTS, H, 1)
    except NoGPUError as error:
        out["message"] = str(error)
    try:
        from stability.free_body.scene import FREE_BODY

        stability.run_adaptive(FREE_BODY, starts() * MOMENTS, MOMENTS, 1.0, rtol=1e-6,
                               atol=1e-9, options=stability.RunOptions(device="gpu"))
    except NoGPUError as error:
        out["adaptive_message"] = str(error)
    return out


def ensemble_on_gpu():
    """run_ensemble(device="gpu") against the CPU run: the same members, every summary."""
    body = stability.RigidBody(1.0, 2.0, 3.0)
    run = dict(body=body, axis=2, spin=2.0, epsilon=0.05, members=12, h=0.05, t_end=6.0,
               seed=5, method="lp2", keep=stability.Keep(save_every=10))
    cpu = stability.run_ensemble(**run)
    gpu = stability.run_ensemble(**run, options=stability.RunOptions(device="gpu"))
    worst = 0.0
    for name in cpu.data_vars:
        a, b = cpu[name].values.astype(float), gpu[name].values.astype(float)
        same_nan = bool(np.array_equal(np.isnan(a), np.isnan(b)))
        if not same_nan:
            return {"worst": float("inf"), "variable": name}
        ok = ~np.isnan(a)
        scale = np.maximum(np.abs(a[ok]), 1e-300)
        worst = max(worst, float(np.max(np.abs(a[ok] - b[ok]) / scale, initial=0.0)))
    return {"worst": worst, "flips": int(np.nansum(cpu.flip_count.values)),
            "device": gpu.attrs["config_toml"].count('device = "gpu"')}


def datasets_compared(cpu, gpu) -> dict:
    """Every variable of a run with events on the CPU against the same on the GPU: the worst
    relative difference, whether bitwise and NaN at the same places, the crossings and stops."""
    worst, bitwise, same_nan = 0.0, True, True
    for variable in cpu.data_vars:
        a, b = (r[variable].values.astype(float) for r in (cpu, gpu))
        same_nan &= bool(np.array_equal(np.isnan(a), np.isnan(b)))
        bitwise &= bool(np.array_equal(a, b, equal_nan=True))
        ok = ~np.isnan(a)
        scale = np.maximum(np.abs(a[ok]), 1e-300)
        worst = max(worst, float(np.max(np.abs(a[ok] - b[ok]) / scale, initial=0.0)))
    return {"worst": worst, "bitwise": bitwise, "same_nan": same_nan,
            "events": int(np.sum(cpu.event_count.values)),
            "stopped": int(np.sum(cpu.stop_event.values >= 0))}


def adaptive_on_gpu():
    """run_adaptive on the GPU against the CPU: the free body with a stop event at its second
    down crossing (the first recorded) and samples, and the user's damped body with an event;
    every variable of the Datasets."""
    from tests.gpu_user_scene import DAMPED_BODY
    from stability.free_body.scene import FREE_BODY, flip_event

    m0 = starts()[:3] * MOMENTS
    x0, sets = DAMPED_BODY.example(2, seed=2)
    cases = {
        "free_body": (FREE_BODY, m0, MOMENTS, 20.0, [  # the loop the CPU tests compile
            stability.Event(flip_event, direction="down", action="stop", count=2,
                            name="second_down")]),
        "user_scene": (DAMPED_BODY, x0, sets[0], 10.0, [
            stability.Event(flip_event, count=3, name="w2_crossings")]),
    }
    out = {}
    for name, (scene, start, parameters, t_end, events) in cases.items():
        runs = [stability.run_adaptive(
            scene, start, parameters, t_end, rtol=1e-7, atol=1e-10, events=events,
            samples=np.linspace(0.0, t_end, 7),
            options=stability.RunOptions(progress=False, device=device))
            for device in ("cpu", "gpu")]
        out[name] = datasets_compared(*runs)
    return out


def fixed_step_events_on_gpu():
    """run_scene with events on the GPU against the CPU: the free body's RK4 with the flips
    recorded and a stop at the second, and the user's damped body with its w2 crossings; every
    variable of the Datasets."""
    from tests.gpu_user_scene import DAMPED_BODY
    from stability.free_body.scene import FREE_BODY, flip_event

    x0, sets = DAMPED_BODY.example(2, seed=2)
    cases = {
        "free_body": (FREE_BODY, starts()[:3] * MOMENTS, MOMENTS, 0.05, 400, [
            stability.Event(flip_event, count=3, name="flips"),
            stability.Event(flip_event, action="stop", count=2, name="second_flip")]),
        "user_scene": (DAMPED_BODY, x0, sets[0], 0.05, 200, [
            stability.Event(flip_event, count=3, name="w2_crossings")]),
    }
    out = {}
    for name, (scene, start, parameters, h, n_steps, events) in cases.items():
        runs = [stability.run_scene(scene, "rk4", start, parameters, h=h, n_steps=n_steps,
                                    events=events,
                                    options=stability.RunOptions(progress=False, device=device))
                for device in ("cpu", "gpu")]
        out[name] = datasets_compared(*runs)
    return out


def main():
    # The simulator runs a block's threads as Python threads that take a lock around every
    # device-function call; preempted every 5 ms they hand that lock over one switch interval
    # at a time (runs 100x slower, and worse the longer the kernel). The kernels never wait
    # for each other (no syncthreads), so let each thread run to its end before the next.
    sys.setswitchinterval(5.0)
    if "--no-device" in sys.argv:
        print(json.dumps(no_device()))
        return
    results = {method: compare(method) for method in GPU_METHODS}
    results["exact_vs_elliptic"] = exact_against_elliptic()
    results["chunks_and_groups"] = chunks_and_groups()
    results["no_kernel_error"] = errors()
    results["ensemble"] = ensemble_on_gpu()
    results["every_scene"] = every_scene()
    results["stored"] = stored_on_gpu()
    results["tennis"] = tennis_on_gpu()
    results["tangents"] = tangents_on_gpu()
    results["adaptive"] = adaptive_on_gpu()
    results["fixed_step_events"] = fixed_step_events_on_gpu()
    print(json.dumps(results))


if __name__ == "__main__":
    main()
