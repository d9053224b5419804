"""Old module paths still import, for one release, as their new modules and with a warning."""

import importlib
import subprocess
import sys

import pytest

import stability
from stability.moved import MOVED, MOVED_INTO


@pytest.mark.parametrize("old", sorted(MOVED))
def test_an_old_path_is_its_new_module_and_warns(old):
    new = importlib.import_module(MOVED[old])
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


def test_a_name_that_never_was_a_module_is_an_attribute_error():
    with pytest.raises(AttributeError, match="has no attribute 'no_such_module'"):
        stability.no_such_module  # noqa: B018


@pytest.mark.parametrize("package", sorted(MOVED_INTO))
def test_a_module_that_became_its_package_still_gives_its_names(package):
    """``from stability.earth import earth_moments`` (the module stability.earth is now the
    family's package): the name of the module it went to, with a warning; a name it never had
    is an AttributeError."""
    new = importlib.import_module(MOVED_INTO[package])
    old = importlib.import_module(package)
    name = next(n for n, v in vars(new).items()
                if not n.startswith("_") and getattr(v, "__module__", None) == new.__name__)
    with pytest.warns(FutureWarning, match=f"{package}.{name} moved to {new.__name__}.{name}"):
        assert getattr(old, name) is getattr(new, name)
    with pytest.raises(AttributeError, match="has no attribute 'no_such_name'"):
        old.no_such_name  # noqa: B018
