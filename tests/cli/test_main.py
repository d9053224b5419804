"""The ``stability`` command: run (quick, end to end), methods, studies, user errors (bench:
``tests/cli/test_bench.py``)."""

import subprocess
import sys
import tomllib
from pathlib import Path

import netCDF4
import numpy as np
import pytest

import stability
from stability.cli import main
from stability.study import STUDIES, load_study
from stability.study.config import toml_text
from stability.free_body.tennis_racket.study import FIGURES

from ..helpers import assert_cf_compliant, assert_declared, one_line

ROOT = Path(__file__).resolve().parents[2]
TENNIS = ROOT / "studies" / "tennis_racket.toml"


def test_methods_lists_every_registered_method(capsys):
    assert main(["methods"]) == 0
    out = capsys.readouterr().out.splitlines()
    rows = {line.split()[0]: line for line in out[2:] if line.strip()}
    assert set(stability.METHODS) <= set(rows)
    for name, spec in stability.METHODS.items():
        facts = spec.describe()
        assert str(facts["order"]) == rows[name].split()[1]
        assert facts["title"] in rows[name]


def test_studies_lists_kinds_and_their_keys(capsys):
    assert main(["studies"]) == 0
    assert "tennis_racket" in capsys.readouterr().out
    assert main(["studies", "tennis_racket"]) == 0
    out = capsys.readouterr().out
    for key in ("members = 10000", "epsilon = 0.0001", 'method = "rk4"', "fit_below = 0.03"):
        assert key in out
    assert main(["studies", "nope"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == ("stability studies: error: unknown study kind 'nope'; known kinds: "
                   + ", ".join(STUDIES))


def test_studies_kind_lists_every_quick_override(capsys):
    """Each kind's ``--quick`` keys are listed with the defaults they replace; the Explorer
    study's (whose quick run changes the physics) says so and why."""
    for name, kind in STUDIES.items():
        assert main(["studies", name]) == 0
        out = " ".join(capsys.readouterr().out.replace("#", " ").split())
        for section, values in kind.quick.items():
            for key, value in values.items():
                default = kind.schema.section(section).key(key).default
                assert f"{section}.{key} = {toml_text(value)} (default: {toml_text(default)})" \
                    in out, (name, section, key)
    assert main(["studies", "explorer"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "damper.inertia = 0.001 (default: 0.0001)" in out
    assert "whips.mass = 0.4 (default: 0.02)" in out
    assert "the physics changes too" in out and "not Explorer 1's" in out


def test_usage_errors_are_one_line(capsys, tmp_path):
    assert main(["frobnicate"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "invalid choice" in err
    assert main(["run", str(TENNIS), "--threads", "999", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "threads must be a whole number from 1 to" in err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("option, value, fragment", [
    ("--fps", "1e308", "gives over 1e308 frames, more than 1000"),  # was OverflowError
    ("--duration", "1e308", "gives over 1e308 frames, more than 1000"),
    ("--fps", "1e6", "gives 3874358 frames, more than 1000"),
    ("--speed", "1e-308", "frames, more than 1000; shorten the duration"),
    ("--fps", "0", "fps must be finite and > 0"),
    ("--fps", "nan", "fps must be finite and > 0"),
    ("--fps", "-1", "fps must be finite and > 0"),
    ("--fps", "inf", "fps must be finite and > 0"),
])
def test_absurd_animation_numbers_are_one_usage_line(option, value, fragment, capsys,
                                                     tmp_path):
    out = tmp_path / "flip.gif"
    line = one_line(capsys, ["animate", "racket", str(out), option, value])
    assert line.startswith("stability animate: error: ") and fragment in line, line
    assert not out.exists()


@pytest.mark.parametrize("value", ["", "  "])
def test_an_empty_scheduler_is_a_usage_error_not_a_run_here(value, capsys, tmp_path):
    line = one_line(capsys, ["run", str(TENNIS), "--quick", "--out", str(tmp_path / "o"),
                             "--scheduler", value])
    assert "--scheduler: must be 'dask'" in line and "leave --scheduler out" in line, line
    assert not (tmp_path / "o").exists()


def test_python_dash_m_runs_the_same_command():
    done = subprocess.run(
        [sys.executable, "-m", "stability", "--version"], capture_output=True, text=True,
        cwd=ROOT, timeout=120,
    )
    assert done.returncode == 0
    assert done.stdout.strip() == f"stability {stability.__version__}"


def test_dry_run_prints_the_resolved_config(capsys):
    assert main(["run", str(TENNIS), "--quick", "--members", "12", "--dry-run"]) == 0
    printed = tomllib.loads(capsys.readouterr().out)
    assert printed == load_study(TENNIS, quick=True, members=12)[1]
    assert printed["ensemble"]["members"] == 12


def test_quick_run_writes_dataset_and_figures(tmp_path, capsys):
    out = tmp_path / "quick"
    args = ["run", str(TENNIS), "--quick", "--members", "64", "--out", str(out), "--no-progress",
            "--threads", "1"]
    assert main(args) == 0
    printed = capsys.readouterr().out
    for row in ("growth rate sqrt(-Omega^2) (analytic)", "growth rate fitted",
                "median flip interval, exact 2K/nu", "max |relative energy error|",
                "member-steps per second"):
        assert row in printed
    assert "--quick sets" in printed  # what quick changed, and what --members made of it
    assert "ensemble.members = 256 (the file: 10000), then 64 by the options" in printed
    assert "integration.t_end = 5.0 (the file: 10.0)" in printed
    written = sorted(p.name for p in out.iterdir())
    expected = ["config.toml", "tennis_racket.nc"] + [
        f"{stem}.{fmt}" for stem in FIGURES for fmt in ("png", "pdf")
    ]
    assert written == sorted(expected)

    ds = stability.load(out / "tennis_racket.nc")
    assert ds.w.dims == ("series_member", "time", "axis") and ds.sizes["member"] == 64
    assert ds.sizes["series_member"] == 64  # the default sample of 256 holds every member
    assert ds.w.attrs["units"] == "rad s-1"
    config = tomllib.loads(ds.attrs["config_toml"])
    assert config == load_study(TENNIS, quick=True, members=64)[1]
    assert config == tomllib.loads((out / "config.toml").read_text())
    assert "stability run" in ds.attrs["history"]
    assert ds.attrs["study"] == "tennis_racket" and ds.attrs["numba_num_threads"] == 1
    for name in ("exact_flip_interval", "flip_interval_asymptote", "perp_amplitude_median"):
        assert ds[name].attrs["units"] in ("s", "rad s-1")
    ok = ds.status == 0
    assert int(ok.sum()) == 64
    # Measured flip intervals agree with the exact 2K/nu: rk4 at h = 2 ms, crossings located
    # within the step (measured: 5e-7 relative over 10,000 members).
    rel = abs(ds.mean_flip_interval - ds.exact_flip_interval) / ds.exact_flip_interval
    assert float(rel.max()) < 1e-5
    assert_cf_compliant(out / "tennis_racket.nc")
    assert_declared(out / "tennis_racket.nc", "tennis_racket")

    # A second run refuses to overwrite, before running anything; --overwrite replaces.
    before = {p.name: p.stat().st_mtime_ns for p in out.iterdir()}
    assert main(args) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "already exists; pass --overwrite" in err
    assert {p.name: p.stat().st_mtime_ns for p in out.iterdir()} == before
    # ... here with the Dataset compressed by zstd: the same numbers, another filter
    assert main(args + ["--overwrite", "--set", "output.figures=false",
                        "--set", "output.compression='zstd'"]) == 0
    with netCDF4.Dataset(out / "tennis_racket.nc") as nc:
        assert nc["passage_time"].filters()["zstd"] and not nc["passage_time"].filters()["zlib"]
    again = stability.load(out / "tennis_racket.nc")
    for name in ("w", "passage_time", "member_growth_rate", "perp_amplitude_count", "status"):
        np.testing.assert_array_equal(again[name].values, ds[name].values)


def test_the_attitude_scene_adds_each_members_attitude_to_the_same_w(tmp_path, capsys):
    """scene = "free_body_attitude": the w of every member bitwise that of scene "free_body"
    (w's kernel does not read q), and each member's attitude close to the exact one (rk4 at
    h = 2 ms over 5 s: measured 4e-7 rad over 256 members)."""
    runs = {}
    for scene in ("free_body", "free_body_attitude"):
        out = tmp_path / scene
        assert main(["run", str(TENNIS), "--quick", "--members", "40", "--out", str(out),
                     "--no-progress", "--set", f"integration.scene={scene}",
                     "--set", "output.figures=false"]) == 0
        runs[scene] = stability.load(out / "tennis_racket.nc")
        assert runs[scene].attrs["scene"] == scene
    assert "max attitude error" in capsys.readouterr().out
    alone, carried = runs["free_body"], runs["free_body_attitude"]
    assert "q" not in alone and carried.q.dims == ("series_member", "time",
                                                   "quaternion_component")
    np.testing.assert_array_equal(carried.w.values, alone.w.values)
    np.testing.assert_array_equal(carried.mean_flip_interval.values,
                                  alone.mean_flip_interval.values)
    assert carried.attrs["growth_rate_fitted"] == alone.attrs["growth_rate_fitted"]
    assert 0.0 < float(carried.attitude_error.max()) < 1e-5
    assert float(abs(carried.q_norm_error).max()) < 1e-9

