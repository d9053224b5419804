"""The package's version (stability.version): the installed distribution's, which is the one
pyproject.toml declares, and what the command line and the Datasets record."""

import subprocess
import sys
import tomllib
from pathlib import Path

from stability.version import __version__

ROOT = Path(__file__).resolve().parents[1]


def test_the_version_is_the_one_pyproject_declares():
    declared = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    assert __version__ == declared


def test_the_command_line_says_it():
    done = subprocess.run([sys.executable, "-m", "stability", "--version"], capture_output=True,
                          text=True, timeout=120, cwd=ROOT)
    assert done.returncode == 0 and __version__ in done.stdout
