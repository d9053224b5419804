"""The frames of the animations (:mod:`stability.animation`) drawn in 3-D.

:class:`FlipScene` draws a body turning over (a racket, or a box of inertia) with its axes and
the fixed angular momentum; :class:`TopScene` a heavy top with the path of its axle's tip.
Each builds one small figure (equal aspect, axes labelled in m) and redraws it for frame k by
``draw(k)``, which the writer calls frame after frame. :func:`frame_figure` returns one frame
as a figure (the gallery shows one).
"""

from __future__ import annotations

import textwrap

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from ..free_body.model import moment_name
from ..core.body import PRESETS, RigidBody
from ..core.quaternions import frame_along
from ..plotting.style import AXIS_COLORS, label
from ..free_body.twisting_racket.figures import BACK_COLOR, FRONT_COLOR, racket_outline

#: Dots per inch of the animation figures; their size is given in pixels.
DPI = 100
_HANDLE_COLOR = "#7a5a2a"


def _axes3d(fig, reach, bottom=None, top=None):
    """3-D axes with one scale on all three axes, labelled in m: x and y in [-reach, reach],
    z in [bottom, top] (default the same as x and y)."""
    ax = fig.add_axes((0.0, 0.0, 1.0, 0.87), projection="3d")
    lo = -reach if bottom is None else bottom
    hi = reach if top is None else top
    ax.set_xlim(-reach, reach)
    ax.set_ylim(-reach, reach)
    ax.set_zlim(lo, hi)
    ax.set_box_aspect((2.0 * reach, 2.0 * reach, hi - lo), zoom=0.95)
    for name, setter in zip("XYZ", (ax.set_xlabel, ax.set_ylabel, ax.set_zlabel)):
        setter(label(name, "m"), fontsize=6, labelpad=-7)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(MaxNLocator(3))
    ax.tick_params(labelsize=5, pad=-3)
    return ax


def _scene_figure(size, fig=None):
    """A new square figure of ``size`` pixels, or ``fig`` (a pyplot figure, say) emptied."""
    if fig is None:
        return Figure(figsize=(size / DPI, size / DPI), dpi=DPI)
    fig.clear()
    return fig


def _inertia_box(body, mass):
    """Faces (6, 4, 3) of the uniform box of mass ``mass`` with ``body``'s principal moments,
    edges a_i = sqrt(6 (I_j + I_k - I_i) / M), in the body frame (m), and their axes (6,)."""
    I = body.moments
    edges = np.sqrt(np.maximum(6.0 * (I.sum() - 2.0 * I) / mass, 0.0))
    half = 0.5 * edges
    faces, normals = [], []
    for i in range(3):
        j, k = [a for a in range(3) if a != i]
        for sign in (1.0, -1.0):
            corners = []
            for sj, sk in ((1, 1), (-1, 1), (-1, -1), (1, -1)):
                p = np.zeros(3)
                p[i], p[j], p[k] = sign * half[i], sj * half[j], sk * half[k]
                corners.append(p)
            faces.append(corners)
            normals.append(i)
    return np.array(faces), np.array(normals)


class _Scene:
    """What both scenes share: the frames, a square figure, its 3-D axes and a title."""

    def _start(self, frames, size, fig, reach, bottom=None, top=None):
        self.data, self.dpi, self.frames = frames, DPI, frames.t.size
        self.figure = _scene_figure(size, fig)
        self.ax = _axes3d(self.figure, reach, bottom, top)
        self.title = self.figure.suptitle("", fontsize=7, y=0.985)
        return self.ax


def _preset_of(body):
    """(name, mass in kg) of the preset ``body`` equals (the same moments), else None."""

    for name in PRESETS:
        composite = RigidBody.composite(PRESETS[name].parts(), name=name)
        if np.array_equal(composite.body.moments, body.moments):
            return name, composite.mass
    return None


