"""Bad input, one table: every mistake answered by one clear line, nothing computed or written.

Each row is a mistake a user can make and a fragment of the line that must answer it. The
command-line rows run the command (``stability.cli.main``, and for one of them ``python -m
stability`` in a new process) on a study file written to ``tmp_path``: exit status 2, one line
on stderr (no traceback), nothing on stdout and no file in the output folder. The Python rows
call the public API and expect a ``ValueError`` whose message holds the fragment.

The in-process rows (``stability.cli.main`` here, as nothing in them runs) cover what a study
run reads besides its options: the study file itself (not a regular file, too large, not UTF-8,
integers beyond a float's range, a byte-order mark that must parse), a run's ``manifest.json``
and ``progress.json`` damaged in every way a reader could trip on, and a dask scheduler address
that takes the connection and never answers or where a web server answers.

Cases covered elsewhere and not repeated here: study-file keys of the wrong type or range, unknown
keys and sections, a section given as a value, a missing or bad top-level ``study`` key, a missing
file and bad ``--set``/``--members`` values (``tests/study/test_config.py``); a count that no
memory holds, for every study kind (``tests/study/test_sections.py``); unknown subcommands and
``--threads`` out of range (``tests/cli/test_main.py``); bad bodies, starts of the wrong shape,
non-finite values, bad seeds, time-series runs above ``max_memory`` (``tests/core/test_body.py``,
``tests/free_body/test_spin_ensembles.py``); hopeless steps at the level of the loop
(``tests/test_hard_cases.py``).
"""

import dataclasses
import contextlib
import functools
import os
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import stability
from stability.free_body import model as analytic, propagate as driver, exact
from stability.analysis.members import zero_crossings
from stability.asteroid import model as asteroid
from stability.core import quaternions
from stability.core.body import Part
from stability.free_body.spin_ensembles import run_ensembles
from stability.ensemble.starts import perturbed_starts
from stability.registry import SCENES

from .helpers import one_line

ROOT = Path(__file__).resolve().parents[1]
BODY = stability.RigidBody(1.0, 2.0, 3.0)
RACKET = stability.RigidBody.preset("tennis_racket")
RUN = dict(h=0.1, t_end=1.0)
#: A heavy top and three starts of it, for the runs of a scene (stability.run_scene).
TOP = np.array([1.0, 1.2, 0.5, 0.0, 0.0, 1.5])
TOP_STARTS = np.tile([0.0, 0.0, 4.0, 0.3, 0.0, 0.95], (3, 1))
SCENE_RUN = dict(h=0.01, n_steps=10)
#: Starts of the relaxing tumbler (scene relaxing_tumbler).
TUMBLER_STARTS = np.array([[1.0, 1.2, 1.4], [0.5, 1.0, -1.2]])


@functools.cache
def small_run():
    """A time series of 4 members, for the estimators' options."""
    return stability.run_ensemble(BODY, 2, 1.0, 0.1, 4, h=0.1, t_end=2.0,
                                  options=stability.RunOptions(progress=False))

# --- the command line -------------------------------------------------------------------------

