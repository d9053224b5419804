"""Faults of the compiled-loop cache, for real: damaged files, umasks, a second user, a held lock.

Each case runs the engine tests' small decay loop (``tests.engine.test_cache.SCRIPT``) in a new
process on a cache folder of its own (``STABILITY_CACHE_DIR``) and reads what the process
printed: its cache hits and misses (a miss is a compile) and its stderr, every line of it. The
loop is compiled for the module by two cold runs at once, under umask 022 and 002; the cases
copy the first cache, and only those that must compile again do (about 10 s each).
"""

import contextlib
import fcntl
import json
import logging
import os
import pickle
import pwd
import shutil
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import pytest

WAIT_NOTICE_S = 3.0  # stability.engine.cache.WAIT_NOTICE_S

from .helpers import STOP_GUARD_S, once_per_run, wait_until
from .engine.test_cache import KERNEL, SCRIPT
from .test_faults import Lines

ROOT = Path(__file__).resolve().parents[1]
NOBODY = 65534
#: The decay loop's final state (explicit Euler, k = 0.5, h = 0.1, 10 steps).
EXPECTED = [0.95 ** 10] * 3


def start(work, cache, *, umask=None, prefix=(), home=None, env=None):
    """The decay loop's script in a new process on the cache folder ``cache`` (``env``: more
    environment variables)."""
    env = {**os.environ, **(env or {}), "STABILITY_CACHE_DIR": str(cache),
           "PYTHONPATH": str(ROOT)}
    env.pop("XDG_CACHE_HOME", None)
    if home is not None:
        env["HOME"] = str(home)
    return subprocess.Popen(
        [*prefix, sys.executable, str(work / "script.py"), str(work)], cwd=ROOT, env=env,
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        preexec_fn=None if umask is None else lambda: os.umask(umask))


def finish(proc, timeout=120):
    """What the process printed: its result, and its stderr lines. AssertionError if it fails
    or runs past ``timeout`` s (it is killed)."""
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        raise AssertionError(f"the run was still going after {timeout} s") from None
    assert proc.returncode == 0, err
    result = json.loads(out.strip().splitlines()[-1])
    assert result["x"] == pytest.approx(EXPECTED, rel=1e-14)
    return result, err.splitlines()


def run(work, cache, **options):
    return finish(start(work, cache, **options))


def loop_files(cache: Path) -> dict:
    """The files of the one loop in ``cache``, by kind: py, lock, nbi, nbc."""
    files = [p for p in (cache / "loops").rglob("*") if p.is_file()]
    return {p.suffix[1:]: p for p in files}


@pytest.fixture(scope="module")
def work(tmp_path_factory):
    """The decay kernel's module and the script that runs its loop."""
    folder = tmp_path_factory.mktemp("decay")
    (folder / "decay.py").write_text(textwrap.dedent(KERNEL.format(factor="1.0")))
    (folder / "script.py").write_text(SCRIPT)
    return folder


UMASKS = (0o022, 0o002)


@pytest.fixture(scope="module")
def made(work, tmp_path_factory):
    """Caches made by a cold run each, under umask 022 and 002 (both at once), by umask: made
    once in a run of the suite (the cases copy them or read their modes)."""
    def make(folder):
        procs = [start(work, folder / f"umask{umask:03o}", umask=umask) for umask in UMASKS]
        for proc in procs:
            result, err = finish(proc)
            assert (result["misses"], result["hits"], err) == (1, 0, [])

    folder = once_per_run(tmp_path_factory, "faults_cache_made", make)
    return {umask: folder / f"umask{umask:03o}" for umask in UMASKS}


@pytest.fixture(scope="module")
def warm(made):
    """A cache holding the compiled loop, written under umask 022 (copy it)."""
    return made[0o022]


def copy_of(warm, tmp_path):
    return Path(shutil.copytree(warm, tmp_path / "cache"))


