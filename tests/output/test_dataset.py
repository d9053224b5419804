"""The attributes a Dataset may store (stability.output.dataset): converted where they can be,
refused by name where not."""

import numpy as np
import pytest

from stability.output.dataset import storable_attrs


def test_storable_attrs_converts_what_it_can():
    out = storable_attrs({"a": True, "b": np.float32(0.5), "c": (1, 2), "d": np.array([3.0]),
                          "e": np.int64(4), "f": "text"})
    assert out["a"] == 1 and type(out["a"]) is int
    assert out["b"] == 0.5 and type(out["b"]) is float
    np.testing.assert_array_equal(out["c"], [1, 2])
    assert out["d"] == 3.0 and type(out["d"]) is float
    assert type(out["e"]) is int and out["f"] == "text"
    with pytest.raises(ValueError, match="attribute 'g'"):
        storable_attrs({"g": None})
