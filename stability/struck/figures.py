"""The struck bat's figure (:mod:`stability.struck`), drawn from its Dataset alone.

:func:`bat_figure`: the body drawn to scale with its hands, centre of mass, centre of percussion
and sweet zone, the reaction impulse at the held hands and the velocity of the free body's
hands against the strike point.
"""

from __future__ import annotations

import numpy as np

from ..plotting.style import EXACT_COLOR, label, new_figure, place_legend, styled

_PIVOT_COLORS = ("#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#e377c2")


@styled
def bat_figure(ds):
    """Bat to scale; reaction impulse (held) and hand velocity (free) against strike point."""
    fig = new_figure(9.0, 8.0)
    body_ax, held_ax, free_ax = fig.subplots(3, 1, sharex=True,
                                             gridspec_kw={"height_ratios": [1.0, 2.0, 2.0]})
    x, r = ds.outline.values[:, 0], ds.outline.values[:, 1]
    body_ax.fill_between(x, -r, r, color="#d8b37a", edgecolor="#7a5a2a")
    centre = ds.attrs["centre_of_mass"]
    body_ax.plot([centre], [0.0], "o", color="black", ms=5, label="centre of mass")
    main = ds.pivot.size // 2
    impulse, sting = ds.attrs["impulse"], ds.attrs["sting"]
    near, far = ds.sweet_zone_measured.values[main]
    if np.isfinite(near):
        body_ax.axvspan(near, far if np.isfinite(far) else x[-1], color="#ffdd55", alpha=0.5,
                        label=f"sweet zone (|reaction| < {sting:g} × the impulse J), hands at "
                              f"{100 * float(ds.pivot[main]):.1f} cm")
    for i, pivot in enumerate(ds.pivot.values):
        color = _PIVOT_COLORS[i % len(_PIVOT_COLORS)]
        cop = float(ds.percussion_centre_measured.sel(hold="held")[i])
        body_ax.plot([pivot], [0.0], "s", color=color, ms=6)
        body_ax.plot([cop], [0.0], "*", color=color, ms=11)
    # to scale by widening the y limits, not by narrowing the panel: its x axis stays the
    # strike axis of the panels below
    body_ax.set_aspect("equal", adjustable="datalim")
    body_ax.set_ylabel(label("half-width", "m"))
    place_legend(body_ax, fontsize=7.5, ncol=2)
    body_ax.set_title(f"{ds.attrs['body']}, {ds.attrs['mass']:.3g} kg, to scale: hands "
                      "(squares) and their centres of percussion (stars)")
    strikes = ds.strike.values
    for i, pivot in enumerate(ds.pivot.values):
        color = _PIVOT_COLORS[i % len(_PIVOT_COLORS)]
        beyond = strikes > pivot
        tag = f"hands at {100 * pivot:.1f} cm"
        held_ax.plot(strikes[beyond], ds.reaction_impulse_across.sel(hold="held")[i, beyond]
                     / impulse, color=color, lw=1.8, label=f"{tag}: run")
        held_ax.plot(strikes[beyond], ds.reaction_impulse_formula[i, beyond] / impulse, "--",
                     color=EXACT_COLOR, lw=0.9)
        free_ax.plot(strikes, ds.hand_velocity_across.sel(hold="free")[i], color=color, lw=1.8,
                     label=f"{tag}: run")
        free_ax.plot(strikes, ds.hand_velocity_formula[i], "--", color=EXACT_COLOR, lw=0.9)
        for ax, hold in ((held_ax, "held"), (free_ax, "free")):
            ax.axvline(float(ds.percussion_centre_measured.sel(hold=hold)[i]), color=color,
                       lw=0.7, ls=":")
    held_ax.axhspan(-sting, sting, color="#ffdd55", alpha=0.4)
    held_ax.set_ylabel(label("reaction at the hands / J", "1"))
    held_ax.set_title(f"held: J = {impulse:g} N s over {1e3 * ds.attrs['contact_time']:g} ms; "
                      "dashed: J (M d s / I_P - 1); zero at the centre of percussion")
    place_legend(held_ax, fontsize=7.5)
    free_ax.axhline(0.0, color="grey", lw=0.6)
    free_ax.set_ylabel(label("hands' velocity after", "m s-1"))
    free_ax.set_xlabel(label("strike point from the end held", "m"))
    free_ax.set_title("free: dashed J / M - d (s - d) J / I_cm; the hands' point stays at rest "
                      "after a hit at the centre of percussion")
    return fig
