"""What the dissipation studies share: keys of a number > 0, and the worst of a measured error."""

from __future__ import annotations

import math

import numpy as np

from ...study.config import Key


def positive_key(name, default, doc, unit):
    """A key of a number > 0.

    Parameters
    ----------
    name : str
        The key's name in its section.
    default : float
        Its value when the file gives none.
    doc : str
        What it is, as the study's reference prints it.
    unit : str
        Its unit.
    """
    return Key(name, "float", default, doc, unit=unit, minimum=0.0, exclusive_minimum=True)


def worst(values) -> float:
    """The largest |value| over the finite ones (NaN if none).

    Parameters
    ----------
    values : array_like
        Measured errors or drifts; NaN where a member measured nothing.
    """
    values = np.abs(np.asarray(values, dtype=float))
    values = values[np.isfinite(values)]
    return float(values.max()) if values.size else math.nan
