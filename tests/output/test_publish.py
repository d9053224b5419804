"""Publishing outputs (stability.output.publish): which names may be an output's, the journal
a publication writes, and a text written whole or not at all. Interrupted and concurrent
publications are the fault suite's (tests/test_faults_boundary.py)."""

import json

import pytest

from stability.output.publish import JOURNAL_FORMAT, journal_text, name_problem, write_text


@pytest.mark.parametrize("name, problem", [
    ("tennis_racket.nc", None), ("figure 1.png", "no white space or control characters"),
    ("", "not empty"), (None, "not empty"), ("a/b.nc", "no folder part"),
    ("..", "no folder part"), ("a\\b.nc", "no folder part"),
    (".hidden.nc", "not hidden: no leading dot"), ("tab\tname", "no white space or control"),
    ("bell\x07.nc", "no white space or control characters"), ("x" * 256, "at most 255 bytes"),
    ("é" * 128, "at most 255 bytes"),  # 256 bytes in UTF-8
])
def test_an_outputs_name_is_a_plain_visible_file_name(name, problem):
    found = name_problem(name)
    assert (found is None) if problem is None else found.startswith(problem)


def test_the_journal_lists_the_names_published():
    text = journal_text(["a.nc", "b.png"])
    assert text.endswith("\n")
    assert json.loads(text) == {"format": JOURNAL_FORMAT, "names": ["a.nc", "b.png"]}


def test_a_text_is_written_whole_under_its_own_name(tmp_path):
    path = write_text(tmp_path / "table.md", "| a |\n")
    assert path.read_text() == "| a |\n"
    write_text(path, "| b |\n")  # replaced by a rename: never a partial file
    assert path.read_text() == "| b |\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["table.md"]  # no temporary left
