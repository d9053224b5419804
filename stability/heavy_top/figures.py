"""Figures of the heavy top's studies.

:func:`sleeping_top_figure` draws the Dataset of
:func:`stability.heavy_top.measure.measure_sleeping_tops`: the measured growth rate of a sleeping
top's tilt against its spin, over the analytic curve, with each top's critical spin marked, and
the relative error of the measurement below. :func:`gyroscope_paths_figure` and
:func:`gyroscope_rates_figure` draw the Dataset of
:func:`stability.heavy_top.measure.measure_gyroscopes`: the looping, cusped and wavy paths of the
figure axis, and the precession and nutation against their fast-top values and the exact ones.
"""

from __future__ import annotations

import numpy as np

from ..util import conventions as cv
from ..plotting.style import (
    AXIS_COLORS, EXACT_COLOR, label, new_figure, place_legend, plain_log_ticks, styled,
)
from .model import HeavyTop, sleeping_growth_rate


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
    top_ax.plot([], [], color="0.5", lw=1.2,
                label="lines, in each top's colour: analytic sqrt(4 A M g l - C² w3²) / (2A)")
    top_ax.set_ylabel(label("growth rate of the tilt", cv.UNITS_RATE))
    top_ax.set_title(f"Sleeping top: tilt growth below the critical spin "
                     f"({ds.attrs.get('method', '')}, {ds.attrs.get('members', '')} members each)")
    place_legend(top_ax, fontsize=8)
    if claim is not None:
        err_ax.axhline(claim, color=EXACT_COLOR, ls="--", lw=1, label=f"claim {claim:g}")
        place_legend(err_ax, fontsize=8)
    err_ax.set_ylabel(label("|relative error|", cv.UNITS_DIMENSIONLESS))
    err_ax.set_xlabel(label("spin w3", cv.UNITS_ANGULAR_VELOCITY))
    return fig


_RELEASE_MARKERS = ("o", "s", "^", "D", "v")


def _release_text(k):
    if k == 0.0:
        return "released at rest (cusps)"
    if k < 0.0:
        return f"phi'(0) = {k:g} W (loops)"
    return f"phi'(0) = {k:g} W (waves)"


@styled
def gyroscope_paths_figure(ds):
    """Paths of the figure axis (tilt against precession angle) of one (tilt, spin) cell.

    Parameters
    ----------
    ds : xarray.Dataset
        The gyroscope Dataset (:func:`stability.heavy_top.measure.measure_gyroscopes`): one
        panel per release, the run's path as a line, the exact path dashed over it.
    """
    releases = ds.release.values
    fig = new_figure(3.2 * releases.size + 0.6, 3.8)
    axes = np.atleast_1d(fig.subplots(1, releases.size, sharey=True))
    for r, (ax, k) in enumerate(zip(axes, releases)):
        one = ds.isel(release=r)
        ax.plot(np.degrees(one.path_phi), np.degrees(one.path_theta), color=AXIS_COLORS[0],
                lw=1.6, label="run")
        ax.plot(np.degrees(one.path_phi_exact), np.degrees(one.path_theta_exact),
                color=EXACT_COLOR, ls="--", lw=0.8, label="exact")
        ax.set_title(_release_text(float(k)), fontsize=9)
        ax.set_xlabel(label("precession angle phi", "degree"))
    axes[0].invert_yaxis()
    axes[0].set_ylabel(label("tilt theta of the figure axis", "degree"))
    place_legend(axes[0], fontsize=8)
    fig.suptitle(f"Gyroscope released at {ds.attrs['path_tilt']:g}° with spin "
                 f"{ds.attrs['path_spin']:.0f} rad/s: paths of the figure axis "
                 f"(W = M g l / (C w3))", fontsize=10)
    return fig


