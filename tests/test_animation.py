"""Animations of the exact motions: valid GIFs of the asked number of frames and size, L fixed in
space in every frame drawn, the top between its turning tilts, one-line errors for bad input."""

import numpy as np
import pytest
from matplotlib.animation import writers
from PIL import Image

import stability
from stability.free_body.animation import FlipScene, animate_flip, flip_frames
from stability.heavy_top.animation import TopScene, animate_top, top_frames
from stability.plotting.animation import MAX_FRAMES, frame_figure
from stability.cli import main
from stability.heavy_top.exact import nutation_roots
from stability.plotting.style import missing_units
from stability.heavy_top.model import HeavyTop

RACKET = stability.RigidBody.preset("tennis_racket")


def _gif(path):
    image = Image.open(path)
    return image.format, image.n_frames, image.size


def test_the_flip_writes_a_gif_of_the_asked_frames_and_size(tmp_path):
    path = animate_flip(path=tmp_path / "flip.gif", duration=0.6, fps=10, size=160)
    assert path == tmp_path / "flip.gif"
    assert _gif(path) == ("GIF", 6, (160, 160))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["flip.gif"]  # no partial file left


def test_the_top_writes_a_gif_of_the_asked_frames_and_size(tmp_path):
    path = animate_top(path=str(tmp_path / "top.GIF"), duration=0.1, speed=0.25, fps=10,
                       size=150)
    assert _gif(path) == ("GIF", 4, (150, 150))  # 0.1 s of motion at 0.25x and 10 fps; even


@pytest.mark.parametrize("body, axis", [(None, None), (RACKET, 1), (RACKET, 3),
                                        (stability.RigidBody.preset("t_handle"), None),
                                        (stability.RigidBody(1.0, 2.0, 2.5), 2)])
def test_l_stays_fixed_along_z_in_every_frame(body, axis):
    frames = flip_frames(body, spin=8.0, epsilon=0.1, axis=axis, duration=3.0, fps=10)
    b = RACKET if body is None else body
    assert frames.t.size == 30 and frames.axis == (axis or 2)
    L = np.einsum("nij,nj->ni", frames.rotation, b.moments * frames.w)  # R(q(t)) I w(t)
    norm = np.linalg.norm(b.moments * frames.w[0])
    np.testing.assert_allclose(frames.momentum, (0.0, 0.0, norm), rtol=1e-15)
    assert np.max(np.abs(L - frames.momentum)) < 1e-12 * norm
    np.testing.assert_allclose(frames.w, stability.exact_omega(b, frames.w[0], frames.t),
                               rtol=0, atol=0)


def test_the_racket_turns_over_in_the_default_animation():
    frames = flip_frames(fps=5)
    spin_axis = frames.rotation[:, :, 1]  # axis 2 in space
    assert spin_axis[0, 2] > 0.99 and spin_axis[:, 2].min() < -0.99  # up, then down
    # one period of w (two flips), to the nearest frame: n = round(fps T), 1/fps apart
    assert 0.0 < stability.full_period(RACKET, frames.w[0]) - frames.t[-1] <= 1.5 / 5


def test_the_scene_draws_the_frames_rotations():
    frames = flip_frames(duration=1.0, fps=6)
    for make in (lambda: FlipScene(frames, 160),
                 lambda: FlipScene(flip_frames(stability.RigidBody.preset("book"),
                                               duration=1.0, fps=6), 160)):
        scene = make()
        for k in (0, 3, 5):
            scene.draw(k)
            R = scene.data.rotation[k]
            for i, line in enumerate(scene.arrows):
                tip = np.array(line.get_data_3d())[:, 1]
                np.testing.assert_allclose(tip, scene.length * R[:, i], atol=1e-15)
            assert f"t = {scene.data.t[k]:.2f} s" in scene.title.get_text()
    fig = frame_figure(frames, k=2, size=200)
    assert missing_units(fig) == [] and fig.get_size_inches() * fig.dpi == pytest.approx(200)


