"""The register of Dataset kinds (``stability.ensemble.schema``): every study's Dataset is declared there,
each study's written file is held to its declaration, and the check fails on a file that departs.

Each study's file is checked where its own tests already run the study (``assert_declared``
beside ``assert_cf_compliant``, on the same quick runs, so that no study runs twice); this module
checks that no study kind is left out, that the register is consistent and low in the imports,
that the Dataset reference shows it, and that the check catches a missing variable, other units,
other dims, another type or an undeclared variable.
"""

import ast
import importlib
import re
import sys
from pathlib import Path

import numpy as np
import pytest

import stability
from stability.ensemble.schema import KINDS, SCHEMAS
from stability.study import STUDIES

from .helpers import assert_declared, default_dataset

ROOT = Path(__file__).resolve().parents[1]
BODY = stability.RigidBody(1.0, 2.0, 3.0, physical=False)


def test_every_study_kind_declares_the_dataset_it_writes():
    for name, kind in STUDIES.items():
        assert name in SCHEMAS, f"study kind {name!r} has no declaration in stability.ensemble.schema"
        assert SCHEMAS[name].file == default_dataset(kind), name


def test_every_study_kinds_written_file_is_held_to_its_declaration():
    """Some test passes each kind's written file to ``assert_declared`` with the kind's name,
    so that a new kind cannot ship a Dataset its declaration does not describe."""
    sources = "".join(path.read_text(encoding="utf-8")
                      for path in sorted(Path(__file__).parent.rglob("test_*.py")))
    checked = set(re.findall(r'assert_declared\([^\n]*, "(\w+)"\)', sources))
    assert set(STUDIES) - checked == set()


def test_every_declaration_is_complete_and_names_the_code_that_writes_it():
    for schema in SCHEMAS.values():
        for dotted in schema.written_by:
            module, _, name = dotted.rpartition(".")
            assert callable(getattr(importlib.import_module(module), name, None)), dotted
        for name, var in schema.variables.items():
            assert var.units and var.long_name and var.kind in KINDS, (schema.name, name)
            assert all(isinstance(d, str) and d for d in var.dims), (schema.name, name)
            if var.dims == (name,):  # an index: a coordinate of its own dimension
                assert var.coordinate, (schema.name, name)
            assert set(dict(var.extra)) <= {"standard_name", "axis", "flag_values",
                                             "flag_masks", "flag_meanings", "comment"}


def test_the_register_imports_nothing_of_the_package_but_the_conventions():
    """It sits low in the import order: every module may import it."""
    tree = ast.parse((ROOT / "stability" / "ensemble" / "schema.py").read_text(encoding="utf-8"))
    inside = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level > 0:
            inside += [".".join(filter(None, (node.module, a.name))) for a in node.names]
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("stability"):
            inside.append(node.module)
        elif isinstance(node, ast.Import):
            inside += [a.name for a in node.names if a.name.startswith("stability")]
    assert sorted(inside) == ["util.conventions"]


def test_the_dataset_reference_shows_every_declared_variable():
    sys.path.insert(0, str(ROOT / "docs" / "_ext"))
    try:
        from stability_docs import dataset_page
    finally:
        sys.path.remove(str(ROOT / "docs" / "_ext"))
    sections = re.split(r"^### ", dataset_page(), flags=re.M)[1:]
    shown = {s.split("`")[1]: s for s in sections}
    assert list(shown) == list(SCHEMAS)
    for schema in SCHEMAS.values():
        for name, var in schema.variables.items():
            row = f"| `{name}` | {', '.join(var.dims) or '(scalar)'} | {var.units} |"
            assert row in shown[schema.name], (schema.name, name)


@pytest.fixture(scope="module")
def ensemble_file(tmp_path_factory):
    """A small time-series ensemble, saved."""
    ds = stability.run_ensemble(BODY, 2, 1.0, 1e-3, 8, h=0.05, t_end=2.0,
                                keep=stability.Keep(save_every=4))
    return stability.save(ds, tmp_path_factory.mktemp("schema") / "ensemble.nc")


