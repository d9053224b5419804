"""Running a study (stability.study.runner): the kind's run is given its options once, as one
StudyRun; the outputs are published together, the work folder goes, and an interrupted run
publishes nothing; bad options are refused before any work."""

import pytest

from stability.ensemble.options import RunOptions
from stability.output.stream import RunInterrupted
from stability.study import Key, Schema, Section, StudyKind, StudyRun, StudySummary, run_study
from stability.study import runner

SCHEMA = Schema((Section("output", "where the results go",
                         (Key("dir", "str", "results/fake", "output folder"),)),))


class Fake:
    """A kind that writes fake.nc and records the options its run is given (``seen``); its run
    raises ``fails`` where that is set."""

    def __init__(self, monkeypatch):
        self.monkeypatch, self.seen, self.fails = monkeypatch, [], None

    def run(self, config, out_dir, options):
        self.seen.append(options)
        if self.fails is not None:
            raise self.fails
        (out_dir / "fake.nc").write_bytes(b"x")
        return StudySummary("fake", out_dir, files=[out_dir / "fake.nc"])

    def kind(self, resumable):
        """The kind, which the runner finds under its name."""
        made = StudyKind("fake", "a fake study", SCHEMA, run=self.run,
                         outputs=lambda config: ["fake.nc"], resumable=resumable)
        self.monkeypatch.setattr(runner, "study_kind", lambda name: made)
        return made


@pytest.fixture
def fake(monkeypatch):
    return Fake(monkeypatch)


def config(out):
    return {"study": "fake", "output": {"dir": str(out)}}


@pytest.mark.parametrize("resumable", [True, False])
def test_the_kinds_run_is_given_one_study_run_and_its_outputs_are_published(
        resumable, fake, tmp_path):
    fake.kind(resumable)
    out = tmp_path / "out"
    summary = run_study(config(out), threads=1, progress=False, history="stability run x")
    work = out / ".stability-work-fake"
    store = work if resumable else None
    assert fake.seen == [StudyRun(RunOptions(store=store, threads=1, progress=False),
                                  overwrite=True, history="stability run x")]
    assert summary.files == [out / "fake.nc"] and (out / "fake.nc").read_bytes() == b"x"
    assert sorted(p.name for p in out.iterdir()) == ["fake.nc"]  # no stage, lock or work left


def test_an_interrupted_run_publishes_nothing_and_removes_the_folder_it_made(fake, tmp_path):
    fake.kind(True)
    fake.fails = KeyboardInterrupt()
    out = tmp_path / "out"
    with pytest.raises(RunInterrupted, match="^interrupted; nothing was published$"):
        run_study(config(out), progress=False)
    assert not out.exists()


@pytest.mark.parametrize("options, words", [
    ({"threads": 0}, "threads must be a whole number from 1 to"),
    ({"scheduler": "nowhere"}, "scheduler must be 'dask' (a local cluster)"),
    ({"resume": True}, "study kind 'fake' runs in one piece; drop --resume"),
    ({"scheduler": "dask"}, "study kind 'fake' runs in one piece; drop --scheduler"),
])
def test_bad_options_are_refused_before_any_work(options, words, fake, tmp_path):
    fake.kind(False)
    with pytest.raises(ValueError, match=words.replace("(", r"\(").replace(")", r"\)")):
        run_study(config(tmp_path / "out"), **options)
    assert fake.seen == [] and not (tmp_path / "out").exists()


def test_resume_into_another_studys_stopped_run_is_refused(fake, tmp_path):
    fake.kind(True)
    out = tmp_path / "out"
    (out / ".stability-work-other").mkdir(parents=True)
    with pytest.raises(ValueError, match="it holds the stopped run of another "
                                         r"\(.stability-work-other, not .stability-work-fake\)"):
        run_study(config(out), resume=True)
    assert fake.seen == []
