"""Old module paths still import, for one release, as their new modules and with a warning."""

import importlib
import subprocess
import sys
import warnings

import pytest

import stability
from stability.moved import MOVED, OLD_NAMES


@pytest.mark.parametrize("old", sorted(MOVED))
def test_an_old_path_is_its_new_module_and_warns(old):
    new = importlib.import_module(MOVED[old])
    parent = old.rpartition(".")[0]
    if parent in MOVED:  # an old package warns for itself when it is first imported: not here
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", FutureWarning)
            importlib.import_module(parent)
    sys.modules.pop(old, None)
    with pytest.warns(FutureWarning, match=f"{old} moved to {MOVED[old]}"):
        module = importlib.import_module(old)
    assert module is new
    assert module.__spec__.name == MOVED[old]  # the new module keeps its own spec


def test_old_paths_work_in_a_fresh_process_as_users_wrote_them():
    """``from stability.body import ...``, ``import stability.conventions as cv`` and the
    attribute ``stability.elliptic`` without an import, each with its warning."""
    code = ("import warnings; warnings.simplefilter('always')\n"
            "import stability\n"
            "from stability.body import RigidBody\n"
            "import stability.conventions as cv\n"
            "assert RigidBody is stability.RigidBody and cv.MEMBER == 'member'\n"
            "assert stability.elliptic is stability.core.elliptic\n")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    for old in ("stability.body", "stability.conventions", "stability.elliptic"):
        assert f"FutureWarning: {old} moved to {MOVED[old]}" in run.stderr


@pytest.mark.parametrize("old, name", sorted((old, name) for old in OLD_NAMES
                                             for name in OLD_NAMES[old]))
def test_an_old_modules_name_is_its_new_modules_and_warns(old, name):
    """A module whose path is now a family's package (``stability.struck``) still serves the
    names it held, each from the module that holds it now."""
    new = importlib.import_module(OLD_NAMES[old][name])
    module = importlib.import_module(old)
    vars(module).pop(name, None)  # served before: kept there since
    with pytest.warns(FutureWarning, match=f"{old}.{name} moved to {OLD_NAMES[old][name]}"):
        value = getattr(module, name)
    assert value is getattr(new, name)
    with pytest.raises(AttributeError, match="has no attribute 'no_such_name'"):
        module.no_such_name  # noqa: B018


def test_old_names_work_in_a_fresh_process_as_users_wrote_them():
    code = ("import warnings; warnings.simplefilter('always')\n"
            "from stability.struck import baseball_bat\n"
            "import stability.struck.model as model\n"
            "assert baseball_bat is model.baseball_bat\n")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert run.stderr.count("FutureWarning: stability.struck.baseball_bat moved to "
                            "stability.struck.model.baseball_bat") == 1


def test_a_name_that_never_was_a_module_is_an_attribute_error():
    with pytest.raises(AttributeError, match="has no attribute 'no_such_module'"):
        stability.no_such_module  # noqa: B018


def test_split_modules_and_moved_commands_work_in_a_fresh_process_as_users_wrote_them():
    """A module split in several (``stability.estimators``, ``stability.scenes``) still
    imports and serves its names, its old submodules included; ``python -m`` on a moved
    module's old path runs the new module."""
    code = ("import warnings; warnings.simplefilter('always')\n"
            "from stability.estimators import measured_growth_rate, Members\n"
            "from stability.scenes import SCENES, define_scene\n"
            "import stability.scenes.free_body as fb\n"
            "import stability.analysis.estimates as e, stability.registry as r\n"
            "assert measured_growth_rate is e.measured_growth_rate and SCENES is r.SCENES\n"
            "assert fb.FREE_BODY is SCENES['free_body']\n")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert ("FutureWarning: stability.estimators.measured_growth_rate moved to "
            "stability.analysis.estimates.measured_growth_rate") in run.stderr
    assert "FutureWarning: stability.scenes.free_body moved to stability.free_body.scene" \
        in run.stderr
    run = subprocess.run([sys.executable, "-m", "stability.gpu.bench", "--help"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert "usage: python -m stability.engine.gpu.bench" in run.stdout
    assert "FutureWarning: stability.gpu.bench moved to stability.engine.gpu.bench" in run.stderr