# --- damaged entries ---------------------------------------------------------------------------

def truncate(path):
    os.truncate(path, path.stat().st_size // 2)


def garble(path):
    path.write_bytes(bytes(range(256)) * (path.stat().st_size // 256 + 1))


@pytest.mark.parametrize("kind, damage", [("nbi", truncate), ("nbc", truncate),
                                          ("py", truncate), ("py", garble)])
def test_a_damaged_entry_is_compiled_again_with_one_warning(kind, damage, work, warm, tmp_path):
    """A truncated Numba index or machine code, a truncated or garbled rendered file: the next
    run discards it with one line naming it and compiles (or renders) it again, and the run
    after that is warm. Numba's entries failed every later run; a rendered file was rewritten
    without a word."""
    cache = copy_of(warm, tmp_path)
    damaged = loop_files(cache)[kind]
    damage(damaged)
    result, err = run(work, cache)
    assert len(err) == 1 and str(damaged) in err[0] and "damaged" in err[0], err
    # The machine code of a rendered file holds: Numba stamps it with the file's contents.
    assert result["misses"] == (0 if kind == "py" else 1)
    again, err = run(work, cache)
    assert (again["misses"], again["hits"], err) == (0, 1, [])


# --- modes -------------------------------------------------------------------------------------

def modes(cache: Path) -> dict:
    return {str(p.relative_to(cache)): p.stat().st_mode & 0o777
            for p in [cache, *cache.rglob("*")]}


@pytest.mark.parametrize("umask", [0o022, 0o002], ids=["022", "002"])
def test_cache_files_are_writable_by_their_owner_alone_whatever_the_umask(umask, made):
    """Every folder and file a cold run creates (rendered loop, lock file, Numba's index and
    machine code) has the mode 0755 or 0644 less the umask: others can read a shared cache,
    and no one but its owner can write it, so that the trust rule holds it. Under umask 002
    they were 0775 and 0664, and any member of the group could plant code in them."""
    cache = made[umask]
    assert set(loop_files(cache)) == {"py", "lock", "nbi", "nbc"}
    expected = {name: (0o755 if (cache / name).is_dir() else 0o644) & ~umask
                for name in modes(cache)}
    assert modes(cache) == expected


# --- a second user -----------------------------------------------------------------------------

@pytest.fixture
def nobody(tmp_path):
    """How to run a process as the user nobody, and a home of its own.

    Nobody is given CAP_DAC_READ_SEARCH, so that it can reach the interpreter and the test's
    files wherever they are (a Python under /root, pytest's 0700 temporary folders); it reads
    past permissions, but writes nothing it may not (what the umask lets others read is
    :func:`test_cache_files_are_writable_by_their_owner_alone_whatever_the_umask`).
    """
    setpriv = shutil.which("setpriv")
    if setpriv is None or os.geteuid() != 0:
        pytest.skip("running a second user needs root and setpriv")
    try:
        pwd.getpwuid(NOBODY)
    except KeyError:
        pytest.skip(f"no user {NOBODY} (nobody)")
    prefix = [setpriv, f"--reuid={NOBODY}", f"--regid={NOBODY}", "--clear-groups",
              "--inh-caps=+dac_read_search", "--ambient-caps=+dac_read_search"]
    home = tmp_path / "home"
    home.mkdir()
    os.chown(home, NOBODY, NOBODY)
    probe = subprocess.run([*prefix, sys.executable, "-c", "import stability"], cwd=ROOT,
                           capture_output=True, text=True,
                           env={**os.environ, "HOME": str(home), "PYTHONPATH": str(ROOT)})
    if probe.returncode != 0:
        pytest.skip(f"nobody cannot run the package: {probe.stderr.strip()[-300:]}")
    return prefix, home


def test_another_user_loads_a_warm_shared_cache_without_writing(work, warm, tmp_path, nobody):
    """A cache root wrote under umask 022 is loaded by nobody, who may not write there: no
    compile, no warning, nothing in the cache touched. Numba's own cache locator skipped the
    read-only folder, and nobody compiled the loop again."""
    prefix, home = nobody
    cache = copy_of(warm, tmp_path)
    before = {str(p): p.stat().st_mtime_ns for p in cache.rglob("*")}
    result, err = run(work, cache, prefix=prefix, home=home)
    assert (result["misses"], result["hits"], err) == (0, 1, [])
    assert {str(p): p.stat().st_mtime_ns for p in cache.rglob("*")} == before


def test_a_cache_another_user_cannot_write_falls_back_to_a_private_one(work, warm, tmp_path,
                                                                      nobody):
    """A cold cache folder nobody may not write (root's, 0755): nobody's run renders the loop in
    its own cache (``~/.cache/stability``; its machine code already there, to spare a compile)
    with one warning naming both folders, and succeeds. It failed with "Permission denied"."""
    prefix, home = nobody
    shared = tmp_path / "shared"
    shared.mkdir(mode=0o755)
    private = home / ".cache" / "stability" / "loops"
    shutil.copytree(warm / "loops" / "__pycache__", private / "__pycache__")
    for path in [home / ".cache", *(home / ".cache").rglob("*")]:
        os.chown(path, NOBODY, NOBODY)
    result, err = run(work, shared, prefix=prefix, home=home)
    assert len(err) == 1 and str(shared) in err[0] and str(private) in err[0], err
    assert (result["misses"], result["hits"]) == (0, 1)
    assert loop_files(home / ".cache" / "stability")["py"].name == loop_files(warm)["py"].name
    assert list(shared.iterdir()) == []


# --- the compile lock --------------------------------------------------------------------------

@contextlib.contextmanager
def holding(lock_file: Path):
    """Hold the compile lock ``lock_file`` as a compiling process does (its id written in)."""
    with open(lock_file, "a") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        f.truncate(0)
        f.write(f"{os.getpid()} on {os.uname().nodename}")
        f.flush()
        yield

def test_a_held_compile_lock_does_not_delay_a_warm_loop(work, warm, tmp_path):
    """Another process holds the loop's compile lock (compiling, or stopped): a run whose
    loop is warm takes no lock and finishes in its usual time, without a word. It waited
    silently for as long as the lock was held."""
    cache = copy_of(warm, tmp_path)
    with holding(loop_files(cache)["lock"]):
        result, err = finish(start(work, cache), timeout=120)
    assert (result["misses"], result["hits"], err) == (0, 1, [])  # no "waiting for" notice


def test_a_run_waiting_for_a_compile_says_so_then_loads_it(work, warm, tmp_path):
    """A cold loop whose lock another process holds while compiling: the run says, once and
    after WAIT_NOTICE_S, which process it waits for, on which loop and lock file; it goes on
    waiting, and once the lock is released loads the machine code the holder saved instead of
    compiling it again. It waited without a word."""
    cache = copy_of(warm, tmp_path)
    machine_code = cache / "loops" / "__pycache__"
    aside = machine_code.rename(tmp_path / "compiled")
    lock_file = loop_files(cache)["lock"]
    with holding(lock_file):
        t0 = time.monotonic()
        proc = start(work, cache)
        lines = Lines(proc)
        wait_until(lambda: lines.seen("waiting for"), proc, timeout=60)
        waited = time.monotonic() - t0
        time.sleep(1.0)  # it goes on waiting
        assert proc.poll() is None
        aside.rename(machine_code)  # the holder's compile, saved
    proc.wait(timeout=STOP_GUARD_S)
    err = lines.wait_done()
    assert proc.returncode == 0, err
    assert waited >= WAIT_NOTICE_S
    assert len(err) == 1, err
    assert f"waiting for process {os.getpid()} on " in err[0] and str(lock_file) in err[0]
    assert lock_file.stem in err[0].replace(str(lock_file), "")
    result = json.loads(proc.stdout.read().strip().splitlines()[-1])
    assert (result["misses"], result["hits"]) == (0, 1)


# --- the trust rule: nothing someone else could have written is run or unpickled --------------

class Plant:
    """A pickle that, once loaded, leaves the file ``marker``: what an attacker would plant."""

    def __init__(self, marker):
        self.marker = str(marker)

    def __reduce__(self):
        return (os.system, (f"touch {self.marker}",))


def seeded_home(warm, tmp_path) -> Path:
    """A home whose own cache holds the loop's machine code, so a fallback to it needs no
    compile (the rendered file is written there by the run)."""
    home = tmp_path / "home"
    shutil.copytree(warm / "loops" / "__pycache__",
                    home / ".cache" / "stability" / "loops" / "__pycache__")
    return home


def test_a_planted_pyc_beside_a_loop_is_never_run(work, warm, tmp_path):
    """A ``.pyc`` for the rendered loop in ``__pycache__``, matching its file's time and size:
    the run executes the bytes it rendered and checked, not the planted code, and stays warm
    without a word. Python's loader ran the ``.pyc``."""
    import importlib.util
    from importlib._bootstrap_external import _code_to_timestamp_pyc

    cache = copy_of(warm, tmp_path)
    source = loop_files(cache)["py"]
    marker = tmp_path / "planted-code-ran"
    planted = compile(f"open({str(marker)!r}, 'w').close()\n" + source.read_text(),
                      str(source), "exec")
    st = source.stat()
    Path(importlib.util.cache_from_source(str(source))).write_bytes(
        _code_to_timestamp_pyc(planted, st.st_mtime, st.st_size))
    result, err = run(work, cache)
    assert not marker.exists()
    assert (result["misses"], result["hits"], err) == (0, 1, [])


def give_to_nobody(path):
    os.chown(path, NOBODY, NOBODY, follow_symlinks=False)


@pytest.mark.parametrize("entry, spoil, words", [
    ("nbi", give_to_nobody, "belongs to user nobody"),
    ("nbc", lambda path: path.chmod(0o664), "is writable by its group"),
    ("pycache", lambda path: path.chmod(0o777), "is writable by every user"),
    ("loops", give_to_nobody, "belongs to user nobody"),
    ("nbi-link", None, "is a symbolic link"),
], ids=["index-of-another-user", "group-writable-machine-code", "folder-open-to-all",
        "loops-of-another-user", "index-a-link"])
def test_a_cache_someone_else_could_have_written_is_never_unpickled(entry, spoil, words, work,
                                                                    warm, tmp_path):
    """Numba's index and machine code are pickles, which run code when loaded. One planted in
    a cache that fails the trust rule (a file or folder of another user's, one its group or
    every user may write, a link) is never loaded: the run keeps the loop in the user's own
    cache instead, with one warning naming the cache and why, and its numbers are right. The
    planted pickle ran, and the run ended normally."""
    if os.geteuid() != 0 and spoil is give_to_nobody:
        pytest.skip("giving a file away needs root")
    cache = copy_of(warm, tmp_path)
    files = loop_files(cache)
    marker = tmp_path / "planted-pickle-ran"
    plant = pickle.dumps(Plant(marker))
    target = files["nbc" if entry == "nbc" else "nbi"]
    target.write_bytes(plant)
    if entry == "nbi-link":
        elsewhere = tmp_path / "elsewhere.nbi"
        elsewhere.write_bytes(plant)
        target.unlink()
        target.symlink_to(elsewhere)
        problem = target
    else:
        problem = {"nbi": target, "nbc": target, "pycache": target.parent,
                   "loops": cache / "loops"}[entry]
        spoil(problem)
    result, err = run(work, cache, home=seeded_home(warm, tmp_path))
    assert not marker.exists()
    assert (result["misses"], result["hits"]) == (0, 1)
    assert len(err) == 1, err
    assert f"cannot use the compiled-loop cache {cache / 'loops'} ({problem} {words}" in err[0]
    assert str(tmp_path / "home" / ".cache" / "stability" / "loops") in err[0]


def test_a_group_or_an_owner_named_by_the_user_is_trusted_with_a_shared_cache(work, warm,
                                                                               tmp_path):
    """A cache prepared by another account (here nobody's), or written by a group whose
    members may all compile into it (group-writable, ``$STABILITY_CACHE_GROUP``): named by the
    user, it is loaded warm without a word; unnamed, it is not loaded (one warning)."""
    if os.geteuid() != 0:
        pytest.skip("giving a file away needs root")
    cache = copy_of(warm, tmp_path)
    for path in [cache, *cache.rglob("*")]:
        give_to_nobody(path)
    result, err = run(work, cache, home=seeded_home(warm, tmp_path))
    assert len(err) == 1 and "belongs to user nobody" in err[0], err
    result, err = run(work, cache, env={"STABILITY_CACHE_OWNER": "nobody"})
    assert (result["misses"], result["hits"], err) == (0, 1, [])

    shared = copy_of(warm, tmp_path / "group")
    for path in [shared, *shared.rglob("*")]:
        os.chown(path, os.getuid(), 0)
        path.chmod(path.stat().st_mode | 0o020)
    result, err = run(work, shared, env={"STABILITY_CACHE_GROUP": "0"})
    assert (result["misses"], result["hits"], err) == (0, 1, [])


def test_a_rendered_loop_swapped_after_its_check_is_not_what_runs(tmp_path, monkeypatch,
                                                                  caplog):
    """Another process replaces the rendered file again and again while loops are loaded: the
    module run is always the one rendered. Loads go on until 30 of them have met the planted
    file at their check (each is a warning, and the file written again), so the race is run
    however the threads are scheduled. The file was read twice (checked, then imported), and
    15 of 1,000 loads ran the planted one."""
    from stability.engine import cache as loop_cache
    from stability.engine.sources import digest

    monkeypatch.setenv("STABILITY_CACHE_DIR", str(tmp_path / "cache"))
    source = "WHO = 'rendered'\n"
    path = loop_cache.cache_dir() / f"race__{digest(source, ())[:20]}.py"
    name = f"{loop_cache.MODULE_PREFIX}__race__{digest(source, ())[:20]}"
    loop_cache.load_module("race", source, ())
    stop, swaps = threading.Event(), [0]

    def swap():
        while not stop.is_set():
            for text in ("WHO = 'planted'\n", source):
                tmp = path.with_name(f"swap-{swaps[0]}")
                tmp.write_text(text)
                os.replace(tmp, path)
                swaps[0] += 1

    swapper = threading.Thread(target=swap, daemon=True)
    seen, loads = set(), 0
    with caplog.at_level(logging.WARNING, logger="stability.engine.cache"):
        swapper.start()
        try:
            while len(caplog.records) < 30 and loads < 20_000:
                sys.modules.pop(name)
                seen.add(loop_cache.load_module("race", source, ()).WHO)
                loads += 1
        finally:
            stop.set()
            swapper.join()
    # each warning is a load that met the planted file (discarded, written again) or caught
    # the swap between the rename's two links (the file refused, the private cache used)
    met = [r for r in caplog.records
           if "discarded the damaged compiled-loop file" in r.getMessage()
           or "hard links); using" in r.getMessage()]
    assert len(met) == len(caplog.records) >= 30, (loads, swaps[0])
    assert seen == {"rendered"}


# --- the compile lock ---------------------------------------------------------------------------

def test_a_lock_file_planted_as_a_link_truncates_nothing(work, warm, tmp_path):
    """The loop's lock file is a link to a file of the user's: the cache is not used (one
    warning naming the link), the run is right, and the file linked to is untouched. A cold
    run opened the lock through the link and truncated that file."""
    cache = copy_of(warm, tmp_path)
    shutil.rmtree(cache / "loops" / "__pycache__")
    victim = tmp_path / "precious.txt"
    victim.write_text("a file the user cares about\n")
    lock_file = loop_files(cache)["lock"]
    lock_file.unlink()
    lock_file.symlink_to(victim)
    result, err = run(work, cache, home=seeded_home(warm, tmp_path))
    assert (result["misses"], result["hits"]) == (0, 1)
    assert len(err) == 1 and f"{lock_file} is a symbolic link" in err[0], err
    assert victim.read_text() == "a file the user cares about\n"


def test_a_lock_file_is_never_truncated_nor_waited_on_when_it_is_a_fifo(tmp_path):
    """An existing lock file of the user's keeps its length (the holder's record is written
    over its start); a FIFO at its name, another user's lock, a hard link to another file:
    no lock, at once (the loop is compiled without it)."""
    from stability.engine.cache import LOCK_RECORD, _CompileLock

    lock_file = tmp_path / "loop.lock"
    lock_file.write_bytes(b"x" * 1000)
    lock = _CompileLock(lock_file)
    assert lock.acquire()
    assert lock_file.read_bytes()[:LOCK_RECORD].decode().startswith(f"{os.getpid()} on ")
    lock.release()
    assert lock_file.stat().st_size == 1000

    fifo = tmp_path / "fifo.lock"
    os.mkfifo(fifo)
    outcome = []
    taker = threading.Thread(target=lambda: outcome.append(_CompileLock(fifo).acquire()),
                             daemon=True)
    taker.start()
    taker.join(timeout=10)
    assert outcome == [False]

    other = tmp_path / "elsewhere"
    other.write_text("keep")
    os.link(other, tmp_path / "linked.lock")
    assert not _CompileLock(tmp_path / "linked.lock").acquire()
    if os.geteuid() == 0:
        theirs = tmp_path / "theirs.lock"
        theirs.write_text("")
        give_to_nobody(theirs)
        assert not _CompileLock(theirs).acquire()


# --- the private fallback -----------------------------------------------------------------------

@pytest.mark.parametrize("case", ["link-to-a-shared-folder", "open-to-others",
                                  "another-users", "loops-a-link"])
def test_a_private_folder_in_the_way_is_passed_over_for_a_fresh_one(case, tmp_path,
                                                                    monkeypatch):
    """``$TMPDIR/stability-<uid>``, where a process keeps loops it can keep nowhere else, is a
    link to a folder every user may write (it passed the owner check, through the link), open
    to others, another user's, or holds ``loops`` as a link: it is passed over for a fresh
    private folder (mode 0700), and the loops are kept there."""
    import tempfile

    from stability.engine import cache as loop_cache
    from stability.util import private

    if case == "another-users" and os.geteuid() != 0:
        pytest.skip("giving a folder away needs root")
    temp = tmp_path / "tmp"
    temp.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(temp))
    monkeypatch.setattr(private, "_FRESH", {})
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.delenv("STABILITY_CACHE_DIR", raising=False)
    folder = temp / f"stability-{os.getuid()}"
    shared = tmp_path / "shared"
    shared.mkdir()
    shared.chmod(0o1777)
    if case == "link-to-a-shared-folder":
        folder.symlink_to(shared)
    else:
        folder.mkdir(mode=0o700)
    if case == "open-to-others":
        folder.chmod(0o755)
    if case == "another-users":
        give_to_nobody(folder)
    if case == "loops-a-link":
        (folder / "loops").symlink_to(shared)
    [place] = list(loop_cache.private_dirs())
    assert place.folder != folder / "loops" and place.root.parent == temp
    assert place.root.stat().st_mode & 0o777 == 0o700
    path = place.take("probe.py", b"X = 1\n")
    assert path.parent == place.folder and list(shared.iterdir()) == []
