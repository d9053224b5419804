"""Figures of the dissipation studies, each drawn from its Dataset alone.

The Explorer study (:func:`stability.dissipation.measure.measure_explorer`):

- :func:`nutation_figure`: the nutation angle against time, growing at the linear rate, then
  the turn into the flat spin at every damping;
- :func:`flat_time_figure`: the growth rate and the time to the flat spin against the damping,
  measured beside the linear theory and the energy-sink estimate, the optimum marked;
- :func:`end_state_figure`: the energy falling to that of the flat spin, and every member's
  measured rates, |H| and energy against the theory.

The dual-spin study (:func:`stability.dissipation.measure_gyrostat.measure_dual_spin`):

- :func:`dual_spin_map_figure`: for each placement of the dampers, the map of the linear growth
  rate over the inertia ratio and the rotor's speed, the eigenvalues' and the energy-sink
  criterion's boundaries, and every cell's measured verdict, the disagreements marked;
- :func:`dual_spin_rate_figure`: every member's fitted rate, and every cell's energy-sink
  estimate, against the linear eigenvalue.
"""

from __future__ import annotations

import numpy as np

from ..util import conventions as cv
from ..plotting.style import (
    AXIS_COLORS, EXACT_COLOR, label, new_figure, place_legend, plain_log_ticks, styled,
)
from .measure_gyrostat import DECAYS, GROWS
from .model_gyrostat import body_of, linear_map
from .model import energy_sink_rate, nutation_growth_rate

#: Minutes per second, for time axes.
MINUTE = 60.0


def _colors(n):
    """n colours from the package's palette, then matplotlib's tab10."""
    palette = list(AXIS_COLORS) + ["#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"]
    return [palette[k % len(palette)] for k in range(n)]


def _nearest_optimum(ds) -> int:
    """Index of the damping nearest the linear optimum."""
    c = ds.c.values
    return int(np.argmin(np.abs(np.log(c / ds.attrs["c_linear_optimum"]))))


@styled
def nutation_figure(ds):
    """The nutation angle against time: every start at the damping nearest the optimum on a log
    scale, with ``theta0 exp(rate t)`` at the linear rate dashed; and the smallest start at
    every damping, in degrees, turning into the flat spin.

    Parameters
    ----------
    ds : xarray.Dataset
        The Explorer study's Dataset.
    """
    fig = new_figure(7.5, 7.0)
    log_ax, flat_ax = fig.subplots(2, 1)
    g = _nearest_optimum(ds)
    t = ds.sample_time.values[g] / MINUTE
    for k, color in enumerate(_colors(ds.angle.size)):
        theta = ds.theta.values[g, k]
        log_ax.semilogy(t, theta, color=color, lw=1.2,
                        label=f"theta0 = {ds.angle.values[k]:g}°")
        rate = float(ds.growth_rate_linear.values[g, k])
        early = t <= ds.flat_time_linear.values[g, k] / MINUTE
        log_ax.semilogy(t[early], theta[0] * np.exp(rate * t[early] * MINUTE), ls="--",
                        color=EXACT_COLOR, lw=0.8)
    log_ax.plot([], [], ls="--", color=EXACT_COLOR, lw=0.8, label="theta0 exp(linear rate t)")
    log_ax.axhline(ds.attrs["flat_angle"], color="gray", ls=":", lw=1)
    log_ax.set_ylim(top=120.0)
    log_ax.set_xlabel(label("time", "min"))
    log_ax.set_ylabel(label("nutation angle theta", "degree"))
    log_ax.set_title(f"c = {ds.damping.values[g]:g} c*: the linear growth, then the flat spin",
                     fontsize=9)
    place_legend(log_ax, fontsize=7)
    for j, color in enumerate(_colors(ds.damping.size)):
        flat_ax.plot(ds.sample_time.values[j] / MINUTE, ds.theta.values[j, 0], color=color,
                     lw=1.2, label=f"c = {ds.damping.values[j]:g} c*")
    if "whip_theta" in ds:
        flat_ax.plot(ds.whip_sample_time.values / MINUTE, ds.whip_theta.values[0], ls="--",
                     color="gray", lw=1.2,
                     label=f"whip antennas, theta0 = {ds.whip_angle.values[0]:g}°")
    flat_ax.axhline(90.0, color=EXACT_COLOR, ls=":", lw=1, label="flat spin (90°)")
    flat_ax.set_xlabel(label("time", "min"))
    flat_ax.set_ylabel(label("nutation angle theta", "degree"))
    flat_ax.set_title(f"theta0 = {ds.angle.values[0]:g}° at every damping", fontsize=9)
    place_legend(flat_ax, fontsize=7)
    fig.suptitle(f"{ds.attrs['body']}, spherical damper J = {ds.attrs['J']:g} kg m²: the "
                 "nutation grows into a flat spin", fontsize=10)
    return fig