#: name -> (study file text, extra arguments, fragments of the one line on stderr).
CLI = {
    "kind as a list": ('study = ["tennis_racket"]\n', [], ["study must be one of", "(a list)"]),
    "kind as a table": ('[study]\nkind = "tennis_racket"\n', [], ["study must be one of",
                                                                  "(a table)"]),
    "kind as a number": ("study = 5\n", [], ["study must be one of", "got 5"]),
    "section as an array of tables": (
        'study = "tennis_racket"\n[[ensemble]]\nmembers = 5\n', [],
        ["[ensemble] must be a section"]),
    "count as a table": ('study = "tennis_racket"\n[ensemble]\nmembers = {n = 5}\n', [],
                         ["[ensemble] members must be an integer", "(a table)"]),
    "step as a list": ('study = "tennis_racket"\n[integration]\nh = [0.002]\n', [],
                       ["[integration] h must be a number", "(a list)"]),
    "seed as a date": ('study = "tennis_racket"\n[ensemble]\nseed = 1979-05-27\n', [],
                       ["[ensemble] seed must be an integer"]),
    "flag as a string": ('study = "stability_map"\n[output]\nfigures = "yes"\n', [],
                         ["[output] figures must be true or false", "(a string)"]),
    "list as a string": ('study = "work_precision"\n[scipy]\nrtols = 1e-3\n', [],
                         ["[scipy] rtols must be a list"]),
    "override into a value": ('study = "tennis_racket"\ntitle = "t"\n', ["--set", "title.x=1"],
                              ["[title] is not a section"]),
    "override of the wrong type": ('study = "tennis_racket"\n',
                                   ["--set", "integration.method=[1]"],
                                   ["method must be one of", "(a list)"]),
    "map too large for memory": ('study = "stability_map"\n[ensemble]\nmembers = 1000000000000\n',
                                 [], ["[ensemble] members", "TiB", "lower [ensemble] members"]),
    "work-precision ensemble too large": (
        'study = "work_precision"\n[tennis]\nmembers = 1000000000000\n', [],
        ["[tennis] members", "TiB", "use fewer members"]),
    "long run too large": (
        'study = "work_precision"\n[long]\nsteps = 1000000000000\nsamples = 1000000000000\n',
        [], ["[long] samples", "keep fewer samples"]),
    "time series too large": ('study = "tennis_racket"\n[ensemble]\nmembers = 1000000000000\n',
                              [], ["would take", "TiB", "save_every"]),
    "series sample named by a word other than all": (
        'study = "tennis_racket"\n[output]\nseries_members = "some"\n', [],
        ["[output] series_members", "'all'", "'some'"]),
    "negative series sample": ('study = "tennis_racket"\n[output]\nseries_members = -1\n', [],
                               ["[output] series_members", ">= 0", "-1"]),
    "series of every member of a huge ensemble": (
        'study = "tennis_racket"\n[ensemble]\nmembers = 100000000\n'
        '[output]\nseries_members = "all"\n', [],
        ["the series of 100000000 of them", "fewer [output] series_members"]),
    "asymmetric sleeping top": (
        'study = "sleeping_top"\n[top]\ncentral_moments = [2e-5, 3e-5, 4.5e-5]\n', [],
        ["[top] central_moments must have I1 = I2"]),
    "top breaking the triangle inequality": (
        'study = "sleeping_top"\n[top]\ncentral_moments = [1e-5, 1e-5, 4.5e-5]\n', [],
        ["[top] central_moments", "triangle inequality"]),
    "top of negative mass": ('study = "sleeping_top"\n[top]\nmass = -0.1\n', [],
                             ["[top] mass must be"]),
    "top with its centre of mass below the pivot": (
        'study = "sleeping_top"\n[top]\nlengths = [0.04, -0.01]\n', [], ["[top] lengths"]),
    "empty spin range": ('study = "sleeping_top"\n[spins]\nmin = 100.0\nmax = 50.0\n', [],
                         ["[spins] max must exceed"]),
    "gyroscope released hanging straight down": (
        'study = "gyroscope"\n[release]\ntilts = [30.0, 180.0]\n', [],
        ["[release] tilts must be below 180 degrees"]),
    "asymmetric gyroscope": (
        'study = "gyroscope"\n[top]\ncentral_moments = [2e-5, 3e-5, 4.5e-5]\n', [],
        ["[top] central_moments must have I1 = I2"]),
    "gyroscope keeping too many states": (
        'study = "gyroscope"\n[integration]\nsamples_per_period = 100000000\n', [],
        ["[integration] samples_per_period", "GiB", "keep fewer samples, periods"]),
    "gyroscope with no precession rate": (
        'study = "gyroscope"\n[release]\nprecession = []\n', [],
        ["[release] precession must list at least one"]),
    "equinoxes over less than the nutation needs": (
        'study = "equinoxes"\n[run]\nyears = 10.0\n', [], ["[run] years must be a number >= 40"]),
    "equinoxes with an unknown method": (
        'study = "equinoxes"\n[integration]\nmethod = "rk4"\n', [],
        ["[integration] method must be one of", "lp2", "lp4"]),
    "equinoxes with no steps a day": (
        'study = "equinoxes"\n[integration]\nsteps_per_day = 0\n', [],
        ["[integration] steps_per_day must be an integer >= 1"]),
    "Earth with no equatorial moment left": (
        'study = "earth_wobble"\n[earth]\nasymmetry = 1.0\n', [],
        ["[earth] asymmetry leaves no positive equatorial moment"]),
    "Earth offset of a negative angle": ('study = "earth_wobble"\n[wobble]\noffset = -0.3\n',
                                         [], ["[wobble] offset must be"]),
    "rolling with kinetic friction above static": (
        'study = "rolling"\n[launch]\nmu_s = 0.2\nmu_k = 0.3\n', [],
        ["[launch] mu_k = 0.3 exceeds mu_s = 0.2"]),
    "rolling with mu_k / mu_s above 1": (
        'study = "rolling"\n[incline]\nmu_k_ratio = 1.2\n', [],
        ["[incline] mu_k_ratio = 1.2 makes mu_k > mu_s"]),
    "rolling with negative friction": ('study = "rolling"\n[launch]\nmu_s = -0.1\n', [],
                                       ["[launch] mu_s must be a number >= 0"]),
    "rolling on a wall": ('study = "rolling"\n[incline]\nangle_max = 95.0\n', [],
                          ["[incline] angle_max must be inside (-90, 90) degrees"]),
    "rolling ball of no mass": ('study = "rolling"\n[launch]\nmass = 0.0\n', [],
                                ["[launch] mass must be a number > 0"]),
    "bat struck off its tip": ('study = "bat"\n[strikes]\nlast = 1.2\n', [],
                               ["[strikes] last = 1.2 m is off the baseball bat"]),
    "bat held at its centre of mass": (
        'study = "bat"\n[hands]\npivots = [0.1, 0.5645]\n', [],
        ["[hands] pivots = 0.5645", "has no centre of percussion"]),
    "bat held off its end": ('study = "bat"\n[hands]\npivots = [-0.1]\n', [],
                             ["[hands] pivots"]),
    "bat of no mass": ('study = "bat"\n[body]\nmass = 0.0\n', [],
                       ["[body] mass must be a number > 0"]),
    "twisting with an unknown preset": (
        'study = "twisting_racket"\n[body]\npreset = "kite"\n', [],
        ["[body] preset must be one of", 'got "kite"']),
    "twisting with the nudges reversed": (
        'study = "twisting_racket"\n[toss]\nepsilon_min = 0.1\nepsilon_max = 0.01\n', [],
        ["[toss] epsilon_max must be at least epsilon_min"]),
    "twisting without the attitude": (
        'study = "twisting_racket"\n[integration]\nmethod = "exact"\n', [],
        ["[integration] method = 'exact' cannot carry the attitude"]),
    "engine rule unknown": ('study = "engine_artefacts"\n[rules]\nengine = ["verlet"]\n', [],
                            ["[rules] engine has 'verlet', not an engine rule"]),
    "engine horizon not whole steps": (
        'study = "engine_artefacts"\n[rules]\nt_end = 10.001\n', [],
        ["[rules] t_end = 10.001 s is not a whole number of steps"]),
    "engine frame rate of zero": (
        'study = "engine_artefacts"\n[rules]\nframe_rates = [60.0, 0.0]\n', [],
        ["[rules] frame_rates"]),
    "moments whose products underflow": (
        'study = "tennis_racket"\n[body]\nmoments = [1e-300, 2e-300, 3e-300]\n', [],
        ["[body] moments (1e-300, 2e-300, 3e-300) kg m^2 are out of a double's range"]),
    "step hopeless for the spin": (
        'study = "tennis_racket"\n[spin]\nrate = 1e6\n[integration]\nmethod = "lp2"\n',
        [], ["[integration] h = 0.002 s is too large for lp2", "choose h <="]),
}


def command_line_case(case, tmp_path):
    """The study file of a row of CLI, written to ``tmp_path``, and the command's arguments."""
    text, args, _ = CLI[case]
    path = tmp_path / "study.toml"
    path.write_text(text)
    return ["run", str(path), "--out", str(tmp_path / "out"), "--no-progress", *args]


