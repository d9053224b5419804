"""A folder of the current user's own in the temporary directory, safe where others write.

``$TMPDIR/stability-<uid>/<name>``: each level checked without following links (``lstat``): a
real directory, owned by the user, with no access for group or others. Where one is not (a link,
another user's folder in the way), a fresh private temporary folder is used instead.
"""

from __future__ import annotations

import os
import stat
import tempfile
from pathlib import Path


def private_folder(name: str) -> Path:
    """``$TMPDIR/stability-<uid>/<name>``, made mode 0700 where missing and checked; else a
    fresh ``$TMPDIR/stability-<uid>-*`` folder (mode 0700)."""
    uid = os.getuid()
    top = Path(tempfile.gettempdir()) / f"stability-{uid}"
    folder = top / name
    if all(_own(path, uid) for path in (top, folder)):
        return folder
    return Path(tempfile.mkdtemp(prefix=f"stability-{uid}-"))


def _own(path: Path, uid: int) -> bool:
    """``path`` made (0700) if missing; True if it is a real directory of ``uid``'s that
    group and others cannot use."""
    try:
        path.mkdir(mode=0o700, exist_ok=True)
        info = os.lstat(path)
    except OSError:
        return False
    return (stat.S_ISDIR(info.st_mode) and info.st_uid == uid
            and not info.st_mode & 0o077)