@styled
def flat_time_figure(ds):
    """Growth rate and time to the flat spin against the damping: measured, by the linear
    eigenvalue and by the energy-sink estimate, the optima marked.

    Parameters
    ----------
    ds : xarray.Dataset
        The Explorer study's Dataset.
    """
    fig = new_figure(7.5, 7.5)
    rate_ax, time_ax = fig.subplots(2, 1, sharex=True)
    I = np.asarray(ds.attrs["moments"], dtype=float)
    I_s, I_t = I[0], float(ds.attrs.get("transverse_moment", I[1]))
    J, W = ds.attrs["J"], ds.attrs["spin"]
    c_star = ds.attrs["c_energy_sink_optimum"]
    dense = np.geomspace(ds.damping.values.min() / 2, ds.damping.values.max() * 2, 200)
    linear = np.array([nutation_growth_rate(I, J, f * c_star, W) for f in dense])
    sink = energy_sink_rate(I_s, I_t, J, dense * c_star, W)
    rate_ax.loglog(dense, linear, color=EXACT_COLOR, lw=1.2, label="linear eigenvalue")
    rate_ax.loglog(dense, sink, color=AXIS_COLORS[1], ls="--", lw=1.2,
                   label="energy-sink estimate")
    measured = ds.growth_rate_measured.values
    for k, color in enumerate(_colors(ds.angle.size)):
        shown = np.isfinite(measured[:, k])
        if shown.any():
            rate_ax.loglog(ds.damping.values[shown], measured[shown, k], "o", ms=5, mfc="none",
                           color=color, label=f"fitted, theta0 = {ds.angle.values[k]:g}°")
    rate_ax.set_ylabel(label("growth rate of the nutation", cv.UNITS_RATE))
    rate_ax.set_title("growth rate about the minor axis", fontsize=9)
    for k, color in enumerate(_colors(ds.angle.size)):
        time_ax.loglog(ds.damping.values, ds.flat_time.values[:, k] / MINUTE, "o", ms=4,
                       color=color, label=f"run, theta0 = {ds.angle.values[k]:g}°")
    log_ratio = np.log(np.tan(np.radians(ds.attrs["flat_angle"]))
                       / np.tan(np.radians(ds.angle.values[0])))
    time_ax.loglog(dense, log_ratio / linear / MINUTE, color=EXACT_COLOR, lw=1.0,
                   label=f"linear rate, theta0 = {ds.angle.values[0]:g}°")
    time_ax.loglog(dense, log_ratio / sink / MINUTE, color=AXIS_COLORS[1], ls="--", lw=1.0,
                   label=f"energy sink, theta0 = {ds.angle.values[0]:g}°")
    optimum = ds.attrs["c_linear_optimum"] / c_star
    for ax in (rate_ax, time_ax):
        ax.axvline(optimum, color=EXACT_COLOR, ls=":", lw=1)
        ax.axvline(1.0, color=AXIS_COLORS[1], ls=":", lw=1)
    time_ax.plot([], [], color=EXACT_COLOR, ls=":", lw=1,
                 label=f"optimum c = {ds.attrs['c_linear_optimum']:.3g} N m s (linear)")
    time_ax.plot([], [], color=AXIS_COLORS[1], ls=":", lw=1,
                 label=f"c* = J W I_s / I_t = {c_star:.3g} N m s")
    time_ax.set_xlabel(label("damping c / c*", cv.UNITS_DIMENSIONLESS))
    time_ax.set_ylabel(label(f"time to {ds.attrs['flat_angle']:g}° (flat spin)", "min"))
    plain_log_ticks(time_ax)
    plain_log_ticks(rate_ax, "y")
    place_legend(rate_ax, fontsize=7)
    place_legend(time_ax, fontsize=7)
    fig.suptitle(f"{ds.attrs['body']}: the damping that turns it over fastest", fontsize=10)
    return fig