def assert_nothing_written(tmp_path):
    out = tmp_path / "out"
    assert not out.exists() or not any(out.iterdir())
    assert sorted(p.name for p in tmp_path.iterdir()) in (["study.toml"], ["out", "study.toml"])


@pytest.mark.parametrize("case", sorted(CLI))
def test_command_line(case, tmp_path, capsys, monkeypatch):
    """Each row through ``stability.cli.main`` here (the command without the interpreter's
    start-up, which took a second of every row); the command in a new process is the next
    test, on one row."""
    monkeypatch.chdir(tmp_path)  # nothing written in the working folder either
    line = one_line(capsys, command_line_case(case, tmp_path))
    for fragment in CLI[case][2]:
        assert fragment in line, (fragment, line)
    assert_nothing_written(tmp_path)


def test_command_line_in_a_new_process_says_the_same_line(tmp_path, capsys):
    """``python -m stability`` in a new process: exit status 2, on stderr the one line
    :func:`stability.cli.main` gives here (no warning or traceback beside it), nothing on
    stdout, nothing written. One row: every row takes the same path from the command line to
    its refusal."""
    argv = command_line_case("seed as a date", tmp_path)
    done = subprocess.run([sys.executable, "-m", "stability", *argv], capture_output=True,
                          text=True, cwd=tmp_path, timeout=120)
    assert done.returncode == 2, done.stderr
    assert done.stderr.strip().splitlines() == [one_line(capsys, argv)], done.stderr
    assert done.stdout == ""
    assert_nothing_written(tmp_path)


# --- the Python API ---------------------------------------------------------------------------

COMPLEX = np.array([1.0, 2.0, 3.0j])
#: name -> (call, fragment of the ValueError's message).
APOPHIS = (0.61, 0.965, 1.0)

def g_that_raises(x, t, p):
    """An event's g that fails at the start (a user's bug)."""
    return x[0] / 0 if x[0] != 0.0 else 1 // 0


def first_component(x, t, p):
    return x[0]