class FlipScene(_Scene):
    """A body turning over in space, frame by frame (:func:`stability.animate_flip`).

    Parameters
    ----------
    frames : FlipFrames
        From :func:`stability.animation.flip_frames`.
    size : int
        Width and height in pixels.
    fig : matplotlib.figure.Figure, optional
        Draw into this figure (``size`` is then unused); default a new one.

    Attributes
    ----------
    figure : matplotlib.figure.Figure
    dpi : int
    frames : int
        The number of frames.
    """

    def __init__(self, frames, size, fig=None):
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        body, axis = frames.body, frames.axis
        preset = _preset_of(body)
        self.racket = preset is not None and preset[0] == "tennis_racket"
        if self.racket:
            self.head, self.handle = racket_outline()
            reach = 1.1 * float(np.abs(np.vstack([self.head, self.handle])).max())
            shape = "tennis racket"
        else:
            mass = preset[1] if preset is not None else 1.0
            self.faces, self.normals = _inertia_box(body, mass)
            reach = 1.05 * float(np.linalg.norm(self.faces[0, 0]))
            name = preset[0].replace("_", " ") if preset is not None else body.name
            shape = f"{name} as its box of inertia ({mass:.2g} kg)"
        self.reach = reach
        ax = self._start(frames, size, fig, reach)
        self.heading = textwrap.fill(f"{shape} spun about axis {axis} "
                                     f"({moment_name(body, axis)} moment)", 60)
        length = 0.9 * reach
        ax.plot([0.0, 0.0], [0.0, 0.0], [0.0, length], color="black", lw=2.2)
        ax.text(0.0, 0.0, 1.04 * length, "L", fontsize=8, fontweight="bold")
        if self.racket:
            self.strings = Poly3DCollection([self.head], alpha=0.45, linewidths=0.0)
            ax.add_collection3d(self.strings)
            (self.rim,) = ax.plot([], [], [], color="black", lw=1.2)
            (self.grip,) = ax.plot([], [], [], color=_HANDLE_COLOR, lw=3.5)
        else:
            colors = [AXIS_COLORS[i] for i in self.normals]
            self.box = Poly3DCollection(list(self.faces), facecolors=colors, alpha=0.35,
                                        edgecolors="0.2", linewidths=0.5)
            ax.add_collection3d(self.box)
        self.arrows, self.names = [], []
        for i in range(3):
            (line,) = ax.plot([], [], [], color=AXIS_COLORS[i], lw=1.6)
            self.arrows.append(line)
            self.names.append(ax.text(0.0, 0.0, 0.0, str(i + 1), color=AXIS_COLORS[i],
                                      fontsize=7, fontweight="bold"))
        (self.path,) = ax.plot([], [], [], color=AXIS_COLORS[axis - 1], lw=0.8, alpha=0.6)
        self.length = length
        self.rotations = frames.rotation

    def draw(self, k):
        """Draw frame k (0 <= k < frames)."""
        R = self.rotations[k]
        if self.racket:
            head, handle = self.head @ R.T, self.handle @ R.T
            self.strings.set_verts([head])
            self.strings.set_facecolor(FRONT_COLOR if R[2, 2] > 0.0 else BACK_COLOR)
            self.rim.set_data_3d(*head.T)
            self.grip.set_data_3d(*handle.T)
        else:
            self.box.set_verts(list(self.faces @ R.T))
        for i, (line, name) in enumerate(zip(self.arrows, self.names)):
            tip = self.length * R[:, i]
            line.set_data_3d([0.0, tip[0]], [0.0, tip[1]], [0.0, tip[2]])
            name.set_position_3d(1.08 * tip)
        tips = self.length * self.rotations[: k + 1, :, self.data.axis - 1]
        self.path.set_data_3d(*tips.T)
        self.title.set_text(f"{self.heading}\nL fixed along Z; t = {self.data.t[k]:.2f} s"
                            + ("" if self.data.speed == 1.0 else
                               f" (played at {self.data.speed:g}x)"))


