"""Figures of the heavy top's studies.

:func:`sleeping_top_figure` draws the Dataset of :func:`stability.sleeping_top.measure_sleeping_tops`:
the measured growth rate of a sleeping top's tilt against its spin, over the analytic curve,
with each top's critical spin marked, and the relative error of the measurement below.
"""

from __future__ import annotations

import numpy as np

from .. import conventions as cv
from .style import AXIS_COLORS, EXACT_COLOR, label, new_figure, styled


@styled
def sleeping_top_figure(ds, claim=None):
    """Growth rate of the tilt against spin, measured and analytic; the relative error below.

    Parameters
    ----------
    ds : xarray.Dataset
        The sleeping-top map (dims length, spin).
    claim : float, optional
        Relative error the study claims (a horizontal line in the lower panel).
    """
    from ..top import HeavyTop, sleeping_growth_rate

    fig = new_figure(7.0, 6.0)
    top_ax, err_ax = fig.subplots(2, 1, sharex=True, height_ratios=(2, 1))
    spins = ds.spin.values
    dense = np.linspace(spins.min(), spins.max(), 600)
    central = ds.attrs.get("central_moments")
    for k, length in enumerate(ds.length.values):
        color = AXIS_COLORS[k % len(AXIS_COLORS)]
        one = ds.isel(length=k)
        crit = float(one.critical_spin)
        if central is not None:
            top = HeavyTop(ds.attrs["mass"], float(length), tuple(central), ds.attrs["gravity"])
            top_ax.plot(dense, sleeping_growth_rate(top, dense), color=color, lw=1.2)
        top_ax.plot(spins, one.growth_rate_measured, "o", color=color, ms=4,
                    label=f"l = {100 * length:g} cm (critical spin {crit:.1f} rad/s)")
        for ax in (top_ax, err_ax):
            ax.axvline(crit, color=color, ls=":", lw=1)
        err = np.abs(one.relative_error.values)
        shown = np.isfinite(err) & (err > 0)
        err_ax.semilogy(spins[shown], err[shown], "o-", color=color, ms=3, lw=0.8)
    top_ax.plot([], [], color=EXACT_COLOR, lw=1.2, label="analytic sqrt(4 A M g l - C² w3²) / (2A)")
    top_ax.set_ylabel(label("growth rate of the tilt", cv.UNITS_RATE))
    top_ax.set_title(f"Sleeping top: tilt growth below the critical spin "
                     f"({ds.attrs.get('method', '')}, {ds.attrs.get('members', '')} members each)")
    top_ax.legend(fontsize=8)
    if claim is not None:
        err_ax.axhline(claim, color=EXACT_COLOR, ls="--", lw=1, label=f"claim {claim:g}")
        err_ax.legend(fontsize=8)
    err_ax.set_ylabel(label("|relative error|", cv.UNITS_DIMENSIONLESS))
    err_ax.set_xlabel(label("spin w3", cv.UNITS_ANGULAR_VELOCITY))
    return fig
