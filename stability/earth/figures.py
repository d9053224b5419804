"""The Earth's figures, each drawn from its study's Dataset alone.

- :func:`wobble_cones_figure` (:mod:`stability.earth.wobble`): the rotation axis seen from the
  body (it circles the figure axis once per wobble period, the body cone) and from space (it
  circles the fixed angular momentum once a day, on the space cone, ~H times narrower), each in
  arcseconds on the sky.
- :func:`equinoxes_figure` (:func:`stability.earth.precession.measure_equinoxes`): the precession
  of the equinoxes, the nutation and a full turn. The longitude of the equinox over the run for
  the Sun alone, the Moon alone and both (full model, member 0) beside the averaged formula; the
  nutation left after the fitted line, full and orbit-averaged models, with the published
  amplitudes; and the pole's circle about the ecliptic pole over the averaged model's long run.
"""

from __future__ import annotations

import numpy as np

from .precession import NODE_PERIOD_DAYS
from .model import ARCSEC
from ..plotting.style import AXIS_COLORS, EXACT_COLOR, label, new_figure, place_legend, styled


def _across(v, axis):
    """Components of the unit vectors ``v`` (T, 3) across ``axis`` (3,), in arcsec."""
    axis = axis / np.linalg.norm(axis)
    first = np.array([1.0, 0.0, 0.0]) - axis[0] * axis
    first /= np.linalg.norm(first)
    second = np.cross(axis, first)
    u = v / np.linalg.norm(v, axis=-1, keepdims=True)
    return u @ first / ARCSEC, u @ second / ARCSEC


@styled
def wobble_cones_figure(ds):
    """Body cone and space cone of the rotation axis, with the measured and Euler periods."""
    fig = new_figure(10.0, 4.8)
    body_ax, space_ax = fig.subplots(1, 2)
    days = ds.cone_time.values
    x, y = _across(ds.w_body.values, np.array([0.0, 0.0, 1.0]))
    points = body_ax.scatter(x, y, c=days, s=4, cmap="viridis")
    body_ax.plot([0], [0], "+", color=EXACT_COLOR, ms=10)
    body_ax.set_aspect("equal")
    body_ax.set_xlabel(label("rotation axis from the figure axis, along axis 1", "arcsec"))
    body_ax.set_ylabel(label("along axis 2", "arcsec"))
    body_ax.set_title(f"body cone: one turn in {float(ds.wobble_period_measured):.2f} d "
                      f"(Euler {float(ds.wobble_period_euler):.2f} d)", fontsize=10)
    fig.colorbar(points, ax=body_ax, label=label("time", "d"))
    moments = np.asarray(ds.attrs["moments"], dtype=float)
    L = moments * ds.w_body.values[0]  # at t = 0 the body and space frames coincide
    sx, sy = _across(ds.w_space.values, L)
    space_ax.plot(1e3 * sx, 1e3 * sy, ".", color="#1f77b4", ms=2)
    space_ax.plot([0], [0], "+", color=EXACT_COLOR, ms=10)
    space_ax.set_aspect("equal")
    space_ax.set_xlabel(label("rotation axis from L, in space", "mas"))
    space_ax.set_ylabel(label("across", "mas"))
    space_ax.set_title(f"space cone: {1e3 * float(ds.space_cone_angle.mean()):.3f} mas, "
                       "one turn a day", fontsize=10)
    fig.suptitle(f"Free wobble of a rigid Earth (observed Chandler period "
                 f"~{ds.attrs['chandler_period_days']:g} d: the Earth is not rigid)")
    return fig



#: The Moon's node period in years of the figure's time axis.
_NODE_YEARS = NODE_PERIOD_DAYS / 365.25


def _detrended(t, y):
    """``y`` (over ``t`` in years) less its line, fitted together with the node's 18.6-year term
    as :func:`stability.earth.precession.fit_precession` fits it: a line alone, fitted over a run
    that is not a whole number of node periods, takes part of the term and tilts what remains
    (peaks of +9.7" and -10.3" about a 9.2" amplitude over 40 years)."""
    w = 2.0 * np.pi / _NODE_YEARS
    design = np.column_stack([np.ones_like(t), t, np.cos(w * t), np.sin(w * t)])
    coef, *_ = np.linalg.lstsq(design, y, rcond=None)
    return y - design[:, :2] @ coef[:2]


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
