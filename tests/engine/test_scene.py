"""The Scene the engine takes (stability.engine.scene): below the door a name is refused in one
line saying how to get the scene."""

import numpy as np
import pytest

from stability.engine import propagate_groups
from stability.ensemble import scene_run
from stability.ensemble.plan import Plan


@pytest.mark.parametrize("call", [
    lambda: propagate_groups("heavy_top", "lp2", np.ones((1, 6)), [[1.0] * 9], [1], 0.1, 1),
    lambda: scene_run.run_scene("heavy_top", "lp2", np.ones((1, 6)), {}, h=0.1, n_steps=1),
    lambda: Plan("heavy_top", "lp2", np.ones((1, 6)), [[1.0] * 9], [1], 0.1, 1),
], ids=["propagate_groups", "ensemble.scene_run.run_scene", "Plan"])
def test_below_the_door_a_name_is_refused_in_one_line_saying_how_to_get_the_scene(call):
    with pytest.raises(TypeError, match=r"takes a Scene, got the name 'heavy_top': "
                                        r"stability.registry.scene\('heavy_top'\)") as caught:
        call()
    assert "\n" not in str(caught.value)