@styled
def end_state_figure(ds, claim=None):
    """The energy falling to the flat spin's, and every member against the theory: rates,
    |H|, the energy lost and the end energy.

    Parameters
    ----------
    ds : xarray.Dataset
        The Explorer study's Dataset.
    claim : float, optional
        The relative difference claimed for the rates (a line).
    """
    fig = new_figure(7.5, 7.5)
    energy_ax, error_ax = fig.subplots(2, 1)
    for j, color in enumerate(_colors(ds.damping.size)):
        t = ds.sample_time.values[j] / MINUTE
        energy_ax.plot(t, ds.energy_ratio.values[j, 0], color=color, lw=1.2,
                       label=f"c = {ds.damping.values[j]:g} c*")
    if "whip_energy_ratio" in ds:
        energy_ax.plot(ds.whip_sample_time.values / MINUTE, ds.whip_energy_ratio.values[0],
                       ls="--", color="gray", lw=1.2,
                       label=f"whip antennas, theta0 = {ds.whip_angle.values[0]:g}°")
    flat = float(ds.flat_energy_ratio.values[0, 0])
    energy_ax.axhline(flat, color=EXACT_COLOR, ls=":", lw=1,
                      label="|H|²/(2 A_max) over the start's energy (damper body)")
    energy_ax.set_yscale("log")
    energy_ax.set_xlabel(label("time", "min"))
    energy_ax.set_ylabel(label("energy / its start", cv.UNITS_DIMENSIONLESS))
    energy_ax.set_title(f"theta0 = {ds.angle.values[0]:g}°: the energy falls to the flat "
                        "spin's and stays there", fontsize=9)
    members = np.arange(ds.damping.size * ds.angle.size)
    rows = (("growth_rate_error", "growth rate vs linear", "o"),
            ("decay_rate_error", "decay about the major axis vs linear", "s"),
            ("angular_momentum_drift", "|H| largest relative change", "^"),
            ("end_energy_error", "end energy vs |H|²/(2 A_max)", "D"))
    for (name, text, marker), color in zip(rows, _colors(len(rows))):
        values = np.abs(ds[name].values.reshape(-1))
        shown = np.isfinite(values)
        error_ax.semilogy(members[shown], np.maximum(values[shown], 1e-17), marker, ms=4,
                          color=color, mfc="none", label=text)
    if claim is not None:
        error_ax.axhline(claim, color=EXACT_COLOR, ls="--", lw=1, label=f"claim {claim:g}")
    error_ax.set_xticks(members, [f"{c:g} c*\n{a:g}°" for c in ds.damping.values
                                  for a in ds.angle.values], fontsize=7)
    error_ax.set_xlabel(label("member: damping c / c* and start tilt theta0", "c*, degree"))
    error_ax.set_ylabel(label("|relative difference|", cv.UNITS_DIMENSIONLESS))
    error_ax.set_title(f"every member against the theory ({ds.attrs['method']})", fontsize=9)
    place_legend(error_ax, fontsize=7)
    place_legend(energy_ax, fontsize=7)  # once the panel below has its two-line tick labels
    fig.suptitle(f"{ds.attrs['body']}: |H| kept, the energy lost to the flat spin", fontsize=10)
    return fig


#: Points per side of the dense grid on which the maps' boundaries are drawn.
BOUNDARY_GRID = 81
#: Colours of the placements in the rate figure.
PLACEMENT_COLORS = {"platform": AXIS_COLORS[0], "rotor": AXIS_COLORS[1], "both": AXIS_COLORS[2]}
#: Titles of the map's panels.
PLACEMENT_TITLES = {"platform": "damper on the platform", "rotor": "damper in the rotor",
                    "both": "one damper on each"}


