"""Roots of many scalar functions at once, to round-off: Newton's method kept in a bracket.

Each of n functions has a bracket [lo, hi] over which it changes sign. A Newton step that
leaves the bracket (or a zero slope) is replaced by bisection, and the bracket shrinks to the
side where the sign changes, so every root converges (quadratically once Newton takes over) and
the iteration stops at round-off: when the step falls below a few ulp of the root or the
bracket can no longer be halved in floating point.
"""

from __future__ import annotations

import numpy as np

#: Iteration cap: 64 bisections halve any double bracket to adjacent floats.
MAX_ITERATIONS = 100


def bracketed_newton(f, lo, hi):
    """Roots of ``f`` on the brackets ``[lo, hi]``, all members at once.

    Parameters
    ----------
    f : callable
        ``f(x) -> (value, slope)``, arrays of shape (n,) for x of shape (n,).
    lo, hi : array_like, shape (n,)
        Brackets, ``f(lo)`` and ``f(hi)`` of opposite signs (or one of them zero).

    Returns
    -------
    ndarray, shape (n,)
        The roots; NaN where the bracket did not hold a sign change, where ``f`` gave a
        non-finite value, or where the iteration cap was reached first.
    """
    lo = np.array(lo, dtype=float)
    hi = np.array(hi, dtype=float)
    f_lo = f(lo)[0]
    f_hi = f(hi)[0]
    valid = np.sign(f_lo) != np.sign(f_hi)
    x = np.where(f_lo == 0.0, lo, np.where(f_hi == 0.0, hi, 0.5 * (lo + hi)))
    done = ~valid | (f_lo == 0.0) | (f_hi == 0.0)
    lo_sign = np.sign(f_lo)
    for _ in range(MAX_ITERATIONS):
        if done.all():
            break
        value, slope = f(x)
        broken = ~np.isfinite(value) & ~done
        valid &= ~broken
        done |= broken
        exact = value == 0.0
        below = np.sign(value) == lo_sign
        lo = np.where(below & ~done, x, lo)
        hi = np.where(~below & ~done, x, hi)
        with np.errstate(divide="ignore", invalid="ignore"):
            newton = x - value / slope
        inside = np.isfinite(newton) & (newton > lo) & (newton < hi)
        x_new = np.where(inside, newton, 0.5 * (lo + hi))
        step = np.abs(x_new - x)
        tiny = 4.0 * np.spacing(np.maximum(np.abs(x), np.abs(x_new)))
        converged = exact | (step <= tiny) | (hi - lo <= tiny)
        x = np.where(done | exact, x, x_new)
        done |= converged
    return np.where(valid & done, x, np.nan)