def test_ctrl_c_while_a_frame_draws_takes_effect_after_that_frame(tmp_path):
    """A real SIGINT sent while frame 2 draws: that frame is finished, no later one begun, and
    KeyboardInterrupt leaves no file and no partial file behind."""
    import os
    import signal
    import time

    from stability.plotting.animation import write_animation

    scene = FlipScene(flip_frames(duration=1.0, fps=6), 160)
    drawn = []
    draw = scene.draw

    def draw_and_interrupt(k):
        draw(k)
        if k == 2:
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.05)  # a Python handler runs at the next instructions
        drawn.append(k)

    scene.draw = draw_and_interrupt
    with pytest.raises(KeyboardInterrupt):
        write_animation(scene, tmp_path / "flip.gif", fps=6)
    assert drawn == [0, 1, 2]
    assert list(tmp_path.iterdir()) == []
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_the_top_nods_between_its_turning_tilts():
    top = HeavyTop.disk(mass=0.2, radius=0.03, length=0.05)
    frames = top_frames(top, spin=200.0, tilt=0.5, duration=0.6, fps=20, speed=1.0)
    np.testing.assert_allclose(np.linalg.norm(frames.trace, axis=1), 1.0, atol=1e-14)
    assert np.arccos(frames.axis[0, 2]) == pytest.approx(0.5, abs=1e-14)
    np.testing.assert_array_equal(frames.axis, frames.trace[::8])
    A, _, C = top.pivot_moments
    tilt = np.arccos(np.clip(frames.trace[:, 2], -1.0, 1.0))
    low, high = frames.tilt_range
    assert low == pytest.approx(0.5, abs=1e-12) and high > low + 0.2  # a visible nod
    assert tilt.min() >= low - 1e-9 and tilt.max() <= high + 1e-9
    assert tilt.max() >= high - 1e-3  # it reaches the lower turning point
    scene = TopScene(frames, 160)
    scene.draw(5)
    tip = np.array(scene.axle.get_data_3d())[:, 1]
    np.testing.assert_allclose(tip, scene.tip * frames.axis[5], atol=1e-15)
    assert missing_units(frame_figure(frames, size=200)) == []
    u1, u2, _ = nutation_roots(
        stability.heavy_top.model.tilted_starts(200.0, 0.5, 1, top=top)[0], A, C, top.mgl)
    np.testing.assert_allclose(np.cos(frames.tilt_range), (u2, u1), rtol=1e-15)


@pytest.mark.parametrize("kwargs, message", [
    ({"path": "flip.png"}, r"path must end in \.gif or \.mp4"),
    ({"path": "flip"}, r"path must end in \.gif or \.mp4"),
    ({"path": 3}, r"path must be a file name ending in \.gif or \.mp4"),
    ({"path": "no/such/folder/flip.gif"}, "the folder 'no/such/folder' does not exist: create it"),
    ({"path": "flip.gif", "fps": 0}, "fps must be finite and > 0"),
    ({"path": "flip.gif", "fps": -5.0}, "fps must be finite and > 0"),
    ({"path": "flip.gif", "duration": 0.0}, "duration must be finite and > 0"),
    ({"path": "flip.gif", "duration": -1.0}, "duration must be finite and > 0"),
    ({"path": "flip.gif", "speed": 0.0}, "speed must be finite and > 0"),
    ({"path": "flip.gif", "duration": 0.05}, "gives 1 frame.*give a longer duration"),
    ({"path": "flip.gif", "duration": 1e4}, f"more than {MAX_FRAMES}; shorten the duration"),
    ({"path": "flip.gif", "size": 50}, "size must be between 120 and 2000 pixels"),
    ({"path": "flip.gif", "axis": 4}, "axis must be 1, 2 or 3"),
    ({"path": "flip.gif", "epsilon": 0.0}, "epsilon must be finite and > 0"),
    ({"path": "flip.gif", "body": (1.0, 2.0, 3.0)}, "body must be a stability.RigidBody"),
])
def test_bad_input_to_the_flip_is_one_line_saying_what_to_do(kwargs, message, tmp_path,
                                                              monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError, match=message) as info:
        animate_flip(**kwargs)
    assert "\n" not in str(info.value)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("kwargs, message", [
    ({"tilt": 0.0}, r"tilt must be in \(0, pi\)"),
    ({"tilt": 4.0}, r"tilt must be in \(0, pi\)"),
    ({"spin": -1.0}, "spin must be finite and > 0"),
    ({"top": HeavyTop(0.1, 0.02, (1e-5, 2e-5, 2.5e-5))}, "the top must be symmetric"),
    ({"top": RACKET}, "top must be a stability.heavy_top.model.HeavyTop"),
])
def test_bad_input_to_the_top_is_one_line(kwargs, message, tmp_path):
    with pytest.raises(ValueError, match=message) as info:
        animate_top(path=tmp_path / "top.gif", **kwargs)
    assert "\n" not in str(info.value)


