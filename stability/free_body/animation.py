"""The tennis-racket effect as an animation: a body turning over in space, from its exact
attitude.

The body is turned by its exact attitude R(q(t))
(:func:`stability.free_body.exact_attitude.exact_attitude`) from
``w0 = spin (e_axis + epsilon (e_j + e_k))``, started with its angular momentum along space Z,
so that L = R(t) I w(t) stays on the Z axis in every frame (Landau & Lifshitz, *Mechanics*,
section 37). :func:`flip_frames` computes what is drawn, :class:`FlipScene` draws it and
:func:`animate_flip` writes the file (:mod:`stability.plotting.animation`).
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core.body import PRESETS, RigidBody
from ..core.quaternions import frame_along, matrix_to_quaternion, quaternion_to_matrix
from ..plotting.animation import (DEFAULT_FPS, DEFAULT_SIZE, Scene3D, TITLE_WIDTH, check_size,
                                  frame_times, output_path, write_animation)
from ..plotting.style import AXIS_COLORS
from ..util.checks import positive_float
from .exact import exact_omega, full_period
from .exact_attitude import exact_attitude
from ..core.axes import intermediate_axis, moment_name
from .twisting_racket.figures import BACK_COLOR, FRONT_COLOR, racket_outline

_HANDLE_COLOR = "#7a5a2a"
#: Colours of a box's two large faces (normal to its largest-moment axis): + side, - side.
LARGE_FACE_COLORS = ("#7b2cbf", "#e6ab02")
#: What a preset's two large faces are (+ side, - side of its largest-moment axis).
LARGE_FACE_NAMES = {"phone": ("screen", "back"), "book": ("front cover", "back cover")}


@dataclass(frozen=True, eq=False)
class FlipFrames:
    """The torque-free body at the frames' times, as :func:`flip_frames` computes it.

    Parameters
    ----------
    body : RigidBody
        The body drawn.
    axis : int
        The spin axis, 1, 2 or 3.
    t : ndarray, shape (n,)
        Times of the frames in s (of the motion; played at ``speed``).
    w : ndarray, shape (n, 3)
        Exact angular velocity along the body's axes, rad/s.
    q : ndarray, shape (n, 4)
        Exact attitude, body-to-space unit quaternions, scalar first.
    momentum : ndarray, shape (3,)
        The angular momentum in space, kg m^2/s: (0, 0, |L|).
    fps : float
        Frames per second of the file.
    speed : float
        Seconds of motion per second of playback.
    """

    body: RigidBody
    axis: int
    t: np.ndarray
    w: np.ndarray
    q: np.ndarray
    momentum: np.ndarray
    fps: float
    speed: float

    @property
    def rotation(self) -> np.ndarray:
        """R(q(t)), body-to-space matrices, shape (n, 3, 3)."""
        return quaternion_to_matrix(self.q)

    def scene(self, size, fig=None) -> FlipScene:
        """The frames drawn (:class:`FlipScene`), ``size`` pixels square or into ``fig``."""
        return FlipScene(self, size, fig)


def flip_frames(body=None, *, spin=6.0, epsilon=0.05, axis=None, duration=None,
                fps=DEFAULT_FPS, speed=1.0) -> FlipFrames:
    """The exact motion of a body spun about one axis and nudged, at the frames' times.

    ``w0 = spin e_axis + epsilon spin (e_j + e_k)`` (j, k the other two axes); the start
    attitude q0 turns I w0 onto space Z, with the smallest-moment axis towards X, so that the
    angular momentum is ``(0, 0, |L|)`` in every frame: R(q(t)) I w(t) = R(q0) I w0.

    Parameters
    ----------
    body : RigidBody, optional
        Default ``RigidBody.preset("tennis_racket")``.
    spin : float, default 6.0
        Spin about ``axis`` in rad/s, > 0.
    epsilon : float, default 0.05
        The nudge, relative to the spin, > 0 (smaller: the body waits longer between flips).
    axis : int, optional
        1, 2 or 3; default the axis of the intermediate moment (the flip).
    duration : float, optional
        Seconds of motion shown; default one period of w (:func:`stability.full_period`: over
        and back), or 4 s where the motion has none.
    fps : float, default 20
        Frames per second of the file. A GIF keeps each frame's time in hundredths of a
        second, so it plays at exactly this rate where 100 / fps is whole (10, 20, 25, 50).
    speed : float, default 1.0
        Seconds of motion per second of playback (0.5: slow motion).

    Returns
    -------
    FlipFrames
    """
    body = RigidBody.preset("tennis_racket") if body is None else body
    if not isinstance(body, RigidBody):
        raise ValueError(f"body must be a stability.RigidBody, got {type(body).__name__}")
    spin = positive_float("spin", spin, "rad/s")
    epsilon = positive_float("epsilon", epsilon)
    axis = intermediate_axis(body) if axis is None else axis
    if isinstance(axis, bool) or axis not in (1, 2, 3):
        raise ValueError(f"axis must be 1, 2 or 3, got {axis!r}")
    w0 = np.full(3, epsilon * spin)
    w0[axis - 1] = spin
    if duration is None:
        period = float(full_period(body, w0))
        duration = period if math.isfinite(period) else 4.0
    t = frame_times(duration, fps, speed)
    m0 = body.moments * w0
    smallest = np.eye(3)[int(np.argmin(body.moments))]
    q0 = matrix_to_quaternion(frame_along(m0, hint=smallest).T)  # I w0 -> +Z
    q = exact_attitude(body, w0, t, q0)
    if not np.all(np.isfinite(q)):
        raise ValueError(f"w0 = {w0.tolist()} rad/s lies on the separatrix of this body, where "
                         "the motion has no period and no exact attitude; change epsilon")
    w = np.asarray(exact_omega(body, w0, t), dtype=float)
    momentum = np.array([0.0, 0.0, float(np.linalg.norm(m0))])
    return FlipFrames(body, int(axis), t, w, q, momentum, float(fps), float(speed))


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


def large_face_names(name, axis) -> tuple[str, str]:
    """Legend entries of a box's two large faces, normal to body axis ``axis`` (1-based): what
    they are on preset ``name`` (the phone's screen and back), and the side of the axis."""
    plus, minus = LARGE_FACE_NAMES.get(name, ("face", "face"))
    return f"{plus} (+{axis} side)", f"{minus} (−{axis} side)"


def _preset_of(body):
    """(name, mass in kg) of the preset ``body`` equals (the same moments), else None."""

    for name in PRESETS:
        composite = RigidBody.composite(PRESETS[name].parts(), name=name)
        if np.array_equal(composite.body.moments, body.moments):
            return name, composite.mass
    return None


class FlipScene(Scene3D):
    """A body turning over in space, frame by frame (:func:`stability.animate_flip`).

    Parameters
    ----------
    frames : FlipFrames
        From :func:`flip_frames`.
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
                                     f"({moment_name(body, axis)} moment)", TITLE_WIDTH)
        length = 0.9 * reach
        ax.plot([0.0, 0.0], [0.0, 0.0], [0.0, length], color="black", lw=2.2)
        ax.text(0.0, 0.0, 1.04 * length, "L", fontsize=self.fonts["name"], fontweight="bold")
        if self.racket:
            self.strings = Poly3DCollection([self.head], alpha=0.45, linewidths=0.0)
            ax.add_collection3d(self.strings)
            (self.rim,) = ax.plot([], [], [], color="black", lw=1.2)
            (self.grip,) = ax.plot([], [], [], color=_HANDLE_COLOR, lw=3.5)
        else:
            self._add_box(ax, preset[0] if preset is not None else None)
        self.arrows, self.names = [], []
        for i in range(3):
            (line,) = ax.plot([], [], [], color=AXIS_COLORS[i], lw=1.6)
            self.arrows.append(line)
            self.names.append(ax.text(0.0, 0.0, 0.0, str(i + 1), color=AXIS_COLORS[i],
                                      fontsize=self.fonts["name"], fontweight="bold"))
        (self.path,) = ax.plot([], [], [], color=AXIS_COLORS[axis - 1], lw=0.8, alpha=0.6)
        self.length = length
        self.rotations = frames.rotation

    def _add_box(self, ax, preset):
        """The box of inertia: its two large faces opaque in :data:`LARGE_FACE_COLORS`, named
        in a legend (the phone's screen and back), the four others pale in their axes'
        colours."""
        from matplotlib.colors import to_rgba
        from matplotlib.patches import Patch
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        largest = int(np.argmax(self.data.body.moments))
        colors = [to_rgba(AXIS_COLORS[i], 0.3) for i in self.normals]
        large = np.flatnonzero(self.normals == largest)  # its + side first (_inertia_box)
        for face, color in zip(large, LARGE_FACE_COLORS):
            colors[face] = to_rgba(color, 0.9)
        self.box = Poly3DCollection(list(self.faces), facecolors=colors, edgecolors="0.2",
                                    linewidths=0.5)
        ax.add_collection3d(self.box)
        names = large_face_names(preset, largest + 1)
        self.legend = self.figure.legend(
            handles=[Patch(facecolor=c, alpha=0.9, label=n)
                     for c, n in zip(LARGE_FACE_COLORS, names)],
            loc="upper left", bbox_to_anchor=(0.0, 0.87), fontsize=self.fonts["legend"],
            frameon=False, handlelength=1.2, borderaxespad=0.2)

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


def animate_flip(body=None, *, path, spin=6.0, epsilon=0.05, axis=None, duration=None,
                 fps=DEFAULT_FPS, speed=1.0, size=DEFAULT_SIZE) -> Path:
    """Write an animation of a body turning over in space (the tennis-racket effect).

    The tennis racket preset is drawn as a racket (strings red on the side facing L, blue on
    the other), any other body as its box of inertia: the uniform box with its principal
    moments, edges ``a_i = sqrt(6 (I_j + I_k - I_i) / M)``, for the preset's mass or 1 kg,
    its two large faces in two colours named in a legend (the phone's screen and back), so
    that its turning over shows. Text grows with ``size``.
    Its body axes 1, 2, 3 are drawn, the path of the spin axis' tip, and L, fixed along Z.
    The motion is exact (:func:`flip_frames`).

    Parameters
    ----------
    body : RigidBody, optional
        Default the tennis racket preset.
    path : str or os.PathLike
        Output file, ``.gif`` or ``.mp4`` (which needs ffmpeg); its folder must exist. An
        existing file is replaced.
    spin, epsilon, axis, duration, fps, speed
        As in :func:`flip_frames`: the default shows one period (two flips) in real time.
    size : int, default 320
        Width and height in pixels, 120 to 2000.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    ValueError
        One line saying what to do, for a bad path (suffix, folder, no ffmpeg for .mp4) or a
        bad number.
    """
    path = output_path(path)
    size = check_size(size)
    frames = flip_frames(body, spin=spin, epsilon=epsilon, axis=axis, duration=duration,
                         fps=fps, speed=speed)
    return write_animation(FlipScene(frames, size), path, frames.fps)


#: The module's public API (the rest serves the package's other modules).
__all__ = ["FlipFrames", "FlipScene", "animate_flip", "flip_frames"]