API = {
    "tumbler mode neither SAM nor LAM": (
        lambda: asteroid.spin_states(APOPHIS, 263.0, 27.38, "XAM"),
        "mode must be 'SAM' (short-axis mode) or 'LAM' (long-axis mode), got 'XAM'"),
    "tumbler period <= 0": (lambda: asteroid.spin_states(APOPHIS, -263.0, 27.38),
                            "period_psi must be finite and > 0, got -263.0"),
    "tumbler period not finite": (lambda: asteroid.spin_states(APOPHIS, 263.0, float("nan")),
                                  "period_phi must be finite and > 0, got nan"),
    "tumbler moment ratios out of order": (
        lambda: asteroid.spin_states((0.965, 0.61, 1.0), 263.0, 27.38),
        "moments must be distinct and ascending, I1 < I2 < I3"),
    "tumbler moment ratios against the triangle inequality": (
        lambda: asteroid.spin_states((0.3, 0.6, 1.0), 263.0, 27.38),
        "violate the triangle inequality I3 <= I1 + I2"),
    "shape model open": (
        lambda: asteroid.mass_properties(
            (np.eye(3).tolist() + [[0.0, 0.0, 0.0]], [[0, 1, 2], [0, 3, 1], [1, 3, 2]])),
        "mesh: the mesh is open or has edges shared by more than two facets"),
    "shape model missing": (lambda: asteroid.mass_properties("no/such/shape.obj"),
                            "no/such/shape.obj: no such file"),
    "complex moment": (lambda: stability.RigidBody(1 + 0j, 2.0, 3.0), "I1 must be a number"),
    "boolean moment": (lambda: stability.RigidBody(True, 2.0, 3.0), "I1 must be a number"),
    "moment as a string": (lambda: stability.RigidBody("1", 2.0, 3.0), "I1 must be a number"),
    # ZeroDivisionError in the kernel parameters, once run
    "moments whose products underflow": (
        lambda: stability.RigidBody(1e-300, 2e-300, 3e-300),
        "moments (1e-300, 2e-300, 3e-300) kg m^2 are out of a double's range"),
    "moments whose products overflow": (
        lambda: stability.RigidBody(1e200, 2e200, 3e200, physical=False),
        "products of two and of three moments, which must lie between 2.23e-308 and 1.8e+308"),
    "tiny moments from a tensor": (lambda: stability.RigidBody.from_tensor(np.eye(3) * 1e-200),
                                   "divide all three by one factor"),
    "complex tensor": (lambda: stability.RigidBody.from_tensor(np.eye(3) * (1 + 1j)),
                       "J must be real numbers"),
    "boolean mass": (lambda: stability.RigidBody.box(True, 1.0, 2.0, 3.0),
                     "mass must be a number"),
    "complex position": (lambda: Part.point(1.0, [0.0, 0.0, 1j]), "position of part"),
    "complex w0 (exact)": (lambda: stability.exact_omega(BODY, COMPLEX, 1.0),
                           "imaginary part would be dropped"),
    "complex times": (lambda: stability.exact_omega(BODY, [1.0, 2.0, 3.0], [1j]),
                      "t must be real numbers"),
    "w0 as strings": (lambda: stability.exact_omega(BODY, ["1", "2", "3"], 1.0),
                      "w0 must be real numbers in rad/s, got strings"),
    "complex time (many starts)": (
        lambda: exact.exact_omega_of_starts(BODY, [[1.0, 2.0, 3.0]], 1j), "t must be a number"),
    "complex w0 (flip interval)": (lambda: stability.flip_interval(BODY, COMPLEX), "w0 must be"),
    "string w0 (period)": (lambda: stability.full_period(BODY, np.array(["a", "b", "c"])),
                           "got strings"),
    "complex w0 (regime)": (lambda: exact.regime(BODY, COMPLEX), "w0 must be real numbers"),
    "complex spin": (lambda: stability.omega_squared(BODY, 2, 1 + 1j), "spin must be real"),
    "boolean spin": (lambda: stability.growth_rate(BODY, 2, True), "got booleans"),
    "complex moments array": (lambda: stability.omega_squared([1.0, 2.0, 3j], 2, 1.0),
                              "body (principal moments"),
    "complex w (energy)": (lambda: analytic.kinetic_energy(BODY, COMPLEX), "w must be real"),
    "object w (|L|)": (lambda: analytic.angular_momentum_norm(BODY, [1.0, None, 3.0]),
                       "it holds None"),
    "boolean w0 (integrate)": (lambda: stability.integrate(BODY, [True, False, True], 1.0, 0.1),
                               "got booleans"),
    "ragged w0 (integrate)": (lambda: stability.integrate(BODY, [1.0, [2.0], 3.0], 1.0, 0.1),
                              "in a regular array"),
    "complex64 w0 (integrate)": (
        lambda: stability.integrate(BODY, np.ones(3, dtype=np.complex64), 1.0, 0.1),
        "imaginary part would be dropped"),
    "complex q0": (lambda: stability.integrate(BODY, [1.0, 2.0, 3.0], 1.0, 0.1,
                                               scene="free_body_attitude", q0=[1j, 0, 0, 0]),
                   "q0 (a unit quaternion"),
    "unknown scene (integrate)": (
        lambda: stability.integrate(BODY, [1.0, 2.0, 3.0], 1.0, 0.1, scene="attitude"),
        "scene must be one of 'free_body', 'free_body_attitude'"),
    "complex horizon": (lambda: stability.integrate(BODY, [1.0, 2.0, 3.0], 1j, 0.1),
                        "t_end must be a number"),
    "string step": (lambda: stability.integrate(BODY, [1.0, 2.0, 3.0], 1.0, "0.1"),
                    "h must be a number"),
    "complex starts": (lambda: stability.run_ensemble(BODY, 2, starts=np.ones((3, 3)) * 1j,
                                                      **RUN), "starts must be real numbers"),
    "object starts": (lambda: stability.run_ensemble(
        BODY, 2, starts=np.array([[1.0, 2.0, None]], dtype=object), **RUN), "it holds None"),
    "keep as a dict": (lambda: stability.run_ensemble(BODY, 2, 1.0, 0.1, 3, keep={"save_every": 2},
                                                      **RUN), "keep must be a stability.Keep"),
    "options as a dict": (lambda: stability.run_ensemble(BODY, 2, 1.0, 0.1, 3,
                                                         options={"progress": False}),
                          "options must be a stability.RunOptions"),
    "levels as strings": (lambda: stability.run_ensemble(BODY, 2, 1.0, 0.1, 3,
                                                         keep=stability.Keep(levels=["1e-3",
                                                                                     "1e-2"]),
                                                                                     **RUN),
                          "levels must be real numbers in rad/s, got strings"),
    "boolean epsilon": (lambda: stability.run_ensemble(BODY, 2, 1.0, True, 3, **RUN),
                        "epsilon must be a number"),
    "string step (ensemble)": (lambda: stability.run_ensemble(BODY, 2, 1.0, 0.1, 3, h="0.1",
                                                              t_end=1.0), "h must be a number"),
    "complex spin (ensemble)": (lambda: stability.run_ensemble(BODY, 2, 1j, 0.1, 3, **RUN),
                                "spin must be a number"),
    "summaries too large": (lambda: stability.run_ensemble(BODY, 2, 1.0, 0.1, 10**12,
                                                           keep=stability.Keep(save_every=0),
                                                           **RUN),
                            "the summaries of 1000000000000 members would take"),
    "hopeless step (the issue's lp2 case)": (
        lambda: stability.run_ensemble(RACKET, 2, 1e6, 1e-4, 10, h=2e-3, t_end=0.2,
                                       method="lp2"),
        "h = 0.002 s is too large for lp2"),
    "spin beyond any step": (
        lambda: stability.run_ensemble(RACKET, 2, 1e300, 1e-4, 10, h=2e-3, t_end=0.2),
        "spin = 1e+300 rad/s is out of range: lp2 needs h max|w| <= 1 rad, so more than 2^53"),
    "spin beyond any step, still finite": (
        lambda: stability.run_ensemble(RACKET, 2, 1e30, 1e-4, 10, h=2e-3, t_end=0.2),
        "spin = 1e+30 rad/s is out of range"),
    "nudge beyond any step": (
        lambda: stability.run_ensemble(RACKET, 2, 10.0, 1e300, 10, h=2e-3, t_end=0.2),
        "epsilon = 1e+300 (of spin = 10 rad/s) is out of range"),
    "a body at rest, no step given (integrate)": (
        lambda: stability.integrate(RACKET, [0.0, 0.0, 0.0]),
        "a body at rest has no time scale to choose the step from; give h and t_end"),
    "a body at rest, no step given (run_ensemble)": (
        lambda: stability.run_ensemble(RACKET, 2, starts=[[0.0, 0.0, 0.0]]),
        "a body at rest has no time scale to choose the step from; give h and t_end"),
    "starts beyond any step": (
        lambda: stability.run_ensemble(RACKET, 2, starts=[[1e200, 1e200, 1.0]], h=2e-3,
                                       t_end=0.2),
        "starts of up to 1e+200 rad/s is out of range"),
    "hopeless step in a batch": (
        lambda: run_ensembles([dict(body=BODY, axis=2, spin=1.0, epsilon=0.1, members=3, **RUN),
                               dict(body=BODY, axis=2, spin=1e3, epsilon=0.1, members=3,
                                    method="rk4", **RUN)]),
        "too large for rk4"),
    "complex direction (starts)": (lambda: perturbed_starts(2, 1.0, 0.1, 3,
                                                            direction=[1j, 0.0, 1.0]),
                                   "direction must be real numbers"),
    "members as a string": (lambda: stability.ensemble_memory("10", 0),
                            "members must be a whole number"),
    "complex moments (propagate)": (
        lambda: driver.propagate("rk4", [1.0, 2.0, 3j], [[1.0, 2.0, 3.0]], 0.1, 10),
        "moments must be real numbers"),
    "string m0 (propagate)": (
        lambda: driver.propagate("rk4", [1.0, 2.0, 3.0], [["1", "2", "3"]], 0.1, 10),
        "m0 must be real numbers"),
    "complex quaternion": (lambda: quaternions.quaternion_multiply([1j, 0, 0, 0], [1, 0, 0, 0]),
                           "a must be real numbers"),
    "boolean rotation matrix": (lambda: quaternions.matrix_to_quaternion(np.eye(3, dtype=bool)),
                                "R must be real numbers, got booleans"),
    "complex signal": (lambda: zero_crossings([0.0, 1.0, 2.0], [1j, -1j, 1j]),
                       "x must be real numbers"),
    "store as a number": (
        lambda: stability.run_ensemble(BODY, 2, 1.0, 0.1, 4,
                                       options=stability.RunOptions(store=123), **RUN),
        "store must be a folder path (a str or pathlib.Path), got 123"),
    "starts without rows": (
        lambda: stability.run_ensemble(BODY, 2, starts=np.ones((0, 3))),
        "starts has no rows: give one start w0 (3 numbers, rad/s) per member"),
    "progress as a word": (
        lambda: stability.run_ensemble(BODY, 2, 1.0, 0.1, 4,
                                       options=stability.RunOptions(progress="yes"), **RUN),
        "progress must be True, False or None (shown for long runs), got 'yes'"),
    "progress as a word (batch)": (
        lambda: run_ensembles([dict(body=BODY, axis=2, spin=1.0, members=3, **RUN)],
                              progress="no"),
        "progress must be True, False or None"),
    "progress as a number (scene)": (
        lambda: stability.run_scene("heavy_top", "lp2", TOP_STARTS, TOP,
                                    options=stability.RunOptions(progress=1),
                                    **SCENE_RUN),
        "progress must be True, False or None"),
    # the estimators' options (the Dataset accessor and the functions behind it)
    "fit window starting below the start": (
        lambda: small_run().stability.measured_growth_rate(low_factor=0.0),
        "low_factor must be >= 1 (the fit starts at low_factor times the initial amplitude), "
        "got 0.0"),
    "fit window as a string": (
        lambda: small_run().stability.measured_growth_rate(low_factor="x"),
        "low_factor must be a number, got 'x'"),
    "fit window ending beyond the spin": (
        lambda: small_run().stability.measured_omega_squared(high_fraction=2.0),
        "high_fraction must be in (0, 1]"),
    "analytic Omega^2 not a number": (
        lambda: small_run().stability.measured_omega_squared(analytic=float("nan")),
        "analytic must be finite (Omega^2 in s-2)"),
    "body as a tuple (flip statistics)": (
        lambda: small_run().stability.flip_statistics(body=(1.0, 2.0, 3.0)),
        "body must be a stability.RigidBody, got tuple"),
    "Dataset naming no axis": (
        lambda: small_run().assign_attrs(axis="banana").stability.member_regimes(),
        "the Dataset's attribute axis must be 1, 2 or 3 (the principal axis of the spin), got "
        "'banana'; pass axis= to override it"),
    "spin as a string (estimators)": (
        lambda: small_run().stability.member_regimes(spin="fast"),
        "spin must be a number in rad/s, got 'fast'"),
    # a run of any scene (stability.run_scene), refused before any work
    "time series of the start alone (scene)": (
        lambda: stability.run_scene("heavy_top", "lp2", TOP_STARTS, TOP, h=0.01, n_steps=10,
                                    save_every=30),
        "save_every = 30 is more than the 10 steps of the longest group, so the series would "
        "hold the start alone"),
    "no members (scene)": (
        lambda: stability.run_scene("heavy_top", "lp2", np.ones((0, 6)), TOP, **SCENE_RUN),
        "x0 has no rows: give at least one member, a row of 6 numbers"),
    "starts of the wrong width (scene)": (
        lambda: stability.run_scene("heavy_top", "lp2", np.ones((3, 5)), TOP, **SCENE_RUN),
        "x0 must have shape (members, 6) for scene 'heavy_top', one column per component "
        "(m1, m2, m3, g1, g2, g3), got shape (3, 5)"),
    "unknown method (scene)": (
        lambda: stability.run_scene("heavy_top", "lp8", TOP_STARTS, TOP, **SCENE_RUN),
        "method 'lp8' does not run scene 'heavy_top'; methods that do: rk4, lp2, lp4"),
    "unknown scene": (lambda: stability.run_scene("heavy_tops", "lp2", TOP_STARTS, TOP,
                                                  **SCENE_RUN), "unknown scene 'heavy_tops'"),
    "negative members (scene)": (
        lambda: stability.run_scene("heavy_top", "lp2", TOP_STARTS, [TOP, TOP], sizes=[4, -1],
                                    **SCENE_RUN),
        "sizes must be whole numbers of members >= 0, got [4, -1]"),
    "members that do not add up (scene)": (
        lambda: stability.run_scene("heavy_top", "lp2", TOP_STARTS, [TOP, TOP], sizes=[1, 1],
                                    **SCENE_RUN), "sizes add up to 2 members but x0 has 3 rows"),
    "parameter set the scene refuses": (
        lambda: stability.run_scene("heavy_top", "lp2", TOP_STARTS, np.ones(3), **SCENE_RUN),
        "parameter set 0 of scene 'heavy_top' (lp2): a top is described by 6 numbers"),
    "relaxing tumbler that gains energy": (
        lambda: stability.run_scene("relaxing_tumbler", "rk4", TUMBLER_STARTS,
                                    np.array([1.0, 2.0, 3.0, -0.1]), **SCENE_RUN),
        "parameter set 0 of scene 'relaxing_tumbler' (rk4): alpha must be >= 0 (it removes "
        "energy; 0 is the free body), got -0.1"),
    "relaxing tumbler's moments out of order": (
        lambda: stability.run_scene("relaxing_tumbler", "rk4", TUMBLER_STARTS,
                                    np.array([2.0, 1.0, 3.0, 0.1]), **SCENE_RUN),
        "the moments (I1, I2, I3) must be positive and ascending (the canonical frame), got "
        "(2.0, 1.0, 3.0)"),
    "relaxing tumbler without alpha": (
        lambda: stability.run_scene("relaxing_tumbler", "rk4", TUMBLER_STARTS, np.ones(3),
                                    **SCENE_RUN),
        "a relaxing tumbler's parameters are 4 numbers (I1, I2, I3, alpha), got 3"),
    "relaxing tumbler's alpha not finite": (
        lambda: stability.run_scene("relaxing_tumbler", "rk4", TUMBLER_STARTS,
                                    np.array([1.0, 2.0, 3.0, np.nan]), **SCENE_RUN),
        "a relaxing tumbler's parameters must be finite, got (1.0, 2.0, 3.0, nan)"),
    "damping time of a body without one major axis": (
        lambda: asteroid.damping_coefficient((1.0, 2.0, 2.0), 1.0, 10.0),
        "the moments (1.0, 2.0, 2.0) have no single major axis (I2 = I3): a wobble about it "
        "does not die out"),
    "damping time shorter than a wobble's turn": (
        lambda: asteroid.damping_coefficient((1.0, 1.999, 2.0), 1.0, 10.0),
        "damping_time = 10 s is too short for these moments and |L|: the wobble would no "
        "longer turn; give more than"),
    "wobble of a body of two moments": (
        lambda: asteroid.wobble_rate((1.0, 2.0), 0, 1.0, 0.1),
        "moments must be three numbers (I1, I2, I3), got 2"),
    "wobble about a boolean axis": (lambda: asteroid.wobble_rate((1.0, 2.0, 3.0), True, 1.0, 0.1),
                                    "axis must be 0, 1 or 2 (canonical, I1 <= I2 <= I3), got True"),
    "damping time <= 0": (lambda: asteroid.damping_coefficient((1.0, 2.0, 3.0), 1.0, -10.0),
                          "damping_time must be finite and > 0 in s, got -10.0"),
    "wobble about no axis": (lambda: asteroid.wobble_rate((1.0, 2.0, 3.0), 3, 1.0, 0.1),
                             "axis must be 0, 1 or 2 (canonical, I1 <= I2 <= I3), got 3"),
    "wobble of a body at rest": (lambda: asteroid.wobble_rate((1.0, 2.0, 3.0), 0, 0.0, 0.1),
                                 "momentum must be finite and > 0 in kg m2 s-1, got 0.0"),
    "time series over two steps (scene)": (
        lambda: stability.run_scene("heavy_top", "lp2", TOP_STARTS, [TOP, TOP], sizes=[2, 1],
                                    h=[0.01, 0.02], n_steps=10, save_every=2),
        "needs one step for every group"),
    "tracking in unknown units (scene)": (
        lambda: stability.run_scene(replace(SCENES["heavy_top"], tracked_units=""), "lp2",
                                    TOP_STARTS, TOP, axes=[2, 0, 1], **SCENE_RUN),
        "say in tracked_units= the units of what scene 'heavy_top' tracks (its observe), or "
        "declare them in the scene (define_scene(..., tracked_units=))"),
    "parameters by a wrong name (scene)": (
        lambda: stability.run_scene("sphere_damper", "rk4", np.ones((2, 6)),
                                    {"I1": 1.0, "I2": 2.0, "I3": 3.0, "J": 0.2}, **SCENE_RUN),
        "parameter set 0: scene 'sphere_damper': the parameter set must name exactly I1, I2, "
        "I3, J, c (or give those numbers in that order); missing: c"),
    "event whose g raises (scene)": (
        lambda: stability.run_scene("heavy_top", "lp2", TOP_STARTS, TOP, **SCENE_RUN,
                                    events=stability.Event(g_that_raises)),
        "event 'g_that_raises': g(x, t, p) raised ZeroDivisionError"),
    "event g not at the top level (scene)": (
        lambda: stability.run_scene("heavy_top", "lp2", TOP_STARTS, TOP, **SCENE_RUN,
                                    events=stability.Event(lambda x, t, p: x[0])),
        "must be defined at the top level of its module (tests.test_bad_input) under its own "
        "name, so the compiled loop can import it"),
    "two events of one name (scene)": (
        lambda: stability.run_scene("heavy_top", "lp2", TOP_STARTS, TOP, **SCENE_RUN,
                                    events=[stability.Event(first_component)] * 2),
        "two events are named 'first_component'; give them names of their own"),
    "run beyond memory (scene)": (
        lambda: stability.run_scene("heavy_top", "lp2", TOP_STARTS, TOP, h=0.01,
                                    n_steps=10**12, save_every=1),
        "a run of 3 members of scene 'heavy_top' keeping 1000000000001 states of 6 numbers "
        "each would take about"),
}


