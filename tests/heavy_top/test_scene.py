"""The heavy top's scene (stability.heavy_top.scene): registered with its three methods, in the
width and components it declares."""

from stability.registry import SCENES

SCENE = SCENES["heavy_top"]


def test_scene_is_registered_with_its_three_methods():
    assert set(SCENE.methods) == {"rk4", "lp2", "lp4"}
    assert SCENE.width == 6 and SCENE.components[3:] == ("g1", "g2", "g3")
