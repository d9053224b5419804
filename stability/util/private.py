"""A folder of the current user's own in the temporary directory, safe where others write.

``$TMPDIR/stability-<uid>/<name>``: each level made mode 0700 where missing and checked without
following links (:func:`stability.util.trust.private_folder_problem`: a real directory, owned by
the user, with no access for group or others). Where one is not (a link, another user's folder
in the way), a fresh private temporary folder is used instead, one per name and process.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

from .trust import private_folder_problem

#: The fresh folders made in this process where the usual one was in the way, by name.
_FRESH: dict[str, Path] = {}


def private_folder(name: str) -> Path:
    """``$TMPDIR/stability-<uid>/<name>``, made mode 0700 where missing and checked; else a
    fresh ``$TMPDIR/stability-<uid>-*`` folder (mode 0700), the same for the process."""
    uid = os.getuid()
    top = Path(tempfile.gettempdir()) / f"stability-{uid}"
    folder = top / name
    for path in (top, folder):  # each level checked before anything is made inside it
        with contextlib.suppress(OSError):
            path.mkdir(mode=0o700)
        if private_folder_problem(path) is not None:
            break
    else:
        return folder
    if name not in _FRESH:
        _FRESH[name] = Path(tempfile.mkdtemp(prefix=f"stability-{uid}-"))
    return _FRESH[name]


__all__ = ["private_folder"]
