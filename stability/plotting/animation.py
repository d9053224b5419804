"""Animations, whatever is drawn: frame times, checked output paths, writing GIF or MP4, and
the square 3-D figure a scene is drawn in frame after frame.

A family's animation (:mod:`stability.free_body.animation`, the flip;
:mod:`stability.heavy_top.animation`, a heavy top nutating) computes its frames from an exact
solution and gives a scene (a :class:`Scene3D` with ``draw(k)``); :func:`write_animation`
writes it and :func:`frame_figure` shows one frame. The file type is the path's suffix:
``.gif`` (matplotlib's PillowWriter; Pillow comes with matplotlib) or ``.mp4`` (matplotlib's
FFMpegWriter, where ffmpeg is installed).
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from ..util.checks import positive_float, positive_int
from ..util.interrupts import deferred_interrupt
from .style import label

#: Frames per second of the files by default (a GIF plays it exactly: 5 hundredths of a second).
DEFAULT_FPS = 20.0
#: Width and height of the files in pixels by default (a GIF of 80 frames stays under 1 MB).
DEFAULT_SIZE = 320
#: The most frames one file may hold (Pillow keeps every frame in memory until the end).
MAX_FRAMES = 1000
#: File types, by suffix.
SUFFIXES = (".gif", ".mp4")
#: Dots per inch of the animation figures; their size is given in pixels.
DPI = 100
#: Font sizes in points on a frame of :data:`DEFAULT_SIZE` pixels; they grow with the frame
#: (:func:`font_sizes`), so that text takes the same share of any frame.
FONT_POINTS = {"title": 8.5, "label": 7.5, "ticks": 6.5, "name": 8.5, "legend": 7.5}
#: Characters per line of a title at these sizes (any frame: the fonts grow with it).
TITLE_WIDTH = 46


def frame_times(duration, fps, speed) -> np.ndarray:
    """Times of the frames: n = round(fps duration / speed) of them, speed / fps apart."""
    duration = positive_float("duration", duration, "s")
    fps = positive_float("fps", fps, "frames/s")
    speed = positive_float("speed", speed, "s of motion per s shown")
    frames = fps * duration / speed  # inf where the product overflows
    if frames > MAX_FRAMES + 0.5:
        count = (round(frames) if frames < 1e9 else f"{frames:.3g}" if math.isfinite(frames)
                 else "over 1e308")
        raise ValueError(f"duration = {duration:g} s at fps = {fps:g} and speed = {speed:g} "
                         f"gives {count} frames, more than {MAX_FRAMES}; shorten the duration, "
                         "lower fps or raise speed")
    n = round(frames)
    if n < 2:
        raise ValueError(f"duration = {duration:g} s at fps = {fps:g} and speed = {speed:g} "
                         f"gives {n} frame(s); give a longer duration or a higher fps "
                         "(at least 2 frames)")
    return np.arange(n) * (speed / fps)


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
    an interrupted run leaves no truncated file. Ctrl-C takes effect between two frames (raised
    inside matplotlib's compiled drawing code, it could come out as another error).

    Parameters
    ----------
    scene : Scene3D
        A :class:`Scene3D`: its ``figure``, ``dpi``, ``frames`` and ``draw(k)``.
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
        with deferred_interrupt() as stop, writer.saving(scene.figure, str(partial),
                                                         dpi=scene.dpi):
            for k in range(scene.frames):
                if stop.requested:
                    raise KeyboardInterrupt
                scene.draw(k)
                writer.grab_frame()
        partial.replace(path)
    except BaseException:
        partial.unlink(missing_ok=True)
        raise
    return path


def check_size(size) -> int:
    """``size`` in pixels checked: 120 to 2000, made even (what H.264 needs)."""
    size = positive_int("size", size)
    if not 120 <= size <= 2000:
        raise ValueError(f"size must be between 120 and 2000 pixels, got {size}")
    return size - size % 2  # even: what H.264 needs


def font_sizes(fig) -> dict:
    """:data:`FONT_POINTS` scaled to ``fig``: times its smaller side over :data:`DEFAULT_SIZE`
    pixels."""
    side = min(fig.get_size_inches()) * fig.dpi
    return {name: points * side / DEFAULT_SIZE for name, points in FONT_POINTS.items()}


def axes3d(fig, reach, bottom=None, top=None):
    """3-D axes with one scale on all three axes, labelled in m: x and y in [-reach, reach],
    z in [bottom, top] (default the same as x and y); fonts scaled to the figure
    (:func:`font_sizes`)."""
    fonts = font_sizes(fig)
    ax = fig.add_axes((0.0, 0.0, 1.0, 0.87), projection="3d")
    lo = -reach if bottom is None else bottom
    hi = reach if top is None else top
    ax.set_xlim(-reach, reach)
    ax.set_ylim(-reach, reach)
    ax.set_zlim(lo, hi)
    ax.set_box_aspect((2.0 * reach, 2.0 * reach, hi - lo), zoom=0.88)
    for name, setter in zip("XYZ", (ax.set_xlabel, ax.set_ylabel, ax.set_zlabel)):
        setter(label(name, "m"), fontsize=fonts["label"], labelpad=fonts["label"] - 10.5)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(MaxNLocator(3))
    ax.tick_params(labelsize=fonts["ticks"], pad=-0.3 * fonts["ticks"])
    ax.zaxis.set_tick_params(pad=0)  # closer, a minus sign hid under its tick mark
    return ax


def scene_figure(size, fig=None):
    """A new square figure of ``size`` pixels, or ``fig`` (a pyplot figure, say) emptied."""
    if fig is None:
        return Figure(figsize=(size / DPI, size / DPI), dpi=DPI)
    fig.clear()
    return fig


class Scene3D:
    """What both scenes share: the frames, a square figure, its 3-D axes, a title and the
    font sizes of its text (``fonts``, :func:`font_sizes`)."""

    def _start(self, frames, size, fig, reach, bottom=None, top=None):
        self.data, self.dpi, self.frames = frames, DPI, frames.t.size
        self.figure = scene_figure(size, fig)
        self.fonts = font_sizes(self.figure)
        self.ax = axes3d(self.figure, reach, bottom, top)
        self.title = self.figure.suptitle("", fontsize=self.fonts["title"], y=0.99)
        return self.ax


def frame_figure(frames, k=-1, size=480, fig=None):
    """One frame of an animation as a figure: the flip (the racket or box, its axes, L, the
    path so far) or the heavy top (the disk on its axle, the tip's path so far).

    Parameters
    ----------
    frames : FlipFrames or TopFrames
        From :func:`stability.free_body.animation.flip_frames` or
        :func:`stability.heavy_top.animation.top_frames`.
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
    if not callable(getattr(frames, "scene", None)):
        raise ValueError("frames must come from stability.free_body.animation.flip_frames or "
                         f"stability.heavy_top.animation.top_frames, got {type(frames).__name__}")
    scene = frames.scene(size, fig)
    scene.draw(range(scene.frames)[k])
    return scene.figure


#: The module's public API (the rest serves the package's other modules).
__all__ = ["DEFAULT_FPS", "DEFAULT_SIZE", "MAX_FRAMES", "SUFFIXES", "frame_figure", "output_path",
           "write_animation"]
