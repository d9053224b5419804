"""Figures of the tennis-racket study (``stability run studies/tennis_racket.toml``).

1. :func:`flips_figure`: w1, w2, w3 of one member against time, the exact solution overlaid.
2. :func:`polhode_figure`: polhodes on the |L| sphere around all three axes, the separatrix.
3. :func:`growth_figure`: median and spread of the perpendicular amplitude (log scale) with the
   analytic slope sqrt(-Omega^2) and the measured one.
4. :func:`flip_interval_figure`: measured flip intervals against the exact 2K/nu of each member
   and the ln(4/k') asymptote.

Each draws the study's Dataset (an ensemble with the variables and attributes the
tennis-racket study adds) and returns a ``matplotlib.figure.Figure`` whose every axis is
labelled with its unit. The body and the spin axis (1, 2, 3) are those the Dataset records
(``I1``, ``I2``, ``I3``, ``body_name``, ``axis``) unless given. Curves of the exact
solution come from the package (:func:`stability.exact_omega`, :mod:`stability.free_body.polhodes`).
"""

from __future__ import annotations

import numpy as np

from ...core.axes import moment_name
from ...util.conventions import perpendicular_axes
from ...analysis.members import sign_change_times
from ..exact import exact_omega
from ..measure import complementary_moduli
from ...output.dataset import body_from_attrs
from ...plotting.style import (
    AXIS_COLORS, ENSEMBLE_COLOR, EXACT_COLOR, label, new_figure, place_legend, styled,
)
from ..polhodes import polhodes, separatrix_circles
from ...util import conventions as cv


def _subtitle(ds, body, axis) -> str:
    spin = ds.attrs.get("spin", float("nan"))
    eps = ds.attrs.get("epsilon", float("nan"))
    return (f"{body.name}: spin {spin:g} rad/s about axis {axis} ({moment_name(body, axis)} "
            f"moment), perturbation ε = {eps:g}")


def _body_and_axis(ds, body, axis):
    """``body`` and ``axis``; by default those the Dataset records."""

    return (body_from_attrs(ds.attrs) if body is None else body,
            int(ds.attrs["axis"]) if axis is None else int(axis))


def nudge_for_modulus(body, axis):
    """``(to_epsilon, to_x, b)``: the size epsilon (relative to the spin) of a nudge across a
    spin about ``axis`` that gives the complementary modulus k', as a function of
    x = ln(4/k'), and back; the nudge is along the perpendicular axis ``b`` whose nudge gives
    the largest k' (a nudge of that size in any other direction gives a smaller k', so a
    member of an ensemble of one epsilon lies at or below it). k' depends on epsilon alone
    (Euler's equations are homogeneous in w) and grows with it.
    """
    eps = np.logspace(-100.0, np.log10(0.5), 600)
    best = None
    for b in perpendicular_axes(axis):
        w0 = np.zeros((eps.size, 3))
        w0[:, axis - 1], w0[:, b - 1] = 1.0, eps
        x = np.log(4.0 / complementary_moduli(body, w0))
        if best is None or x[0] < best[1][0]:  # the larger k' at the smallest nudge
            best = (b, x)
    b, x = best
    log_eps = np.log(eps)
    to_epsilon = lambda v: np.exp(np.interp(v, x[::-1], log_eps[::-1]))
    to_x = lambda e: np.interp(np.log(np.maximum(e, 1e-300)), log_eps, x)
    return to_epsilon, to_x, b


def _epsilon_axis(ax, body, axis, epsilon=None):
    """A top axis in epsilon over an axis in ln(4/k') (:func:`nudge_for_modulus`)."""
    from matplotlib.ticker import LogFormatterSciNotation, LogLocator, NullFormatter

    to_epsilon, to_x, b = nudge_for_modulus(body, axis)
    top = ax.secondary_xaxis("top", functions=(to_epsilon, to_x))
    top.set_xscale("log")
    top.xaxis.set_major_locator(LogLocator(numticks=8))
    top.xaxis.set_major_formatter(LogFormatterSciNotation())
    top.xaxis.set_minor_formatter(NullFormatter())
    text = f"ε along axis {b} giving k′" + ("" if epsilon is None else f" (run: {epsilon:.3g})")
    top.set_xlabel(label(text, cv.UNITS_DIMENSIONLESS))
    return top


