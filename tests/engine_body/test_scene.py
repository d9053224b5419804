"""The engines' scene (stability.engine_body.scene): its methods are the engine rules, not the
package's methods."""

from stability.engine_body.methods import ENGINE_RULES
from stability.free_body.methods import METHODS

from .test_methods import CONSISTENT, SCENE


def test_the_rules_are_the_scene_s_own_and_not_the_package_s_methods():
    assert set(SCENE.methods) == set(ENGINE_RULES) == {
        "explicit_euler", "semi_implicit_euler", "implicit_euler", "rescaled_momentum",
        "rescaled_energy", "no_gyroscopic"}
    assert not set(ENGINE_RULES) & set(METHODS)
    assert ENGINE_RULES["no_gyroscopic"].order == 0
    assert all(ENGINE_RULES[name].order == 1 for name in CONSISTENT)
