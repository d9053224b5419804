"""Numbers as the package's messages show them to a person.

Below every other module (it imports none of the package), so that any of them, the publishing
of results as much as the ensembles, words sizes the same way.
"""

from __future__ import annotations

import math
import sys


def format_bytes(n: float) -> str:
    """``n`` bytes in binary units, e.g. ``"1.5 GiB"``.

    Parameters
    ----------
    n : float
        A number of bytes.

    Returns
    -------
    str
        Whole bytes below 1 KiB, else one decimal in KiB, MiB, GiB or TiB (three digits
        from 1e5 TiB).
    """
    try:
        n = float(n)
    except OverflowError:  # a product of counts beyond a float
        n = math.inf
    if not math.isfinite(n):
        return f"more than {sys.float_info.max / 2**40:.3g} TiB"
    for unit in ("B", "KiB", "MiB", "GiB", "TiB"):
        if abs(n) < 1024.0 or unit == "TiB":
            if unit == "TiB" and abs(n) >= 1e5:
                return f"{n:.3g} TiB"
            return f"{n:.0f} {unit}" if unit == "B" else f"{n:.1f} {unit}"
        n /= 1024.0
