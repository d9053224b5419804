"""Error-free transformations and double-double arithmetic (stability.core.compensated),
checked exactly with rational arithmetic: s + e = a + b and p + e = a b hold to the last bit, and
the double-double sum and product are within a few 2^-104 of the exact result."""

from fractions import Fraction

import numpy as np

from stability.core.compensated import dd_add, dd_mul, fast_two_sum, two_prod, two_sum

RNG = np.random.default_rng(7)
#: Doubles over many binades, signs mixed, and cases that cancel.
VALUES = np.concatenate([RNG.standard_normal(300) * 10.0 ** RNG.integers(-30, 30, 300),
                         [1.0, -1.0, 1e16, -1e16 + 2.0, 3.0, 1.0 / 3.0, 2.0 ** -52]])


def exact(x) -> Fraction:
    return Fraction(float(x))


def test_two_sum_and_fast_two_sum_are_exact():
    for a, b in zip(VALUES, RNG.permutation(VALUES)):
        s, e = two_sum(a, b)
        assert exact(s) + exact(e) == exact(a) + exact(b)
        assert s == a + b  # s is the rounded sum, e what it lost
        big, small = (a, b) if abs(a) >= abs(b) else (b, a)
        s, e = fast_two_sum(big, small)
        assert exact(s) + exact(e) == exact(a) + exact(b)


def test_two_prod_is_exact_by_veltkamp_splitting():
    for a, b in zip(VALUES, RNG.permutation(VALUES)):
        p, e = two_prod(a, b)
        assert exact(p) + exact(e) == exact(a) * exact(b)
        assert p == a * b


def test_double_double_sum_and_product_are_accurate_to_about_2_to_the_minus_104():
    worst_sum = worst_product = 0.0
    for _ in range(300):
        ah, bh = RNG.standard_normal(2)
        al, bl = ah * 2.0 ** -60 * RNG.standard_normal(), bh * 2.0 ** -60 * RNG.standard_normal()
        a, b = exact(ah) + exact(al), exact(bh) + exact(bl)
        sh, sl = dd_add(ah, al, bh, bl)
        if a + b != 0:
            worst_sum = max(worst_sum, abs(float((exact(sh) + exact(sl) - (a + b)) / (a + b))))
        ph, pl = dd_mul(ah, al, bh, bl)
        worst_product = max(worst_product,
                            abs(float((exact(ph) + exact(pl) - a * b) / (a * b))))
    assert worst_product < 2 * 2.0 ** -104  # measured 0.12 x 2^-104
    assert worst_sum < 2 * 2.0 ** -104  # measured 0.22 x 2^-104
    # under cancellation the sum of the parts is still that of the exact numbers
    sh, sl = dd_add(1.0, 2.0 ** -70, -1.0, 2.0 ** -80)
    assert exact(sh) + exact(sl) == Fraction(1, 2 ** 70) + Fraction(1, 2 ** 80)
