"""Poinsot's construction of a torque-free body, from the body and a start (no Dataset).

:func:`poinsot_figure`: the polhodes on Poinsot's ellipsoid x . I x = 1 in the body, the
ellipsoid rolling on the invariable plane in space, and the herpolhode on that plane with the
annulus it fills (equations in :mod:`stability.free_body.polhodes`).
"""

from __future__ import annotations

import numpy as np
from matplotlib.ticker import MaxNLocator

from .model import angular_momentum_norm, kinetic_energy
from ..core.quaternions import IDENTITY, quaternion_to_matrix
from .exact import full_period
from ..plotting.style import AXIS_COLORS, EXACT_COLOR, label, new_figure, styled
from .polhodes import (
    energy_ellipsoid_polhodes, energy_ellipsoid_separatrix, herpolhode, poinsot_polhode,
)

#: Unit of rho = w / sqrt(2E) and of every length in the construction.
UNIT = "kg^-1/2 m^-1"


def _ellipsoid_mesh(moments, n=(41, 21)):
    """Points of x . I x = 1 as three (v, u) arrays, body axes."""
    u, v = np.meshgrid(np.linspace(0.0, 2.0 * np.pi, n[0]), np.linspace(0.0, np.pi, n[1]))
    a = 1.0 / np.sqrt(moments)
    return a[0] * np.cos(u) * np.sin(v), a[1] * np.sin(u) * np.sin(v), a[2] * np.cos(v)