@pytest.mark.parametrize("case", sorted(API))
def test_python_api(case):
    call, fragment = API[case]
    with pytest.raises(ValueError) as info:
        call()
    message = str(info.value)
    assert fragment in message, message
    assert "\n" not in message
    assert " inf " not in message and " nan " not in message, message


def test_save_to_a_folder_says_what_to_do(tmp_path):
    folder = tmp_path / "run.nc"
    folder.mkdir()
    ds = stability.run_ensemble(BODY, 2, 1.0, 0.1, 2, keep=stability.Keep(save_every=0), **RUN)
    for overwrite in (False, True):
        with pytest.raises(ValueError) as info:
            stability.save(ds, folder, overwrite=overwrite)
        message = str(info.value)
        assert f"{folder} is a folder" in message and str(folder / "run.nc") in message
        assert "never replaced, not even with overwrite=True" in message
        assert "pass overwrite=True" not in message
    assert list(folder.iterdir()) == []


def test_the_table_is_large_enough():
    assert len(CLI) + len(API) >= 45


# --- in process: the file itself, a run's work folder, the scheduler ------------------------------
#
# Refused before any work, so ``stability.cli.main`` runs in this process (no interpreter to
# start): exit status 2, one line on stderr naming the file or key, nothing on stdout.

#: A whole number beyond a float's range (about 1.8e308), written as a TOML literal.
HUGE = "1" + "0" * 400


