"""Figures of the stability map (``stability run studies/stability_map.toml``).

1. :func:`map_figure`: the shape triangle coloured by the analytic Omega^2 / W^2 for each spin
   axis, the measured values overlaid as dots; below, the relative error of the measurement.
2. :func:`scatter_figure`: measured against analytic Omega^2 for every (shape, axis) and method
   with the identity line, and the relative error against |Omega^2| with the accuracy bar.
3. :func:`flip_interval_figure`: flip interval against epsilon for a few shapes, the exact 2K/nu
   curve and the ln(1/epsilon) law; below, the relative error of each method.
4. :func:`edges_figure`: time series on the equal-moment edges and the sphere: a departure linear
   in t, the distinct-axis component constant, no flip.
5. :func:`ftle_map_figure`: the map from tangents (:mod:`.ftle_map`), the FTLE of each cell as
   a colour with the analytic rate's contours over it, like REBOUND's MEGNO maps.

Each takes the study's Dataset and returns a ``matplotlib.figure.Figure`` whose every axis is
labelled with its unit.
"""

from __future__ import annotations

import numpy as np

from ...util.conventions import REGIME_ALGEBRAIC, REGIME_MEANINGS, REGIME_NEUTRAL
from ..model import growth_rate
from ...util.conventions import perpendicular_axes
from ...analysis.regimes import DEPARTURE_FACTOR, MIN_POINTS
from ..tennis_racket.flipsweep import exact_flip_curve
from ...plotting.style import AXIS_COLORS, EXACT_COLOR, label, new_figure, place_legend, styled
from .ftle_map import eigenvector_aspect, physical
from .shapes import analytic_omega_squared, shape_grid

#: Marker of each method in the scatter and sweep figures (cycled).
_MARKERS = ("o", "s", "^", "D", "v", "P")
#: Colours of the flip-sweep shapes.
_SHAPE_COLORS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#8c564b")


def _triangle_outline(ax):
    """The allowed region's edges in the (I1, I2) plane, labelled."""
    ax.plot([0.0, 0.5, 1.0, 0.0], [1.0, 0.5, 1.0, 1.0], color="0.3", lw=0.8)
    ax.set_xlim(-0.03, 1.03)
    ax.set_ylim(0.47, 1.03)
    ax.set_aspect("equal")