def typical_member(ds) -> int:
    """An ok member whose series is kept (``series_member``) and whose mean flip interval is
    the median one among those; the first kept member if none is ok."""
    kept = ds[cv.SERIES_MEMBER].values
    ok = ((ds.status == cv.STATUS_OK).values & np.isfinite(ds.mean_flip_interval.values))[kept]
    if not ok.any():
        return int(kept[0])
    candidates = kept[ok]
    intervals = ds.mean_flip_interval.values[candidates]
    return int(candidates[np.argsort(intervals, kind="stable")[len(candidates) // 2]])


@styled
def flips_figure(ds, body=None, axis=None, member=None, samples=2000):
    """Figure 1: w1, w2, w3 of one member against time, with the exact solution overlaid.

    Parameters
    ----------
    ds : xarray.Dataset
        The study's Dataset (``w`` (series_member, time, axis) in rad/s, ``w0``).
    body : RigidBody, optional
        Default: the body the Dataset records.
    axis : int, optional
        Spin axis (1, 2, 3); its sign changes (flips) are marked. Default: the Dataset's.
    member : int, optional
        Member to show, one whose series is kept; default :func:`typical_member`.
    samples : int
        Points of the exact curve.
    """

    body, axis = _body_and_axis(ds, body, axis)
    j = typical_member(ds) if member is None else int(member)
    kept = ds[cv.SERIES_MEMBER].values
    if j not in kept:
        raise ValueError(f"member {j}'s time series is not kept: choose one of the "
                         f"{kept.size} series_member values ({', '.join(map(str, kept[:5]))}, "
                         "...), or run with more [output] series_members")
    t = ds[cv.TIME].values
    w = ds.w.sel({cv.SERIES_MEMBER: j}).values
    t_fine = np.linspace(t[0], t[-1], samples)
    exact = np.asarray(exact_omega(body, ds.w0.values[j], t_fine), dtype=float)
    flips = sign_change_times(t_fine, exact[:, axis - 1])

    fig = new_figure(7.5, 6.5)
    axes = fig.subplots(3, 1, sharex=True)
    method = ds.attrs.get("method", "")
    h = ds.attrs.get("h", float("nan"))
    for i, ax in enumerate(axes):
        for k, tf in enumerate(flips):
            ax.axvline(tf, color="0.6", lw=0.8, ls=":",
                       label=f"flip (w{axis} = 0)" if k == 0 else None)
        ax.plot(t, w[:, i], "o", ms=3.0, color=AXIS_COLORS[i],
                label=f"numerical ({method}, h = {h:g} s)")
        ax.plot(t_fine, exact[:, i], "-", lw=1.0, color=EXACT_COLOR,
                label="exact (Jacobi elliptic functions)")
        ax.set_ylabel(label(f"w{i + 1}", cv.UNITS_ANGULAR_VELOCITY))
        if i + 1 == axis:
            ax.set_title(f"w{axis}: spin axis, changes sign at every flip", loc="left", fontsize=9)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=3, framealpha=0.9)
    axes[-1].set_xlabel(label("time", cv.UNITS_TIME))
    interval = ds.mean_flip_interval.values[j]
    exact_interval = ds.exact_flip_interval.values[j] if "exact_flip_interval" in ds else np.nan
    fig.suptitle(
        f"Repeated flips of member {j}: mean interval {interval:.4f} s "
        f"(exact 2K/ν = {exact_interval:.4f} s)\n{_subtitle(ds, body, axis)}",
        fontsize=10,
    )
    return fig


@styled
def polhode_figure(ds, body=None, axis=None, levels=(0.12, 0.35, 0.6, 0.82, 0.96), samples=400):
    """Figure 2: polhodes (paths of the body angular momentum m/|L|) on the unit sphere.

    Around each stable axis (smallest and largest moment) orbits are drawn at energies
    ``2E/L^2 = 1/I_centre + f (1/I_intermediate - 1/I_centre)`` for f in ``levels`` (f = 0 is the
    centre, f = 1 the separatrix), each followed for one full period with the exact solution
    (:func:`stability.free_body.polhodes.polhodes`), together with its mirror image. The separatrix
    D2 = 0 is drawn from its closed form (:func:`stability.free_body.polhodes.separatrix_circles`).
    Left: 3-D view of the near side; right: the hemisphere around the saddle seen head-on.
    """
    body, axis = _body_and_axis(ds, body, axis)
    I = body.moments
    a, b, c = np.argsort(I, kind="stable")  # body axes (0-based) of the smallest ... largest
    families = polhodes(body, levels, samples)
    separatrix = separatrix_circles(body)

    fig = new_figure(12.0, 6.0)
    grid = fig.add_gridspec(1, 2, width_ratios=(1.15, 1.0))
    ax3 = fig.add_subplot(grid[0], projection="3d")
    ax2 = fig.add_subplot(grid[1])
    colors = {a: AXIS_COLORS[0], c: AXIS_COLORS[2]}
    names = {a: "smallest", c: "largest"}
    # Look from a direction with the saddle +e_b and both stable axes on the near side.
    view = np.zeros(3)
    view[a], view[b], view[c] = 0.55, 1.0, 0.6
    view /= np.linalg.norm(view)
    elev = np.degrees(np.arcsin(view[2]))
    azim = np.degrees(np.arctan2(view[1], view[0]))

    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 49), np.linspace(0, np.pi, 25))
    ax3.plot_surface(np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v),
                     color="0.8", alpha=0.12, linewidth=0, shade=False)
    for centre, curves in families:
        for k, m in enumerate(curves):
            near = np.where((m @ view >= 0.0)[:, None], m, np.nan)
            ax3.plot(*near.T, color=colors[centre], lw=1.1,
                     label=f"polhodes around axis {centre + 1} ({names[centre]} moment)"
                     if k == 0 else None)
    for k, m in enumerate(separatrix):
        near = np.where((m @ view >= 0.0)[:, None], m, np.nan)
        ax3.plot(*near.T, color="crimson", lw=2.2, label="separatrix (D2 = 0)" if k == 0 else None)
    points = ((a, "o", 45, AXIS_COLORS[0], "stable centre"),
              (c, "o", 45, AXIS_COLORS[2], "stable centre"),
              (b, "X", 90, "crimson", "saddle (unstable spin)"))
    for axis_index, marker, size, color, what in points:
        for sign in (1.0, -1.0):
            p = sign * np.eye(3)[axis_index]
            if p @ view < -0.2:
                continue  # far side: hidden behind the sphere
            ax3.scatter(*p, marker=marker, s=size, color=color, edgecolor="black",
                        depthshade=False, zorder=10,
                        label=f"{what}: axis {axis_index + 1}" if sign > 0 else None)
            ax3.text(*(1.15 * p), f"{'+' if sign > 0 else '−'}{axis_index + 1}", fontsize=10,
                     ha="center", va="center", zorder=11)
    ax3.view_init(elev=elev, azim=azim)
    ax3.set_box_aspect((1, 1, 1), zoom=1.15)
    for setter, k in ((ax3.set_xlabel, 0), (ax3.set_ylabel, 1), (ax3.set_zlabel, 2)):
        setter(label(f"m{k + 1}/|L|", cv.UNITS_DIMENSIONLESS), fontsize=8, labelpad=-2)
    for ticks in (ax3.set_xticks, ax3.set_yticks, ax3.set_zticks):
        ticks([-1, 0, 1])
    ax3.tick_params(labelsize=7, pad=-2)
    ax3.set_title("near side of the sphere |m| = |L|")

    theta = np.linspace(0, 2 * np.pi, 361)
    ax2.plot(np.cos(theta), np.sin(theta), color="0.5", lw=0.8)
    for centre, curves in families:
        for m in curves:
            near = np.where(m[:, b] >= 0.0, 1.0, np.nan)
            ax2.plot(m[:, a] * near, m[:, c] * near, color=colors[centre], lw=1.1)
    for m in separatrix:
        near = np.where(m[:, b] >= 0.0, 1.0, np.nan)
        ax2.plot(m[:, a] * near, m[:, c] * near, color="crimson", lw=2.2)
    ax2.scatter([0], [0], marker="X", s=110, color="crimson", edgecolor="black", zorder=5)
    ax2.annotate(f"saddle +{b + 1}", (0, 0), xytext=(0.1, 0.08), fontsize=10)
    for x, y, axis_index in ((1, 0, a), (-1, 0, a), (0, 1, c), (0, -1, c)):
        ax2.scatter([x], [y], s=55, color=colors[axis_index], edgecolor="black", zorder=5,
                    clip_on=False)
        ax2.annotate(f"{'+' if x + y > 0 else '−'}{axis_index + 1}", (x, y),
                     xytext=(13 * x, 9 * y - 4 - 6 * (y < 0)),
                     textcoords="offset points", fontsize=10, ha="center")
    ax2.set_aspect("equal")
    ax2.set_xlim(-1.15, 1.15)
    ax2.set_ylim(-1.15, 1.15)
    ax2.set_xlabel(label(f"m{a + 1}/|L|", cv.UNITS_DIMENSIONLESS))
    ax2.set_ylabel(label(f"m{c + 1}/|L|", cv.UNITS_DIMENSIONLESS))
    ax2.set_title(f"the hemisphere m{b + 1} > 0 seen head-on from the saddle")
    handles, labels = ax3.get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=3, framealpha=0.9)
    fig.suptitle(
        f"Polhodes of the torque-free {body.name}, I = ({', '.join(f'{x:.4g}' for x in I)}) "
        "kg m²: two stable centres, two saddles, the separatrix between them",
        fontsize=10,
    )
    return fig