@styled
def gyroscope_rates_figure(ds, claim=None):
    """Precession rate, nutation frequency and amplitude against their fast-top values.

    Parameters
    ----------
    ds : xarray.Dataset
        The gyroscope Dataset (dims tilt, spin, release).
    claim : float, optional
        Relative error the study claims (a line in the error panel).
    """
    fig = new_figure(10.0, 8.0)
    (prec_ax, nut_ax), (amp_ax, err_ax) = fig.subplots(2, 2)
    spins = ds.spin.values
    for i, tilt in enumerate(ds.tilt.values):
        color = AXIS_COLORS[i % len(AXIS_COLORS)]
        for r, k in enumerate(ds.release.values):
            one = ds.isel(tilt=i, release=r)
            marker = _RELEASE_MARKERS[r % len(_RELEASE_MARKERS)]
            tag = dict(label=f"tilt {tilt:g}°") if r == 0 else {}
            prec_ax.loglog(ds.precession_rate_gyroscopic, one.precession_rate_measured, marker,
                           color=color, ms=4, mfc="none", **tag)
            prec_ax.loglog(ds.precession_rate_gyroscopic, one.precession_rate_exact, "-",
                           color=color, lw=0.6)
            nut_ax.loglog(ds.nutation_frequency_gyroscopic, one.nutation_frequency_measured,
                          marker, color=color, ms=4, mfc="none", **tag)
            nut_ax.loglog(ds.nutation_frequency_gyroscopic, one.nutation_frequency_exact, "-",
                          color=color, lw=0.6)
            if k != 1.0:
                amp_ax.loglog(spins, np.degrees(one.nutation_amplitude_measured), marker,
                              color=color, ms=4, mfc="none", **tag)
                amp_ax.loglog(spins, np.degrees(one.nutation_amplitude_exact), "-", color=color,
                              lw=0.6)
                amp_ax.loglog(spins, np.degrees(one.nutation_amplitude_gyroscopic), ":",
                              color=color, lw=0.8)
    for r, k in enumerate(ds.release.values):
        prec_ax.plot([], [], _RELEASE_MARKERS[r % len(_RELEASE_MARKERS)], color="gray",
                     mfc="none", label=_release_text(float(k)))
    for ax, x in ((prec_ax, ds.precession_rate_gyroscopic),
                  (nut_ax, ds.nutation_frequency_gyroscopic)):
        ends = np.array([float(x.min()), float(x.max())])
        ax.plot(ends, ends, color=EXACT_COLOR, ls=":", lw=1, label="fast-top value (y = x)")
    prec_ax.plot([], [], "-", color="gray", lw=0.6, label="exact (lines)")
    prec_ax.set_xlabel(label("M g l / (C w3)", cv.UNITS_ANGULAR_VELOCITY))
    prec_ax.set_ylabel(label("mean precession rate", cv.UNITS_ANGULAR_VELOCITY))
    prec_ax.set_title("precession: run (markers), exact (lines)", fontsize=9)
    place_legend(prec_ax, fontsize=7)
    nut_ax.set_xlabel(label("C w3 / A", cv.UNITS_ANGULAR_VELOCITY))
    nut_ax.set_ylabel(label("nutation frequency 2 pi / T", cv.UNITS_ANGULAR_VELOCITY))
    nut_ax.set_title("nutation frequency", fontsize=9)
    place_legend(nut_ax, fontsize=7)
    amp_ax.plot([], [], ":", color="gray", label="2 |1 - k| A M g l sin(theta0) / (C w3)²")
    amp_ax.set_xlabel(label("spin w3", cv.UNITS_ANGULAR_VELOCITY))
    amp_ax.set_ylabel(label("nutation amplitude theta_max - theta_min", "degree"))
    amp_ax.set_title("nutation amplitude", fontsize=9)
    place_legend(amp_ax, fontsize=7)
    for name, quantity, color in (("precession_rate_error", "precession rate", AXIS_COLORS[0]),
                                  ("nutation_frequency_error", "nutation frequency",
                                   AXIS_COLORS[1]),
                                  ("nutation_amplitude_error", "nutation amplitude",
                                   AXIS_COLORS[2])):
        worst = np.abs(ds[name]).max(dim=("tilt", "release")).values
        err_ax.semilogy(spins, np.maximum(worst, 1e-17), "o-", color=color, ms=3, lw=0.8,
                        label=quantity)
    if claim is not None:
        err_ax.axhline(claim, color=EXACT_COLOR, ls="--", lw=1, label=f"claim {claim:g}")
        low, high = err_ax.get_ylim()
        err_ax.set_ylim(low, max(high, 10.0 * claim))  # the claim's line inside the panel
    err_ax.set_xscale("log")
    for ax in (prec_ax, nut_ax, amp_ax):
        plain_log_ticks(ax)
    plain_log_ticks(err_ax, "x")
    err_ax.set_xlabel(label("spin w3", cv.UNITS_ANGULAR_VELOCITY))
    err_ax.set_ylabel(label("max |run - exact| / exact", cv.UNITS_DIMENSIONLESS))
    err_ax.set_title(f"run against the exact motion ({ds.attrs.get('method', '')})", fontsize=9)
    place_legend(err_ax, fontsize=7)
    fig.suptitle(f"Gyroscope: {ds.attrs.get('top_name', 'top')}, M g l = {ds.attrs['mgl']:.4g} "
                 f"N m", fontsize=10)
    return fig