@styled
def map_figure(ds, method=None):
    """Figure 1: the map of Omega^2 / W^2 over the shape triangle, per spin axis.

    Top row: the analytic Omega^2 / W^2 (colour, diverging at 0: red grows, blue oscillates),
    the measured values as dots in the same colours (a dot that stands out would be a
    disagreement), crosses where the regime's sign is wrong, open markers where no rate was
    measured (Omega^2 = 0 on the edges: algebraic drift or no motion). Bottom row:
    log10 |relative error| of the measured Omega^2 (worst over the methods, or ``method``).
    """
    import matplotlib.tri as mtri
    from matplotlib.colors import TwoSlopeNorm


    spin = float(ds.attrs["spin"])
    I1, I2 = ds.I1.values, ds.I2.values
    fine, _ = shape_grid(120)  # the analytic background on a fine grid of the same triangle
    tri = mtri.Triangulation(fine[:, 0], fine[:, 1])
    analytic_fine = analytic_omega_squared(fine, 1.0).T
    vmax = float(np.nanmax(ds.omega_squared_normalised.values))
    vmin = float(np.nanmin(ds.omega_squared_normalised.values))
    norm = TwoSlopeNorm(vcenter=0.0, vmin=min(vmin, -1e-3), vmax=max(vmax, 1e-3))
    if method is None:
        pick = slice(None)
        which = "worst over " + ", ".join(str(m) for m in ds.integrator.values)
    else:
        pick = [list(ds.integrator.values).index(method)]
        which = method
    measured = ds.omega_squared_measured.values[pick] / spin**2
    rel = np.abs(ds.relative_error.values[pick])
    worst_rel = np.max(np.where(np.isfinite(rel), rel, -np.inf), axis=0)
    worst_rel = np.where(np.isfinite(worst_rel), worst_rel, np.nan)
    # The measured value shown is the first method's where it has one.
    shown = np.full(measured.shape[1:], np.nan)
    for values in measured[::-1]:
        shown = np.where(np.isfinite(values), values, shown)
    sign = ds.sign_agrees.values[pick].astype(bool).all(axis=0)
    regime = ds.regime.values[pick]

    fig = new_figure(11.5, 6.6)
    axes = fig.subplots(2, 3)
    log_err = np.log10(np.maximum(worst_rel, 1e-12))
    err_lo = max(float(np.nanmin(log_err)) if np.isfinite(log_err).any() else -8.0, -9.0)
    err_hi = max(float(np.nanmax(log_err)) if np.isfinite(log_err).any() else -3.0,
                 np.log10(float(ds.attrs["tolerance"])))
    for k in range(3):
        ax = axes[0, k]
        pc = ax.tripcolor(tri, analytic_fine[k], cmap="RdBu_r", norm=norm, shading="gouraud",
                          rasterized=True)
        ok = np.isfinite(shown[:, k])
        ax.scatter(I1[ok], I2[ok], c=shown[ok, k], cmap="RdBu_r", norm=norm, s=16,
                   edgecolors="black", linewidths=0.5, zorder=3,
                   label="measured (the background's colour scale)")
        drift = np.any(regime[:, :, k] == REGIME_ALGEBRAIC, axis=0)
        still = np.any(regime[:, :, k] == REGIME_NEUTRAL, axis=0)
        ax.scatter(I1[drift], I2[drift], marker="o", s=16, facecolors="none",
                   edgecolors="k", linewidths=0.7, zorder=4, label="algebraic drift (Ω² = 0)")
        ax.scatter(I1[still], I2[still], marker="s", s=22, facecolors="none",
                   edgecolors="k", linewidths=0.8, zorder=4, label="no departure (sphere)")
        bad = ~sign[:, k]
        if bad.any():
            ax.scatter(I1[bad], I2[bad], marker="x", s=30, color="k", zorder=5,
                       label="regime sign wrong")
        _triangle_outline(ax)
        ax.set_title(f"spin about axis {k + 1}")
        ax.set_xlabel(label("I1 / I3", "1"))
        ax.set_ylabel(label("I2 / I3", "1"))
        ax.grid(False)
        ax.annotate("rod", (0.0, 1.0), xytext=(2, 3), textcoords="offset points", fontsize=7)
        ax.annotate("disk", (0.5, 0.5), xytext=(6, -2), textcoords="offset points",
                    fontsize=7)
        ax.annotate("sphere", (1.0, 1.0), xytext=(-30, 3), textcoords="offset points",
                    fontsize=7)
        if k == 0:
            handles, labels = ax.get_legend_handles_labels()

        ax = axes[1, k]
        sc = ax.scatter(I1, I2, c=log_err[:, k], cmap="viridis", vmin=err_lo, vmax=err_hi,
                        s=14, zorder=3)
        miss = ~np.isfinite(worst_rel[:, k])
        ax.scatter(I1[miss], I2[miss], marker="o", s=14, facecolors="none", edgecolors="0.5",
                   linewidths=0.6, zorder=3, label="no rate fitted")
        _triangle_outline(ax)
        ax.set_title(f"axis {k + 1}: relative error ({which})", fontsize=8.5)
        ax.set_xlabel(label("I1 / I3", "1"))
        ax.set_ylabel(label("I2 / I3", "1"))
        ax.grid(False)
        if k == 0:
            more, texts = ax.get_legend_handles_labels()
            handles, labels = handles + more, labels + texts
    fig.legend(handles, labels, loc="outside lower center", ncol=len(labels), fontsize=7.5)
    cb = fig.colorbar(pc, ax=axes[0, :], shrink=0.9)
    cb.set_label(label("analytic Ω² / W²", "1"))
    cb = fig.colorbar(sc, ax=axes[1, :], shrink=0.9)
    cb.set_label(label("log10 relative error of Ω²", "1"))
    fig.suptitle(f"Stability map: {ds.sizes['shape']} shapes × 3 axes, "
                 f"{ds.attrs['members']} members each, ε = {ds.attrs['epsilon']:g}, "
                 f"W = {spin:g} rad/s")
    return fig


