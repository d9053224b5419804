"""
The flip, animated
==================

A tennis racket spun at 6 rad/s about its intermediate axis and nudged by 5 % of the spin turns
over and back while its angular momentum L stays fixed in space. The animation is the exact
motion (:func:`stability.free_body.exact_attitude.exact_attitude`), written by
:func:`stability.animate_flip` as a GIF (or an MP4 where ffmpeg is installed), the same as the
command ``stability animate racket flip.gif``:

.. image:: ../../data/readme/flip.gif
   :alt: the tennis racket turning over and back while L stays fixed

:func:`stability.free_body.animation.flip_frames` gives what is drawn: the times, the exact w(t) and
attitude q(t) of every frame. L = R(q) I w is the same in all of them.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import stability
from stability.free_body.animation import flip_frames
from stability.heavy_top.animation import top_frames
from stability.plotting.animation import frame_figure

frames = flip_frames()  # the defaults of animate_flip: the racket, 6 rad/s, a nudge of 0.05
L = np.einsum("nij,nj->ni", frames.rotation, frames.body.moments * frames.w)
print(f"{frames.t.size} frames over {frames.t[-1]:.2f} s; L along Z, |L| = "
      f"{frames.momentum[2]:.6f} kg m2/s; its largest change over the frames: "
      f"{np.ptp(L, axis=0).max():.1e} kg m2/s")
with tempfile.TemporaryDirectory() as folder:
    path = stability.animate_flip(path=Path(folder) / "short.gif", duration=1.0, size=200)
    print(f"a 1 s GIF of 200 x 200 pixels: {path.stat().st_size / 1024:.0f} KiB")

# %%
# The frame where the racket is half-way over: axis 2, along L at the start, lies across it.
# The orange curve is the path of axis 2's tip so far.

half = int(np.argmin(np.abs(frames.rotation[: frames.t.size // 2, 2, 1])))
fig = plt.figure(figsize=(4.8, 4.8), dpi=100)
frame_figure(frames, half, fig=fig)

# %%
# A heavy top (:func:`stability.animate_top`, ``stability animate top top.gif``): a disk top
# released at a tilt nods between two tilts (dashed circles) while it precesses; the red curve
# is the path of its axle's tip, with a cusp at each stop.

fig = plt.figure(figsize=(4.8, 4.8), dpi=100)
frame_figure(top_frames(), fig=fig)
