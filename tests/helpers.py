"""Reference solutions and checks shared by the tests."""

import contextlib
import fcntl
import functools
import importlib.util
import json
import os
import shutil
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from scipy.integrate import solve_ivp

import stability

def euler_rhs(moments):
    """Right-hand side of the torque-free Euler equations for scipy, in w."""
    I1, I2, I3 = moments

    def rhs(t, w):
        return [
            (I2 - I3) / I1 * w[1] * w[2],
            (I3 - I1) / I2 * w[2] * w[0],
            (I1 - I2) / I3 * w[0] * w[1],
        ]

    return rhs


def dop853_omega(moments, w0, t_end, rtol=1e-13, atol=1e-15):
    """w(t_end) from scipy's DOP853 at tight tolerance (an independent reference)."""
    sol = solve_ivp(euler_rhs(moments), (0.0, t_end), np.asarray(w0, float), method="DOP853",
                    rtol=rtol, atol=atol)
    return sol.y[:, -1]


def reference_omega(body, w0, t_end):
    """The best available reference for w(t_end): the exact solution, else DOP853."""
    if hasattr(stability, "exact_omega"):
        return stability.exact_omega(body, w0, np.array([t_end]))[0]
    return dop853_omega(body.moments, w0, t_end)


#: Seconds a signalled or killed run may take to end, as a guard against a hang, not a measure:
#: a compile under way finishes before Ctrl-C or SIGTERM takes effect (about 10 s quiet, and
#: several times that on a machine loaded by other work, past the 60 s once allowed).
STOP_GUARD_S = 600.0


def wait_until(predicate, proc, timeout=180.0, show_stderr=False):
    """Poll ``predicate()`` until it holds while the subprocess ``proc`` runs.

    AssertionError if ``proc`` ends first (with its stderr when ``show_stderr``, for a
    process whose stderr nobody else reads) or after ``timeout`` s (``proc`` is killed).
    """
    t0 = time.monotonic()
    while not predicate():
        if proc.poll() is not None:
            detail = f": {proc.stderr.read()}" if show_stderr else ""
            raise AssertionError(f"the process ended (exit {proc.returncode}) before the "
                                 f"state awaited{detail}")
        if time.monotonic() - t0 > timeout:
            proc.kill()
            raise AssertionError("timed out waiting for the state awaited")
        time.sleep(0.02)


@functools.cache
def _cf_suite():
    from compliance_checker.suite import CheckSuite

    with warnings.catch_warnings():  # loading every checker warns of the deprecated ioos_sos
        warnings.simplefilter("ignore", DeprecationWarning)
        CheckSuite.load_all_available_checkers()
    return CheckSuite


def cf_findings(path) -> list:
    """What the CF checker (``compliance-checker --test cf:1.10``) finds in the netCDF file
    ``path``: one line per finding, errors, warnings and notes alike, and per check that could
    not run.

    The checker takes differences of every coordinate variable to check that it is strictly
    monotonic, and fails on string labels (``rule``, ``method``): where it does, the numeric
    coordinate variables are checked here instead.
    """
    suite = _cf_suite()()
    nc = suite.load_dataset(str(path))
    try:
        groups, failed = suite.run_all(nc, ["cf:1.10"])["cf:1.10"]
        findings = [line for group in groups for line in _failures(group)]
        for check, (error, _) in failed.items():
            if check == "check_coordinate_variables_strict_monotonicity":
                findings += _not_monotonic(nc)
            else:
                findings.append(f"the check {check} could not run: {error!r}")
    finally:
        nc.close()
    return list(dict.fromkeys(findings))  # a finding is told once per variable it concerns


def _failures(result, where=()):
    """The messages of the failed leaves of a checker's result tree."""
    where = (*where, str(result.name))
    if result.children:
        return [line for child in result.children for line in _failures(child, where)]
    if result.value[0] >= result.value[1]:
        return []
    level = {3: "error", 2: "warning"}.get(result.weight, "note")
    return [f"{level}: {' / '.join(where)}: {msg}" for msg in result.msgs or ["failed"]]


def _not_monotonic(nc) -> list:
    """Numeric coordinate variables of ``nc`` that are not strictly monotonic."""
    bad = []
    for name, var in nc.variables.items():
        if var.dimensions == (name,) and var.dtype != str and var.dtype.kind in "iuf":
            step = np.diff(var[:])
            if not (np.all(step > 0) or np.all(step < 0)):
                bad.append(f"error: coordinate variable {name!r} is not strictly monotonic")
    return bad


