"""The input checks every public function starts with (stability.util.checks): what each takes,
what it refuses, and that each refusal is one line naming the argument."""

import math
from pathlib import Path

import numpy as np
import pytest

from stability.util.checks import (
    checked_progress, did_you_mean, folder_path, positive_float, positive_int, real_array,
    real_number, registered, step_count, vectors3,
)


def one_line(call, *args, match):
    with pytest.raises(ValueError, match=match) as info:
        call(*args)
    assert "\n" not in str(info.value)
    return str(info.value)


def test_real_numbers_are_taken_and_lookalikes_refused():
    assert real_number("h", 3) == 3.0 and real_number("h", np.float32(0.5)) == 0.5
    assert real_number("h", np.array(2.5)) == 2.5  # a 0-d array's number
    for bad in (True, "2", 1j, None):
        one_line(real_number, "h", bad, match="h must be a number")
    assert "in s" in one_line(real_number, "h", "x", "s", match="h must be a number")


def test_real_arrays_refuse_what_numpy_would_convert_silently():
    assert real_array("x0", [[1, 2], [3, 4.5]]).dtype == np.float64
    given = np.arange(3.0)
    assert real_array("x0", given, copy=False) is given
    assert real_array("x0", given) is not given
    for bad, why in (([1 + 2j], "complex"), ([True, False], "bool"), (["2"], "str"),
                     ([[1, 2], [3]], "regular array"), ([1.0, None], "NoneType")):
        text = one_line(real_array, "x0", bad, match="x0 must be real numbers")
        assert why in text, text


def test_positive_numbers_and_whole_numbers():
    assert positive_float("rtol", 1e-9) == 1e-9
    for bad in (0.0, -1.0, math.inf, math.nan):
        one_line(positive_float, "rtol", bad, match="rtol must be finite and > 0")
    assert positive_int("members", 5) == 5 and positive_int("members", 4.0) == 4
    assert positive_int("keep", 0, allow_zero=True) == 0
    one_line(positive_int, "members", 0, match="members must be >= 1, got 0")
    for bad in (2.5, True, "3"):
        one_line(positive_int, "members", bad, match="members must be a whole number")


def test_vectors_of_three_components():
    assert vectors3("w0", [1, 2, 3]).shape == (3,)
    assert vectors3("w0", np.zeros((4, 3))).shape == (4, 3)
    one_line(vectors3, "w0", [1, 2], match=r"w0 must have shape \(3,\) or \(N, 3\)")
    one_line(vectors3, "w0", [1, np.nan, 3], match="w0 must be finite")


def test_names_looked_up_and_misspelt():
    table = {"rk4": 1, "lp2": 2}
    assert registered(table, "lp2", "method") == 2
    text = one_line(registered, table, "rk5", "method", match="unknown method 'rk5'")
    assert text.endswith("known methods: rk4, lp2")
    one_line(registered, table, ["rk4"], "method", match="unknown method")  # unhashable
    assert did_you_mean("membres", ["members", "seed"]) == " (did you mean 'members'?)"
    assert did_you_mean("zzz", ["members", "seed"]) == ""


def test_folders_progress_and_step_counts():
    assert folder_path("out", "runs") == Path("runs")
    for bad in ("", 3, None):
        one_line(folder_path, "out", bad, match="out must be a folder path")
    assert checked_progress(None) is None and checked_progress(np.bool_(True)) is True
    one_line(checked_progress, "no", match="progress must be True, False or None")
    assert step_count(1.0, 0.1) == 10 and step_count(2.0, 2e-3) == 1000
    one_line(step_count, 1.0, 0.3, match="is not a whole number of steps")
