"""Figures of the twisting racket (:mod:`stability.free_body.twisting_racket.measure`).

:func:`twist_figure`: the twist's defect from a half turn against the ratio of the moments and
against the nudge, with Montgomery's angle run against formula. :func:`flip_figure`: the racket
drawn at instants across one flip, seen across L, its strings' two sides in two colours.
"""

from __future__ import annotations

import numpy as np

from ...core.quaternions import quaternion_to_matrix, spatial_angular_momentum
from ...plotting.style import AXIS_COLORS, label, new_figure, place_legend, styled

#: A stylised racket in its body frame (handle along axis 1, head across axis 2), metres.
_HEAD_CENTRE, _HEAD_HALF_LENGTH, _HEAD_HALF_WIDTH = 0.17, 0.165, 0.125
_HANDLE = (-0.36, 0.005)
#: Colours of the strings' side facing L (front) and facing away (back).
FRONT_COLOR, BACK_COLOR = "#d62728", "#1f77b4"


@styled
def twist_figure(ds):
    """Defect pi - |twist| against I1/I2 and against the nudge; Montgomery run vs formula."""
    fig = new_figure(11.0, 4.2)
    ratio_ax, eps_ax, mont_ax = fig.subplots(1, 3)
    ratio = ds.moments.values[:, 0] / ds.moments.values[:, 1]
    defect = ds.twist_defect.values
    eps = ds.epsilon.values
    shade = ratio_ax.scatter(ratio, defect, c=np.log10(eps), s=14, cmap="viridis")
    bar = fig.colorbar(shade, ax=ratio_ax)
    bar.set_label(label("log10 of the nudge epsilon", "1"))
    ratio_ax.set_xlabel(label("I1 / I2", "1"))
    ratio_ax.set_ylabel(label("pi - |twist|", "rad"))
    ratio_ax.set_title("twist over one turn of the handle")
    same = np.isclose(ratio, ratio[0], rtol=1e-12)
    eps_ax.semilogx(eps[same], defect[same], "o", ms=4, color=AXIS_COLORS[1])
    eps_ax.set_xlabel(label("nudge epsilon", "1"))
    eps_ax.set_ylabel(label("pi - |twist|", "rad"))
    eps_ax.set_title(f"the body itself (I1/I2 = {ratio[0]:.3f})")
    err = np.maximum(ds.montgomery_error.values, 1e-17)  # exact agreement drawn at 1e-17
    mont_ax.semilogy(ds.montgomery_formula.values, err, "o", ms=4, color=AXIS_COLORS[0],
                     label="Montgomery: run vs 2 E T/|L| - S")
    mont_ax.semilogy(ds.montgomery_formula.values, np.maximum(ds.twist_error.values, 1e-17),
                     "s", ms=3, color=AXIS_COLORS[2], label="twist: run vs exact")
    mont_ax.axhline(ds.attrs["claim"], color="black", lw=0.8, ls=":",
                    label=f"the claim, {ds.attrs['claim']:g} rad")
    mont_ax.set_xlabel(label("Montgomery's angle", "rad"))
    mont_ax.set_ylabel(label("|difference|", "rad"))
    mont_ax.set_title(f"run against the formulas\n({ds.attrs['method']}, "
                      f"{ds.attrs['steps_per_period']} steps per period)", fontsize=9)
    place_legend(mont_ax)
    fig.suptitle("The twisting racket: while the handle goes once round L, the body turns about "
                 "the handle by nearly, not exactly, pi", fontsize=10)
    return fig


def racket_outline():
    """The stylised racket in its body frame, in m: the head ellipse (73, 3) (strings in the
    1-2 plane) and the handle's centre line (2, 3) along axis 1 (also :mod:`.animation`)."""
    a = np.linspace(0.0, 2.0 * np.pi, 73)
    head = np.column_stack([_HEAD_CENTRE + _HEAD_HALF_LENGTH * np.cos(a),
                            _HEAD_HALF_WIDTH * np.sin(a), np.zeros_like(a)])
    handle = np.array([[_HANDLE[0], 0.0, 0.0], [_HEAD_CENTRE - _HEAD_HALF_LENGTH, 0.0, 0.0]])
    return head, handle


@styled
def flip_figure(ds):
    """The first member drawn at the snapshot instants, seen down L (space X, Y; Z along L).

    The strings' side facing L is red, the other blue: over the window the handle turns once
    about L while the face turns over.
    """
    n = ds.snapshot.size
    fig = new_figure(1.9 * n, 3.0)
    axes = fig.subplots(1, n, sharey=True)
    head, handle = racket_outline()
    space_l = spatial_angular_momentum(ds.snapshot_q.values[0],
                                       ds.moments.values[0] * ds.w0.values[0])
    z = space_l / np.linalg.norm(space_l)
    x = np.cross([0.0, 1.0, 0.0], z) if abs(z[1]) < 0.9 else np.cross([1.0, 0.0, 0.0], z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    t0 = float(ds.flip_time_exact[0])
    for ax, q, t in zip(axes, ds.snapshot_q.values, ds.snapshot_time.values):
        R = quaternion_to_matrix(q)
        h, g = head @ R.T, handle @ R.T
        facing = (R[:, 2] @ z) > 0.0
        ax.fill(h @ x, h @ y, color=FRONT_COLOR if facing else BACK_COLOR, alpha=0.35)
        ax.plot(h @ x, h @ y, color="black", lw=1.0)
        ax.plot(g @ x, g @ y, color="#7a5a2a", lw=3.0)
        ax.set_aspect("equal")
        ax.set_xlim(-0.55, 0.55)
        ax.set_ylim(-0.55, 0.55)
        ax.set_title(f"t - t_flip = {t - t0:+.3f} s", fontsize=8)
        ax.set_xlabel(label("X", "m"))
    axes[0].set_ylabel(label("Y", "m"))
    fig.suptitle(f"one flip of member 0 seen down L: the handle turns once about L while the "
                 f"face turns by {abs(float(ds.twist_exact[0])):.4f} rad about the handle "
                 "(red: strings facing L, blue: facing away)", fontsize=9)
    return fig
