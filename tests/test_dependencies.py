"""Every study runs on the README's install: the package imports nothing beyond its core
requirements, but for the optional extras, each in the modules that say in one line what to
install when it is missing.

Read from the source (every import, those inside functions included), so that no code path of
any study can reach a module that ``pip install -e .`` does not bring.
"""

import ast
import re
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "stability"

#: The import name of a distribution where the two differ.
IMPORT_NAMES = {"tomli-w": "tomli_w"}
#: Further packages a distribution installs beside its own (matplotlib's wheel brings
#: mpl_toolkits, whose mplot3d draws the 3-D figures and animations).
ALSO_INSTALLS = {"matplotlib": ("mpl_toolkits",)}

#: Optional modules: the extra that brings each, and the one module or package that may import
#: it (and refuses in one line, naming what to install, when it is missing).
OPTIONAL = {
    "distributed": ("distributed", "stability.stream"),
    "numba.cuda": ("gpu", "stability.gpu"),
}


def core_requirements() -> set[str]:
    """Import names of the ``[project] dependencies`` of pyproject.toml."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    names = set()
    for requirement in project["dependencies"]:
        name = re.match(r"[A-Za-z0-9_.-]+", requirement).group(0)
        names.add(IMPORT_NAMES.get(name.lower(), name))
        names.update(ALSO_INSTALLS.get(name.lower(), ()))
    return names


def imports():
    """(module, imported name) for every absolute import in the package."""
    for path in sorted(PACKAGE.rglob("*.py")):
        module = ".".join(path.relative_to(ROOT).with_suffix("").parts).removesuffix(".__init__")
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                for alias in node.names:
                    yield module, alias.name
            elif isinstance(node, ast.ImportFrom) and node.level == 0:
                yield module, node.module
                for alias in node.names:  # "from numba import cuda" imports numba.cuda
                    yield module, f"{node.module}.{alias.name}"


def test_the_package_imports_only_its_core_requirements_and_guarded_extras():
    core = core_requirements()
    outside = []
    for module, name in imports():
        top = name.split(".")[0]
        optional = next((key for key in OPTIONAL
                         if name == key or name.startswith(key + ".")), None)
        if optional is not None:
            extra, where = OPTIONAL[optional]
            if module != where and not module.startswith(where + "."):
                outside.append(f"{module} imports {name} (extra [{extra}])")
        elif top not in core and top not in sys.stdlib_module_names and top != "stability":
            outside.append(f"{module} imports {name}, not a core requirement")
    assert outside == [], "\n".join(outside)


def test_the_core_requirements_hold_what_the_studies_need():
    """The work-precision study's references are SciPy's DOP853: a core requirement."""
    assert {"numba", "numpy", "xarray", "netCDF4", "matplotlib", "scipy"} <= core_requirements()