def assert_cf_compliant(path, known=()):
    """Assert that the netCDF file ``path`` follows CF as netCDF users check it.

    The CF checker (cf:1.10) finds nothing at any priority but the ``known`` findings, and
    xarray opens the file (time decoded, as a CF reader does) without a warning, where
    ``cf_xarray`` finds every standard name and every time coordinate as the time axis.

    Parameters
    ----------
    path : path-like
    known : sequence of str
        Parts of findings the file is known to have, each with its reason where it is given;
        each must still be found, so that a fixed one is struck from the list.
    """
    import cf_xarray  # noqa: F401 (registers ds.cf)

    findings = cf_findings(path)
    unexpected = [f for f in findings if not any(k in f for k in known)]
    stale = [k for k in known if not any(k in f for f in findings)]
    assert not unexpected and not stale, (
        f"{path}: CF checker findings {unexpected}" + (f"; known but not found {stale}"
                                                       if stale else ""))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with xr.open_dataset(path, engine="netcdf4") as ds:
            names = ds.cf.standard_names
            axes = ds.cf.axes
            for name, var in ds.variables.items():
                standard = var.attrs.get("standard_name")
                if standard is not None:
                    assert name in names.get(standard, []), (path, name, standard)
                if standard == "time":
                    assert name in axes.get("T", []), (path, name)


def assert_readable(fig):
    """Every axis label of ``fig`` carries its unit, and no legend covers its data."""
    from stability.plotting.style import covered_data, missing_units

    assert missing_units(fig) == []
    assert covered_data(fig) == []


def assert_declared(path, kind):
    """Assert that the netCDF file ``path``, as :func:`stability.load` reads it, is what the
    register declares for the Dataset kind ``kind`` (:data:`stability.ensemble.schema.SCHEMAS`):
    every declared variable there (but those declared optional) with its dims, units, long name,
    type, role and flags, and no undeclared variable.
    """
    from stability.ensemble.schema import SCHEMAS

    problems = SCHEMAS[kind].problems(stability.load(path))
    assert problems == [], f"{path} departs from the {kind} Dataset's declaration: {problems}"


def one_line(capsys, argv) -> str:
    """Run ``stability ARGV`` here; assert exit 2, one line on stderr, none on stdout, and
    return that line."""
    from stability.cli import main

    status = main(argv)
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert status == 2, captured.err
    assert len(lines) == 1 and "Traceback" not in captured.err, captured.err
    assert captured.out == ""
    return lines[0]


def bad_study_line(tmp_path, capsys, kind: str, text: str) -> str:
    """Run a study file of kind ``kind`` with ``text`` below its first line; assert it fails in
    one line (:func:`one_line`) and writes no output folder, and return that line."""
    path = tmp_path / "bad.toml"
    path.write_text(f'study = "{kind}"\n' + text)
    out = tmp_path / "out"
    line = one_line(capsys, ["run", str(path), "--out", str(out), "--no-progress"])
    assert not out.exists()
    return line


def quick_study(tmp_path_factory, kind: str, **options):
    """Run ``studies/<kind>.toml`` in quick mode into a fresh folder, PNG figures only, no
    progress bar (``options``: further ``run_study`` arguments); ``(summary, folder)``."""
    from stability.study import run_study

    out = tmp_path_factory.mktemp(kind)
    summary = run_study(Path(__file__).resolve().parents[1] / "studies" / f"{kind}.toml", out,
                        quick=True, progress=False, overrides=[("output.formats", "['png']")],
                        **options)
    return summary, out


def once_per_run(tmp_path_factory, name: str, make) -> Path:
    """The folder ``make(folder)`` filled, made once in a run of the suite, by the first
    pytest-xdist worker that asks; the others wait for it and share it.

    A module-scoped fixture is made by every worker that runs a test of its module, and
    pytest-xdist splits a module between workers as it goes: an expensive one whose result
    the tests only read (a simulation's numbers, a finished study folder they copy, caches
    they copy) is made here instead. Where ``make`` fails, the next worker tries it again.
    """
    root = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        root = root.parent  # the run's folder, above each worker's own
    folder = root / f"once-{name}"
    with open(root / f"once-{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (folder / ".made").exists():
            with contextlib.suppress(FileNotFoundError):
                shutil.rmtree(folder)  # what a failed make left
            folder.mkdir()
            make(folder)
            (folder / ".made").touch()
    return folder


def invariants(moments, m):
    """Relative |m| and energy of states m (..., 3) against the first one."""
    L = np.linalg.norm(m, axis=-1)
    E = 0.5 * np.sum(m * m / moments, axis=-1)
    return np.abs(L / L[0] - 1.0), E / E[0] - 1.0


def starts(scene, n, seed=0):
    """n starts of the scene's own example (for the free body: near the intermediate axis)."""
    return scene.example(n, seed)[0]


# Signals whose growth rate and flips are known exactly, for the estimators' tests.

LAM = 0.7  # s-1
SPIN = 1.0  # rad/s


def series_dataset(w, t, axis, spin=SPIN):
    n = w.shape[0]
    return xr.Dataset(
        {"w": (("member", "time", "axis"), w, {"units": "rad s-1"})},
        coords={"member": np.arange(n), "time": t, "axis": [1, 2, 3]},
        attrs={"axis": axis, "spin": spin},
    )


def separatrix(n_members, lam=LAM, dt=0.05, t_end=60.0, seed=0):
    """One exact flip per member: the sech/tanh separatrix (literature 1.4) about axis 2.

    Perpendicular amplitude A_max sech(lam (t - t0)), spin-axis component -W tanh(lam (t - t0)):
    growth at exactly ``lam`` while small, saturation at A_max, one flip at t0.
    """
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, t_end + dt / 2, dt)
    t0 = rng.uniform(0.4 * t_end, 0.5 * t_end, n_members)
    phi = rng.uniform(0, 2 * np.pi, n_members)
    a_max = 0.6 * SPIN
    u = lam * (t[None, :] - t0[:, None])
    w = np.empty((n_members, t.size, 3))
    w[:, :, 0] = a_max * np.cos(phi)[:, None] / np.cosh(u)
    w[:, :, 2] = a_max * np.sin(phi)[:, None] / np.cosh(u)
    w[:, :, 1] = -SPIN * np.tanh(u)
    return t, w, t0, a_max