def _equal_aspect(ax, points):
    """Limits around ``points`` (n, 3) with one scale on all three axes."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre, half = 0.5 * (lo + hi), 0.5 * float(np.max(hi - lo)) * 1.05
    for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre):
        setter(c - half, c + half)
    ax.set_box_aspect((1, 1, 1))


@styled
def poinsot_figure(body, w0, t_end=None, q0=None, levels=(0.2, 0.5, 0.8, 0.95),
                   samples=4000, fig=None):
    """Poinsot's construction: polhodes on the energy ellipsoid, the herpolhode on the plane.

    Left: Poinsot's ellipsoid ``x . I x = 1`` in the body with polhodes around the stable axes
    (:func:`stability.free_body.polhodes.energy_ellipsoid_polhodes`), the separatrix, and the
    polhode of this start (:func:`stability.free_body.polhodes.poinsot_polhode`). Middle: in space,
    with L up, the ellipsoid at t = 0 touching the invariable plane ``x . L/|L| = sqrt(2E)/|L|`` at
    rho = w / sqrt(2E), and the herpolhode it traces as it rolls. Right: the herpolhode in the
    plane (:func:`stability.free_body.polhodes.herpolhode`) between the circles r_min and r_max
    (:func:`stability.free_body.polhodes.herpolhode_radii`). Poinsot 1834; Landau & Lifshitz
    section 37.

    Parameters
    ----------
    body : RigidBody
    w0 : array_like, shape (3,)
        Angular velocity at t = 0 along the body's axes, rad/s, off the separatrix.
    t_end : float, optional
        Length of the herpolhode in s; default six periods of w (:func:`stability.full_period`).
    q0 : array_like, shape (4,), optional
        Attitude at t = 0; the picture in space is drawn about L, so it only turns the start.
    levels : sequence of float
        Polhode energies as fractions of the way from a centre to the separatrix, in (0, 1).
    samples : int
        Points of the herpolhode.
    fig : matplotlib.figure.Figure, optional
        Draw into this figure (e.g. ``plt.figure(figsize=(15, 5.8))`` to show it with
        pyplot); default a new one, 15 x 5.8 inches.

    Returns
    -------
    matplotlib.figure.Figure
    """

    own = poinsot_polhode(body, w0, 600)  # checks body and w0
    w0 = np.asarray(w0, dtype=float)
    energy, momentum = float(kinetic_energy(body, w0)), float(angular_momentum_norm(body, w0))
    I = body.moments
    if t_end is None:
        period = float(full_period(body, w0))
        t_end = 6.0 * period if np.isfinite(period) else 2.0 * np.pi / float(np.linalg.norm(w0))
    t = np.linspace(0.0, float(t_end), int(samples))
    herp = herpolhode(body, w0, t, q0)
    a, b, c = np.argsort(I, kind="stable")

    fig = new_figure(15.0, 5.8) if fig is None else fig
    fig.set_layout_engine("none")  # constrained layout crowds the 3-D axes' labels together
    grid = fig.add_gridspec(1, 3, width_ratios=(1.0, 1.0, 0.8), left=0.02, right=0.97,
                            bottom=0.2, top=0.9, wspace=0.22)
    body_ax = fig.add_subplot(grid[0], projection="3d")
    space_ax = fig.add_subplot(grid[1], projection="3d")
    plane_ax = fig.add_subplot(grid[2])

    # (a) the body: the ellipsoid, the polhodes, the separatrix and this motion's polhode.
    x, y, z = _ellipsoid_mesh(I)
    body_ax.plot_wireframe(x, y, z, color="0.7", lw=0.3, rstride=2, cstride=2)
    colors = {a: AXIS_COLORS[0], c: AXIS_COLORS[2]}
    for centre, curves in energy_ellipsoid_polhodes(body, levels, 300):
        for k, curve in enumerate(curves):
            body_ax.plot(*curve.T, color=colors[centre], lw=0.9,
                         label=f"polhodes around axis {centre + 1}" if k == 0 else None)
    for k, curve in enumerate(energy_ellipsoid_separatrix(body, 361)):
        body_ax.plot(*curve.T, color=AXIS_COLORS[1], lw=1.4,
                     label="separatrix" if k == 0 else None)
    body_ax.plot(*own.T, color=EXACT_COLOR, lw=2.2, label="this start's polhode")
    body_ax.scatter(*own[0], color=EXACT_COLOR, s=25, depthshade=False)
    _equal_aspect(body_ax, np.column_stack([x.ravel(), y.ravel(), z.ravel()]))
    for k, setter in enumerate((body_ax.set_xlabel, body_ax.set_ylabel, body_ax.set_zlabel)):
        setter(label(f"rho{k + 1} = w{k + 1}/sqrt(2E)", UNIT), fontsize=8)
    for ax in (body_ax, space_ax):
        for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
            axis.set_major_locator(MaxNLocator(5))
    body_ax.tick_params(labelsize=7)
    body_ax.set_title("body frame: Poinsot's ellipsoid x.Ix = 1")

    # (b) space, L up: the ellipsoid at t = 0 on the plane, and the herpolhode.
    to_l = herp.frame.T @ quaternion_to_matrix(IDENTITY if q0 is None else q0)
    mesh = np.stack([x, y, z], axis=-1) @ to_l.T
    space_ax.plot_wireframe(*np.moveaxis(mesh, -1, 0), color="0.6", lw=0.3, rstride=2, cstride=2)
    space_ax.plot(*(own @ to_l.T).T, color=EXACT_COLOR, lw=1.2, label="polhode (on the body)")
    d = herp.distance
    reach = 1.15 * max(herp.radii[1], float(np.abs(mesh[..., :2]).max()))
    corners = np.array([[-reach, -reach], [reach, -reach], [reach, reach], [-reach, reach],
                        [-reach, -reach]])
    space_ax.plot(corners[:, 0], corners[:, 1], np.full(5, d), color="0.4", lw=0.8,
                  label="invariable plane")
    space_ax.plot(herp.plane[:, 0], herp.plane[:, 1], np.full(len(t), d), color="crimson",
                  lw=0.9, label=f"herpolhode, over {t[-1]:.3g} s")
    space_ax.plot([0, 0], [0, 0], [0, 1.3 * d], color="black", lw=2.0)
    space_ax.text(0, 0, 1.35 * d, "L", fontsize=10)
    _equal_aspect(space_ax, np.vstack([mesh.reshape(-1, 3),
                                       np.column_stack([corners[:, :2], np.full(5, d)])]))
    space_ax.set_xlabel(label("x in the plane", UNIT), fontsize=8)
    space_ax.set_ylabel(label("y in the plane", UNIT), fontsize=8)
    space_ax.set_zlabel(label("along L", UNIT), fontsize=8)
    space_ax.tick_params(labelsize=7)
    space_ax.view_init(elev=12.0, azim=-60.0)
    space_ax.set_title(f"space: the ellipsoid rolls on the plane at sqrt(2E)/|L| = {d:.4g} "
                       f"{UNIT}")

    # (c) the herpolhode in the plane, between r_min and r_max.
    turn = np.linspace(0.0, 2.0 * np.pi, 361)
    for r, what, dash in zip(herp.radii, ("r_min", "r_max"), (":", "--")):
        plane_ax.plot(r * np.cos(turn), r * np.sin(turn), color="0.5", lw=0.9, ls=dash,
                      label=f"{what} = {r:.4g} {UNIT}")
    plane_ax.plot(herp.plane[:, 0], herp.plane[:, 1], color="crimson", lw=0.8)
    plane_ax.plot(*herp.plane[0], "o", color=EXACT_COLOR, ms=4, label="start")
    plane_ax.set_aspect("equal")
    plane_ax.set_xlabel(label("x in the invariable plane", UNIT))
    plane_ax.set_ylabel(label("y in the invariable plane", UNIT))
    plane_ax.set_title("the herpolhode seen down L")

    handles, labels = [], []
    for ax in (body_ax, space_ax, plane_ax):
        more, more_labels = ax.get_legend_handles_labels()
        handles, labels = handles + more, labels + more_labels
    fig.legend(handles, labels, loc="lower center", ncols=5, framealpha=0.9)
    name = body.name.replace("_", " ")
    fig.suptitle(
        f"Poinsot's construction for the {name}, I = ({', '.join(f'{v:.4g}' for v in I)}) "
        f"kg m², w0 = ({', '.join(f'{v:.3g}' for v in w0)}) rad/s: E = {energy:.4g} J, "
        f"|L| = {momentum:.4g} kg m²/s", fontsize=10)
    return fig
