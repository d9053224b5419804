"""Names are resolved at the door: ``stability.run_scene``, ``stability.run_adaptive`` and
``stability.run_tangents`` take a registered scene's name or a Scene (the layers below take the
Scene alone: ``tests/engine/test_scene.py``)."""

import inspect

import numpy as np
import pytest

import stability
from stability.ensemble import adaptive_run, scene_run
from stability.tangents import ftle
from stability.heavy_top.scene import HEAVY_TOP
from stability.registry import scene


@pytest.mark.parametrize("door,run", [(stability.run_scene, scene_run.run_scene),
                                       (stability.run_adaptive, adaptive_run.run_adaptive),
                                       (stability.run_tangents, ftle.run_tangents)])
def test_the_door_has_the_signature_and_docs_of_the_run_it_opens(door, run):
    assert door.__wrapped__ is run  # what inspect.signature and help() read through
    assert inspect.signature(door) == inspect.signature(run)
    assert door.__doc__ == run.__doc__


def test_the_door_looks_a_name_up_in_the_registry():
    assert scene("heavy_top") is HEAVY_TOP
    with pytest.raises(ValueError, match="heavy_tops"):
        stability.run_scene("heavy_tops", "lp2", np.ones((1, 6)), HEAVY_TOP.example(1)[1][0],
                            h=0.01, n_steps=1)



@pytest.mark.parametrize("door,module,name,more,options", [
    (stability.run_adaptive, adaptive_run, "run_adaptive", (0.5,), {"rtol": 1e-8, "atol": 0.0}),
    (stability.run_tangents, ftle, "run_tangents", (), {"h": 0.01, "every": 10, "windows": 2}),
], ids=["run_adaptive", "run_tangents"])
def test_a_run_by_name_runs_the_registered_scene(monkeypatch, door, module, name, more, options):
    """The door hands the run below it the registered Scene and every argument as given."""
    calls = []
    monkeypatch.setattr(module, name, lambda *args, **kwargs: calls.append((args, kwargs)) or "ran")
    x0, sets = HEAVY_TOP.example(2)
    assert door("heavy_top", x0, sets[0], *more, **options) == "ran"
    (args, kwargs), = calls
    assert args[0] is HEAVY_TOP and args[1] is x0 and args[2] is sets[0] and args[3:] == more
    assert kwargs == options
    with pytest.raises(ValueError, match="heavy_tops"):
        door("heavy_tops", x0, sets[0], *more, **options)
