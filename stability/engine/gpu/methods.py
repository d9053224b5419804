"""Which scenes and methods the GPU runs, and the launch shape (no CUDA import here)."""

from __future__ import annotations

from ...registry import scene as registered_scene

#: (scene, method) pairs whose stage kernel cannot be compiled for the device, with the reason.
#: Every other method of every scene, the user's own included, runs on the GPU: its kernels are
#: retargeted (:mod:`stability.engine.gpu.retarget`).
NOT_ON_GPU: dict = {}

#: Threads per block: 128 keeps 16 resident blocks per SM within the register file at up to
#: 128 registers a thread (FP64 state, tracking and stage temporaries).
THREADS_PER_BLOCK = 128


def gpu_methods(scene="free_body") -> tuple:
    """Names of the methods of ``scene`` (a name or a Scene) with a GPU kernel."""
    scene = registered_scene(scene)
    return tuple(name for name in scene.methods if (scene.name, name) not in NOT_ON_GPU)


#: Methods with a GPU kernel for the free body (``gpu_methods("free_body")``).
GPU_METHODS = gpu_methods("free_body")


def gpu_method(method, scene="free_body"):
    """The spec of ``method`` in ``scene`` if it has a GPU kernel, else ValueError naming those
    that do."""
    scene = registered_scene(scene)
    spec = scene.method(method)
    if (scene.name, spec.name) in NOT_ON_GPU:
        raise ValueError(
            f"method {spec.name!r} of scene {scene.name!r} has no GPU kernel "
            f"({NOT_ON_GPU[scene.name, spec.name]}); methods with one: "
            f"{', '.join(gpu_methods(scene))}"
        )
    return spec
