"""The study kinds (stability.study.kind): each declares a complete schema, its Dataset is checked
against CF, the register loads a kind when first asked for, a run's options refuse what they do
not hold, and a run's summary table aligns."""

import re
import tomllib
from pathlib import Path

import pytest

from stability.ensemble.options import RunOptions
from stability.study import STUDIES, ConfigError, load_study
from stability.registry import STUDY_KINDS
from stability.study.kind import StudyKind, StudyKinds, StudyRun, quick_notes, study_kind

from ..helpers import default_dataset

ROOT = Path(__file__).resolve().parents[2]

#: Each study kind's study file in studies/, by kind.
STUDY_FILES = {tomllib.loads(path.read_text(encoding="utf-8"))["study"]: path
               for path in sorted((ROOT / "studies").glob("*.toml"))}


def test_every_kind_declares_a_complete_schema():
    for name, kind in STUDIES.items():
        assert kind.name == name
        described = kind.schema.describe()
        for section in kind.schema.sections:
            assert f"[{section.name}]" in described
            for key in section.keys:
                assert key.doc and f"{key.name} = " in described
        assert "output" in [s.name for s in kind.schema.sections]
        assert "dir" in [k.name for k in kind.schema.section("output").keys]
        # Quick mode is valid, alone or over the kind's study file (a kind whose sections
        # have no defaults: what a dispersion study disperses is the user's to say), and the
        # members option, if any, points at a real key.
        try:
            kind.resolve({"study": name, **kind.quick})
        except ConfigError:
            load_study(STUDY_FILES[name], quick=True)
        if kind.members_key is not None:
            kind.schema.section(kind.members_key[0]).key(kind.members_key[1])


def test_every_kind_has_its_dataset_checked_against_cf():
    """Some test passes each kind's Dataset (its file name) to ``assert_cf_compliant``, so that
    a new kind cannot ship a file that CF readers reject."""
    sources = "".join(path.read_text(encoding="utf-8")  # family folders too (tests/<family>/)
                      for path in sorted(Path(__file__).parents[1].rglob("test_*.py")))
    checked = set(re.findall(r'assert_cf_compliant\([^,\n]*"([^"\n]+\.nc)"', sources))
    for name, kind in STUDIES.items():
        assert default_dataset(kind) in checked, name


def test_summary_table_aligns_names_over_units_and_cells():
    from stability.study.kind import StudySummary, SummaryTable

    table = SummaryTable("two rules", [("rule", ""), ("error", "rel."), ("step", "s")],
                         [("a", "+1.0e-03", "0.1"), ("long_name", "no flip", "12.5")])
    assert table.text().splitlines() == [
        "two rules",
        "rule          error  step",
        "             (rel.)   (s)",
        "a          +1.0e-03   0.1",
        "long_name   no flip  12.5",
    ]
    summary = StudySummary("x", ".", rows=[("wall time", "1.0", "s")], tables=[table])
    assert summary.table().split("\n\n") == ["wall time  1.0  s", table.text()]


def test_a_study_run_holds_run_options_and_refuses_anything_else():
    options = StudyRun()
    assert (options.run, options.overwrite, options.history) == (RunOptions(), False, None)
    with pytest.raises(ValueError, match="run must be a stability.RunOptions, got dict"):
        StudyRun({"threads": 2})
    with pytest.raises(ValueError, match="overwrite must be True or False, got 'yes'"):
        StudyRun(overwrite="yes")


def test_the_register_loads_a_kind_only_when_it_is_first_asked_for():
    asked = []
    kinds = StudyKinds()
    kinds.declare({"b": ("m", "B"), "a": ("m", "A")}, lambda where: asked.append(where) or where[1])
    assert (list(kinds), len(kinds), asked) == (["b", "a"], 2, [])
    assert kinds["a"] == "A" and asked == [("m", "A")]


def test_the_register_holds_the_kinds_the_families_declare():
    assert list(STUDIES) == list(STUDY_KINDS) == sorted(STUDY_KINDS)


def test_a_kind_is_found_by_name_or_refused_naming_the_kinds():
    assert study_kind("bat") is STUDIES["bat"]
    with pytest.raises(ValueError, match="unknown study kind 'bats'; known kinds: bat, "):
        study_kind("bats")


def test_quick_notes_say_what_quick_sets_or_that_it_sets_nothing():
    bare = StudyKind("bare", "no quick mode", STUDIES["bat"].schema, run=print, outputs=list)
    assert quick_notes(bare) == ["--quick changes nothing in this kind"]
    notes = quick_notes(STUDIES["bat"])
    assert notes[0] == "--quick sets (a small, fast run):"
    assert all(line.startswith("  ") and len(line) <= 96 for line in notes[1:])
