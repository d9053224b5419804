"""Sizes in the messages (stability.util.formatting.format_bytes): whole bytes, then one decimal
in binary units, and a size past any float said as such rather than as "inf"."""

from stability.util.formatting import format_bytes


def test_sizes_in_binary_units():
    assert format_bytes(0) == "0 B"
    assert format_bytes(1023) == "1023 B"
    assert format_bytes(1024) == "1.0 KiB"
    assert format_bytes(1.5 * 2 ** 30) == "1.5 GiB"
    assert format_bytes(3 * 2 ** 40) == "3.0 TiB"
    assert format_bytes(2.5e5 * 2 ** 40) == "2.5e+05 TiB"


def test_a_size_beyond_a_float_is_said_in_words():
    assert format_bytes(float("inf")).startswith("more than ")
    assert format_bytes(10 ** 400).startswith("more than ")  # an int product of counts
