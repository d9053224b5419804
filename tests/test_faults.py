"""Faults, for real: signals at each phase of a study run, a full disk, read-only folders.

Each case runs ``stability run`` in a subprocess and sends it a real SIGINT, SIGTERM or SIGKILL
while it compiles, integrates, or writes its Dataset and draws its figures, over an earlier
result (``--overwrite``). Then: the exit status (130, 143), one line saying what was kept and
how to continue, the earlier result byte for byte, no temporary file left (after SIGKILL: none
left once the next run has started), and ``--resume`` finishing the run. File-system faults
use a real small tmpfs or a read-only mount where the platform allows (root on Linux), and are
skipped with the reason otherwise. Bad input of every kind is in ``test_bad_input.py``.
"""

import contextlib
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from stability.cli import main
from stability.output.publish import JOURNAL, STAGE_PREFIX, Stage, clean_leftovers, journal_text
from stability.output.store import find_stores, read_progress
from stability.study import STUDIES

from .helpers import STOP_GUARD_S, once_per_run, wait_until

ROOT = Path(__file__).resolve().parents[1]
TENNIS = ROOT / "studies" / "tennis_racket.toml"
QUICK = ["--quick", "--members", "512", "--set", "run.chunk_members=128",
         "--set", "output.formats=['png']"]  # with progress: its lines tell the phase
#: Long enough to be caught integrating (chunks of 512 members of 20000 steps).
LONG = ["--quick", "--members", "8192", "--set", "run.chunk_members=512",
        "--set", "integration.t_end=40", "--set", "integration.save_every=1000",
        "--set", "output.formats=['png']"]


def stability_cmd(*args):
    return [sys.executable, "-m", "stability", "run", str(TENNIS), *args]


def start(args, env=None):
    return subprocess.Popen(stability_cmd(*args), cwd=ROOT, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True,
                            env={**os.environ, **(env or {})})


class Lines:
    """The stderr lines of a process, read in a thread (so waiting never blocks on a pipe)."""

    def __init__(self, proc):
        self.lines = []
        self.thread = threading.Thread(target=self._read, args=(proc.stderr,), daemon=True)
        self.thread.start()

    def _read(self, stream):
        for line in stream:
            self.lines.append(line.rstrip("\n").split("\r")[-1])  # past progress bars

    def seen(self, text):
        return any(text in line for line in self.lines)

    def wait_done(self):
        self.thread.join(timeout=30)
        return self.lines


def snapshot(folder: Path) -> dict:
    """Every visible file of a folder with its bytes."""
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()
            and not p.name.startswith(".")}


def temporaries(folder: Path) -> list:
    """Stage folders, partial and temporary files anywhere under ``folder``."""
    found = [p for p in folder.rglob("*") if p.name.startswith(STAGE_PREFIX)
             or p.name.endswith((".tmp", ".part"))]
    return sorted(str(p.relative_to(folder)) for p in found)


