"""The member loop (stability.engine.loop): one compiled signature for every kind of run, and the
exact square boundaries that spare it a square root per step."""

import numpy as np
import pytest

from stability.engine import compiled_loop, propagate_groups
from stability.engine.loop import level_thresholds
from stability.registry import SCENES

from ..helpers import starts

MOMENTS = np.array([1.0, 2.0, 3.0])  # canonical already


def test_every_scene_method_pair_compiles_to_one_signature():
    """A second run of any kind (saving, tracking, groups) reuses the compiled loop."""
    scene = SCENES["free_body_attitude"]
    spec = scene.method("lp2")
    x0 = starts(scene, 3)
    p = spec.params(MOMENTS, 0.1)[None, :]
    propagate_groups(scene, spec, x0, p, [3], 0.1, 20, save_every=5, progress=False)
    propagate_groups(scene, spec, x0, p, [3], 0.1, 20, axes=[[1, 0, 2]], levels=[[0.1]],
                     progress=False)
    assert len(compiled_loop(scene, spec).signatures) == 1


@pytest.mark.parametrize("level", [1e-300, 3e-7, 0.1, 1.0, 2.0 ** 0.5, 7.3e12, 1e150])
def test_level_thresholds_are_the_exact_square_boundaries(level):
    """sqrt(x) >= level exactly when x >= threshold: no square root per step is needed."""
    x = float(level_thresholds([level])[0])
    assert np.sqrt(x) >= level
    assert np.sqrt(np.nextafter(x, 0.0)) < level
