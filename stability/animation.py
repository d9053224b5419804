"""Animations of the exact motions: the tennis racket turning over, a heavy top nutating.

Every frame comes from an exact solution, not from an integrator:

- the flip (:func:`animate_flip`): the body turned by its exact attitude R(q(t))
  (:func:`stability.free_body.exact_attitude.exact_attitude`) from ``w0 = spin (e_axis + epsilon (e_j +
  e_k))``, started with its angular momentum along space Z, so that L = R(t) I w(t) stays on
  the Z axis in every frame (Landau & Lifshitz, *Mechanics*, section 37);
- the heavy top (:func:`animate_top`): its figure axis from the exact symmetric-top solution
  (:func:`stability.heavy_top.exact.figure_axis_path`; Goldstein, *Classical Mechanics*, 3rd ed.,
  section 5.7) for a top released at a tilt with no transverse angular velocity.

The file type is the path's suffix: ``.gif`` (matplotlib's PillowWriter; Pillow comes with
matplotlib) or ``.mp4`` (matplotlib's FFMpegWriter, where ffmpeg is installed).
:func:`flip_frames` and :func:`top_frames` return what is drawn, and
:mod:`stability.figures.animation` draws one frame as a figure.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .core.body import RigidBody
from .util.checks import positive_float, positive_int, real_number

#: Frames per second of the files by default (a GIF plays it exactly: 5 hundredths of a second).
DEFAULT_FPS = 20.0
#: Width and height of the files in pixels by default (a GIF of 80 frames stays under 1 MB).
DEFAULT_SIZE = 320
#: The most frames one file may hold (Pillow keeps every frame in memory until the end).
MAX_FRAMES = 1000
#: File types, by suffix.
SUFFIXES = (".gif", ".mp4")


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
        from .free_body.attitude import quaternion_to_matrix

        return quaternion_to_matrix(self.q)


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


def _frame_times(duration, fps, speed) -> np.ndarray:
    """Times of the frames: n = round(fps duration / speed) of them, speed / fps apart."""
    duration = positive_float("duration", duration, "s")
    fps = positive_float("fps", fps, "frames/s")
    speed = positive_float("speed", speed, "s of motion per s shown")
    n = round(fps * duration / speed)
    if n < 2:
        raise ValueError(f"duration = {duration:g} s at fps = {fps:g} and speed = {speed:g} "
                         f"gives {n} frame(s); give a longer duration or a higher fps "
                         "(at least 2 frames)")
    if n > MAX_FRAMES:
        raise ValueError(f"duration = {duration:g} s at fps = {fps:g} and speed = {speed:g} "
                         f"gives {n} frames, more than {MAX_FRAMES}; shorten the duration, "
                         "lower fps or raise speed")
    return np.arange(n) * (speed / fps)


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
    from .free_body.model import intermediate_axis
    from .core.quaternions import frame_along, matrix_to_quaternion
    from .free_body.exact import exact_omega, full_period
    from .free_body.exact_attitude import exact_attitude

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
    t = _frame_times(duration, fps, speed)
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


def _default_top():
    from .heavy_top.model import HeavyTop

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
    from .heavy_top.exact import figure_axis_path, mean_precession_rate, nutation_roots
    from .heavy_top.model import HeavyTop, tilted_starts

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
    t = _frame_times(duration, fps, speed)
    trace_t = np.linspace(0.0, t[-1], 8 * (t.size - 1) + 1)
    trace = figure_axis_path(trace_t, x0, A, C, top.mgl)
    u1, u2, _ = nutation_roots(x0, A, C, top.mgl)
    return TopFrames(top, spin, t, trace[::8], trace, trace_t,
                     np.arccos(np.clip([u2, u1], -1.0, 1.0)), float(fps), float(speed))


def output_path(path) -> Path:
    """``path`` checked for writing an animation: a .gif or .mp4 in a folder that exists.

    Parameters
    ----------
    path : str or os.PathLike
        Where the file goes; its suffix picks the type.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    ValueError
        One line saying what to do: an unknown suffix, a missing folder, a path that is a
        folder, or .mp4 without ffmpeg.
    """
    from matplotlib.animation import writers

    try:
        path = Path(os.fspath(path))
    except TypeError:
        raise ValueError(f"path must be a file name ending in .gif or .mp4, got {path!r}") from None
    suffix = path.suffix.lower()
    if suffix not in SUFFIXES:
        raise ValueError(f"path must end in .gif or .mp4 (the suffix picks the file type), got "
                         f"{str(path)!r}")
    if not path.parent.is_dir():
        raise ValueError(f"the folder {str(path.parent)!r} does not exist: create it first or "
                         f"write {path.name!r} elsewhere")
    if path.is_dir():
        raise ValueError(f"{str(path)!r} is a folder; give a file name ending in {suffix}")
    if suffix == ".mp4" and not writers.is_available("ffmpeg"):
        raise ValueError("writing .mp4 needs ffmpeg, which matplotlib does not find on this "
                         "machine: install ffmpeg (e.g. apt install ffmpeg, or conda install "
                         "ffmpeg) or write a .gif")
    return path


def write_animation(scene, path, fps) -> Path:
    """Draw every frame of ``scene`` into ``path`` (.gif or .mp4); return the path.

    The file is written under a temporary name in the same folder and renamed when whole, so
    an interrupted run leaves no truncated file.

    Parameters
    ----------
    scene : FlipScene or TopScene
        From :mod:`stability.figures.animation`: its ``figure``, ``dpi``, ``frames`` and
        ``draw(k)``.
    path : str or os.PathLike
        Checked by :func:`output_path`.
    fps : float
        Frames per second.

    Returns
    -------
    pathlib.Path
    """
    from matplotlib.animation import FFMpegWriter, PillowWriter

    path = output_path(path)
    fps = positive_float("fps", fps, "frames/s")
    writer = PillowWriter(fps=fps) if path.suffix.lower() == ".gif" else FFMpegWriter(fps=fps)
    partial = path.with_name(f".{path.stem}.part{path.suffix}")
    try:
        with writer.saving(scene.figure, str(partial), dpi=scene.dpi):
            for k in range(scene.frames):
                scene.draw(k)
                writer.grab_frame()
        partial.replace(path)
    except BaseException:
        partial.unlink(missing_ok=True)
        raise
    return path


def _size(size) -> int:
    size = positive_int("size", size)
    if not 120 <= size <= 2000:
        raise ValueError(f"size must be between 120 and 2000 pixels, got {size}")
    return size - size % 2  # even: what H.264 needs


def animate_flip(body=None, *, path, spin=6.0, epsilon=0.05, axis=None, duration=None,
                 fps=DEFAULT_FPS, speed=1.0, size=DEFAULT_SIZE) -> Path:
    """Write an animation of a body turning over in space (the tennis-racket effect).

    The tennis racket preset is drawn as a racket (strings red on the side facing L, blue on
    the other), any other body as its box of inertia: the uniform box with its principal
    moments, edges ``a_i = sqrt(6 (I_j + I_k - I_i) / M)``, for the preset's mass or 1 kg.
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
    from .figures.animation import FlipScene

    path = output_path(path)
    size = _size(size)
    frames = flip_frames(body, spin=spin, epsilon=epsilon, axis=axis, duration=duration,
                         fps=fps, speed=speed)
    return write_animation(FlipScene(frames, size), path, frames.fps)


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
    from .figures.animation import TopScene

    path = output_path(path)
    size = _size(size)
    frames = top_frames(top, spin=spin, tilt=tilt, duration=duration, fps=fps, speed=speed)
    return write_animation(TopScene(frames, size), path, frames.fps)