@styled
def scatter_figure(ds):
    """Figure 2: measured against analytic Omega^2 / W^2 for every (shape, axis) and method.

    Left: measured against analytic with the identity line. Right: |relative error| against
    |analytic| (log-log) with the accuracy bar and the |Omega^2| floor below which it does not
    apply; the ensembles with Omega^2 = 0 (no rate fitted) are counted in the legend.
    """

    spin = float(ds.attrs["spin"])
    tol = float(ds.attrs["tolerance"])
    floor = float(ds.attrs["min_omega_squared"])
    analytic = ds.omega_squared_normalised.values
    fig = new_figure(12.0, 4.8)
    left, right = fig.subplots(1, 2)
    lim = [float(np.nanmin(analytic)) * 1.05 - 0.02, float(np.nanmax(analytic)) * 1.05 + 0.02]
    left.plot(lim, lim, color=EXACT_COLOR, lw=0.8, label="measured = analytic")
    for k, method in enumerate(ds.integrator.values):
        h = float(ds.h.values[k])
        marker = _MARKERS[k % len(_MARKERS)]
        measured = ds.omega_squared_measured.values[k] / spin**2
        ok = np.isfinite(measured)
        left.scatter(analytic[ok], measured[ok], s=10, marker=marker, alpha=0.6,
                     label=f"{method}, h = {h:g} s ({int(ok.sum())})")
        rel = np.abs(ds.relative_error.values[k])
        color = f"C{k}"
        for grows, face in ((False, color), (True, "none")):
            good = np.isfinite(rel) & ((analytic < 0) if grows else (analytic > 0))
            right.scatter(np.abs(analytic[good]), np.maximum(rel[good], 1e-12), s=12,
                          marker=marker, facecolors=face, edgecolors=color, alpha=0.7,
                          label=f"{method}, {'growth (open)' if grows else 'oscillation'}")
    zero = analytic == 0
    reg = ds.regime.values[:, zero]
    n_alg = int(np.sum(reg == REGIME_ALGEBRAIC))
    n_neu = int(np.sum(reg == REGIME_NEUTRAL))
    right.axhline(tol, color="k", ls="--", lw=0.8, label=f"bar {tol:g}")
    right.axvline(floor, color="0.5", ls=":", lw=0.8, label=f"|Ω²|/W² = {floor:g}")
    methods = f"the {reg.shape[0]} methods" if reg.shape[0] != 1 else "the method"
    right.plot([], [], " ", label=f"Ω² = 0: no rate fitted; over {methods},\n"
                                  f"{n_alg} algebraic drift, {n_neu} no departure")
    left.set_xlabel(label("analytic Ω² / W²", "1"))
    left.set_ylabel(label("measured Ω² / W²", "1"))
    left.set_title("measured against analytic: −rate² (growth), +frequency² (oscillation)",
                   fontsize=9)
    place_legend(left)
    right.set_xscale("log")
    right.set_yscale("log")
    right.set_xlabel(label("|analytic Ω²| / W²", "1"))
    right.set_ylabel(label("|measured − analytic| / |analytic|", "1"))
    right.set_title("relative error of Ω²", fontsize=9)
    right.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7)
    return fig