def _earlier(folder):
    done = subprocess.run(stability_cmd(*QUICK, "--out", str(folder / "out")), cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr


@pytest.fixture(scope="module")
def earlier(tmp_path_factory):
    """A finished quick result, the one every interrupted run is started over (copied by
    each): made once in a run of the suite."""
    return once_per_run(tmp_path_factory, "faults_earlier", _earlier) / "out"


PHASES = {
    # phase: (arguments, environment, how to know the run is in it, extra delay in s)
    "compile": (QUICK, "fresh cache", lambda out, lines: lines.seen("members x"), 1.0),
    "integrate": (LONG, None, lambda out, lines: (read_progress(
        out / ".stability-work-tennis_racket") or {}).get("chunks_done", 0) >= 2, 0.0),
    "write": (QUICK, None, lambda out, lines: lines.seen("writing"), 0.0),
    "figures": (QUICK, None, lambda out, lines: lines.seen("writing"), 0.4),
}


@pytest.mark.parametrize("sig", ["SIGINT", "SIGTERM", "SIGKILL"])
@pytest.mark.parametrize("phase", list(PHASES))
def test_signal_at_each_phase_loses_nothing_and_leaves_nothing(earlier, tmp_path, phase, sig):
    out = tmp_path / "out"
    shutil.copytree(earlier, out)
    before = snapshot(out)
    args, env, in_phase, delay = PHASES[phase]
    env = {"STABILITY_CACHE_DIR": str(tmp_path / "cache")} if env else None
    proc = start([*args, "--out", str(out), "--overwrite"], env)
    lines = Lines(proc)
    wait_until(lambda: in_phase(out, lines), proc)
    time.sleep(delay)
    proc.send_signal(getattr(signal, sig))
    proc.wait(timeout=STOP_GUARD_S)
    err = lines.wait_done()
    if proc.returncode == 0:  # the signal came as the run was publishing: it finished whole
        assert snapshot(out).keys() == before.keys() and temporaries(out) == []
        return
    assert snapshot(out) == before, "the earlier result changed"
    if sig == "SIGKILL":
        assert proc.returncode == -signal.SIGKILL
    else:
        assert proc.returncode == (130 if sig == "SIGINT" else 143), err
        last = err[-1]
        assert last.startswith(f"stability run: {'Ctrl-C' if sig == 'SIGINT' else 'SIGTERM'}: "
                               "interrupted; nothing was published"), err
        assert "Traceback" not in "\n".join(err)
        assert temporaries(out) == []
        if phase in ("write", "figures"):  # the ensemble was finished: it is kept
            assert "run the same command with --resume" in last
    if sig != "SIGKILL" and (phase, sig) != ("integrate", "SIGINT"):
        return
    # The next run cleans up after a killed one and finishes only what is missing.
    done = subprocess.run(stability_cmd(*args, "--out", str(out), "--overwrite", "--resume"),
                          cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert temporaries(out) == [] and not list(out.glob(".stability-work-*"))
    assert snapshot(out).keys() == before.keys()


def test_ctrl_c_while_a_figure_draws_takes_effect_after_that_figure(tmp_path):
    """A real SIGINT sent while a study's figure is being drawn: the figure is finished (an
    interrupt raised inside matplotlib's compiled code came out as another error, or a crash),
    the next one is not begun, the Dataset's write ends, and KeyboardInterrupt follows."""
    from stability.plotting.style import new_figure
    from stability.study.outputs import write_outputs

    ds = xr.Dataset({"x": ("n", np.arange(3.0), {"units": "1", "long_name": "x"})})
    config = {"title": "t", "output": {"dataset": "d.nc", "figures": True, "formats": ["png"]}}
    drawn = []

    def first(ds):
        fig = new_figure()
        fig.subplots().plot(ds.x)
        os.kill(os.getpid(), signal.SIGINT)  # Ctrl-C, in the middle of this figure
        for _ in range(100):  # the interpreter runs a Python handler at the next instructions
            time.sleep(0.001)
        drawn.append("first")
        return fig

    def second(ds):
        drawn.append("second")
        return new_figure()

    with pytest.raises(KeyboardInterrupt):
        write_outputs(ds, config, tmp_path, "test", {"a": first, "b": second})
    assert drawn == ["first"]
    assert (tmp_path / "a.png").is_file() and not (tmp_path / "b.png").exists()
    written = xr.load_dataset(tmp_path / "d.nc")  # the Dataset's write was let finish
    np.testing.assert_array_equal(written.x, ds.x)
    assert written.attrs["title"] == "t"
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # given back



def test_publication_killed_half_way_is_completed_by_the_next_run(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "a.nc").write_text("old a")
    (out / "b.png").write_text("old b")
    stage = Stage(out)
    stage.path("a.nc").write_text("new a")
    stage.path("b.png").write_text("new b")
    (stage.dir / JOURNAL).write_text(journal_text(["a.nc", "b.png"]))  # the journal ...
    os.replace(stage.path("a.nc"), out / "a.nc")  # ... and one file renamed, then the kill
    stage.dir.rename(out / f"{STAGE_PREFIX}otherhost-1-abcdef01")  # any host: it was whole
    assert clean_leftovers(out) == [f"completed the publication of {STAGE_PREFIX}"
                                    "otherhost-1-abcdef01"]
    assert snapshot(out) == {"a.nc": b"new a", "b.png": b"new b"}
    assert temporaries(out) == []


def test_unpublished_stage_of_a_dead_process_is_removed_not_of_a_live_one(tmp_path):
    out = tmp_path / "out"
    mine = Stage(out)  # this process is alive: its stage stays
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True).stdout.strip()
    host = mine.dir.name[len(STAGE_PREFIX):].split("-")[0]
    orphan = out / f"{STAGE_PREFIX}{host}-{dead}-0000abcd"
    orphan.mkdir()
    (orphan / "tennis_racket.nc").write_bytes(b"x" * 1000)
    assert clean_leftovers(out) == [f"removed the unfinished {orphan.name}"]
    assert mine.dir.is_dir() and not orphan.exists()
    mine.discard()


# --- file systems -----------------------------------------------------------------------------


@contextlib.contextmanager
def tmpfs(where: Path, size: str, read_only=False):
    """A real tmpfs of ``size`` mounted at ``where`` (skips the test where that is not allowed)."""
    where.mkdir(parents=True, exist_ok=True)
    options = f"size={size}" + (",ro" if read_only else "")
    if os.geteuid() != 0 or not sys.platform.startswith("linux"):
        pytest.skip("mounting a small file system needs root on Linux")
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(where)],
                          capture_output=True, text=True)
    if done.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {done.stderr.strip()}")
    try:
        yield where
    finally:
        subprocess.run(["umount", "-l", str(where)], capture_output=True)


