"""Bad input, one table: every mistake answered by one clear line, nothing computed or written.

Each row is a mistake a user can make and a fragment of the line that must answer it. The
command-line rows run ``python -m stability`` as a real subprocess on a study file written to
``tmp_path``: exit status 2, one line on stderr (no traceback), nothing on stdout and no file in
the output folder. The Python rows call the public API and expect a ``ValueError`` whose message
holds the fragment.

Cases covered elsewhere and not repeated here: study-file keys of the wrong type or range,
unknown keys and sections, a section given as a value, a missing or bad top-level ``study``
key, a missing file and bad ``--set``/``--members`` values (``tests/test_study_config.py``);
unknown subcommands and ``--threads`` out of range (``tests/test_cli.py``); bad bodies, starts
of the wrong shape, non-finite values, bad seeds, time-series runs above ``max_memory``
(``tests/test_body.py``, ``tests/test_ensemble.py``); hopeless steps at the level of the loop
(``tests/test_hard_cases.py``).
"""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import stability
from stability import analytic, attitude, driver, estimators, exact
from stability.body import Part
from stability.ensemble import perturbed_starts, run_ensembles

ROOT = Path(__file__).resolve().parents[1]
BODY = stability.RigidBody(1.0, 2.0, 3.0)
RACKET = stability.RigidBody.preset("tennis_racket")
RUN = dict(h=0.1, t_end=1.0)

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
    "step hopeless for the spin": (
        'study = "tennis_racket"\n[spin]\nrate = 1e6\n[integration]\nmethod = "lp2"\n',
        [], ["h = 0.002 s is too large for lp2", "choose h <="]),
}


@pytest.mark.parametrize("case", sorted(CLI))
def test_command_line(case, tmp_path):
    text, args, fragments = CLI[case]
    out = tmp_path / "out"
    path = tmp_path / "study.toml"
    path.write_text(text)
    done = subprocess.run(
        [sys.executable, "-m", "stability", "run", str(path), "--out", str(out),
         "--no-progress", *args],
        capture_output=True, text=True, cwd=tmp_path, timeout=120,
    )
    lines = done.stderr.strip().splitlines()
    assert done.returncode == 2, done.stderr
    assert len(lines) == 1 and "Traceback" not in done.stderr, done.stderr
    assert done.stdout == ""
    for fragment in fragments:
        assert fragment in lines[0], (fragment, lines[0])
    assert not out.exists() or not any(out.iterdir())
    assert sorted(p.name for p in tmp_path.iterdir()) in (["study.toml"], ["out", "study.toml"])


# --- the Python API ---------------------------------------------------------------------------

COMPLEX = np.array([1.0, 2.0, 3.0j])
#: name -> (call, fragment of the ValueError's message).
API = {
    "complex moment": (lambda: stability.RigidBody(1 + 0j, 2.0, 3.0), "I1 must be a number"),
    "boolean moment": (lambda: stability.RigidBody(True, 2.0, 3.0), "I1 must be a number"),
    "moment as a string": (lambda: stability.RigidBody("1", 2.0, 3.0), "I1 must be a number"),
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
    "complex direction": (lambda: stability.run_ensemble(BODY, 2, 1.0, 0.1, 3,
                                                         direction=[1.0, 0.0, 1j], **RUN),
                          "direction must be real numbers"),
    "levels as strings": (lambda: stability.run_ensemble(BODY, 2, 1.0, 0.1, 3,
                                                         levels=["1e-3", "1e-2"], **RUN),
                          "levels must be real numbers in rad/s, got strings"),
    "boolean epsilon": (lambda: stability.run_ensemble(BODY, 2, 1.0, True, 3, **RUN),
                        "epsilon must be a number"),
    "string step (ensemble)": (lambda: stability.run_ensemble(BODY, 2, 1.0, 0.1, 3, h="0.1",
                                                              t_end=1.0), "h must be a number"),
    "complex spin (ensemble)": (lambda: stability.run_ensemble(BODY, 2, 1j, 0.1, 3, **RUN),
                                "spin must be a number"),
    "summaries too large": (lambda: stability.run_ensemble(BODY, 2, 1.0, 0.1, 10**12,
                                                           summaries_only=True, **RUN),
                            "the summaries of 1000000000000 members would take"),
    "hopeless step (the issue's lp2 case)": (
        lambda: stability.run_ensemble(RACKET, 2, 1e6, 1e-4, 10, h=2e-3, t_end=0.2,
                                       method="lp2"),
        "h = 0.002 s is too large for lp2"),
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
    "complex quaternion": (lambda: attitude.quaternion_multiply([1j, 0, 0, 0], [1, 0, 0, 0]),
                           "a must be real numbers"),
    "boolean rotation matrix": (lambda: attitude.matrix_to_quaternion(np.eye(3, dtype=bool)),
                                "R must be real numbers, got booleans"),
    "complex signal": (lambda: estimators.zero_crossings([0.0, 1.0, 2.0], [1j, -1j, 1j]),
                       "x must be real numbers"),
}


@pytest.mark.parametrize("case", sorted(API))
def test_python_api(case):
    call, fragment = API[case]
    with pytest.raises(ValueError) as info:
        call()
    message = str(info.value)
    assert fragment in message, message
    assert "\n" not in message


def test_the_table_is_large_enough():
    assert len(CLI) + len(API) >= 45