@styled
def growth_figure(ds, body=None, axis=None):
    """Figure 3: ensemble growth of the perpendicular amplitude against the analytic slope.

    The median over members of ``sqrt(w_b^2 + w_c^2)`` and its 10-90 % band on a log scale;
    the measured rate (``growth_rate_fitted``: :func:`stability.measured_growth_rate`, the mean
    of the members' fits over the linear phase) drawn through the median over the window where
    the median is in the linear phase (shaded; ``growth_fit_window``, ``growth_fit_intercept``);
    the analytic ``exp(lambda t)`` (lambda = sqrt(-Omega^2)) through the same point at the
    middle of the window.
    """
    body, axis = _body_and_axis(ds, body, axis)
    t = ds[cv.TIME].values
    median = ds.perp_amplitude_median.values
    lo, hi = ds.perp_amplitude_p10.values, ds.perp_amplitude_p90.values
    rate = ds.attrs["growth_rate_analytic"]
    fitted = ds.attrs["growth_rate_fitted"]
    intercept = ds.attrs["growth_fit_intercept"]
    t0, t1 = np.asarray(ds.attrs["growth_fit_window"], dtype=float)
    first_flips = ds.first_flip_time.values[np.isfinite(ds.first_flip_time.values)]
    t_show = min(t[-1], 2.0 * np.median(first_flips)) if first_flips.size else t[-1]
    shown = t <= t_show

    fig = new_figure(7.5, 4.8)
    ax = fig.subplots()
    ax.fill_between(t[shown], lo[shown], hi[shown], color=ENSEMBLE_COLOR, alpha=0.25, lw=0,
                    label="10–90 % of members")
    ax.plot(t[shown], median[shown], "o-", ms=3, color=ENSEMBLE_COLOR, lw=1.2,
            label=f"median over {int((ds.status == cv.STATUS_OK).sum())} members")
    if np.isfinite(t0) and np.isfinite(t1):
        ax.axvspan(t0, t1, color="0.5", alpha=0.12, lw=0, label="linear phase of the median")
        mid = 0.5 * (t0 + t1)
        anchor = fitted * mid + intercept  # ln(median) at the window's middle, per the line
        tt = np.linspace(0.0, t_show, 200)
        line = np.exp(anchor + rate * (tt - mid))
        keep = line < 2.0 * np.nanmax(hi)
        ax.plot(tt[keep], line[keep], "-", color=EXACT_COLOR, lw=1.2,
                label=f"analytic slope √(−Ω²) = {rate:.5f} 1/s")
        tf = np.linspace(t0, t1, 50)
        ax.plot(tf, np.exp(intercept + fitted * tf), "--", color="crimson", lw=2.0,
                label=f"measured {fitted:.5f} 1/s, mean of member fits "
                      f"(rel. error {(fitted - rate) / rate:+.1e})")
    spin = ds.attrs.get("spin", np.nan)
    eps = ds.attrs.get("epsilon", np.nan)
    ax.axhline(eps * spin, color="0.4", lw=0.8, ls=":", label="start: ε × spin")
    ax.set_yscale("log")
    ax.set_xlim(0.0, t_show)
    ax.set_xlabel(label("time", cv.UNITS_TIME))
    b, c = perpendicular_axes(axis)
    ax.set_ylabel(label(f"perpendicular amplitude √(w{b}² + w{c}²)", cv.UNITS_ANGULAR_VELOCITY))
    # Below the axes: seven entries inside it covered the band or the growth line.
    fig.legend(loc="outside lower center", ncols=2, framealpha=0.9)
    if rate > 0:
        headline = (f"Exponential growth away from the {moment_name(body, axis)} axis, then "
                    "saturation at the flip")
    else:
        headline = (f"Bounded oscillation about the {moment_name(body, axis)} axis "
                    f"(Ω² = {ds.attrs['omega_squared']:.4g} 1/s² > 0: stable)")
    ax.set_title(f"{headline}\n{_subtitle(ds, body, axis)}", fontsize=10)
    return fig