def test_too_little_space_is_refused_before_computing(tmp_path):
    with tmpfs(tmp_path / "tiny", "2m") as tiny:
        done = subprocess.run(stability_cmd(*QUICK, "--out", str(tiny / "out")), cwd=ROOT,
                              capture_output=True, text=True, timeout=120)
        assert done.returncode == 2
        err = done.stderr.strip().splitlines()
        assert len(err) == 1 and "not enough free space: the result needs about" in err[0], err
        assert "members x" not in done.stderr  # nothing was run
        assert not (tiny / "out").exists() or list((tiny / "out").iterdir()) == []


def test_disk_full_while_writing_is_one_line_and_leaves_nothing(tmp_path):
    with tmpfs(tmp_path / "small", "40m") as small:
        out = small / "out"
        proc = start([*QUICK, "--out", str(out)])
        lines = Lines(proc)
        wait_until(lambda: lines.seen("writing"), proc)
        with open(small / "ballast", "wb") as f:  # the disk fills up meanwhile
            with contextlib.suppress(OSError):
                while True:
                    f.write(b"\0" * 2**20)
                    f.flush()
        proc.wait(timeout=120)
        err = lines.wait_done()
        assert proc.returncode == 2, err
        assert "No space left on device" in err[-1] and "Traceback" not in "\n".join(err)
        assert snapshot(out) == {}  # nothing under a final name
        assert temporaries(out) == []
        (small / "ballast").unlink()


def test_read_only_output_folder_is_refused_before_computing(tmp_path):
    with tmpfs(tmp_path / "ro", "1m", read_only=True) as ro:
        done = subprocess.run(stability_cmd(*QUICK, "--out", str(ro / "out")), cwd=ROOT,
                              capture_output=True, text=True, timeout=120)
        assert done.returncode == 2
        err = done.stderr.strip().splitlines()
        assert err == [f"stability run: error: output folder is not writable: {ro}"], err


