"""Every scene and method on a real CUDA GPU against the CPU loop; not a test module.

``python tests/gpu_device.py reference FILE`` runs the cases of ``tests/gpu_simulated.py``
(``scene_case``: every scene's every method and a scene of the user's own, two groups, tracked,
saved) on the CPU and writes the results to FILE (``.npz``); ``python tests/gpu_device.py check
FILE`` runs them on the GPU and prints, per case, the largest relative difference from FILE's
(states, saved samples, event times over the run's length), and whether the counts, statuses
and solver iterations are equal. So a GPU machine without the CPU loops compiled can check
itself against a CPU run made elsewhere.
"""

import sys

import numpy as np

from tests.gpu_simulated import scene_case, scene_differences
from tests.gpu_user_scene import DAMPED_BODY


def cases():
    from stability.engine.gpu import gpu_methods
    from stability.registry import SCENES

    for scene in (*SCENES.values(), DAMPED_BODY):
        for method in gpu_methods(scene):
            yield scene, method


def reference(path):
    from stability.engine import propagate_groups

    out = {}
    for scene, method in cases():
        run = scene_case(scene, method, propagate_groups)
        key = f"{scene.name}/{method}"
        for name in ("x_final", "saved", "status", "iterations", "steps_done"):
            out[f"{key}:{name}"] = getattr(run, name)
        for name, value in run.extras.items():
            out[f"{key}:extras.{name}"] = value
    np.savez_compressed(path, **out)


def check(path):
    from stability.engine import Propagation
    from stability.engine.gpu import propagate_groups_gpu

    stored = np.load(path)
    worst = 0.0
    print(f"{'case':<36} {'final':>9} {'saved':>9} {'times':>9}  equal (counts status iters)")
    for scene, method in cases():
        key = f"{scene.name}/{method}"
        fields = {k.split(":", 1)[1]: stored[k] for k in stored.files if k.startswith(key + ":")}
        cpu = Propagation(
            x_final=fields["x_final"], saved=fields["saved"], status=fields["status"],
            fail_step=None, iterations=fields["iterations"], steps_done=fields["steps_done"],
            extras={k[7:]: v for k, v in fields.items() if k.startswith("extras.")})
        try:
            gpu = scene_case(scene, method, propagate_groups_gpu, chunk_steps=8)
        except Exception as error:
            print(f"{key:<36} failed: {type(error).__name__}: {str(error)[:300]}", flush=True)
            continue
        r = scene_differences(gpu, cpu)
        worst = max(worst, r["final"], r["saved"], r["times"])
        print(f"{key:<36} {r['final']:>9.1e} {r['saved']:>9.1e} {r['times']:>9.1e}  "
              f"{r['counts_equal']} {r['status_equal']} {r['iterations_equal']}", flush=True)
    print(f"worst relative difference: {worst:.2e}")


if __name__ == "__main__":
    {"reference": reference, "check": check}[sys.argv[1]](sys.argv[2])
