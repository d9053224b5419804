"""Compensated arithmetic: sums and products of doubles with their rounding errors, and
double-double numbers built on them.

Compiled helpers (``@njit``, inlined) of the exact solution's cancellation-free invariants
(:mod:`stability.free_body.exact`); the GPU replaces :func:`two_prod` by one fused multiply-add
(:mod:`stability.engine.gpu.retarget`).
"""

from numba import njit

#: Dekker's splitter 2^27 + 1 for the exact product of two doubles (Dekker 1971).
SPLITTER = 134217729.0


@njit(forceinline=True, error_model="numpy")
def two_sum(a, b):
    """s + e = a + b exactly (Knuth, TAOCP vol. 2, 4.2.2, Theorem B)."""
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


@njit(forceinline=True, error_model="numpy")
def fast_two_sum(a, b):
    """s + e = a + b exactly, for |a| >= |b| (Dekker 1971)."""
    s = a + b
    return s, b - (s - a)


@njit(forceinline=True, error_model="numpy")
def two_prod(a, b):
    """p + e = a b exactly, by Veltkamp splitting (Dekker 1971); |a|, |b| < 2^996."""
    p = a * b
    t = SPLITTER * a
    ah = t - (t - a)
    al = a - ah
    t = SPLITTER * b
    bh = t - (t - b)
    bl = b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


@njit(forceinline=True, error_model="numpy")
def dd_mul(ah, al, bh, bl):
    """Double-double product (relative error ~2^-104)."""
    p, e = two_prod(ah, bh)
    e += ah * bl + al * bh
    return fast_two_sum(p, e)


@njit(forceinline=True, error_model="numpy")
def dd_add(ah, al, bh, bl):
    """Double-double sum, accurate under cancellation (Shewchuk-style two-sum of both parts)."""
    s, e = two_sum(ah, bh)
    t, f = two_sum(al, bl)
    e += t
    s, e = fast_two_sum(s, e)
    e += f
    return fast_two_sum(s, e)