@pytest.mark.parametrize("dataset, message", [
    ("sub/run.nc", "must be a plain file name"),
    ("", "[output] dataset must be a string ending in .nc"),
    ("folder.nc", "is a folder, where the output file 'folder.nc' goes"),
])
def test_bad_output_names_are_refused_before_computing(tmp_path, dataset, message):
    (tmp_path / "out" / "folder.nc").mkdir(parents=True)
    done = subprocess.run(stability_cmd(*QUICK, "--out", str(tmp_path / "out"), "--set",
                                        f"output.dataset='{dataset}'"),
                          cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 2
    err = done.stderr.strip().splitlines()
    assert len(err) == 1 and message in err[0], err
    assert [p.name for p in (tmp_path / "out").iterdir()] == ["folder.nc"]


@pytest.mark.parametrize("phase", ["integrate", "write"])
def test_sigterm_stops_a_run_started_with_ctrl_c_ignored(earlier, tmp_path, phase):
    """A background job of a script (``stability run ... &``) starts with SIGINT ignored, as
    the shell asks; SIGTERM, a batch system's stop, still stops it cleanly in every phase
    (it used to be passed on as a SIGINT, which such a process ignores)."""
    out = tmp_path / "out"
    shutil.copytree(earlier, out)
    before = snapshot(out)
    args, _, in_phase, delay = PHASES[phase]
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)  # inherited, as from `cmd &`
    try:
        proc = start([*args, "--out", str(out), "--overwrite"])
    finally:
        signal.signal(signal.SIGINT, previous)
    lines = Lines(proc)
    wait_until(lambda: in_phase(out, lines), proc)
    time.sleep(delay)
    proc.send_signal(signal.SIGTERM)
    proc.wait(timeout=STOP_GUARD_S)
    err = lines.wait_done()
    assert proc.returncode == 143, err
    assert err[-1].startswith("stability run: SIGTERM: interrupted; nothing was published"), err
    assert snapshot(out) == before and temporaries(out) == []


def test_stopped_map_resumed_on_dask_is_the_map_of_an_uninterrupted_run(tmp_path):
    import numpy as np
    import xarray as xr

    study = str(ROOT / "studies" / "stability_map.toml")
    args = ["--quick", "--members", "256", "--no-progress", "--set", "output.figures=false"]

    def cmd(out, *more):
        return [sys.executable, "-m", "stability", "run", study, *args, "--out", str(out), *more]

    whole = subprocess.run(cmd(tmp_path / "whole"), cwd=ROOT, capture_output=True, text=True,
                           timeout=600)
    assert whole.returncode == 0, whole.stderr
    stopped = tmp_path / "stopped"
    proc = subprocess.Popen(cmd(stopped), cwd=ROOT, stderr=subprocess.PIPE, text=True,
                            stdout=subprocess.DEVNULL)
    work = stopped / ".stability-work-stability_map"
    wait_until(lambda: (read_progress(work) or {}).get("chunks_done", 0) >= 1, proc)
    proc.send_signal(signal.SIGINT)
    sent = read_progress(work)  # where the run was when the signal went
    err = proc.communicate(timeout=120)[1].strip().splitlines()
    assert proc.returncode == 130 and "kept in" in err[-1] and "--resume" in err[-1], (err, sent)
    assert snapshot(stopped) == {} and temporaries(stopped) == []
    resumed = subprocess.run(cmd(stopped, "--resume", "--scheduler", "dask"), cwd=ROOT,
                             capture_output=True, text=True, timeout=600)
    assert resumed.returncode == 0, resumed.stderr
    with xr.open_dataset(tmp_path / "whole" / "stability_map.nc") as a, \
            xr.open_dataset(stopped / "stability_map.nc") as b:
        assert set(a.variables) == set(b.variables)
        for name in a.variables:
            if "time" in name and "wall" in name:
                continue
            floats = a[name].dtype.kind == "f"
            assert np.array_equal(a[name].values, b[name].values, equal_nan=floats), name


def test_output_folder_removed_while_writing_is_one_line(tmp_path):
    out = tmp_path / "out"
    proc = start([*QUICK, "--out", str(out)])
    lines = Lines(proc)
    wait_until(lambda: lines.seen("writing"), proc)
    shutil.rmtree(out, ignore_errors=True)  # someone cleans up the folder under the running
    # study (which may remove a file of its own meanwhile: the lock, as it gives up)
    proc.wait(timeout=120)
    err = lines.wait_done()
    assert proc.returncode == 2, err
    assert "No such file or directory" in err[-1] or "vanished" in err[-1], err
    assert "Traceback" not in "\n".join(err)


#: Studies that integrate in one piece: (study, label of its progress bar or the seconds to
#: wait, arguments that make the run long enough to be stopped while it integrates).
ONE_PIECE = {
    # No progress output on a pipe (its runs are short and timed): stopped 4 s into 110 s
    # (more on one thread, which is all it needs to be stopped while it integrates).
    "work_precision": (4.0, ["--threads", "1"]),
    # No progress bar: stopped 4 s into about 30 s of light curves of 2000 tumblers.
    "tumbler": (4.0, ["--set", "ensemble.members=2000"]),
}