@styled
def dual_spin_map_figure(ds, fig=None):
    """For each placement of the dampers: the linear growth rate over the inertia ratio and the
    rotor's relative speed (colour), the boundary where the eigenvalues change sign (solid) and
    where the energy-sink criterion does (dashed), both on a dense grid, and at every cell the
    measured verdict, ringed where the criterion and marked where the measurement disagree with
    the eigenvalues.

    Parameters
    ----------
    ds : xarray.Dataset
        The dual-spin study's Dataset.
    fig : matplotlib.figure.Figure, optional
        Draw into this figure (e.g. one made by ``plt.figure``, which a notebook or the gallery
        shows), resized to the map's size; by default a new one.
    """
    from matplotlib.colors import TwoSlopeNorm
    from matplotlib.lines import Line2D

    placements = [str(p) for p in ds.placement.values]
    size = (7.5, 3.4 if len(placements) > 1 else 4.0)
    if fig is None:
        fig = new_figure(*size)
    else:
        fig.set_size_inches(*size)
        fig.set_layout_engine("constrained")
    axes = np.atleast_1d(fig.subplots(1, len(placements), sharey=True, squeeze=False)[0])
    ratios, speeds = ds.ratio.values, ds.speed.values
    body = body_of(ds)
    dense_r = np.linspace(ratios.min(), ratios.max(), BOUNDARY_GRID)
    dense_s = np.linspace(speeds.min(), speeds.max(), BOUNDARY_GRID)
    top = float(np.nanmax(np.abs(ds.rate_linear.values))) or 1.0
    norm = TwoSlopeNorm(vmin=-top, vcenter=0.0, vmax=top)
    mesh = None
    for ax, placement in zip(axes, placements):
        d = ds.sel(placement=placement)
        mesh = ax.pcolormesh(ratios, speeds, d.rate_linear.values.T, shading="nearest",
                             cmap="RdBu_r", norm=norm)
        linear, sink = linear_map(body, placement, dense_r, dense_s)
        ax.contour(dense_r, dense_s, linear.T, levels=[0.0], colors=EXACT_COLOR,
                   linewidths=1.4)
        ax.contour(dense_r, dense_s, sink.T, levels=[0.0], colors="#ffbf00",
                   linewidths=1.4, linestyles="--")
        R, S = np.meshgrid(ratios, speeds, indexing="ij")
        verdict = d.verdict_measured.values
        for flag, marker in ((DECAYS, "o"), (GROWS, "^")):
            shown = verdict == flag
            ax.scatter(R[shown], S[shown], marker=marker, s=14, facecolors="white",
                       edgecolors=EXACT_COLOR, linewidths=0.6, zorder=3)
        sink_off = d.verdict_energy_sink.values != d.verdict_linear.values
        ax.scatter(R[sink_off], S[sink_off], marker="s", s=70, facecolors="none",
                   edgecolors="#ffbf00", linewidths=1.5, zorder=4)
        measured_off = (verdict != d.verdict_linear.values)
        ax.scatter(R[measured_off], S[measured_off], marker="x", s=50, color="#d62728",
                   linewidths=1.5, zorder=5)
        ax.axvline(1.0, color="gray", ls=":", lw=0.8)
        ax.set_title(PLACEMENT_TITLES.get(placement, placement), fontsize=9)
        ax.set_xlabel(label("A3 / A_t", cv.UNITS_DIMENSIONLESS))
    axes[0].set_ylabel(label("rotor speed rel. to the platform", cv.UNITS_ANGULAR_VELOCITY))
    bar = fig.colorbar(mesh, ax=list(axes), shrink=0.9)
    bar.set_label(label("linear growth rate", cv.UNITS_RATE))
    handles = [
        Line2D([], [], color=EXACT_COLOR, lw=1.4, label="eigenvalues' boundary"),
        Line2D([], [], color="#ffbf00", lw=1.4, ls="--", label="energy-sink criterion"),
        Line2D([], [], ls="", marker="o", mfc="white", mec=EXACT_COLOR, label="measured: decays"),
        Line2D([], [], ls="", marker="^", mfc="white", mec=EXACT_COLOR, label="measured: grows"),
        Line2D([], [], ls="", marker="s", mfc="none", mec="#ffbf00", mew=1.5,
               label="criterion ≠ eigenvalues"),
        Line2D([], [], ls="", marker="x", color="#d62728", mew=1.5,
               label="measured ≠ eigenvalues"),
    ]
    fig.legend(handles=handles, loc="outside lower center", ncols=3, fontsize=7.5)
    fig.suptitle(f"dual spin, platform at {ds.attrs['platform_spin']:g} rad/s: dampers at "
                 f"{ds.attrs['platform_damping']:g} c* (platform), "
                 f"{ds.attrs['rotor_damping']:g} c* (rotor)", fontsize=10)
    return fig


