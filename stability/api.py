"""The top-level functions that take a registered scene by its name: the door where a name
becomes a :class:`~stability.engine.scene.Scene`.

Below the families, the engine and the ensembles take scenes alone; a name such as
``"heavy_top"`` is looked up here, in :mod:`stability.registry`, before the layer below runs.
"""

from __future__ import annotations

import functools

from .ensemble import adaptive_run, scene_run
from .registry import scene as registered_scene
from .tangents import ftle


@functools.wraps(scene_run.run_scene)
def run_scene(scene, method, x0, parameters, **kwargs):
    return scene_run.run_scene(registered_scene(scene), method, x0, parameters, **kwargs)


@functools.wraps(adaptive_run.run_adaptive)
def run_adaptive(scene, x0, parameters, t_end, **kwargs):
    return adaptive_run.run_adaptive(registered_scene(scene), x0, parameters, t_end, **kwargs)


@functools.wraps(ftle.run_tangents)
def run_tangents(scene, x0, parameters, **kwargs):
    return ftle.run_tangents(registered_scene(scene), x0, parameters, **kwargs)


__all__ = ["run_adaptive", "run_scene", "run_tangents"]