def test_every_study_that_runs_in_one_piece_is_stopped_in_the_fault_suite():
    assert set(ONE_PIECE) == {name for name, kind in STUDIES.items() if not kind.resumable}


#: Studies of a scene run through the stored grouped path (stability.ensemble.chunks): the
#: arguments of a quick run in chunks small enough (eight or more, each taking tens of
#: milliseconds) to be killed after two, and whether it is resumed on a local dask cluster (a
#: few are: a cluster takes seconds to start). The tennis racket and the stability map have
#: their own cases above.
RESUMED = {
    "bat": (["--set", "run.chunk_members=10"], False),
    "dispersion": (["--set", "integration.members=16", "--set", "integration.steps_per_flip=100000",
                    "--set", "run.chunk_members=2"], False),
    "dual_spin": (["--set", "run.chunk_members=8"], True),
    "earth_wobble": (["--set", "wobble.members=16", "--set", "run.chunk_members=2"], False),
    "engine_artefacts": (["--set", "run.chunk_members=8"], False),
    "equinoxes": (["--set", "run.chunk_members=1"], False),
    "explorer": (["--set", "run.chunk_members=1"], True),
    "explorer_dispersion": (["--set", "integration.members=6", "--set",
                             "integration.step_angle=0.05"], False),
    "gyroscope": (["--set", "run.chunk_members=1"], True),
    "rolling": (["--set", "run.chunk_members=25"], True),
    "sleeping_top": (["--set", "run.chunk_members=16"], False),
    "twisting_racket": (["--set", "run.chunk_members=2"], False),
}
#: Variables that are wall-clock measurements, different in any two runs.
TIMED = {"cost_per_step"}


def chunks_done(work: Path) -> tuple[int, int]:
    """(chunks done, chunks) over the stores of a work folder, from their progress files."""
    done = total = 0
    for store in find_stores(work):
        progress = read_progress(store) or {}
        done += progress.get("chunks_done", 0)
        total += progress.get("chunks", 0)
    return done, total


def test_every_resumable_study_is_killed_and_resumed_in_the_fault_suite():
    assert set(RESUMED) | {"tennis_racket", "stability_map"} == {
        name for name, kind in STUDIES.items() if kind.resumable}