@styled
def dual_spin_rate_figure(ds, claim=None):
    """Every member's fitted growth rate, and every cell's energy-sink estimate, against the
    linear eigenvalue; and their relative differences from it.

    Parameters
    ----------
    ds : xarray.Dataset
        The dual-spin study's Dataset.
    claim : float, optional
        The relative difference claimed for the fitted rates (a line).
    """
    fig = new_figure(7.5, 7.0)
    rate_ax, error_ax = fig.subplots(2, 1)
    linear_all = ds.rate_linear.values
    lo, hi = float(np.nanmin(linear_all)), float(np.nanmax(linear_all))
    rate_ax.plot([lo, hi], [lo, hi], color=EXACT_COLOR, lw=0.8, label="= linear eigenvalue")
    for placement in ds.placement.values:
        d = ds.sel(placement=placement)
        color = PLACEMENT_COLORS.get(str(placement), "gray")
        linear = np.broadcast_to(d.rate_linear.values[..., None], d.rate_measured.shape)
        measured = d.rate_measured.values
        shown = np.isfinite(measured)
        rate_ax.plot(linear[shown], measured[shown], "o", ms=4, mfc="none", color=color,
                     label=f"fitted, {PLACEMENT_TITLES.get(str(placement), placement)}")
        rate_ax.plot(d.rate_linear.values.ravel(), d.rate_energy_sink.values.ravel(), "x",
                     ms=4, color=color, alpha=0.6, label=f"energy sink, on {placement}")
        error = np.abs(d.rate_error.values)
        shown = np.isfinite(error)
        error_ax.semilogy(linear[shown], np.maximum(error[shown], 1e-9), "o", ms=4, mfc="none",
                          color=color, label=f"fitted, on {placement}")
        sink = np.abs(d.rate_sink_error.values.ravel())
        shown = np.isfinite(sink)
        error_ax.semilogy(d.rate_linear.values.ravel()[shown], np.maximum(sink[shown], 1e-9),
                          "x", ms=4, color=color, alpha=0.6, label=f"energy sink, on {placement}")
    if claim is not None:
        error_ax.axhline(claim, color=EXACT_COLOR, ls="--", lw=1,
                         label=f"claim {claim:g} (fitted rates)")
    rate_ax.axhline(0.0, color="gray", lw=0.5)
    rate_ax.set_xlabel(label("growth rate by the linear eigenvalue", cv.UNITS_RATE))
    rate_ax.set_ylabel(label("fitted / energy-sink growth rate", cv.UNITS_RATE))
    rate_ax.set_title("growth (> 0) and decay (< 0) of the nutation", fontsize=9)
    error_ax.set_xlabel(label("growth rate by the linear eigenvalue", cv.UNITS_RATE))
    error_ax.set_ylabel(label("|relative difference from the eigenvalue|",
                              cv.UNITS_DIMENSIONLESS))
    error_ax.set_title("fitted rates (floored at 1e-9) and the energy sink's error", fontsize=9)
    place_legend(rate_ax, fontsize=7)
    place_legend(error_ax, fontsize=7)
    fig.suptitle("dual spin: the nutation's rate measured against the linear theory",
                 fontsize=10)
    return fig