class TopScene(_Scene):
    """A heavy top nutating, frame by frame (:func:`stability.animate_top`).

    Parameters
    ----------
    frames : TopFrames
        From :func:`stability.animation.top_frames`.
    size : int
        Width and height in pixels.
    fig : matplotlib.figure.Figure, optional
        Draw into this figure (``size`` is then unused); default a new one.

    Attributes
    ----------
    figure : matplotlib.figure.Figure
    dpi : int
    frames : int
        The number of frames.
    """

    def __init__(self, frames, size, fig=None):
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        top = frames.top
        self.radius = float(np.sqrt(2.0 * top.central_moments[2] / top.mass))
        self.centre = top.length if top.length > 0.0 else self.radius
        self.tip = self.centre + max(0.5 * self.centre, 0.5 * self.radius)
        reach = 1.1 * max(self.tip, float(np.hypot(self.centre, self.radius)))
        lowest = min(float((self.tip * frames.trace[:, 2]).min()),
                     self.centre * float(np.cos(frames.tilt_range[1]))
                     - self.radius * float(np.sin(frames.tilt_range[1])))
        bottom = min(-0.1 * reach, lowest - 0.05 * reach)
        top_z = 1.1 * self.tip
        ax = self._start(frames, size, fig, reach, bottom=bottom, top=top_z)
        self.heading = textwrap.fill(
            f"{top.name}, spin {frames.spin:g} rad/s, released at a tilt of "
            f"{np.degrees(np.arccos(frames.axis[0, 2])):.0f}°", 58)
        ax.plot([0.0, 0.0], [0.0, 0.0], [bottom, top_z], color="0.4", lw=0.8, ls=":")
        ax.scatter([0.0], [0.0], [0.0], color="black", s=12, depthshade=False)
        turn = np.linspace(0.0, 2.0 * np.pi, 121)
        for theta in frames.tilt_range:  # the circles of the turning tilts
            r, z = self.tip * np.sin(theta), self.tip * np.cos(theta)
            ax.plot(r * np.cos(turn), r * np.sin(turn), np.full(turn.size, z), color="0.5",
                    lw=0.7, ls="--")
        self.turn = turn
        (self.path,) = ax.plot([], [], [], color="crimson", lw=0.9)
        (self.axle,) = ax.plot([], [], [], color="black", lw=1.8)
        self.disk = Poly3DCollection([np.zeros((turn.size, 3))], facecolors=AXIS_COLORS[0],
                                     alpha=0.4, edgecolors="0.15", linewidths=0.6)
        ax.add_collection3d(self.disk)
        self.steps = frames.trace_t.size // max(frames.t.size - 1, 1)

    def draw(self, k):
        """Draw frame k (0 <= k < frames)."""
        a = self.data.axis[k]
        tip = self.tip * a
        self.axle.set_data_3d([0.0, tip[0]], [0.0, tip[1]], [0.0, tip[2]])
        frame = frame_along(a)
        rim = (self.centre * a + self.radius * (np.cos(self.turn)[:, None] * frame[:, 0]
                                                + np.sin(self.turn)[:, None] * frame[:, 1]))
        self.disk.set_verts([rim])
        path = self.tip * self.data.trace[: k * self.steps + 1]
        self.path.set_data_3d(*path.T)
        tilt = np.degrees(np.arccos(np.clip(a[2], -1.0, 1.0)))
        self.title.set_text(f"{self.heading}\nt = {self.data.t[k]:.3f} s, tilt {tilt:.1f}° "
                            f"(played at {self.data.speed:g}x)")


def frame_figure(frames, k=-1, size=480, fig=None):
    """One frame of an animation as a figure: the flip (the racket or box, its axes, L, the
    path so far) or the heavy top (the disk on its axle, the tip's path so far).

    Parameters
    ----------
    frames : FlipFrames or TopFrames
        From :func:`stability.animation.flip_frames` or :func:`stability.animation.top_frames`.
    k : int, default -1
        The frame; negative counts from the end.
    size : int, default 480
        Width and height in pixels (at 100 dots per inch).
    fig : matplotlib.figure.Figure, optional
        Draw into this figure (e.g. ``plt.figure(figsize=(5, 5))`` to show it with pyplot);
        default a new one of ``size`` pixels.

    Returns
    -------
    matplotlib.figure.Figure
    """
    # Told apart by what they hold (the drawing does not import the module computing them).
    if all(hasattr(frames, name) for name in ("body", "q", "momentum")):
        scene_type = FlipScene
    elif all(hasattr(frames, name) for name in ("top", "axis", "trace")):
        scene_type = TopScene
    else:
        raise ValueError("frames must come from stability.animation.flip_frames or top_frames, "
                         f"got {type(frames).__name__}")
    scene = scene_type(frames, size, fig)
    scene.draw(range(scene.frames)[k])
    return scene.figure
