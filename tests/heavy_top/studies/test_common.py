"""What the heavy-top studies share (stability.heavy_top.studies.common): the top built from
``[top]`` (its moments about the pivot by the parallel-axis theorem), the refusals of a top that
is not symmetric or not physical and of an empty spin range, each naming its key."""

import pytest

from stability.heavy_top.methods import METHODS
from stability.heavy_top.studies.common import check_spins, symmetric_top, top_keys, top_methods
from stability.study.config import ConfigError, Key

TOP = {"mass": 0.1, "central_moments": [2.25e-5, 2.25e-5, 4.5e-5], "gravity": 9.80665}


def test_the_top_of_the_section_has_its_moments_about_the_pivot():
    top = symmetric_top({"top": TOP}, 0.04)
    a, b, c = top.pivot_moments
    assert a == pytest.approx(2.25e-5 + 0.1 * 0.04 ** 2, rel=1e-15) and a == b
    assert c == pytest.approx(4.5e-5, rel=1e-15)
    assert top.mgl == pytest.approx(0.1 * 9.80665 * 0.04, rel=1e-15)


def test_the_keys_and_methods_the_studies_offer():
    length = Key("length", "float", 0.04, "distance of the centre of mass", unit="m")
    names = [key.name for key in top_keys(length)]
    assert names == ["mass", "central_moments", "length", "gravity"]
    assert top_methods() == tuple(METHODS) and "rk4" in top_methods()


@pytest.mark.parametrize("moments, message", [
    ([2.25e-5, 3e-5, 4.5e-5], "must have I1 = I2"),
    ([2.25e-5, 2.25e-5, 9e-5], "central_moments"),  # I3 > I1 + I2: no such body
])
def test_a_top_not_symmetric_or_not_physical_is_refused_naming_its_key(moments, message):
    with pytest.raises(ConfigError, match=message) as info:
        symmetric_top({"top": {**TOP, "central_moments": moments}}, 0.04, "top.toml")
    assert "[top] central_moments" in str(info.value) and "\n" not in str(info.value)


def test_an_empty_spin_range_is_refused():
    check_spins({"spins": {"min": 100.0, "max": 300.0}}, "top.toml")
    with pytest.raises(ConfigError, match=r"\[spins\] max must exceed \[spins\] min \(300\)"):
        check_spins({"spins": {"min": 300.0, "max": 300.0}}, "top.toml")