def test_a_frame_figure_needs_frames():
    with pytest.raises(ValueError, match="frames must come from stability.free_body.animation"):
        frame_figure(np.zeros((3, 4)))


def test_a_folder_is_not_a_file(tmp_path):
    (tmp_path / "x.gif").mkdir()
    with pytest.raises(ValueError, match="is a folder; give a file name ending in .gif"):
        animate_flip(path=tmp_path / "x.gif")


@pytest.mark.skipif(writers.is_available("ffmpeg"), reason="ffmpeg is installed here")
def test_mp4_without_ffmpeg_says_to_install_it_or_write_a_gif(tmp_path):
    with pytest.raises(ValueError, match=r"\.mp4 needs ffmpeg.*install ffmpeg.*or write a "
                                         r"\.gif"):
        animate_flip(path=tmp_path / "flip.mp4")


@pytest.mark.skipif(not writers.is_available("ffmpeg"), reason="ffmpeg is not installed")
def test_mp4_where_ffmpeg_exists(tmp_path):
    path = animate_top(path=tmp_path / "top.mp4", duration=0.1, fps=10, size=161)
    assert path.stat().st_size > 0 and b"ftyp" in path.read_bytes()[:32]


def test_the_command_writes_the_animation_and_reports_mistakes_in_one_line(tmp_path, capsys):
    out = tmp_path / "top.gif"
    assert main(["animate", "top", str(out), "--duration", "0.1", "--fps", "10",
                 "--size", "140"]) == 0
    assert "wrote" in capsys.readouterr().out and _gif(out) == ("GIF", 4, (140, 140))
    assert main(["animate", "racket", str(tmp_path / "flip.png")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "path must end in .gif or .mp4" in err


PHONE = stability.RigidBody.preset("phone")


def test_the_command_takes_a_preset_or_moments_a_spin_and_a_nudge():
    from stability.cli.main import build_parser

    parse = build_parser().parse_args
    args = parse(["animate", "phone", "p.gif", "--spin", "8", "--epsilon", "0.02", "--axis", "2"])
    assert (args.what, args.spin, args.epsilon, args.axis) == ("phone", 8.0, 0.02, 2)
    assert parse(["animate", "book", "b.gif"]).what == "book"
    args = parse(["animate", "body", "b.gif", "--moments", "1", "2", "2.5"])
    assert (args.what, args.moments) == ("body", [1.0, 2.0, 2.5])


@pytest.mark.parametrize("argv, message", [
    (["phon"], "invalid choice: 'phon'"),
    (["phone", "--spin", "-1"], "--spin: must be a finite number > 0, got '-1'"),
    (["phone", "--epsilon", "nan"], "--epsilon: must be a finite number > 0"),
    (["phone", "--axis", "4"], "--axis: invalid choice: 4"),
    (["body", "--moments", "1", "2"], "--moments: expected 3 arguments"),
    (["body"], "--moments I1 I2 I3 goes with WHAT = body"),
    (["phone", "--moments", "1", "2", "3"], "--moments I1 I2 I3 goes with WHAT = body"),
    (["body", "--moments", "1", "2", "4"], "--moments (1.0, 2.0, 4.0) violate the triangle"),
    (["top", "--epsilon", "0.1"], "--epsilon is for a flipping body, not the top"),
])
def test_bad_animate_options_are_one_line(argv, message, tmp_path, capsys):
    out = tmp_path / "x.gif"
    assert main(["animate", argv[0], str(out), *argv[1:]]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err and "physical=False" not in err
    assert not out.exists()


def test_the_command_writes_the_phone(tmp_path, capsys):
    out = tmp_path / "phone.gif"
    assert main(["animate", "phone", str(out), "--spin", "8", "--epsilon", "0.1",
                 "--duration", "0.4", "--fps", "10", "--size", "160"]) == 0
    assert "wrote" in capsys.readouterr().out and _gif(out) == ("GIF", 4, (160, 160))


def _pixels_near(rgb, color, alpha=0.9, tolerance=40.0):
    """Pixels of ``rgb`` (h, w, 3) within ``tolerance`` of ``color`` drawn at ``alpha`` on white."""
    from matplotlib.colors import to_rgb

    target = 255.0 * (alpha * np.array(to_rgb(color)) + (1.0 - alpha))
    return int((np.linalg.norm(rgb - target, axis=-1) < tolerance).sum())


def test_the_phones_screen_and_back_have_two_colours_and_turn_over():
    """Drawn to an array: where the screen (+3 side) faces the camera its colour covers the
    frame and the back's hardly shows, and the other way round half a turn later."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from stability.free_body.animation import LARGE_FACE_COLORS

    frames = flip_frames(PHONE, spin=8.0, epsilon=0.1, duration=1.0, fps=10)
    scene = FlipScene(frames, 200)
    assert [t.get_text() for t in scene.legend.get_texts()] == ["screen (+3 side)",
                                                                "back (−3 side)"]
    elev, azim = np.radians(scene.ax.elev), np.radians(scene.ax.azim)
    camera = np.array([np.cos(elev) * np.cos(azim), np.cos(elev) * np.sin(azim), np.sin(elev)])
    facing = frames.rotation[:, :, 2] @ camera  # the screen's normal towards the camera
    canvas = FigureCanvasAgg(scene.figure)
    counts = {}
    for k in (int(np.argmax(facing)), int(np.argmin(facing))):
        scene.draw(k)
        canvas.draw()
        rgb = np.asarray(canvas.buffer_rgba())[..., :3].astype(float)
        counts[k] = [_pixels_near(rgb, color) for color in LARGE_FACE_COLORS]
    (screen_up, back_up), (screen_down, back_down) = counts.values()
    assert facing.max() > 0.5 and facing.min() < -0.5
    assert screen_up > 1000 and screen_up > 5 * back_up
    assert back_down > 1000 and back_down > 5 * screen_down


def test_text_grows_with_the_frame():
    frames = flip_frames(PHONE, duration=0.4, fps=10)
    small, large = FlipScene(frames, 160), FlipScene(frames, 640)
    sizes = [(s.title.get_fontsize(), s.ax.xaxis.label.get_fontsize(),
              s.names[0].get_fontsize(), s.legend.get_texts()[0].get_fontsize(),
              s.ax.xaxis.get_major_ticks()[0].label1.get_fontsize()) for s in (small, large)]
    np.testing.assert_allclose(np.array(sizes[1]) / np.array(sizes[0]), 4.0)
    default = FlipScene(frames, 320)
    assert default.title.get_fontsize() >= 8 and min(sizes[0]) * 2 >= 6  # readable at 320 px
    top = top_frames(duration=0.1, speed=0.25, fps=10)
    assert TopScene(top, 640).title.get_fontsize() == 4 * TopScene(top, 160).title.get_fontsize()