def test_the_ensemble_as_run_summaries_only_and_with_its_attitude_is_as_declared(
        ensemble_file, tmp_path):
    assert_declared(ensemble_file, "ensemble")
    summaries = stability.run_ensemble(BODY, 2, 1.0, 1e-3, 8, h=0.05, t_end=2.0,
                                       keep=stability.Keep(save_every=0))
    attitude = stability.run_ensemble(BODY, 2, 1.0, 1e-3, 4, h=0.05, t_end=1.0,
                                      keep=stability.Keep(save_every=4, attitude=True),
                                      method="rk4")
    assert "w" not in summaries and "q" in attitude  # the optional variables, absent and there
    assert_declared(stability.save(summaries, tmp_path / "summaries.nc"), "ensemble")
    assert_declared(stability.save(attitude, tmp_path / "attitude.nc"), "ensemble")


def _drop(ds):
    return ds.drop_vars("fail_time")


def _units(ds):
    ds["w0"].attrs["units"] = "rad/s"
    return ds


def _long_name(ds):
    ds["passage_time"].attrs["long_name"] = "passage time"
    return ds


def _dims(ds):
    return ds.assign(w0=ds.w0.transpose())


def _kind(ds):
    return ds.assign(status=ds.status.astype(float))


def _undeclared(ds):
    return ds.assign(spin_rate=("member", np.zeros(ds.sizes["member"]),
                                {"long_name": "spin", "units": "rad s-1"}))


def _role(ds):
    return ds.set_coords("fail_time")


@pytest.mark.parametrize("change, found", [
    (_drop, "fail_time: missing"),
    (_units, "w0: units 'rad/s', declared 'rad s-1'"),
    (_long_name, "passage_time: long_name 'passage time'"),
    (_dims, "w0: dims ('axis', 'member'), declared ('member', 'axis')"),
    (_kind, "status: float, declared integer"),
    (_undeclared, "spin_rate: not declared"),
    (_role, "fail_time: a coordinate, declared a data variable"),
])
def test_the_check_fails_on_a_file_that_departs_from_its_declaration(ensemble_file, tmp_path,
                                                                   change, found):
    path = stability.save(change(stability.load(ensemble_file)), tmp_path / "changed.nc")
    with pytest.raises(AssertionError, match=re.escape(found)):
        assert_declared(path, "ensemble")


def test_a_scene_runs_declaration_is_the_scenes_and_the_check_reads_which_scene_it_is():
    """The scene template (``scene_run``) declares a run of heavy tops with the heavy top's
    components, units and invariants; the check reads the scene from the Dataset's attributes,
    so other units, a missing component or a scene it does not name are found; two variables
    of one name are refused when the declaration is made."""
    from stability.registry import SCENES
    from stability.ensemble.schema import SCENE_RUN

    scene = SCENES["heavy_top"]
    ds = stability.run_scene("heavy_top", "lp2", scene.example(4)[0], scene.example(1)[1][0],
                             h=0.01, n_steps=20, save_every=5,
                             options=stability.RunOptions(progress=False))
    declared = SCENE_RUN.of(scene.name, scene.components, scene.units,
                            invariants=scene.invariants)
    assert declared["g3"].dims == ("member", "time") and declared["g3"].units == "1"
    assert declared["m1_final"].units == "kg m2 s-1" and "vertical_norm_drift" in declared
    assert SCENE_RUN.problems(ds) == declared.problems(ds) == []
    changed = ds.copy()
    changed["m1"].attrs["units"] = "rad s-1"
    assert SCENE_RUN.problems(changed) == ["m1: units 'rad s-1', declared 'kg m2 s-1'"]
    assert SCENE_RUN.problems(ds.drop_vars("g2_final")) == ["g2_final: missing"]
    unnamed = ds.copy()
    del unnamed.attrs["scene_units"]
    assert SCENE_RUN.problems(unnamed) == ["attribute scene_units: missing (it names the scene "
                                           "the Dataset is declared by)"]
    with pytest.raises(ValueError, match="'h' would name two variables"):
        SCENE_RUN.of("clock", ["h"], ["s"])
