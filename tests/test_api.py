"""Names are resolved at the door: ``stability.run_scene`` takes a registered scene's name or a
Scene (the layers below take the Scene alone: ``tests/engine/test_scene.py``)."""

import inspect

import numpy as np
import pytest

import stability
from stability.ensemble import scene_run
from stability.heavy_top.scene import HEAVY_TOP
from stability.registry import scene


def test_the_door_has_the_signature_and_docs_of_the_run_it_opens():
    assert inspect.signature(stability.run_scene) == inspect.signature(scene_run.run_scene)
    assert stability.run_scene.__doc__ == scene_run.run_scene.__doc__


def test_the_door_looks_a_name_up_in_the_registry():
    assert scene("heavy_top") is HEAVY_TOP
    with pytest.raises(ValueError, match="heavy_tops"):
        stability.run_scene("heavy_tops", "lp2", np.ones((1, 6)), HEAVY_TOP.example(1)[1][0],
                            h=0.01, n_steps=1)

