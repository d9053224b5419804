"""The study kinds (stability.study.kind): each declares a complete schema and is whole in the
registry when imported first, its Dataset is checked against CF, and a run's summary table
aligns."""

import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from stability.ensemble.options import RunOptions
from stability.study import STUDIES, ConfigError, load_study
from stability.study.kind import StudyRun

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


#: Imports the homes of the kinds in turn, each first in a process of its own: forked from one
#: that holds the libraries the package uses (a new interpreter each took a second and a half
#: to import them) and no module of the package, so each child imports the package afresh.
FRESH_IMPORTS = """
import importlib, os, sys, traceback
import matplotlib.figure, numba, numpy, pandas, scipy.integrate, xarray
assert not [name for name in sys.modules if name.split(".")[0] == "stability"]
failed = []
for home in sys.argv[1:]:
    pid = os.fork()
    if pid == 0:
        try:
            importlib.import_module(home)
            from stability.study import STUDIES
            assert all(kind.schema is not None for kind in STUDIES.values())
        except BaseException:
            traceback.print_exc()
            os._exit(1)
        os._exit(0)
    if os.waitpid(pid, 0)[1] != 0:
        failed.append(home)
print("failed:", failed)
sys.exit(1 if failed else 0)
"""


def test_a_kind_imported_first_in_a_fresh_process_is_complete_in_the_registry():
    """A kind's module imports the framework, which registers every kind: imported first, the
    kind is still whole when the registry reads it (``import stability.dissipation.studies``)."""
    homes = sorted({kind.run.__module__ for kind in STUDIES.values()})
    run = subprocess.run([sys.executable, "-c", FRESH_IMPORTS, *homes], capture_output=True,
                         text=True, timeout=300)
    assert run.returncode == 0, (run.stdout[-500:], run.stderr[-4000:])
    assert run.stdout.strip() == "failed: []"