def study_file(tmp_path, text) -> Path:
    path = tmp_path / "study.toml"
    path.write_bytes(text if isinstance(text, bytes) else text.encode())
    return path


#: name -> (study file text, or a callable(tmp_path) -> path; fragments of the line).
FILES = {
    "count beyond a float": ('study = "tennis_racket"\n[ensemble]\nmembers = ' + HUGE + "\n",
                             ["study.toml: [ensemble] members must be an integer",
                              "got an integer of 401 digits, beyond the range of a number"]),
    "seed beyond a float": ('study = "tennis_racket"\n[ensemble]\nseed = ' + HUGE + "\n",
                            ["[ensemble] seed must be", "beyond the range"]),
    "horizon beyond a float": ('study = "tennis_racket"\n[integration]\nt_end = ' + HUGE + "\n",
                               ["[integration] t_end must be a number", "beyond the range"]),
    "step list with a number beyond a float": (
        'study = "work_precision"\n[scipy]\nrtols = [1e-3, ' + HUGE + "]\n",
        ["[scipy] rtols must be", "an integer of 401 digits"]),
    "integer too long to read": ('study = "tennis_racket"\n[ensemble]\nmembers = 1'
                                 + "0" * 5000 + "\n",
                                 ["study.toml: holds an integer of more than"]),
    "not UTF-8": (b'study = "tennis_racket"\ntitle = "\xff"\n', ["study.toml: is not UTF-8"]),
    "larger than 1 MiB": (lambda tmp: study_file(tmp, "#" * (2**20 + 1)),
                          ["study.toml: is larger than the 1 MiB a study file may have"]),
    "a folder": (lambda tmp: tmp, ["is a folder, not a study file"]),
    "a FIFO": (lambda tmp: (os.mkfifo(tmp / "fifo.toml"), tmp / "fifo.toml")[1],
               ["fifo.toml: is a FIFO (named pipe), not a study file"]),
    "a device that never ends": (lambda tmp: Path("/dev/zero"),
                                 ["/dev/zero: is a character device, not a study file"]),
}


