"""Rolling's figures (:mod:`stability.rolling`), drawn from its Dataset alone.

:func:`rolling_map_figure`: the fraction of members that slip over (incline angle, mu_s) per
shape, with the analytic boundary. :func:`rolling_launch_figure`: launched balls' v and R w
meeting where rolling starts, and the final speed and heat against the formulas.
"""

from __future__ import annotations

import numpy as np

from ..plotting.style import EXACT_COLOR, label, new_figure, place_legend, styled

_COLORS = ("#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#e377c2")


@styled
def rolling_map_figure(ds):
    """Fraction of members slipping over (angle, mu_s), one panel per shape, with the boundary
    ``mu_s = tan(theta) / (1 + M R^2 / I)``."""
    shapes = ds.shape.values
    fig = new_figure(4.2 * shapes.size, 4.2)
    axes = np.atleast_1d(fig.subplots(1, shapes.size, sharey=True))
    angle, mu = ds.angle.values, ds.mu_s.values
    for ax, name in zip(axes, shapes):
        cell = ds.sel(shape=name)
        mesh = ax.pcolormesh(angle, mu, cell.slip_fraction.values.T, cmap="RdYlBu_r",
                             vmin=0.0, vmax=1.0, shading="nearest")
        fine = np.linspace(angle.min(), angle.max(), 200)
        k = float(cell.shape_factor)
        ax.plot(fine, np.tan(np.radians(fine)) / (1.0 + 1.0 / k), color="black", lw=1.5,
                label="tan(theta) = mu_s (1 + M R^2 / I)")
        wrong = cell.wrong_side.values
        if wrong.any():
            i, j = np.nonzero(wrong)
            ax.plot(angle[i], mu[j], "kx", ms=7, label="cell on the wrong side")
        ax.set_ylim(mu.min(), mu.max())
        ax.set_title(f"{name}, I / (M R^2) = {k:.3g}\n{int(wrong.sum())} cells on the wrong "
                     "side")
        ax.set_xlabel(label("incline angle theta", "degree"))
        place_legend(ax, fontsize=7.5)
    axes[0].set_ylabel(label("static friction coefficient mu_s", "1"))
    fig.colorbar(mesh, ax=axes, label=label("fraction of the cell's members that slip", "1"))
    fig.suptitle("Released at rest on an incline: rolls above the line (friction enough), "
                 "slips below it "
                 f"(mu_s scattered {100 * ds.attrs['incline_mu_scatter']:g}%, shape "
                 f"{100 * ds.attrs['incline_shape_scatter']:g}%, mu_k = "
                 f"{ds.attrs['incline_mu_ratio']:g} mu_s)")
    return fig


@styled
def rolling_launch_figure(ds):
    """Launched balls: v and R w converge at the start of rolling; final speed and heat."""
    fig = new_figure(13.0, 4.2)
    path_ax, speed_ax, heat_ax = fig.subplots(1, 3)
    t = ds.time.values
    for i in range(ds.path.size):
        color = _COLORS[i % len(_COLORS)]
        member = int(ds.path_member[i])
        path_ax.plot(t, ds.path_v[i], color=color, lw=1.6,
                     label=f"R w0 / v0 = {float(ds.spin_ratio[member]):+.2f}")
        path_ax.plot(t, ds.path_rw[i], "--", color=color, lw=1.0)
        path_ax.axvline(float(ds.t_roll_formula[member]), color=color, lw=0.6, ls=":")
    path_ax.set_xlabel(label("time", "s"))
    path_ax.set_ylabel(label("v (solid) and R w (dashed)", "m s-1"))
    path_ax.set_title("slip ends where they meet (dotted: the formula's time)")
    place_legend(path_ax, fontsize=7.5)
    k = ds.attrs["launch_shape_factor"]
    ratio = ds.spin_ratio.values
    speed_ax.plot(ratio, ds.v_final / ds.v0, ".", ms=3, label="run")
    line = np.linspace(ratio.min(), ratio.max(), 50)
    speed_ax.plot(line, (1.0 + k * line) / (1.0 + k), color=EXACT_COLOR, lw=1.0,
                  label="(1 + k R w0 / v0) / (1 + k)")
    speed_ax.set_xlabel(label("launch spin R w0 / v0", "1"))
    speed_ax.set_ylabel(label("rolling speed / launch speed", "1"))
    speed_ax.set_title("final speed (5/7 v0 + 2/7 R w0 for a solid sphere)")
    place_legend(speed_ax, fontsize=7.5)
    e0 = 0.5 * ds.attrs["launch_mass"] * ds.v0**2 * (1.0 + k * ratio**2)
    heat_ax.plot(ratio, ds.heat / e0, ".", ms=3, label="run: work of friction")
    heat_ax.plot(line, (1.0 - line) ** 2 * k / ((1.0 + k) * (1.0 + k * line**2)),
                 color=EXACT_COLOR, lw=1.0,
                 label="(1 - R w0/v0)^2 k / ((1 + k)(1 + k (R w0/v0)^2))")
    heat_ax.set_xlabel(label("launch spin R w0 / v0", "1"))
    heat_ax.set_ylabel(label("heat / launch energy", "1"))
    heat_ax.set_title("energy lost to friction")
    place_legend(heat_ax, fontsize=7.5)
    fig.suptitle(f"{ds.member.size} balls launched along a level floor (R = "
                 f"{100 * ds.attrs['launch_radius']:.2f} cm, mu_k = {ds.attrs['launch_mu_k']:g}"
                 f" +- {100 * ds.attrs['launch_mu_scatter']:g}%)")
    return fig
