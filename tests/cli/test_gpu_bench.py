"""The GPU benchmark's command (stability.cli.gpu_bench): without a GPU it says it skipped."""

import os
import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_bench_without_gpu_skips():
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_ENABLE_CUDASIM"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    done = subprocess.run([sys.executable, "-m", "stability.cli.gpu_bench"], env=env, cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-4000:]
    if "member-steps/s" in done.stdout:
        pytest.skip("a CUDA GPU is present (the benchmark ran)")
    assert done.stdout.strip() == "no CUDA GPU: skipped"
