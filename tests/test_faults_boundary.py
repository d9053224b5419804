"""The output folder is a boundary: planted journals, links, two runs at once, odd names, chunks
of another run.

Every case uses real files, real symbolic links and real concurrent processes: what a run
finds in its output folder is untrusted, it writes only inside that folder and never through a
link, it never removes what another live run owns, and a refusal is one line (exit 2) that
touches nothing. Where rights matter, a case runs a process as an unprivileged user
(``setpriv``), and is skipped with the reason where that is not possible.
"""

import dataclasses
import json
import logging
import os
import shutil
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import stability
from stability.cli import main
from stability.output.lock import OUTPUT_LOCK, FolderBusy, holder_of
from stability.output.publish import (
    JOURNAL, STAGE_PREFIX, Stage, check_target, clean_leftovers, journal_text,
)
from stability.output.store import LOCK, ChunkStore, read_progress

from .helpers import STOP_GUARD_S, wait_until
from .test_faults import LONG, QUICK, Lines, snapshot, start, stability_cmd

ROOT = Path(__file__).resolve().parents[1]
WORK = ".stability-work-tennis_racket"


def stored(kwargs: dict, **where) -> dict:
    """``kwargs`` of run_ensemble with their run options placed ``where`` (a store, resume)."""
    return {**kwargs, "options": dataclasses.replace(kwargs["options"], **where)}

def tree(folder: Path) -> dict:
    """Every entry under ``folder`` (links as their targets' text, files as bytes)."""
    found = {}
    for p in sorted(folder.rglob("*")):
        rel = str(p.relative_to(folder))
        found[rel] = (f"-> {os.readlink(p)}" if p.is_symlink() else
                      p.read_bytes() if p.is_file() else "folder")
    return found


def dead_pid() -> int:
    """The id of a process that has ended."""
    done = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True)
    return int(done.stdout)


def stage_name(folder: Path) -> str:
    """The name of a stage of this host, of a dead process (so it counts as left over)."""
    probe = Stage(folder)
    host = probe.dir.name[len(STAGE_PREFIX):].rsplit("-", 2)[0]
    probe.discard()
    return f"{STAGE_PREFIX}{host}-{dead_pid()}-0123abcd"


# --- planted publishing journals -----------------------------------------------------------


@pytest.fixture
def victim(tmp_path):
    """An output folder, and beside it a folder with a file no run may move or remove."""
    out = tmp_path / "out"
    out.mkdir()
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "payload").write_text("not the run's")
    return out, elsewhere


def plant(out: Path, journal, files=(), name=None) -> Path:
    """A leftover stage in ``out`` with the journal text ``journal`` and ``files``."""
    stage = out / (name or stage_name(out))
    stage.mkdir()
    for file in files:
        (stage / file).write_text("staged")
    (stage / JOURNAL).write_text(journal if isinstance(journal, str) else journal_text(journal))
    return stage


@pytest.mark.parametrize("case", [
    "dot-dot", "through a link in the stage", "a staged link", "old text journal",
    "not JSON", "JSON of another shape", "absolute path", "a folder of out", "too large",
])
def test_a_planted_journal_moves_nothing_and_is_left_untouched(victim, caplog, case):
    out, elsewhere = victim
    if case == "dot-dot":
        stage = plant(out, ["../elsewhere/payload", "ok.nc"], ["ok.nc"])
    elif case == "through a link in the stage":
        stage = plant(out, ["L/payload"])
        (stage / "L").symlink_to(elsewhere)
    elif case == "a staged link":
        stage = plant(out, ["payload.nc"])
        (stage / "payload.nc").symlink_to(elsewhere / "payload")
    elif case == "old text journal":
        stage = plant(out, "../elsewhere/payload\n")
    elif case == "not JSON":
        stage = plant(out, "\xff\xfe not a journal")
    elif case == "JSON of another shape":
        stage = plant(out, json.dumps(["payload"]))
    elif case == "absolute path":
        stage = plant(out, [str(elsewhere / "payload")])
    elif case == "a folder of out":
        (out / "sub").mkdir()
        stage = plant(out, ["sub"], ["sub"])
    else:
        stage = plant(out, journal_text(["a" * 64] * 40000))
    before, outside = tree(out), tree(elsewhere)
    with caplog.at_level(logging.WARNING, logger="stability.output.publish"):
        assert clean_leftovers(out) == []
    assert tree(out) == before and tree(elsewhere) == outside
    lines = [r.getMessage() for r in caplog.records]
    assert len(lines) == 1 and f"left {stage} untouched" in lines[0], lines


def test_a_stage_that_is_a_link_is_neither_completed_nor_removed(victim, caplog):
    out, elsewhere = victim
    (elsewhere / JOURNAL).write_text(journal_text(["payload"]))
    (out / stage_name(out)).symlink_to(elsewhere)  # with a valid journal, of a dead process
    (out / f"{STAGE_PREFIX}not-ours").mkdir()  # a name that does not parse as a stage
    before, outside = tree(out), tree(elsewhere)
    with caplog.at_level(logging.WARNING, logger="stability.output.publish"):
        assert clean_leftovers(out) == []
    assert tree(out) == before and tree(elsewhere) == outside
    assert len(caplog.records) == 2