@styled
def flip_interval_figure(ds, samples=120):
    """Figure 3: flip interval against epsilon, measured, exact 2K/nu and the ln(1/eps) law.

    Top: the time between flips for a perturbation epsilon W along axis 1 of a few shapes
    spinning about axis 2; lines: the exact 2K/nu, dashed: the asymptote (2/lambda) ln(4/k'),
    a straight line in ln(1/epsilon); markers: each method. Bottom: |measured - exact| / exact.
    """

    spin = float(ds.attrs["spin"])
    eps = ds.epsilon.values
    fine = np.logspace(np.log10(eps.min()), np.log10(eps.max()), samples)
    fig = new_figure(7.5, 7.4)
    top, bottom = fig.subplots(2, 1, sharex=True)
    for f in range(ds.sizes["flip_shape"]):
        color = _SHAPE_COLORS[f % len(_SHAPE_COLORS)]
        I = (float(ds.flip_I1[f]), float(ds.flip_I2[f]), 1.0)
        exact, asymptote = exact_flip_curve(I, fine, spin)
        top.plot(fine, exact, color=color, lw=1.2,
                 label=f"I = ({I[0]:.3g}, {I[1]:.3g}, 1): exact 2K/ν")
        top.plot(fine, asymptote, color=color, lw=0.9, ls="--",
                 label="(2/λ) ln(4/k′)" if f == 0 else None)
        for k, method in enumerate(ds.integrator.values):
            marker = _MARKERS[k % len(_MARKERS)]
            measured = ds.sweep_flip_interval.values[k, f]
            top.plot(eps, measured, ls="none", marker=marker, ms=4.5, mfc="none", color=color,
                     label=f"{method}, h = {float(ds.h.values[k]):g} s" if f == 0 else None)
            with np.errstate(invalid="ignore", divide="ignore"):
                rel = np.abs(measured - ds.sweep_flip_interval_exact.values[f]) / (
                    ds.sweep_flip_interval_exact.values[f])
            bottom.plot(eps, np.maximum(rel, 1e-16), marker=marker, ms=4, color=color,
                        mfc="none", lw=0.7)
    top.set_xscale("log")
    top.set_xlabel(label("perturbation ε", "1"))
    top.set_ylabel(label("flip interval", "s"))
    top.set_title("time between flips against the perturbation (spin about axis 2, "
                  "perturbation along axis 1)", fontsize=9)
    place_legend(top, fontsize=7, ncol=2)
    bottom.set_yscale("log")
    bottom.set_xlabel(label("perturbation ε (relative to the spin)", "1"))
    bottom.set_ylabel(label("|measured − exact| / exact", "1"))
    return fig


@styled
def edges_figure(ds):
    """Figure 4: time series on the equal-moment edges and the sphere (ERRATA 3).

    For each case, the two components perpendicular to the spin axis against time (linear
    axes): the one along the distinct axis stays at its start, the other moves off on the
    straight line predicted by Euler's equations at the start (dashed): algebraic departure,
    no exponential growth, no flip.
    """

    t = ds.edge_time.values
    cases = ds.sizes["edge_case"]
    fig = new_figure(4.0 * cases, 3.8)
    axes = np.atleast_1d(fig.subplots(1, cases))
    meanings = REGIME_MEANINGS.split()
    for c, ax in enumerate(axes):
        a = int(ds.edge_axis.values[c])
        w = ds.edge_w.values[c]
        others = perpendicular_axes(a)
        for k, b in enumerate(others):  # the second dashed: on a sphere the two coincide
            ax.plot(t, w[:, b - 1], color=AXIS_COLORS[b - 1], lw=2.4 - k, ls=("-", "--")[k],
                    label=f"w{b}")
        slope = float(ds.edge_slope_predicted.values[c])
        drifting = others[int(np.argmax(np.abs(w[-1, [b - 1 for b in others]] -
                                               w[0, [b - 1 for b in others]])))]
        ax.plot(t, w[0, drifting - 1] + slope * t, color=EXACT_COLOR, ls="--", lw=0.9,
                label="start + t × dw/dt(0)")
        I = (float(ds.edge_I1[c]), float(ds.edge_I2[c]), float(ds.edge_I3[c]))
        ax.set_title(f"I = ({I[0]:g}, {I[1]:g}, {I[2]:g}), spin about axis {a}\n"
                     f"{meanings[int(ds.edge_regime.values[c])].replace('_', ' ')}, "
                     f"flips: {int(ds.edge_flips.values[c])}", fontsize=8.5)
        ax.text(0.97, 0.03, _misfits(float(ds.edge_linear_residual[c]),
                                     float(ds.edge_exponential_residual[c])),
                transform=ax.transAxes, ha="right", va="bottom", fontsize=7)
        ax.set_xlabel(label("time", "s"))
        ax.set_ylabel(label("perpendicular components of w", "rad s-1"))
        ax.ticklabel_format(axis="y", style="sci", scilimits=(-2, 3))
        place_legend(ax, fontsize=7)
    fig.suptitle(f"Equal moments: Ω² = 0, departure linear in t ({ds.attrs['edge_method']}, "
                 f"h = {float(ds.attrs['edge_h']):g} s, ε = {ds.attrs['edge_epsilon']:g})",
                 fontsize=9.5)
    return fig


