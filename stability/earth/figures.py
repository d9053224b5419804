"""Figures of the Earth's free wobble (:mod:`stability.earth.wobble`).

:func:`wobble_cones_figure`: the rotation axis seen from the body (it circles the figure axis
once per wobble period, the body cone) and from space (it circles the fixed angular momentum
once a day, on the space cone, ~H times narrower), each in arcseconds on the sky.
"""

from __future__ import annotations

import numpy as np

from .model import ARCSEC
from ..plotting.style import EXACT_COLOR, label, new_figure, styled


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