#: Cases that would never end if they were read: run in a process with a time limit and 2 GiB
#: of address space, so that such a read fails the test instead of stopping the suite or
#: filling the machine's memory.
UNENDING = {"a FIFO", "a device that never ends"}


def one_line_in_a_process(argv) -> str:
    """:func:`one_line` in a subprocess under a time and memory limit."""
    import resource

    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (2 * 2**30, 2 * 2**30))

    done = subprocess.run([sys.executable, "-m", "stability", *argv], capture_output=True,
                          text=True, cwd=ROOT, timeout=60, preexec_fn=limit)
    lines = done.stderr.strip().splitlines()
    assert done.returncode == 2, done.stderr[-2000:]
    assert len(lines) == 1 and "Traceback" not in done.stderr, done.stderr[-2000:]
    assert done.stdout == ""
    return lines[0]


@pytest.mark.parametrize("case", sorted(FILES))
def test_study_file_refused_before_it_is_read(case, tmp_path, capsys):
    given, fragments = FILES[case]
    path = given(tmp_path) if callable(given) else study_file(tmp_path, given)
    if not path.exists():
        pytest.skip(f"{path} does not exist here")
    argv = ["run", str(path), "--dry-run"]
    line = one_line_in_a_process(argv) if case in UNENDING else one_line(capsys, argv)
    for fragment in fragments:
        assert fragment in line, (fragment, line)


def test_override_beyond_a_float_names_its_key(capsys):
    line = one_line(capsys, ["run", str(ROOT / "studies" / "tennis_racket.toml"), "--dry-run",
                             "--set", f"integration.h={HUGE}"])
    assert "(--set integration.h): [integration] h must be a number" in line, line


def test_study_file_with_a_byte_order_mark_parses(tmp_path, capsys):
    from stability.cli import main

    path = study_file(tmp_path, "\ufeffstudy = 'tennis_racket'\n[ensemble]\nmembers = 7\n"
                      .encode("utf-8"))
    assert main(["run", str(path), "--dry-run"]) == 0
    assert "members = 7" in capsys.readouterr().out


def work_folder(tmp_path) -> Path:
    """The work folder a stopped tennis-racket run leaves in ``tmp_path/out``, with a real
    manifest (written by ChunkStore) and no chunk done."""
    from stability.output.store import ChunkStore

    work = tmp_path / "out" / ".stability-work-tennis_racket"
    ChunkStore(work, {"run_ensemble": {"spin": 10.0}}, members=10, chunk_members=4)
    return work


def damaged(**fields):
    """A change to a real manifest: its fields replaced (None: the field removed)."""
    def change(manifest):
        manifest.update(fields)
        return manifest
    return change


#: name -> (what manifest.json holds: bytes, or a change to the real one; fragment).
MANIFESTS = {
    "a list": (b"[]", "(it holds a list, not an object)"),
    "a number": (b"3", "(it holds 3 (a number), not an object)"),
    "null": (b"null", "(it holds null, not an object)"),
    "not UTF-8": (b'{"layout": "\xff"}', "(UnicodeDecodeError"),
    "chunks as a string": (damaged(chunks="x"), "('chunks' is \"x\" (a string))"),
    "negative members": (damaged(members=-1), "('members' is -1, below 0)"),
    "fingerprint as a number": (damaged(fingerprint=3), "('fingerprint' is 3 (a number))"),
    "attrs as a list": (damaged(attrs=[]), "('attrs' is a list)"),
    "chunks that do not add up": (damaged(chunks=7), "but 10 members in chunks of 4 make 3"),
    "another layout": (damaged(layout=99), "is of store layout 99, written by another version"),
}


@pytest.mark.parametrize("case", sorted(MANIFESTS))
@pytest.mark.parametrize("command", ["run --resume", "run", "status"])
def test_damaged_manifest_is_named_in_one_line(case, command, tmp_path, capsys):
    import json

    work = work_folder(tmp_path)
    content, fragment = MANIFESTS[case]
    manifest = work / "manifest.json"
    if callable(content):
        content = json.dumps(content(json.loads(manifest.read_text()))).encode()
    manifest.write_bytes(content)
    tennis = str(ROOT / "studies" / "tennis_racket.toml")
    argv = {"run --resume": ["run", tennis, "--quick", "--out", str(tmp_path / "out"),
                             "--no-progress", "--resume"],
            "run": ["run", tennis, "--quick", "--out", str(tmp_path / "out"), "--no-progress"],
            "status": ["status", str(tmp_path / "out")]}[command]
    line = one_line(capsys, argv)
    assert f"{manifest}" in line and fragment in line, line
    assert manifest.read_bytes() == content  # nothing touched what it could not read


