"""Numba's environment (stability.util.numba_env): a bad NUMBA_NUM_THREADS is one line naming it,
from the command and from the Python API, before Numba runs anything."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
TENNIS = ROOT / "studies" / "tennis_racket.toml"


@pytest.mark.parametrize("value", ["0", "abc"])
def test_a_bad_numba_num_threads_is_one_line_naming_it(value, tmp_path):
    """Numba stopped the import on 0 (ValueError: Number of threads specified must be > 0) and
    warned with a traceback on abc; the command is now one usage line, and a run of the
    Python API the same ValueError, from stability's check, before Numba runs anything."""
    line = (f"NUMBA_NUM_THREADS must be a whole number of threads >= 1 (this machine has "
            f"{os.cpu_count()} cores), got {value!r}; set it so, or unset it to use all cores")
    env = {**os.environ, "NUMBA_NUM_THREADS": value}
    done = subprocess.run([sys.executable, "-m", "stability", "run", str(TENNIS), "--quick",
                           "--out", str(tmp_path / "o"), "--no-progress"], env=env, cwd=ROOT,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2, done.stderr
    assert done.stderr.strip().splitlines() == [f"stability run: error: {line}"]
    assert not (tmp_path / "o").exists()
    api = subprocess.run([sys.executable, "-c", "import stability\nstability.run_ensemble("
                          "stability.RigidBody(1.0, 2.0, 3.0), 2, 1.0, 0.1, 4, h=0.1, "
                          "t_end=1.0, options=stability.RunOptions(progress=False))"], env=env,
                         cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert api.stderr.strip().splitlines()[-1] == f"ValueError: {line}", api.stderr
    assert "site-packages/numba" not in api.stderr and "Warning" not in api.stderr
