"""Names are resolved at the door: ``stability.run_scene`` takes a registered scene's name or a
Scene; the layers below take the Scene alone and refuse a name in one line."""

import inspect

import numpy as np
import pytest

import stability
from stability.engine import propagate_groups
from stability.ensemble import run as scene_run
from stability.ensemble.plan import Plan
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


@pytest.mark.parametrize("call", [
    lambda: propagate_groups("heavy_top", "lp2", np.ones((1, 6)), [[1.0] * 9], [1], 0.1, 1),
    lambda: scene_run.run_scene("heavy_top", "lp2", np.ones((1, 6)), {}, h=0.1, n_steps=1),
    lambda: Plan("heavy_top", "lp2", np.ones((1, 6)), [[1.0] * 9], [1], 0.1, 1),
], ids=["propagate_groups", "ensemble.run.run_scene", "Plan"])
def test_below_the_door_a_name_is_refused_in_one_line_saying_how_to_get_the_scene(call):
    with pytest.raises(TypeError, match=r"takes a Scene, got the name 'heavy_top': "
                                        r"stability.registry.scene\('heavy_top'\)") as caught:
        call()
    assert "\n" not in str(caught.value)