def oscillation(n_members, omega, dt=0.05, periods=12, aspect=3.0, seed=2):
    """Motion near a stable axis 3: an ellipse of aspect ``aspect`` at angular frequency omega."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, periods * 2 * np.pi / omega, dt)
    amp = 1e-4 * rng.uniform(0.5, 1.5, n_members)
    phase = rng.uniform(0, 2 * np.pi, n_members)
    arg = omega * t[None, :] + phase[:, None]
    w = np.empty((n_members, t.size, 3))
    w[:, :, 0] = amp[:, None] * np.cos(arg)
    w[:, :, 1] = aspect * amp[:, None] * np.sin(arg)
    w[:, :, 2] = SPIN
    return t, w


def summaries_from_separatrix(n_members, levels, lam=LAM, seed=3):
    """Summaries-only Dataset of the separatrix flip: passage times known in closed form."""
    rng = np.random.default_rng(seed)
    t0 = rng.uniform(20.0, 30.0, n_members)
    a_max = 0.6 * SPIN
    a0 = a_max / np.cosh(lam * t0)
    # First time a_max sech(lam (t - t0)) reaches the level, before the peak at t0.
    passage = t0[:, None] - np.arccosh(a_max / levels[None, :]) / lam
    passage = np.where(levels[None, :] <= a0[:, None], 0.0, passage)
    w0 = np.stack([a0, SPIN * np.tanh(lam * t0), np.zeros(n_members)], axis=1)
    nan = np.full(n_members, np.nan)
    return xr.Dataset(
        {
            "passage_time": (("member", "level"), passage),
            "flip_count": (("member",), np.ones(n_members)),
            "first_flip_time": (("member",), t0),
            "last_flip_time": (("member",), t0),
            "perp_crossing_count": (("member",), np.zeros(n_members)),
            "first_perp_crossing": (("member",), nan),
            "last_perp_crossing": (("member",), nan),
            "max_perp_amplitude": (("member",), np.full(n_members, a_max)),
            "w0": (("member", "axis"), w0),
        },
        coords={"member": np.arange(n_members), "level": levels, "axis": [1, 2, 3]},
        attrs={"axis": 2, "spin": SPIN},
    )


def default_dataset(kind) -> str:
    """The Dataset's file name of ``kind``'s default study (the tennis study's is named from
    the body)."""
    default = kind.schema.section("output").key("dataset").default
    return default if default is not None else kind.outputs(kind.resolve({}))[0]


def random_members(n, seed):
    """Random asymmetric bodies (canonical) and starts in both regimes, off the separatrix."""
    rng = np.random.default_rng(seed)
    a, b = np.sort(rng.uniform(0.2, 1.0, (2, n)), axis=0)
    moments = np.column_stack([a, b, (a + b) * rng.uniform(0.55, 1.0, n)])
    moments.sort(axis=1)
    w0 = rng.normal(size=(n, 3)) * rng.uniform(0.5, 5.0, (n, 1))
    return moments, w0


# The GPU kernels under numba-cuda's CUDA simulator, in a subprocess (tests/engine/gpu/__init__.py
# says why), for the GPU tests and the ``simulated`` fixture of tests/conftest.py.

GPU_SCRIPT = Path(__file__).resolve().parent / "gpu_simulated.py"
#: What a GPU must meet against the CPU loop, relative (under the simulator: bitwise).
GPU_TOLERANCE = 1e-12

needs_numba_cuda = pytest.mark.skipif(
    importlib.util.find_spec("numba_cuda") is None, reason="numba-cuda is not installed"
)


def run_gpu_script(simulator, *args):
    """The JSON ``tests/gpu_simulated.py`` prints, run with the simulator on or off."""
    root = Path(__file__).resolve().parents[1]
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_ENABLE_CUDASIM"}
    if simulator:
        env["NUMBA_ENABLE_CUDASIM"] = "1"
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(root), env.get("PYTHONPATH")]))
    done = subprocess.run([sys.executable, str(GPU_SCRIPT), *args], env=env, cwd=root,
                          capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr[-4000:]
    return json.loads(done.stdout.strip().splitlines()[-1])
