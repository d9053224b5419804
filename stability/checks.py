"""Input checks at the boundary between users and kernels: one clear ValueError each."""

from __future__ import annotations

import math
import numbers

import numpy as np


def positive_float(name: str, value, unit: str = "") -> float:
    """``value`` as a float that is finite and > 0, else ValueError naming ``name``."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number{_in(unit)}, got {value!r}") from None
    if not math.isfinite(x) or x <= 0.0:
        raise ValueError(f"{name} must be finite and > 0{_in(unit)}, got {value!r}")
    return x


def positive_int(name: str, value, allow_zero: bool = False) -> int:
    """``value`` as an int >= 1 (or >= 0), else ValueError naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        if isinstance(value, float) and value.is_integer():
            value = int(value)
        else:
            raise ValueError(f"{name} must be a whole number, got {value!r}")
    lowest = 0 if allow_zero else 1
    if value < lowest:
        raise ValueError(f"{name} must be >= {lowest}, got {value}")
    return int(value)


def vectors3(name: str, value, unit: str = "") -> np.ndarray:
    """``value`` as a finite float64 array of shape (3,) or (N, 3)."""
    try:
        x = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be numbers{_in(unit)}, got {value!r}") from None
    if x.ndim not in (1, 2) or x.shape[-1] != 3:
        raise ValueError(
            f"{name} must have shape (3,) or (N, 3) (components along body axes 1, 2, 3), "
            f"got shape {x.shape}"
        )
    if not np.all(np.isfinite(x)):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return x


def step_count(t_end: float, h: float) -> int:
    """Number of steps of size ``h`` in ``t_end``; it must be a whole number (to 1e-9)."""
    n = round(t_end / h)
    if n < 1 or abs(n * h - t_end) > 1e-9 * t_end:
        raise ValueError(
            f"t_end = {t_end} s is not a whole number of steps h = {h} s "
            f"(t_end / h = {t_end / h:.12g}); choose h = t_end / N for an integer N"
        )
    return int(n)


def _in(unit: str) -> str:
    return f" in {unit}" if unit else ""
