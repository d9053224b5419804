"""Which scenes and methods the GPU runs, and the launch shape (no CUDA import here)."""

from __future__ import annotations

from ..scene import checked_scene

#: (scene, method) pairs whose stage kernel cannot be compiled for the device, with the reason.
#: Every other method of every scene, the user's own included, runs on the GPU: its kernels are
#: retargeted (:mod:`stability.engine.gpu.retarget`).
NOT_ON_GPU: dict = {}

#: Threads per block: 128 keeps 16 resident blocks per SM within the register file at up to
#: 128 registers a thread (FP64 state, tracking and stage temporaries).
THREADS_PER_BLOCK = 128


def gpu_methods(scene) -> tuple:
    """Names of the methods of ``scene`` (a Scene) with a GPU kernel."""
    scene = checked_scene(scene, "gpu_methods")
    return tuple(name for name in scene.methods if (scene.name, name) not in NOT_ON_GPU)


def gpu_method(method, scene):
    """The spec of ``method`` in ``scene`` (a Scene) if it has a GPU kernel, else ValueError
    naming those that do."""
    scene = checked_scene(scene, "gpu_method")
    spec = scene.method(method)
    if (scene.name, spec.name) in NOT_ON_GPU:
        raise ValueError(
            f"method {spec.name!r} of scene {scene.name!r} has no GPU kernel "
            f"({NOT_ON_GPU[scene.name, spec.name]}); methods with one: "
            f"{', '.join(gpu_methods(scene))}"
        )
    return spec