@pytest.mark.parametrize("content", [b"[]", b"null", b"\xff\xfe",
                                     b'{"state": ["x"], "chunks_done": "x", "pid": 1e400, '
                                     b'"members_per_second": -1, "updated": "a\\nb"}'])
def test_damaged_progress_is_shown_and_never_trusted(content, tmp_path, capsys):
    from stability.cli import main
    from stability.output.store import ChunkStore, read_progress

    work = work_folder(tmp_path)
    (work / "progress.json").write_bytes(content)
    assert main(["status", str(tmp_path / "out")]) == 0
    captured = capsys.readouterr()
    assert f"{work / 'progress.json'} is damaged" in captured.out, captured.out
    assert captured.err == "" and "a\nb" not in captured.out
    progress = read_progress(work)
    assert progress is None or progress == {}
    # a stopped run with such a file is resumed: the file does not say it is running
    ChunkStore(work, {"run_ensemble": {"spin": 10.0}}, members=10, chunk_members=4,
               resume=True)


#: ``python -m stability`` with the connect timeout of stability.output.stream.scheduler_client
#: at 1 s instead of 10 (plus the 2 s its answer may take): the wait is the same code, shorter.
QUICK_CONNECT = ("import sys; from stability.output import stream; "
                 "stream.scheduler_client.__defaults__ = (1.0,); "
                 "from stability.cli import console; sys.argv[0] = 'stability'; "
                 "raise SystemExit(console())")


def test_scheduler_that_never_answers_is_given_up_in_seconds(tmp_path):
    """A server that takes the TCP connection and never speaks dask (another service on the
    port): one line within the connect timeout, not minutes of waiting. A subprocess, so that
    a wait that never ends fails the test instead of hanging the suite; its connect timeout
    is 1 s (:data:`QUICK_CONNECT`), so that the test does not wait 12 s for the line."""
    import socket
    import threading

    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    taken = []

    def accept():
        with contextlib.suppress(OSError):
            while True:
                taken.append(server.accept()[0])  # and never a byte back

    threading.Thread(target=accept, daemon=True).start()
    address = f"tcp://127.0.0.1:{server.getsockname()[1]}"
    out = tmp_path / "out"
    try:
        done = subprocess.run(
            [sys.executable, "-c", QUICK_CONNECT, "run",
             str(ROOT / "studies" / "tennis_racket.toml"), "--quick", "--out", str(out),
             "--no-progress", "--scheduler", address],
            capture_output=True, text=True, cwd=ROOT, timeout=60)
    finally:
        server.close()
        for conn in taken:
            conn.close()
    assert "within 3 s" in done.stderr  # the shortened timeout was the one that ran out
    assert taken, "the server was never reached"
    lines = done.stderr.strip().splitlines()
    assert done.returncode == 2 and len(lines) == 1, done.stderr
    assert f"cannot reach the dask scheduler at {address}" in lines[0], lines[0]
    assert "did not answer as a dask scheduler" in lines[0], lines[0]
    assert not out.exists() or not any(out.iterdir())


def test_scheduler_address_where_a_web_server_answers_is_one_line(tmp_path, capsys):
    """An HTTP server on the port, answering the dask handshake with "HTTP/1.1 400" at once (as
    servers that refuse a binary request line do): dask read "HTTP/1.1" as a frame count and
    asked for 3.07 EiB, a MemoryError traceback. One line now, nothing written."""
    import http.server
    import threading

    class Refusing(http.server.BaseHTTPRequestHandler):
        protocol_version = "HTTP/1.1"

        def handle_one_request(self):  # the request line is binary: refused as it arrives
            self.connection.recv(65536)
            self.command, self.request_version, self.requestline = "", "HTTP/1.1", ""
            self.send_error(400)
            self.close_connection = True

        def log_message(self, *args):
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Refusing)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    address = f"tcp://127.0.0.1:{server.server_address[1]}"
    out = tmp_path / "out"
    try:
        line = one_line(capsys, ["run", str(ROOT / "studies" / "tennis_racket.toml"), "--quick",
                                 "--out", str(out), "--no-progress", "--scheduler", address])
    finally:
        server.shutdown()
        server.server_close()
    assert line.startswith(f"stability run: error: cannot reach the dask scheduler at {address} "
                           "(it answered, but not as a dask scheduler does"), line
    assert "web server" in line, line
    assert not out.exists() or not any(out.iterdir())


def test_changed_spin_on_resume_leads_with_the_change(tmp_path):
    store = tmp_path / "s"
    run = dict(body=BODY, axis=2, epsilon=0.1, members=8, h=0.1, t_end=1.0, method="rk4",
               keep=stability.Keep(save_every=0),
               options=stability.RunOptions(store=store, chunk_members=4, progress=False))
    stability.run_ensemble(spin=1.0, **run)
    with pytest.raises(ValueError) as info:
        stability.run_ensemble(spin=1.5, **{**run, "options": dataclasses.replace(
            run["options"], resume=True)})
    message = str(info.value)
    assert message.startswith(f"the settings changed since the run kept in {store} was started: "
                              "run_ensemble.spin 1.0 there, 1.5 here; "), message
    assert "run_ensemble.levels differs too" in message and "[1e-06" not in message
    assert "\n" not in message


@pytest.mark.parametrize("rate", ["1e300", "1e308"])
def test_spin_beyond_any_step_is_named_not_computed(tmp_path, capsys, rate):
    """Refused by the study file's check, naming its key (the line said "spin = ...", the
    argument of run_ensemble, not the key to change)."""
    line = one_line(capsys, ["run", str(ROOT / "studies" / "tennis_racket.toml"), "--quick",
                             "--out", str(tmp_path / "out"), "--no-progress",
                             "--set", f"spin.rate={rate}"])
    assert (f"(--set spin.rate): [spin] rate = {float(rate):g} rad/s is out of range: rk4 needs "
            "h max|w| <= 2 rad") in line, line
    assert line.endswith("; use a smaller rate"), line
    assert "inf" not in line and "nan" not in line and "h <= 0 s" not in line, line
    assert not (tmp_path / "out").exists()