def test_a_planted_journal_is_left_alone_by_a_real_run_that_then_publishes(victim):
    out, elsewhere = victim
    stage = plant(out, ["../elsewhere/payload"])
    done = subprocess.run(stability_cmd(*QUICK, "--out", str(out)), cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert (elsewhere / "payload").read_text() == "not the run's"
    assert stage.is_dir() and (stage / JOURNAL).exists()
    warned = [line for line in done.stderr.splitlines() if "untouched" in line]
    assert len(warned) == 1 and str(stage) in warned[0], done.stderr
    assert (out / "tennis_racket.nc").is_file()


def test_a_valid_journal_of_a_killed_run_is_still_completed(victim):
    out, _ = victim
    (out / "a.nc").write_text("old a")
    stage = plant(out, ["a.nc", "b.png"], ["a.nc", "b.png"])
    assert clean_leftovers(out) == [f"completed the publication of {stage.name}"]
    assert snapshot(out) == {"a.nc": b"staged", "b.png": b"staged"}
    assert not stage.exists()


# --- links where a run writes ------------------------------------------------------------


def run_here(capsys, *args) -> tuple[int, list]:
    """``stability run`` of the quick tennis study in this process: (exit status, stderr lines).

    For runs refused before any work, which need no process of their own."""
    status = main(["run", str(ROOT / "studies" / "tennis_racket.toml"), *QUICK, *args])
    return status, capsys.readouterr().err.strip().splitlines()


@pytest.mark.parametrize("options", [[], ["--overwrite"], ["--resume"]])
def test_a_work_folder_that_is_a_link_is_refused_and_nothing_is_touched(victim, capsys,
                                                                       options):
    out, elsewhere = victim
    (out / WORK).symlink_to(elsewhere)
    (elsewhere / "chunk-000000.nc").write_text("someone's file")
    before, outside = tree(out), tree(elsewhere)
    status, err = run_here(capsys, "--out", str(out), *options)
    assert status == 2, err
    assert len(err) == 1 and "is a symbolic link" in err[0] and WORK in err[0], err
    assert tree(out) == before and tree(elsewhere) == outside


def test_links_inside_a_store_are_never_written_through(tmp_path, body123):
    """A chunk file or checksum planted as a link is discarded (the link), never followed."""
    kwargs = dict(body=body123, axis=2, spin=1.0, epsilon=1e-3, members=64, h=0.01,
                  t_end=0.1, method="rk4", seed=3, keep=stability.Keep(save_every=0),
                  options=stability.RunOptions(chunk_members=32, progress=False))
    first = stability.run_ensemble(**stored(kwargs, store=tmp_path / "a")).load()
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "x.nc").write_text("someone's file")
    store = tmp_path / "a"
    for name in ("chunk-000001.nc", "chunk-000001.nc.sha256"):
        (store / name).unlink()
        (store / name).symlink_to(elsewhere / "x.nc")
    outside = tree(elsewhere)
    again = stability.run_ensemble(**stored(kwargs, store=store, resume=True)).load()
    assert tree(elsewhere) == outside
    assert not any(p.is_symlink() for p in store.iterdir())
    xr.testing.assert_equal(again, first)


# --- two runs at once --------------------------------------------------------------------


#: A run still integrating after three more processes have started and been refused on a
#: loaded machine: LONG's members, a hundred times the steps, in 128 short chunks (it is stopped
#: with Ctrl-C after its first chunks, never waited for), on one thread: it only has to be
#: busy, and on all cores it took them from the runs it waits for and from the other tests.
BUSY = [*LONG, "--set", "integration.t_end=4000", "--set", "integration.save_every=100000",
        "--set", "run.chunk_members=64", "--threads", "1"]


def test_a_second_run_into_a_busy_folder_is_refused_and_destroys_nothing(tmp_path, capsys):
    out = tmp_path / "out"
    first = start([*BUSY, "--out", str(out)])
    lines = Lines(first)
    wait_until(lambda: (read_progress(out / WORK) or {}).get("chunks_done", 0) >= 1, first)
    for options in ([], ["--overwrite"], ["--overwrite", "--resume"]):
        done = subprocess.run(stability_cmd(*BUSY, "--out", str(out), *options), cwd=ROOT,
                              capture_output=True, text=True, timeout=300)
        assert done.returncode == 2, (options, done.stderr)
        err = done.stderr.strip().splitlines()
        assert len(err) == 1 and f"process {first.pid} on host" in err[0], err
        assert "in use by another run" in err[0], err
        assert first.poll() is None and (out / WORK / "manifest.json").is_file()
    assert f"process {first.pid}" in holder_of(out)
    assert main(["status", str(out)]) == 0  # the holder, then how far its chunks are
    shown = capsys.readouterr().out.splitlines()
    assert shown[0].startswith(f"{out}: in use by a run (process {first.pid} on host"), shown
    assert shown[1].startswith(f"{out / WORK}: 8192 members in 128 chunks"), shown
    first.send_signal(signal.SIGINT)  # the first run stops cleanly, its chunks kept
    first.wait(timeout=STOP_GUARD_S)
    assert first.returncode == 130, lines.wait_done()
    assert ChunkStore.verify_path(out / WORK, 0, json.loads(
        (out / WORK / "manifest.json").read_text())["fingerprint"])
    assert holder_of(out) is None and not (out / OUTPUT_LOCK).exists()


