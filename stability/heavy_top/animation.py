"""A symmetric heavy top nutating and precessing, as an animation, from the exact motion.

Its figure axis comes from the exact symmetric-top solution
(:func:`stability.heavy_top.exact.figure_axis_path`; Goldstein, *Classical Mechanics*, 3rd ed.,
section 5.7) for a top released at a tilt with no transverse angular velocity.
:func:`top_frames` computes what is drawn, :class:`TopScene` draws it and :func:`animate_top`
writes the file (:mod:`stability.plotting.animation`).
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core.quaternions import frame_along
from ..plotting.animation import (DEFAULT_FPS, DEFAULT_SIZE, Scene3D, check_size, frame_times,
                                  TITLE_WIDTH, output_path, write_animation)
from ..plotting.style import AXIS_COLORS
from ..util.checks import positive_float, real_number
from .exact import figure_axis_path, mean_precession_rate, nutation_roots
from .model import HeavyTop, tilted_starts


@dataclass(frozen=True, eq=False)
class TopFrames:
    """A symmetric heavy top at the frames' times, as :func:`top_frames` computes it.

    Parameters
    ----------
    top : HeavyTop
        The top drawn (symmetric: I1 = I2 about the pivot).
    spin : float
        w3 at the start, rad/s.
    t : ndarray, shape (n,)
        Times of the frames in s.
    axis : ndarray, shape (n, 3)
        The figure axis (unit vectors, space frame, Z up) at those times.
    trace : ndarray, shape (m, 3)
        The figure axis on a finer grid of times ``trace_t``, for the path of its tip.
    trace_t : ndarray, shape (m,)
        Times of ``trace`` in s, from 0 to ``t[-1]``.
    tilt_range : ndarray, shape (2,)
        The least and greatest tilt from the vertical in rad (the turning points u2, u1 of
        :func:`stability.heavy_top.exact.nutation_roots`).
    fps : float
        Frames per second of the file.
    speed : float
        Seconds of motion per second of playback.
    """

    top: object
    spin: float
    t: np.ndarray
    axis: np.ndarray
    trace: np.ndarray
    trace_t: np.ndarray
    tilt_range: np.ndarray
    fps: float
    speed: float

    def scene(self, size, fig=None) -> TopScene:
        """The frames drawn (:class:`TopScene`), ``size`` pixels square or into ``fig``."""
        return TopScene(self, size, fig)


def _default_top():
    return HeavyTop.disk(mass=0.2, radius=0.03, length=0.05, name="disk top")


def top_frames(top=None, *, spin=200.0, tilt=0.5, duration=None, fps=DEFAULT_FPS,
               speed=0.25) -> TopFrames:
    """The exact figure axis of a symmetric heavy top released at a tilt, at the frames' times.

    The top starts at ``tilt`` from the vertical, spinning at ``spin`` about its axis, with no
    transverse angular velocity (:func:`stability.heavy_top.model.tilted_starts`), so its axis
    dips and precesses in cusps (Goldstein section 5.7, fig. 5.9 c).

    Parameters
    ----------
    top : HeavyTop, optional
        Symmetric (I1 = I2); default a disk top of 0.2 kg, radius 3 cm, 5 cm from the pivot.
    spin : float, default 200.0
        w3 in rad/s, > 0.
    tilt : float, default 0.5
        Start tilt from the vertical in rad, in (0, pi).
    duration : float, optional
        Seconds of motion shown; default one turn of the mean precession (at most 20 s).
    fps : float, default 20
        Frames per second of the file. A GIF keeps each frame's time in hundredths of a
        second, so it plays at exactly this rate where 100 / fps is whole (10, 20, 25, 50).
    speed : float, default 0.25
        Seconds of motion per second of playback (the default plays it four times slower).

    Returns
    -------
    TopFrames
    """
    top = _default_top() if top is None else top
    if not isinstance(top, HeavyTop):
        raise ValueError("top must be a stability.heavy_top.model.HeavyTop, "
                         f"got {type(top).__name__}")
    if not top.symmetric:
        raise ValueError("the top must be symmetric (equal moments about axes 1 and 2): the "
                         "exact solution drawn is the Lagrange top's")
    spin = positive_float("spin", spin, "rad/s")
    tilt = real_number("tilt", tilt, "rad")
    if not 0.0 < tilt < math.pi:
        raise ValueError(f"tilt must be in (0, pi) rad from the vertical, got {tilt!r}")
    A, _, C = top.pivot_moments
    x0 = tilted_starts(spin, tilt, 1, top=top)[0]
    if duration is None:
        rate = abs(float(mean_precession_rate(x0, A, C, top.mgl)))
        duration = min(2.0 * math.pi / rate, 20.0) if rate > 0.0 else 4.0
    t = frame_times(duration, fps, speed)
    trace_t = np.linspace(0.0, t[-1], 8 * (t.size - 1) + 1)
    trace = figure_axis_path(trace_t, x0, A, C, top.mgl)
    u1, u2, _ = nutation_roots(x0, A, C, top.mgl)
    return TopFrames(top, spin, t, trace[::8], trace, trace_t,
                     np.arccos(np.clip([u2, u1], -1.0, 1.0)), float(fps), float(speed))


class TopScene(Scene3D):
    """A heavy top nutating, frame by frame (:func:`stability.animate_top`).

    Parameters
    ----------
    frames : TopFrames
        From :func:`top_frames`.
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
            f"{np.degrees(np.arccos(frames.axis[0, 2])):.0f}°", TITLE_WIDTH)
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


def animate_top(top=None, *, path, spin=200.0, tilt=0.5, duration=None, fps=DEFAULT_FPS,
                speed=0.25, size=DEFAULT_SIZE) -> Path:
    """Write an animation of a symmetric heavy top nutating and precessing about the vertical.

    The top is drawn as the disk with its mass and axial moment (radius sqrt(2 I3 / M)) on its
    axle, with the path of the axle's tip and the two circles of the turning tilts between
    which it nods (:func:`top_frames`; exact, Goldstein section 5.7). The disk's own turn about
    the axle is not drawn: it is symmetric, and at a spin of tens of rad/s it would alias at
    any frame rate.

    Parameters
    ----------
    top : HeavyTop, optional
        Symmetric; default the disk top of :func:`top_frames`.
    path : str or os.PathLike
        Output file, ``.gif`` or ``.mp4`` (which needs ffmpeg); its folder must exist. An
        existing file is replaced.
    spin, tilt, duration, fps, speed
        As in :func:`top_frames`: the default shows one turn of the precession at a quarter of
        real time.
    size : int, default 320
        Width and height in pixels, 120 to 2000.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    ValueError
        One line saying what to do, for a bad path or a bad number.
    """
    path = output_path(path)
    size = check_size(size)
    frames = top_frames(top, spin=spin, tilt=tilt, duration=duration, fps=fps, speed=speed)
    return write_animation(TopScene(frames, size), path, frames.fps)


#: The module's public API (the rest serves the package's other modules).
__all__ = ["TopFrames", "TopScene", "animate_top", "top_frames"]
