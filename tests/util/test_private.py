"""The private folder: made 0700 in the temporary directory, never found through a link or in
a folder others may use."""

import os
import tempfile

import pytest

from stability.util import private
from stability.util.private import private_folder


@pytest.fixture
def temp(tmp_path, monkeypatch):
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    monkeypatch.setattr(private, "_FRESH", {})  # the fresh folder is made once a process
    return tmp_path


def test_the_folder_is_made_private_and_found_again(temp):
    folder = private_folder("numba")
    assert folder == temp / f"stability-{os.getuid()}" / "numba"
    assert all(os.lstat(p).st_mode & 0o777 == 0o700 for p in (folder, folder.parent))
    assert private_folder("numba") == folder


@pytest.mark.parametrize("planted", ["link", "open to others"])
def test_a_folder_in_the_way_gives_a_fresh_one(temp, planted):
    other = temp / "elsewhere"
    other.mkdir(mode=0o700)
    top = temp / f"stability-{os.getuid()}"
    if planted == "link":
        top.symlink_to(other)
    else:
        top.mkdir()
        os.chmod(top, 0o777)
    folder = private_folder("numba")
    assert folder.parent == temp and folder.name.startswith(f"stability-{os.getuid()}-")
    assert os.lstat(folder).st_mode & 0o777 == 0o700
    assert list(other.iterdir()) == []
    assert private_folder("numba") == folder  # one fresh folder, not one a call
