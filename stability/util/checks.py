"""Input checks at the boundary between users and kernels: one clear ValueError each."""

from __future__ import annotations

import difflib
import math
import numbers
import os
from pathlib import Path

import numpy as np


#: NumPy dtype kinds refused by :func:`real_array`, in words.
_REFUSED_KINDS = {
    "c": "complex numbers (their imaginary part would be dropped)",
    "b": "booleans",
    "U": "strings",
    "S": "bytes",
    "M": "dates",
    "m": "time differences",
    "V": "structured records",
}


def real_number(name: str, value, unit: str = "") -> float:
    """``value`` as a float if it is a real number (int or float, Python or NumPy), else error.

    Booleans, strings and complex numbers are refused rather than converted: ``float(True)`` is
    1.0 and ``float("2")`` is 2.0, which would hide a mistake.
    """
    value = scalar(value)
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise ValueError(f"{name} must be a number{_in(unit)}, got {_short(value)}")
    return float(value)


def scalar(value):
    """The number a 0-d array or a scalar DataArray holds (``value.item()``); anything else as
    it is."""
    if getattr(value, "ndim", None) == 0 and hasattr(value, "item") and not isinstance(
            value, (numbers.Number, np.generic)):
        return value.item()
    return value


def real_array(name: str, value, unit: str = "", copy: bool = True) -> np.ndarray:
    """``value`` as a new float64 array if it holds real numbers only, else ValueError.

    The one gate for array input at the public boundary. Integers and floats (Python or NumPy,
    in lists, tuples or arrays of any shape) are accepted; complex numbers, booleans, strings,
    bytes, dates, ``None``, ragged lists and other objects are refused with one line naming
    ``name``, where ``np.array(value, dtype=float)`` would silently drop an imaginary part,
    read True as 1 or parse "2". Shape and finiteness are the caller's to check. With
    ``copy=False``, an array given comes back as it is (a view, of its own dtype: nothing of
    its size allocated), for a caller that checks the memory its shape needs before it
    converts it.
    """
    try:
        x = np.asarray(value)
    except (TypeError, ValueError):  # ragged nesting
        raise ValueError(
            f"{name} must be real numbers{_in(unit)} in a regular array, got {_short(value)}"
        ) from None
    kind = x.dtype.kind
    if kind == "O":
        items = x.ravel()
        if not all(isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_))
                   for v in items):
            bad = next(v for v in items
                       if not isinstance(v, numbers.Real) or isinstance(v, (bool, np.bool_)))
            raise ValueError(
                f"{name} must be real numbers{_in(unit)}, got {_short(value)} "
                f"(it holds {_short(bad)}, a {type(bad).__name__})"
            )
    elif kind in _REFUSED_KINDS:
        raise ValueError(
            f"{name} must be real numbers{_in(unit)}, got {_REFUSED_KINDS[kind]}: {_short(value)}"
        )
    elif kind not in "iuf":
        raise ValueError(f"{name} must be real numbers{_in(unit)}, got {_short(value)}")
    return np.array(x, dtype=float) if copy else x


def positive_float(name: str, value, unit: str = "") -> float:
    """``value`` as a float that is finite and > 0, else ValueError naming ``name``."""
    x = real_number(name, value, unit)
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
    """``value`` as a finite float64 array of shape (3,) or (N, 3) (a new array)."""
    x = real_array(name, value, unit)
    if x.ndim not in (1, 2) or x.shape[-1] != 3:
        raise ValueError(
            f"{name} must have shape (3,) or (N, 3) (components along body axes 1, 2, 3), "
            f"got shape {x.shape}"
        )
    if not np.all(np.isfinite(x)):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return x


def registered(table, name, what: str, plural: str = ""):
    """``table[name]``, or a ValueError listing the names ``table`` has: ``unknown <what>
    'name'; known <plural>: a, b`` (``plural`` defaults to ``what`` + "s"); an unhashable
    ``name`` is unknown too."""
    try:
        return table[name]
    except (KeyError, TypeError):
        raise ValueError(
            f"unknown {what} {name!r}; known {plural or what + 's'}: {', '.join(table)}"
        ) from None


def folder_path(name: str, value) -> Path:
    """``value`` as a Path if it is a path (a str or path-like), else ValueError naming
    ``name``; whether the folder exists is the caller's to check."""
    if isinstance(value, (str, os.PathLike)) and os.fspath(value) not in ("", b""):
        return Path(value)
    raise ValueError(f"{name} must be a folder path (a str or pathlib.Path), got "
                     f"{_short(value)}")


def checked_progress(progress):
    """``progress`` if it is True, False or None (the bar shown, never, or on long runs on a
    terminal), else ValueError: a string such as "no" would read as True."""
    if progress is None or isinstance(progress, (bool, np.bool_)):
        return None if progress is None else bool(progress)
    raise ValueError(f"progress must be True, False or None (shown for long runs), got "
                     f"{_short(progress)}")


def did_you_mean(name, options) -> str:
    """`` (did you mean 'x'?)`` naming the option closest to ``name``, or "" if none is close."""
    close = difflib.get_close_matches(str(name), [str(o) for o in options], n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


def step_count(t_end: float, h: float) -> int:
    """Number of steps of size ``h`` in ``t_end``; it must be a whole number (to 1e-9)."""
    n = round(t_end / h)
    if n < 1 or abs(n * h - t_end) > 1e-9 * t_end:
        raise ValueError(
            f"t_end = {t_end} s is not a whole number of steps h = {h} s "
            f"(t_end / h = {t_end / h:.12g}); choose h = t_end / N for an integer N"
        )
    return int(n)


def _short(value, limit: int = 80) -> str:
    """``repr(value)`` cut to ``limit`` characters; an array as its dtype and shape."""
    if isinstance(value, np.ndarray) and value.size > 6:
        return f"an array of {value.dtype} with shape {value.shape}"
    text = (repr(value).splitlines() or [""])[0]
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _in(unit: str) -> str:
    return f" in {unit}" if unit else ""
