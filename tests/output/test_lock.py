"""The output folder's lock (stability.output.lock), for real: a stale lock file of another user
does not block a run, a lock file planted as a hard link truncates nothing, a longer note left
behind is written over, not truncated."""

import json
import os
import shutil
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

import pytest

from stability.output.lock import OUTPUT_LOCK, FolderBusy, FolderLock, holder_of

ROOT = Path(__file__).resolve().parents[2]

UNPRIVILEGED = ["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups"]


def unprivileged_python():
    """A Python the unprivileged user may run, or skip (with the reason)."""
    if os.geteuid() != 0 or shutil.which("setpriv") is None:
        pytest.skip("needs root and setpriv to run a process as another user")
    for python in (sys.executable, "/usr/bin/python3"):
        done = subprocess.run([*UNPRIVILEGED, python, "-c", "pass"], capture_output=True)
        if done.returncode == 0:
            return python
    pytest.skip("no Python that the unprivileged user may run")


def test_a_stale_lock_file_of_another_user_does_not_block_a_run(request):
    """A root run killed -9 leaves its lock file (0644, root's); another user's run in the
    shared folder still takes the lock, and root is then refused naming it."""
    python = unprivileged_python()
    shared = Path(tempfile.mkdtemp(prefix="stability-shared-"))  # pytest's tmp is root's only
    request.addfinalizer(lambda: shutil.rmtree(shared, ignore_errors=True))
    os.chmod(shared, 0o1777)
    old = os.umask(0o022)
    try:
        killed = subprocess.Popen([sys.executable, "-c", textwrap.dedent(f"""
            import sys, time
            sys.path.insert(0, {str(ROOT)!r})
            from stability.output.lock import FolderLock
            held = FolderLock({str(shared)!r}).acquire()
            print("held", flush=True)
            time.sleep(60)
            """)], stdout=subprocess.PIPE, text=True)
        assert killed.stdout.readline().strip() == "held"
    finally:
        os.umask(old)
    killed.kill()
    killed.wait()
    assert (shared / OUTPUT_LOCK).stat().st_mode & 0o777 == 0o644
    other = subprocess.Popen([*UNPRIVILEGED, python, "-c", textwrap.dedent(f"""
        import importlib.util, time
        spec = importlib.util.spec_from_file_location(
            "lock", {str(ROOT / "stability" / "output" / "lock.py")!r})
        lock = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(lock)
        held = lock.FolderLock({str(shared)!r}).acquire()
        print("held", flush=True)
        time.sleep(60)
        """)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=shared)
    try:
        line = other.stdout.readline().strip()
        assert line == "held", other.stderr.read()
        with pytest.raises(FolderBusy, match="in use by another run \\(a process"):
            FolderLock(shared).acquire()  # its note could not be written: no pid known
    finally:
        other.kill()
        other.wait()
    with FolderLock(shared):
        pass


def test_a_lock_file_planted_as_a_hard_link_truncates_nothing(tmp_path):
    """An output folder whose lock file is a second name of a file of the user's (a hard
    link): the run is refused in one line and the file keeps its contents. The lock was taken
    and its note written over the file, truncated."""
    victim = tmp_path / "thesis.tex"
    victim.write_text("three years of work\n")
    out = tmp_path / "out"
    out.mkdir()
    os.link(victim, out / OUTPUT_LOCK)
    with pytest.raises(ValueError, match="2 names \\(a hard link\\).*remove it"):
        FolderLock(out).acquire()
    assert victim.read_text() == "three years of work\n"


def test_a_lock_file_left_with_a_longer_note_is_written_over_not_truncated(tmp_path):
    """A lock file left by a killed run, with a longer note than this run's: the new note is
    written over it, padded, so the file is never truncated, and it reads as this run's."""
    (tmp_path / OUTPUT_LOCK).write_text(json.dumps({"pid": 1, "host": "h" * 300}) + "\n")
    size = (tmp_path / OUTPUT_LOCK).stat().st_size
    with FolderLock(tmp_path):
        assert (tmp_path / OUTPUT_LOCK).stat().st_size == size
        note = json.loads((tmp_path / OUTPUT_LOCK).read_text())
        assert note["pid"] == os.getpid()
        assert holder_of(tmp_path).startswith(f"process {os.getpid()}")