def test_of_two_runs_started_together_into_an_empty_folder_one_publishes(tmp_path):
    out = tmp_path / "out"
    runs = [start([*QUICK, "--out", str(out)]) for _ in range(2)]
    for run in runs:
        run.wait(timeout=300)
    codes = sorted(run.returncode for run in runs)
    errs = [run.stderr.read() for run in runs]
    assert codes == [0, 2], errs
    refused = errs[[run.returncode for run in runs].index(2)].strip().splitlines()
    assert len(refused) == 1 and ("in use by another run" in refused[0]
                                  or "already exists" in refused[0]), refused
    assert (out / "tennis_racket.nc").is_file() and not list(out.glob(".stability-*"))


def test_a_store_held_by_another_process_is_refused_naming_it(tmp_path):
    folder = tmp_path / "store"
    folder.mkdir()
    holder = subprocess.Popen([sys.executable, "-c", textwrap.dedent(f"""
        import sys, time
        sys.path.insert(0, {str(ROOT)!r})
        from stability.output.lock import FolderLock
        held = FolderLock({str(folder)!r}, {LOCK!r}).acquire()
        print("held", flush=True)
        time.sleep(60)
        """)], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        with pytest.raises(FolderBusy, match=f"process {holder.pid} on host"):
            ChunkStore(folder, {"run": 1}, 10, 5)
    finally:
        holder.kill()
        holder.wait()
    ChunkStore(folder, {"run": 1}, 10, 5).close()  # a lock dies with its process


# --- output names ------------------------------------------------------------------------


@pytest.mark.parametrize("dataset, message", [
    ("a b.nc", "no white space"),
    ("a\nb.nc", "no white space"),
    ("a\tb.nc", "no white space"),
    (".hidden.nc", "not hidden"),
    ("config.toml", "[output] dataset must be a string ending in .nc"),
    ("fig1_flips.png", "[output] dataset must be a string ending in .nc"),
])
def test_output_names_that_would_be_lost_are_refused_before_computing(tmp_path, capsys,
                                                                       dataset, message):
    status, err = run_here(capsys, "--out", str(tmp_path / "out"), "--set",
                           f"output.dataset={json.dumps(dataset)}")
    assert status == 2, err
    assert len(err) == 1 and message in err[0], err
    assert not (tmp_path / "out").exists()


def test_two_outputs_of_one_name_are_refused_before_computing(tmp_path):
    """Names that one file system would hold as one file (they differ in case only)."""
    for names in (["run.nc", "config.toml", "run.nc"], ["fig1_flips.png", "FIG1_FLIPS.png"]):
        with pytest.raises(ValueError, match="two outputs of this run are named"):
            check_target(tmp_path / "out", names, overwrite=False)
    assert not (tmp_path / "out").exists()


def test_a_dangling_link_at_an_output_name_is_an_existing_output(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "tennis_racket.nc").symlink_to(tmp_path / "nowhere.nc")
    with pytest.raises(ValueError, match="tennis_racket.nc already exists; pass --overwrite"):
        check_target(out, ["tennis_racket.nc"], overwrite=False)
    done = subprocess.run(stability_cmd(*QUICK, "--out", str(out), "--overwrite"), cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert not (tmp_path / "nowhere.nc").exists()  # the link was replaced, not written through
    assert (out / "tennis_racket.nc").is_file() and not (out / "tennis_racket.nc").is_symlink()


# --- chunks of another run ---------------------------------------------------------------


def test_a_chunk_of_another_run_is_not_taken_on_resume(tmp_path, body123, caplog):
    kwargs = dict(body=body123, axis=2, spin=1.0, epsilon=1e-3, members=64, h=0.01,
                  t_end=0.1, method="rk4", keep=stability.Keep(save_every=0),
                  options=stability.RunOptions(chunk_members=32, progress=False))
    mine = stability.run_ensemble(**stored(kwargs, store=tmp_path / "mine"), seed=1).load()
    stability.run_ensemble(**stored(kwargs, store=tmp_path / "other"), seed=2)
    for name in ("chunk-000000.nc", "chunk-000000.nc.sha256"):  # with its own valid checksum
        shutil.copy(tmp_path / "other" / name, tmp_path / "mine" / name)
    with caplog.at_level(logging.WARNING, logger="stability.output.store"):
        again = stability.run_ensemble(**stored(kwargs, store=tmp_path / "mine", resume=True),
                                       seed=1).load()
    xr.testing.assert_equal(again, mine)
    assert any("is not a chunk of this run" in r.getMessage() for r in caplog.records)
    np.testing.assert_array_equal(again.w0.values, mine.w0.values)