@styled
def ftle_map_figure(ds, fine: int = 200, fig=None):
    """Figure 5: the FTLE over the grid of inertia ratios (colour, s-1), the triangle of real
    bodies outlined; over it, contours of the analytic rate sqrt(-Omega^2) on a fine grid
    (about the intermediate axis), or of the linear bound log(rho) / T on the FTLE (about a
    stable one, where the rate is 0).

    Parameters
    ----------
    ds : xarray.Dataset
        Of :func:`~.ftle_map.ftle_map`.
    fine : int, default 200
        Points per side of the analytic contours' grid.
    fig : matplotlib.figure.Figure, optional
        Draw into this figure (e.g. one made by ``plt.figure``, which a notebook or the gallery
        shows); by default a new one.
    """
    axis, spin, horizon = int(ds.attrs["axis"]), float(ds.attrs["spin"]), float(ds.attrs["horizon"])
    if fig is None:
        fig = new_figure(6.4, 4.6)
    else:
        fig.set_size_inches(6.4, 4.6)
        fig.set_layout_engine("constrained")
    ax = fig.subplots()
    mesh = ax.pcolormesh(ds.I1.values, ds.I2.values, np.ma.masked_invalid(ds.ftle.values),
                         shading="nearest", cmap="magma", vmin=0.0, rasterized=True)
    x, y = np.meshgrid(np.linspace(0.5 / fine, 1.0, fine), np.linspace(0.5, 1.0, fine))
    moments = np.stack([x, y, np.ones_like(x)], axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        if axis == 2:
            theory, what = growth_rate(moments, axis, spin), "analytic √(−Ω²)"
        else:
            theory, what = np.log(eigenvector_aspect(moments, axis)) / horizon, "bound log ρ / T"
    theory = np.where(physical(x[0], y[:, 0]), theory, np.nan)
    levels = np.linspace(0.0, float(np.nanmax(ds.ftle.values)), 7)[1:]
    lines = ax.contour(x, y, theory, levels=levels, colors="white", linewidths=0.8)
    ax.clabel(lines, fmt="%.2f", fontsize=7)
    ax.plot([], [], color="white", lw=0.8, label=f"{what} (s⁻¹)")
    _triangle_outline(ax)
    ax.set_facecolor("0.85")
    ax.set_xlabel(label("I1 / I3", "1"))
    ax.set_ylabel(label("I2 / I3", "1"))
    ax.grid(False)
    place_legend(ax, fontsize=7.5, facecolor="0.4", labelcolor="white")
    cb = fig.colorbar(mesh, ax=ax, shrink=0.9)
    cb.set_label(label("FTLE", "s-1"))
    ax.set_title(f"FTLE of spin about axis {axis}, W = {spin:g} rad/s, T = {horizon:g} s, "
                 f"ε = {float(ds.attrs['epsilon']):g}", fontsize=9)
    return fig


def _misfits(linear: float, exponential: float) -> str:
    """The two departure models' misfits, or in words why there are none."""
    if not (np.isfinite(linear) and np.isfinite(exponential)):
        return (f"misfit: not fitted (fewer than {MIN_POINTS} samples\n"
                f"past {DEPARTURE_FACTOR:g} x the start's amplitude in this run)")
    return f"misfit: straight line {linear:.1e}\nexponential {exponential:.1e}"
