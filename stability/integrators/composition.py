"""Higher-order Lie-Poisson methods: symmetric compositions of the second-order splitting lp2.

A composition S(g_s h) o ... o S(g_1 h) of the Strang step S = A(h/2) B(h) A(h/2) with palindromic
weights g (sum g = 1) is the rotation sequence

    A(a_0 h) B(b_1 h) A(a_1 h) ... B(b_s h) A(a_s h),   b_i = g_i,  a_i = (g_i + g_{i+1}) / 2,

with neighbouring A half-flows merged (exact, since the A flow keeps m1), so s stages cost
2s + 1 rotations instead of 3s. Order conditions: sum g = 1 and, for order 2k, sum g^3 = ... =
sum g^(2k-1) = 0 for the palindromic sets below (checked in the tests).
"""

import numpy as np

from .lie_poisson import splitting_spec

# Suzuki, Phys. Lett. A 146, 319 (1990): order 4 from 5 stages, g = (p, p, 1 - 4p, p, p).
SUZUKI4_P = 1.0 / (4.0 - 4.0 ** (1.0 / 3.0))  # 0.41449077179437573
SUZUKI4 = (SUZUKI4_P, SUZUKI4_P, 1.0 - 4.0 * SUZUKI4_P, SUZUKI4_P, SUZUKI4_P)

# Kahan & Li, Math. Comp. 66, 1089 (1997), s9odr6a: order 6 from 9 stages.
_KL6_HALF = (
    0.39216144400731413928,
    0.33259913678935943860,
    -0.70624617255763935981,
    0.08221359629355080023,
)
KAHAN_LI6 = _KL6_HALF + (0.79854399093482996340,) + _KL6_HALF[::-1]

# Kahan & Li (1997), s17odr8a: order 8 from 17 stages.
_KL8_HALF = (
    0.13020248308889008088,
    0.56116298177510838456,
    -0.38947496264484728641,
    0.15884190655515560090,
    -0.39590389413323757734,
    0.18453964097831570709,
    0.25837438768632204729,
    0.29501172360931029887,
)
KAHAN_LI8 = _KL8_HALF + (-0.60550853383003451170,) + _KL8_HALF[::-1]


def partitioned_coefficients(gammas):
    """Rotation-sequence weights ``(a, b)`` equivalent to composing lp2 with weights ``gammas``."""
    g = tuple(float(x) for x in gammas)
    a = (0.5 * g[0],) + tuple(0.5 * (g[i] + g[i + 1]) for i in range(len(g) - 1)) + (0.5 * g[-1],)
    return a, g


def strang_table(gammas, outer, inner) -> np.ndarray:
    """Stage table ``(kind, weight), ...`` (flat) of Strang steps composed with weights ``gammas``.

    Strang step i of weight g_i is ``outer(g_i / 2)``, the ``inner`` flows, ``outer(g_i / 2)``;
    the outer flows of neighbouring steps merge (their weights are ``partitioned_coefficients``'
    a), so s steps cost ``s (len(inner) + 1) + 1`` stages.

    Parameters
    ----------
    gammas : sequence of float
        Palindromic composition weights (sum 1); ``(1.0,)`` is the Strang step itself.
    outer : float
        Stage kind of the outer flow.
    inner : sequence of (float, float)
        ``(kind, fraction of g_i)`` of each inner flow, in order.

    Returns
    -------
    ndarray
        ``kind_0, weight_0, kind_1, weight_1, ...`` (weights as fractions of h).
    """
    a, b = partitioned_coefficients(gammas)  # a: merged outer weights, b: the steps' weights
    table = []
    for a_i, b_i in zip(a[:-1], b):
        table += [(outer, a_i), *((kind, fraction * b_i) for kind, fraction in inner)]
    table.append((outer, a[-1]))
    return np.array(table, dtype=float).ravel()


def composition_spec(name, title, order, gammas, reference, note="", max_step_angle=None):
    """A registry entry for lp2 composed with the palindromic weights ``gammas``."""
    a, b = partitioned_coefficients(gammas)
    return splitting_spec(name, title, order, a, b, reference, note, max_step_angle)


LP4 = composition_spec(
    "lp4",
    "Suzuki composition of lp2 (5 stages)",
    4,
    SUZUKI4,
    "Suzuki, Phys. Lett. A 146, 319 (1990)",
    note="fourth order at 11 rotations per step; |L| to round-off, bounded energy error",
    max_step_angle=1.4,  # median w error 0.04 at 1.4 rad, flips off by 2 at 1.7
)
LP6 = composition_spec(
    "lp6",
    "Kahan-Li composition of lp2 (9 stages)",
    6,
    KAHAN_LI6,
    "Kahan & Li, Math. Comp. 66, 1089 (1997), s9odr6a",
    note="sixth order at 19 rotations per step; for errors of 1e-8 and below",
    max_step_angle=2.0,  # median w error 0.09 at 2 rad; flips off by 2 at 2.5
)
LP8 = composition_spec(
    "lp8",
    "Kahan-Li composition of lp2 (17 stages)",
    8,
    KAHAN_LI8,
    "Kahan & Li, Math. Comp. 66, 1089 (1997), s17odr8a",
    note="eighth order at 35 rotations per step; reaches round-off at moderate h",
    max_step_angle=3.0,  # median w error 0.19 at 3 rad, 0.43 at 3.5
)
