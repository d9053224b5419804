"""Which principal axis carries which moment (stability.core.axes): names and labels agree,
in any order of the moments, and a name that is no moment's is refused in one line."""

import numpy as np
import pytest

from stability.core.axes import (MOMENT_NAMES, intermediate_axis, moment_name, principal_axis,
                                 principal_moments, spin_axis)
from stability.core.body import RigidBody


def test_principal_and_named_axes():
    body = RigidBody(3.0, 1.0, 2.0)
    assert [principal_axis(body, w) for w in MOMENT_NAMES] == [2, 3, 1]
    assert [moment_name(body, a) for a in (1, 2, 3)] == ["largest", "smallest", "intermediate"]
    assert principal_axis(body, "intermediate") == intermediate_axis(body)
    with pytest.raises(ValueError, match="smallest, intermediate, largest"):
        principal_axis(body, "middle")


@pytest.mark.parametrize("moments", [(1.0, 2.0, 3.0), (3.0, 1.0, 2.0), (2.0, 3.0, 1.0)])
def test_a_spin_axis_by_name_is_the_label_of_that_moment(moments):
    """spin_axis reads an axis as study files give it: a name becomes the label of the axis
    carrying that moment, a label is passed on as it is (checked by the caller)."""
    for name in MOMENT_NAMES:
        label = spin_axis(moments, name)
        assert moment_name(moments, label) == name
        assert moments[label - 1] == sorted(moments)[MOMENT_NAMES.index(name)]
    assert spin_axis(moments, 2) == 2
    with pytest.raises(ValueError, match="name of its moment"):
        spin_axis(moments, "middle")


def test_equal_moments_are_ranked_by_label():
    assert [principal_axis((2.0, 2.0, 1.0), w) for w in MOMENT_NAMES] == [3, 1, 2]
    np.testing.assert_array_equal(intermediate_axis(np.array([[1.0, 2.0, 3.0],
                                                              [2.0, 1.0, 3.0]])), [2, 1])


@pytest.mark.parametrize("body, match", [((1.0, 2.0), "shape"), ((1.0, -2.0, 3.0), "> 0"),
                                         ((1.0, np.nan, 3.0), "finite")])
def test_bad_moments_are_refused_in_one_line(body, match):
    with pytest.raises(ValueError, match=match):
        principal_moments(body)
