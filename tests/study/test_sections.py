"""The checks the study kinds share (stability.study.sections): a count too large for memory is
refused, naming its key, before any work; a run's options completed by its file's ``[run]``."""

import os
from pathlib import Path

import pytest

from stability.ensemble.options import RunOptions
from stability.study.kind import StudyRun
from stability.study.sections import study_run_options

from ..helpers import one_line

ROOT = Path(__file__).resolve().parents[2]
#: An ensemble no machine holds.
ABSURD = "10000000000000"


#: kind -> (arguments making its count absurd, fragments of the line).
MEMORY = {
    "bat": (["--set", f"strikes.count={ABSURD}"], ["[strikes] count = " + ABSURD]),
    "dual_spin": (["--set", f"integration.samples={ABSURD}"],
                  ["[integration] samples = " + ABSURD]),
    "earth_wobble": (["--members", ABSURD], ["(--members): [wobble] members = " + ABSURD,
                                             "the summaries of"]),
    "engine_artefacts": (["--set", f"ensemble.members={ABSURD}"],
                         ["[ensemble] members = " + ABSURD]),
    "explorer": (["--set", f"integration.samples={ABSURD}"],
                 ["[integration] samples = " + ABSURD]),
    "gyroscope": (["--set", f"spins.count={ABSURD}"], ["[spins] count = " + ABSURD]),
    "rolling": (["--members", ABSURD], ["(--members): [launch] members = " + ABSURD]),
    "rolling samples": (["--set", f"launch.samples={ABSURD}"],
                        ["[launch] samples = " + ABSURD]),
    "sleeping_top": (["--members", ABSURD], ["(--members): [ensemble] members = " + ABSURD]),
    "twisting_racket": (["--set", f"ensemble.members={ABSURD}"],
                        ["[ensemble] members = " + ABSURD]),
}


@pytest.mark.parametrize("case", sorted(MEMORY))
def test_absurd_count_is_refused_by_the_memory_check(case, tmp_path, capsys):
    args, fragments = MEMORY[case]
    out = tmp_path / "out"
    kind = case.split()[0]
    line = one_line(capsys, ["run", str(ROOT / "studies" / f"{kind}.toml"), "--quick",
                             "--out", str(out), "--no-progress", *args])
    for fragment in [*fragments, "TiB in memory, above the", "a run may hold; "]:
        assert fragment in line, (fragment, line)
    assert "this machine has" in line or not hasattr(os, "sysconf")
    assert not out.exists()


def test_a_studys_run_options_take_the_files_scheduler_and_chunks_where_none_is_given():
    given = StudyRun(RunOptions(store="work", resume=True, threads=2, progress=False))
    assert study_run_options({"run": {"scheduler": "dask", "chunk_members": 64}}, given) == (
        RunOptions(store="work", resume=True, scheduler="dask", chunk_members=64, threads=2,
                   progress=False))
    given = StudyRun(RunOptions(scheduler="tcp://host:8786"))
    assert study_run_options({"run": {"scheduler": "dask", "chunk_members": 0}}, given) == (
        RunOptions(scheduler="tcp://host:8786"))
