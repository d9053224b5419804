"""The regime of each member's motion, and of an ensemble: neutral, oscillation, exponential
growth or algebraic drift.

Every member is put in a regime from its own data, so that no rate is forced on a departure that
is not exponential (:func:`member_regimes`):

- *oscillation*: the first perpendicular component crosses zero at least ``MIN_CROSSINGS``
  times and the spin-axis component never does;
- *exponential growth* / *algebraic drift*: the spin-axis component flips, or the perpendicular
  amplitude grows past ``DEPARTURE_FACTOR`` times its start. The amplitude between those bounds
  is fitted by an exponential (``ln A = a + r t``) and by a straight line (``A = b + c t``, the
  departure along an equal-moment axis, ERRATA 3); the better relative fit names the regime;
- *neutral*: no crossing and no departure within the run (the sphere, or an axis whose period is
  far longer than the run).

An ensemble takes the regime of more than half of its valid members (:func:`ensemble_regime`).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..ensemble.schema import ESTIMATES
from ..util import conventions as cv

# Regime codes (int8), per member and per ensemble, declared with the other codes.
from ..util.conventions import (
    REGIME_ALGEBRAIC,
    REGIME_EXPONENTIAL,
    REGIME_FLAG_VALUES,
    REGIME_NEUTRAL,
    REGIME_OSCILLATION,
    REGIME_UNDETERMINED,
)
from .fits import exponential_fit, linear_fit, window_points
from .members import Members, members

#: Lower edge of the growth-rate window, in units of the member's initial perpendicular
#: amplitude a0. A start off the unstable eigenvector carries a decaying mode; at 100 a0 it is
#: below (1/100)^2 = 1e-4 of the growing mode in ln A.
WINDOW_LOW_FACTOR = 100.0
#: Upper edge of the growth-rate window, as a fraction of min(spin, saturation amplitude):
#: nonlinear corrections to ln A are O((A / A_sat)^2) = 1e-4 there (sech form, literature 1.4).
WINDOW_HIGH_FRACTION = 1e-2
#: Dataset attributes that record the growth-rate window an ensemble was analysed with (as a
#: study writes them): :func:`measured_growth_rate` and :func:`measured_omega_squared` use them
#: when no window is passed, so ``ds.stability.measured_growth_rate()`` gives the study's number.
WINDOW_ATTRS = {"low_factor": "growth_window_low_factor",
                "high_fraction": "growth_window_high_fraction"}
#: A member "departs" once its perpendicular amplitude reaches this many times a0; the points
#: from here to the upper edge decide exponential against algebraic departure.
DEPARTURE_FACTOR = 3.0
#: Fewest points in a per-member fit.
MIN_POINTS = 3
#: Fewest zero crossings of the first perpendicular component for a frequency.
MIN_CROSSINGS = 3
#: Fraction of valid members that must share a regime for the ensemble to take it.
MAJORITY = 0.5

#: Sign of Omega^2 each regime stands for (NaN: no statement).
REGIME_SIGN = {
    REGIME_UNDETERMINED: math.nan,
    REGIME_NEUTRAL: 0.0,
    REGIME_OSCILLATION: 1.0,
    REGIME_EXPONENTIAL: -1.0,
    REGIME_ALGEBRAIC: 0.0,
}


def saturation(mem: Members):
    """Per-member amplitude scale of the window's upper edge: min(spin, saturation)."""
    flipped = mem.axis_crossings >= 1
    return np.where(flipped, np.minimum(mem.spin, mem.max_perp), mem.spin)


def member_regimes(ds: xr.Dataset, axis=None, spin=None) -> xr.Dataset:
    """Classify each member's motion: neutral, oscillation, exponential growth or algebraic drift.

    The rules are in the module docstring; they use the member's own data only (no analytic
    input), so they can be set beside linear theory.

    Parameters
    ----------
    ds : xarray.Dataset or Members
        One ensemble, time series or summaries only (see the module docstring).
    axis : int, optional
        Spin axis, 1-based; by default from ``ds.attrs``.
    spin : float, optional
        Spin in rad/s; by default from ``ds.attrs`` or the start.

    Returns
    -------
    xarray.Dataset
        ``regime`` (member) int8 with CF flag attributes; ``exponential_residual`` and
        ``linear_residual`` (member): rms relative misfit of the two departure models over
        [``DEPARTURE_FACTOR`` a0, upper edge); ``drift_rate`` (member), slope c of the straight
        line ``A = b + c t`` in rad s-2 (meaningful for algebraic drift).
    """
    mem = members(ds, axis, spin)
    regime, exp_rms, lin_rms, drift = classify(mem)
    return xr.Dataset(
        {
            "regime": ((cv.MEMBER,), regime, regime_attrs("regime of each member's motion")),
            "exponential_residual": (
                (cv.MEMBER,), exp_rms,
                {"long_name": "rms misfit of ln A to a line in t (exponential model)",
                 "units": cv.UNITS_DIMENSIONLESS},
            ),
            "linear_residual": (
                (cv.MEMBER,), lin_rms,
                {"long_name": "rms relative misfit of A to a line in t (algebraic model)",
                 "units": cv.UNITS_DIMENSIONLESS},
            ),
            "drift_rate": (
                (cv.MEMBER,), drift,
                {"long_name": "slope of the perpendicular amplitude in the algebraic model",
                 "units": "rad s-2"},
            ),
        },
        coords={cv.MEMBER: mem.member},
        attrs={"axis": mem.axis, "spin": mem.spin},
    )


def classify(mem: Members):
    n = mem.a0.size
    high = WINDOW_HIGH_FRACTION * saturation(mem)
    t, a = window_points(mem, DEPARTURE_FACTOR * mem.a0, high)
    _, exp_rms, n_pts = exponential_fit(t, a)
    drift, lin_rms, _ = linear_fit(t, a)
    flipped = mem.axis_crossings >= 1
    oscillating = (~flipped) & (mem.perp_crossings >= MIN_CROSSINGS)
    departed = flipped | (mem.max_perp > DEPARTURE_FACTOR * mem.a0)
    fitted = n_pts >= MIN_POINTS
    regime = np.full(n, REGIME_UNDETERMINED, dtype=np.int8)
    growth = departed & ~oscillating & fitted
    regime[growth & (exp_rms <= lin_rms)] = REGIME_EXPONENTIAL
    regime[growth & (lin_rms < exp_rms) & (drift > 0)] = REGIME_ALGEBRAIC
    regime[oscillating] = REGIME_OSCILLATION
    regime[~departed & ~oscillating] = REGIME_NEUTRAL
    regime[~mem.valid] = REGIME_UNDETERMINED
    return regime, exp_rms, lin_rms, np.where(regime == REGIME_ALGEBRAIC, drift, np.nan)


def regime_attrs(long_name):
    """The regime flags' attributes (:data:`stability.ensemble.schema.ESTIMATES`) under ``long_name``."""
    return ESTIMATES["regime"].on((), long_name=long_name).attrs()


def ensemble_regime(regime, valid):
    r = regime[valid]
    if r.size == 0:
        return REGIME_UNDETERMINED
    counts = np.bincount(r.astype(np.int64), minlength=len(REGIME_FLAG_VALUES))
    best = int(np.argmax(counts))
    return best if counts[best] > MAJORITY * r.size else REGIME_UNDETERMINED


#: The module's public API (the rest serves the package's other modules).
__all__ = ["DEPARTURE_FACTOR", "MIN_CROSSINGS", "MIN_POINTS", "WINDOW_ATTRS",
           "WINDOW_HIGH_FRACTION", "WINDOW_LOW_FACTOR", "member_regimes"]