def _cloud(ax, x, y, dense, label, what="measured"):
    """One dot per member (``label``), or (``dense``) the members per cell of a hexagonal grid
    on a log colour scale: a figure whose cost does not grow with the member count."""
    if not dense:
        ax.plot(x, y, "o", ms=2.5, color=ENSEMBLE_COLOR, alpha=0.6, zorder=2, label=label)
        return
    ax.hexbin(x, y, gridsize=(60, 30), bins="log", mincnt=1, cmap="Blues", zorder=2,
              linewidths=0.0)
    ax.plot([], [], "h", ms=6, color=ENSEMBLE_COLOR,
            label=f"{what}: density of {x.size} members (log colour)")


@styled
def flip_interval_figure(ds, body=None, axis=None, max_points=3000):
    """Figure 4: measured flip intervals against the exact 2K/nu and the ln(4/k') asymptote.

    Left: histograms over members of the measured mean flip interval and of the exact 2K/nu of
    each member's start. Middle: flip interval against ln(4/k') (k' is proportional to epsilon
    for a given direction, so the axis is ln(1/epsilon) up to a constant): measured (dots),
    exact 2K/nu, and the asymptote (2/lambda) ln(4/k') (literature notes 1.5). Right: the
    relative differences from 2K/nu of the measured intervals and of the asymptote. With more
    than ``max_points`` members the measured ones are drawn as a density and the curves
    through ``max_points`` of them, so the figure costs the same for any member count.
    """
    body, axis = _body_and_axis(ds, body, axis)
    ok = (ds.status == cv.STATUS_OK).values
    good = ok & np.isfinite(ds.mean_flip_interval.values) & np.isfinite(
        ds.exact_flip_interval.values)
    n_good, n_ok = int(good.sum()), int(ok.sum())
    # the members drawn, once each (a million-member figure holds these four arrays)
    measured = ds.mean_flip_interval.values[good]
    exact = ds.exact_flip_interval.values[good]
    asymptote = ds.flip_interval_asymptote.values[good]
    x = np.log(4.0 / ds.complementary_modulus.values[good])
    rate = ds.attrs["growth_rate_analytic"]

    fig = new_figure(15.0, 4.8)
    left, middle, right = fig.subplots(1, 3, width_ratios=(1.1, 1.0, 1.0))
    if n_good:
        lo, hi = np.quantile(np.concatenate([measured, exact]), [0.0, 0.99])
        bins = np.linspace(lo, hi, 60)
        left.hist(measured, bins=bins, color=ENSEMBLE_COLOR, alpha=0.6,
                  label=f"measured mean interval\n({n_good} of {n_ok} members with ≥ 2 flips)")
        left.hist(exact, bins=bins, histtype="step", color=EXACT_COLOR, lw=1.5,
                  label="exact 2K/ν of each member's start")
        med = np.median(measured)
        left.axvline(med, color="crimson", lw=1.2, ls="--", label=f"median {med:.4f} s")
    left.set_xlabel(label("flip interval", cv.UNITS_TIME))
    left.set_ylabel(label("members per bin", "count"))
    left.set_title("Over the ensemble (1 % longest not shown)")

    if n_good:
        idx = np.arange(n_good)
        if n_good > max_points:
            idx = np.random.default_rng(0).choice(n_good, max_points, replace=False)
        line = idx[np.argsort(x[idx], kind="stable")]  # the curves through those members
        dense = n_good > max_points  # a cloud of more members is drawn as a density
        _cloud(middle, x, measured, dense, "measured (one dot per member)")
        middle.plot(x[line], exact[line], "-", color=EXACT_COLOR, lw=1.2, label="exact 2K/ν")
        middle.plot(x[line], asymptote[line], "--", color="crimson", lw=1.5,
                    label=f"asymptote (2/λ) ln(4/k′), λ ≈ {rate:.4f} 1/s")

        rel_measured = (measured - exact) / exact
        rel_asymptote = (asymptote[idx] - exact[idx]) / exact[idx]
        # the asymptote's difference depends on each member's start, not on ln(4/k') alone:
        # one marker per member (of at most max_points), under the measured ones
        worst_asymptote = np.max(np.abs((asymptote - exact) / exact))
        right.plot(x[idx], rel_asymptote, "s", ms=2.0, color="crimson", zorder=1,
                   label=f"asymptote (max |·| = {worst_asymptote:.1e})")
        worst = f"max |·| = {np.max(np.abs(rel_measured)):.1e}"
        _cloud(right, x, rel_measured, dense, f"measured ({worst})", f"measured ({worst})")
        right.axhline(0.0, color=EXACT_COLOR, lw=1.0)
        right.ticklabel_format(axis="y", style="sci", scilimits=(-2, 2))
    middle.set_xlabel(label("ln(4/k′), k′ = complementary modulus ∝ ε", cv.UNITS_DIMENSIONLESS))
    if rate > 0:  # k' is the modulus of a flip: an axis in epsilon beside ln(4/k')
        for ax in (middle, right):
            _epsilon_axis(ax, body, axis, ds.attrs.get("epsilon"))
    middle.set_ylabel(label("flip interval", cv.UNITS_TIME))
    middle.set_title("The ln(1/ε) law")
    right.set_xlabel(label("ln(4/k′)", cv.UNITS_DIMENSIONLESS))
    right.set_ylabel(label("(interval − 2K/ν) / (2K/ν)", cv.UNITS_DIMENSIONLESS))
    right.set_title("Relative difference from the exact 2K/ν")
    for ax in (left, middle, right):
        if n_good:
            place_legend(ax, framealpha=0.9)
        else:
            ax.text(0.5, 0.5, "no member flipped twice", transform=ax.transAxes,
                    ha="center", va="center", color="0.4")
    fig.suptitle(_subtitle(ds, body, axis), fontsize=10)
    return fig
