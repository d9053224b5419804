"""Figure of the precession of the equinoxes: the precession, the nutation and a full turn.

:func:`equinoxes_figure` draws the Dataset of :func:`stability.earth.equinoxes.measure_equinoxes`:
the longitude of the equinox over the run for the Sun alone, the Moon alone and both (full model,
member 0) beside the averaged formula; the nutation left after the fitted line, full and
orbit-averaged models, with the published amplitudes; and the pole's circle about the ecliptic
pole over the averaged model's long run.
"""

from __future__ import annotations

import numpy as np

from ..plotting.style import AXIS_COLORS, EXACT_COLOR, label, new_figure, place_legend, styled


def _detrended(t, y):
    """``y`` less its least-squares line in ``t``."""
    coef = np.polyfit(t, y, 1)
    return y - np.polyval(coef, t)


@styled
def equinoxes_figure(ds):
    """Precession of the equinox, its nutation, and the pole over a full turn (a third panel,
    when the Dataset holds the long run of the averaged model)."""
    long_run = "cycle_longitude" in ds  # the averaged model over a full turn, if it was run
    fig = new_figure(11.0 if long_run else 7.0, 7.5)
    grid = fig.add_gridspec(2, 2, width_ratios=(1.5, 1.0)) if long_run else fig.add_gridspec(2, 1)
    prec_ax = fig.add_subplot(grid[0, 0])
    nut_ax = fig.add_subplot(grid[1, 0], sharex=prec_ax)
    t = ds.full_time.values
    for i, torque in enumerate(ds.torque.values):
        color = AXIS_COLORS[i % len(AXIS_COLORS)]
        measured = float(ds.precession_rate.sel(model="full", torque=torque).mean())
        prec_ax.plot(t, -ds.longitude.sel(torque=torque), color=color, lw=1.2,
                     label=f"{torque}: {measured:.3f}\"/yr")
        formula = float(ds.precession_rate_formula.sel(torque=torque))
        prec_ax.plot(t, formula * t, color=EXACT_COLOR, ls=":", lw=0.8)
    prec_ax.plot([], [], color=EXACT_COLOR, ls=":", lw=0.8, label="averaged formula")
    prec_ax.set_ylabel(label("precession in longitude -(phi - phi0)", "arcsec"))
    prec_ax.set_title(f"full model ({ds.attrs['method']}, {ds.attrs['steps_per_day']} steps a "
                      f"day); published {ds.attrs['published_precession']:.3f}\"/yr", fontsize=9)
    place_legend(prec_ax, fontsize=8)
    prec_ax.tick_params(labelbottom=False)
    both = ds.sel(torque="both")
    nut_ax.plot(t, -_detrended(t, both.longitude.values), color=AXIS_COLORS[0], lw=0.6,
                label="in longitude (full)")
    nut_ax.plot(t, _detrended(t, both.obliquity.values), color=AXIS_COLORS[1], lw=0.6,
                label="in obliquity (full)")
    ta = ds.averaged_time.values
    nut_ax.plot(ta, -_detrended(ta, both.longitude_averaged.values), color=EXACT_COLOR,
                lw=0.8, ls="--", label="orbit-averaged model")
    nut_ax.plot(ta, _detrended(ta, both.obliquity_averaged.values), color=EXACT_COLOR, lw=0.8,
                ls="--")
    for value, color in ((ds.attrs["published_nutation_longitude"], AXIS_COLORS[0]),
                         (ds.attrs["published_nutation_obliquity"], AXIS_COLORS[1])):
        for sign in (1, -1):
            nut_ax.axhline(sign * value, color=color, ls=":", lw=0.8)
    nut_ax.set_xlabel(label("time since J2000", "yr"))
    nut_ax.set_ylabel(label("nutation (line removed)", "arcsec"))
    nut_ax.set_title("18.6-year nutation; dotted: published amplitudes (IAU 1980)", fontsize=9)
    place_legend(nut_ax, fontsize=7)
    if long_run:
        cycle_ax = fig.add_subplot(grid[:, 1])
        phi = np.radians(ds.cycle_longitude.values)
        eps = ds.cycle_obliquity.values
        # The pole seen from above the ecliptic pole: (sin eps sin phi, -sin eps cos phi).
        x, y = eps * np.sin(phi), -eps * np.cos(phi)
        points = cycle_ax.scatter(x, y, c=ds.cycle_time.values, s=2, cmap="viridis")
        fig.colorbar(points, ax=cycle_ax, label=label("time since J2000", "yr"),
                     orientation="horizontal")
        cycle_ax.plot([0], [0], "+", color=EXACT_COLOR)
        cycle_ax.set_aspect("equal")
        cycle_ax.set_xlabel(label("pole toward the J2000 equinox", "degree"))
        cycle_ax.set_ylabel(label("pole from the ecliptic pole, across", "degree"))
        cycle_ax.set_title(f"one turn in {ds.attrs['precession_period_years']:.0f} yr "
                           "(orbit-averaged model)", fontsize=9)
    fig.suptitle("Precession of the equinoxes: a rigid oblate Earth under the Sun and the Moon",
                 fontsize=10)
    return fig
