"""What Numba reads from the environment as it is imported, made safe before it is.

- ``NUMBA_NUM_THREADS``: Numba stops its own import with a traceback on ``0`` and warns with
  one on ``abc`` (then starts all cores). A value that is not a whole number >= 1 is taken out
  of the environment before Numba is imported, so that ``import stability`` works, and every run
  and the command line refuse it in one line (:func:`check_threads_variable`).
- Where the package's own ``@njit(cache=True)`` functions are cached: Numba takes
  ``NUMBA_CACHE_DIR``, else a ``__pycache__`` beside each module, else ``~/.cache/numba``, and
  stops the import (``RuntimeError: cannot cache function ...: no locator available``) where
  none can be written: a read-only install run by a user without a home of their own, as a
  dask worker or a service account is. ``NUMBA_CACHE_DIR`` is then set to a private folder
  (:func:`stability.util.private.private_folder`), with one warning.

Importing this module does both (:func:`prepare`); the package's ``__init__`` imports it first.
"""

from __future__ import annotations

import logging
import os
import sys
import tempfile
from pathlib import Path

from .private import private_folder

log = logging.getLogger(__name__)

#: The one line about a bad ``NUMBA_NUM_THREADS``, or None.
THREADS_PROBLEM: str | None = None


def prepare() -> None:
    """Check ``NUMBA_NUM_THREADS`` and find a cache folder Numba can write, before Numba is
    imported."""
    global THREADS_PROBLEM
    text = os.environ.get("NUMBA_NUM_THREADS")
    if text is not None and not (text.strip().isdigit() and int(text) >= 1):
        THREADS_PROBLEM = (
            f"NUMBA_NUM_THREADS must be a whole number of threads >= 1 (this machine has "
            f"{os.cpu_count()} cores), got {text!r}; set it so, or unset it to use all cores")
        if "numba" not in sys.modules:
            del os.environ["NUMBA_NUM_THREADS"]
    if not _numba_can_cache(Path(__file__).resolve().parents[1]):
        folder = private_folder("numba")
        os.environ["NUMBA_CACHE_DIR"] = str(folder)
        if "numba" in sys.modules:
            sys.modules["numba"].config.CACHE_DIR = str(folder)
        log.warning("stability: Numba cannot write its cache beside the package, in "
                    "NUMBA_CACHE_DIR or in ~/.cache; the compiled functions are cached in %s "
                    "(set NUMBA_CACHE_DIR to a folder of yours to choose)", folder)


def check_threads_variable() -> None:
    """ValueError in one line where ``NUMBA_NUM_THREADS`` is not a whole number >= 1."""
    if THREADS_PROBLEM is not None:
        raise ValueError(THREADS_PROBLEM)


def _numba_can_cache(package: Path) -> bool:
    """Whether one of Numba's cache locations can be written for every module of
    ``package``: ``NUMBA_CACHE_DIR``, the ``__pycache__`` of every folder, or the user's
    cache folder (probed in that order, as Numba does, each by writing a file)."""
    chosen = os.environ.get("NUMBA_CACHE_DIR")
    if chosen and _writable(Path(chosen)):
        return True
    folders = []
    for top, dirs, _ in os.walk(package):
        dirs[:] = [name for name in dirs if name != "__pycache__"]
        folders.append(Path(top))
    if all(_writable(folder / "__pycache__") for folder in folders):
        return True
    user = os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache")
    return _writable(Path(user) / "numba")


def _writable(folder: Path) -> bool:
    """Whether a file can be made in ``folder`` (created if missing)."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        tempfile.TemporaryFile(dir=folder).close()
    except OSError:
        return False
    return True


prepare()