@pytest.mark.parametrize("name", sorted(RESUMED))
def test_a_study_killed_then_resumed_is_bitwise_an_uninterrupted_run(tmp_path, name, capsys):
    """kill -9 after two of its chunks, then --resume (on a local dask cluster for some): the
    Dataset's numbers are bitwise those of a run that was never stopped, on this machine.
    Another study's --resume into that folder is refused first, and a --resume after the run
    finished, touching nothing."""
    study = str(ROOT / "studies" / f"{name}.toml")
    small, on_dask = RESUMED[name]
    args = ["run", study, "--quick", *small, "--no-progress", "--set", "output.formats=['png']"]
    # in this process (no start-up), and only the Dataset compared against: no figures (they
    # took three quarters of a quick run); the resumed run below draws its own
    assert main([*args, "--set", "output.figures=false", "--out", str(tmp_path / "whole")]) == 0
    out = tmp_path / "out"
    work = out / f".stability-work-{name}"
    proc = subprocess.Popen([sys.executable, "-m", "stability", *args, "--out", str(out)],
                            cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wait_until(lambda: chunks_done(work)[0] >= 2, proc, show_stderr=True)
    proc.kill()
    proc.wait(timeout=STOP_GUARD_S)
    done, total = chunks_done(work)
    assert done < total or not (out / f"{name}.nc").exists(), "the run ended first"
    other = "rolling" if name != "rolling" else "bat"
    before = snapshot(out)
    capsys.readouterr()
    assert main(["run", str(ROOT / "studies" / f"{other}.toml"), "--quick", "--no-progress",
                 "--out", str(out), "--resume"]) == 2
    said = capsys.readouterr().err.strip()
    assert said.count("\n") == 0 and f"nothing of study {other!r} to resume in {out}" in said
    assert f".stability-work-{name}" in said and "drop --resume to start afresh" in said
    assert snapshot(out) == before
    resume = ["--resume", *(["--scheduler", "dask"] if on_dask else [])]
    assert main([*args, "--out", str(out), *resume]) == 0
    assert not work.exists() and temporaries(out) == []
    finished = snapshot(out)
    capsys.readouterr()
    assert main([*args, "--out", str(out), "--resume"]) == 2  # once more: nothing to resume
    said = capsys.readouterr().err.strip()
    assert f"nothing of study {name!r} to resume in {out}: its run there is finished" in said
    assert snapshot(out) == finished
    with xr.open_dataset(tmp_path / "whole" / f"{name}.nc") as whole, \
            xr.open_dataset(out / f"{name}.nc") as resumed:
        assert set(whole.variables) == set(resumed.variables)
        for variable in set(whole.variables) - TIMED:
            assert np.array_equal(whole[variable].values, resumed[variable].values,
                                  equal_nan=whole[variable].dtype.kind == "f"), variable


@pytest.mark.parametrize("name, sig", [
    (name, ("SIGINT", "SIGTERM")[k % 2]) for k, name in enumerate(sorted(ONE_PIECE))])
def test_one_piece_study_stopped_while_integrating_keeps_the_earlier_result(tmp_path, name, sig):
    """A study that runs in one piece (sleeping tops, gyroscopes, the equinoxes): a signal
    while it integrates publishes nothing, leaves the earlier result byte for byte and no
    temporary file, and says so in one line. Both signals reach a run the same way (the
    command's SIGTERM handler stops it as Ctrl-C does), so the studies take them in turn."""
    label, longer = ONE_PIECE[name]
    study = str(ROOT / "studies" / f"{name}.toml")
    out = tmp_path / "out"
    quick = [sys.executable, "-m", "stability", "run", study, "--quick", "--no-progress",
             "--set", "output.formats=['png']", "--out", str(out)]
    done = subprocess.run(quick, cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    before = snapshot(out)
    proc = subprocess.Popen(
        [sys.executable, "-m", "stability", "run", study, *longer, "--out", str(out),
         "--overwrite"], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    lines = Lines(proc)
    if isinstance(label, float):
        time.sleep(label)
        assert proc.poll() is None, lines.wait_done()
    else:
        wait_until(lambda: lines.seen(label), proc)  # its progress bar: integrating
    proc.send_signal(getattr(signal, sig))
    proc.wait(timeout=STOP_GUARD_S)
    err = lines.wait_done()
    assert proc.returncode == (130 if sig == "SIGINT" else 143), err
    assert err[-1].startswith(f"stability run: {'Ctrl-C' if sig == 'SIGINT' else 'SIGTERM'}: "
                              "interrupted; nothing was published"), err
    assert "Traceback" not in "\n".join(err)
    assert snapshot(out) == before and temporaries(out) == []


#: A stored run of a registered scene through the one generic path (stability.run_scene): 48
#: heavy tops in 12 chunks of 4, each of some tens of milliseconds, tracked. A new process runs
#: it into the store sys.argv[1].
SCENE_RUN = '''
import sys
import tempfile
import numpy as np
import stability
from stability.registry import SCENES

scene = SCENES["heavy_top"]
x0 = np.concatenate([scene.example(24, seed=k)[0] for k in range(2)])
tops = scene.example(1)[1][:2]
kwargs = dict(sizes=[24, 24], h=[0.01, 0.02], n_steps=[40000, 20000], axes=[2, 0, 1],
              levels=[0.1, 0.5], tracked_units="1")
stored = dict(chunk_members=4, progress=False)
if __name__ == "__main__":
    stability.run_scene("heavy_top", "lp2", x0, tops, **kwargs,
                        options=stability.RunOptions(store=sys.argv[1], **stored))
'''


def test_a_scene_run_killed_then_resumed_is_bitwise_an_uninterrupted_run(tmp_path):
    """kill -9 after two of its chunks, then resume=True here: the Dataset of a registered
    scene's stored run is bitwise the one of a run that was never stopped, made in memory."""
    store = tmp_path / "store"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))}
    proc = subprocess.Popen([sys.executable, "-c", SCENE_RUN, str(store)], cwd=ROOT, env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    wait_until(lambda: (read_progress(store) or {}).get("chunks_done", 0) >= 2, proc,
               show_stderr=True)
    proc.kill()
    proc.wait(timeout=STOP_GUARD_S)
    done, total = chunks_done(tmp_path)
    assert 2 <= done < total, "the run ended first"
    kept = {p.name: p.stat().st_mtime_ns for p in store.glob("chunk-*.nc")}
    setup = {"__name__": "members"}
    exec(SCENE_RUN, setup)  # the same members, here (not run)
    import stability

    args = ("heavy_top", "lp2", setup["x0"], setup["tops"])
    with pytest.raises(ValueError, match="resume"):
        stability.run_scene(*args, **setup["kwargs"],
                            options=stability.RunOptions(store=store, **setup["stored"]))
    resumed = stability.run_scene(*args, **setup["kwargs"], options=stability.RunOptions(
        store=store, resume=True, **setup["stored"]))
    assert all(store.joinpath(name).stat().st_mtime_ns == t for name, t in kept.items())
    whole = stability.run_scene(*args, **setup["kwargs"],
                                options=stability.RunOptions(progress=False))
    assert set(whole.variables) == set(resumed.variables)
    for name in whole.variables:
        assert np.array_equal(whole[name].values, resumed[name].values,
                              equal_nan=whole[name].dtype.kind == "f"), name
    assert temporaries(store) == []


# --- a read-only install, a user without a home ------------------------------------------------

#: nobody, given CAP_DAC_READ_SEARCH so that it reaches the interpreter under /root; it reads
#: past permissions but writes nothing it may not.
NOBODY = ["setpriv", "--reuid=65534", "--regid=65534", "--clear-groups",
          "--inh-caps=+dac_read_search", "--ambient-caps=+dac_read_search"]


def test_a_read_only_install_run_by_a_user_without_a_home_caches_in_a_private_folder(request):
    """The package copied to root's folder (0755, no __pycache__), imported by nobody with
    HOME=/nonexistent: Numba had no folder to cache the package's own njit(cache=True)
    functions in and the import ended in "RuntimeError: cannot cache function 'agm': no
    locator available". Now one warning names the private folder they go to, and they run."""
    if os.geteuid() != 0 or shutil.which("setpriv") is None:
        pytest.skip("needs root and setpriv to run a process as another user")
    install = Path(tempfile.mkdtemp(prefix="stability-install-"))
    temp = Path(tempfile.mkdtemp(prefix="stability-tmp-"))
    request.addfinalizer(lambda: [shutil.rmtree(p, ignore_errors=True) for p in (install, temp)])
    shutil.copytree(ROOT / "stability", install / "stability",
                    ignore=shutil.ignore_patterns("__pycache__"))
    os.chmod(install, 0o755)
    os.chmod(temp, 0o1777)
    done = subprocess.run(
        [*NOBODY, sys.executable, "-c", "import stability\n"
         "from stability.core.elliptic import agm\nprint(agm(1.0, 2.0))"],
        cwd=temp, capture_output=True, text=True, timeout=120,
        env={**{k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")},
             "HOME": "/nonexistent", "PYTHONPATH": str(install), "TMPDIR": str(temp)})
    if "Operation not permitted" in done.stderr and done.returncode != 0:
        pytest.skip(f"setpriv cannot run nobody here: {done.stderr.strip()}")
    assert done.returncode == 0, done.stderr
    assert float(done.stdout) == pytest.approx(1.4567910310469068, rel=1e-15)
    private = temp / "stability-65534" / "numba"
    assert done.stderr.strip().splitlines() == [
        "stability: Numba cannot write its cache beside the package, in NUMBA_CACHE_DIR or in "
        f"~/.cache; the compiled functions are cached in {private} (set NUMBA_CACHE_DIR to a "
        "folder of yours to choose)"]
    assert any(p.suffix == ".nbi" for p in private.rglob("*"))  # agm's index, kept there
    assert not any((install / "stability").rglob("__pycache__"))
