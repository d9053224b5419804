"""The store of a run's chunks (stability.output.store): it refuses another run and unasked
reuse, and does not open an unfinished run."""

import json

import pytest

import stability
from stability.output.store import open_store

from .test_stream import RUN


def test_store_refuses_another_run_and_unasked_reuse(tmp_path):
    stability.run_ensemble(**RUN,
                           options=stability.RunOptions(store=tmp_path / "s", chunk_members=256))
    with pytest.raises(ValueError, match=r"the settings changed since the run kept in .*s was "
                                         r"started: run_ensemble.h 0.01 there, 0.02 here; "):
        stability.run_ensemble(**dict(RUN, h=0.02),
                               options=stability.RunOptions(store=tmp_path / "s",
                                                            chunk_members=256))
    with pytest.raises(ValueError, match="started: chunk_members 256 there, 128 here; "):
        stability.run_ensemble(**RUN,
                               options=stability.RunOptions(store=tmp_path / "s",
                                                            chunk_members=128))
    with pytest.raises(ValueError, match="already holds this run, complete"):
        stability.run_ensemble(**RUN,
                               options=stability.RunOptions(store=tmp_path / "s",
                                                            chunk_members=256))
    with pytest.raises(ValueError, match=r"need a store: RunOptions\(store=...\)"):
        stability.run_ensemble(**RUN, options=stability.RunOptions(resume=True))


def test_unfinished_store_is_not_opened(tmp_path):
    stability.run_ensemble(**RUN,
                           options=stability.RunOptions(store=tmp_path / "s", chunk_members=256))
    manifest = tmp_path / "s" / "manifest.json"
    m = json.loads(manifest.read_text())
    m["complete"] = False
    manifest.write_text(json.dumps(m))
    with pytest.raises(ValueError, match="unfinished run; finish it with --resume"):
        open_store(tmp_path / "s")
