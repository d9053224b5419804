"""Every study runs on the README's install: the package imports nothing beyond its core
requirements, but for the optional extras, each in the modules that say in one line what to
install when it is missing. And the package's own modules import one another one way: no circle,
no private name of another module.

Read from the source (every import, those inside functions included), so that no code path of
any study can reach a module that ``pip install -e .`` does not bring, and no import made late
inside a function hides a circle.
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
    "distributed": ("distributed", "stability.output.stream"),
    "numba.cuda": ("gpu", "stability.engine.gpu"),
    "trimesh": ("shapes", "stability.asteroid.model"),
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


def modules():
    """(dotted module name, path, parsed source) of every module of the package; a package is
    its ``__init__``."""
    for path in sorted(PACKAGE.rglob("*.py")):
        module = ".".join(path.relative_to(ROOT).with_suffix("").parts).removesuffix(".__init__")
        yield module, path, ast.parse(path.read_text(encoding="utf-8"))


def imports():
    """(module, imported name) for every absolute import in the package."""
    for module, _, tree in modules():
        for node in ast.walk(tree):
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


def internal_imports():
    """(importer, imported module, name or None, line, local name of the module or None) for
    every import of the package's own modules, those inside functions included: relative
    imports resolved, ``from pkg import sub`` an import of the submodule ``pkg.sub``,
    ``from pkg import name`` an import of ``pkg`` (its ``__init__``)."""
    parsed = list(modules())
    known = {module for module, _, _ in parsed}

    def owner(name):  # the module a dotted name lives in: "stability.a.f" -> "stability.a"
        while name not in known and "." in name:
            name = name.rsplit(".", 1)[0]
        return name

    for module, path, tree in parsed:
        package = module.split(".") if path.name == "__init__.py" else module.split(".")[:-1]
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                for alias in node.names:
                    if alias.name.split(".")[0] == "stability":
                        yield (module, owner(alias.name), None, node.lineno,
                               alias.asname if owner(alias.name) == alias.name else None)
                continue
            if not isinstance(node, ast.ImportFrom):
                continue
            source = node.module
            if node.level:  # relative: from the package, up level - 1
                base = package[:len(package) - (node.level - 1)]
                source = ".".join(base + ([node.module] if node.module else []))
            if source.split(".")[0] != "stability":
                continue
            for alias in node.names:
                if f"{source}.{alias.name}" in known:
                    yield (module, f"{source}.{alias.name}", None, node.lineno,
                           alias.asname or alias.name)
                else:
                    yield module, owner(source), alias.name, node.lineno, None


def circles(edges):
    """The strongly connected components of more than one node of the graph ``edges`` (node ->
    set of nodes), each sorted (Tarjan's algorithm, iterative)."""
    index, low, on_stack, stack, found = {}, {}, set(), [], []
    for start in sorted(edges):
        if start in index:
            continue
        work = [(start, iter(sorted(edges[start])))]
        index[start] = low[start] = len(index)
        stack.append(start)
        on_stack.add(start)
        while work:
            node, successors = work[-1]
            for nxt in successors:
                if nxt not in index:
                    index[nxt] = low[nxt] = len(index)
                    stack.append(nxt)
                    on_stack.add(nxt)
                    work.append((nxt, iter(sorted(edges.get(nxt, ())))))
                    break
                if nxt in on_stack:
                    low[node] = min(low[node], index[nxt])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        component.append(member)
                        if member == node:
                            break
                    if len(component) > 1:
                        found.append(sorted(component))
    return found


def _loaded_names(tree, known):
    """The modules ``importlib.import_module`` loads in ``tree`` by a name written there: a
    literal, or an f-string whose fields each stand for one or more parts of a dotted name
    (``f"stability.{family}"``: every module it can name)."""
    for node in ast.walk(tree):
        if not (isinstance(node, ast.Call) and node.args
                and ast.unparse(node.func) in ("importlib.import_module", "import_module")):
            continue
        name = node.args[0]
        if isinstance(name, ast.Constant) and isinstance(name.value, str):
            pattern = re.escape(name.value)
        elif isinstance(name, ast.JoinedStr) and name.values and isinstance(
                name.values[0], ast.Constant):
            pattern = "".join(re.escape(part.value) if isinstance(part, ast.Constant)
                              else r"[\w.]+" for part in name.values)
        else:
            continue
        yield from (module for module in known if re.fullmatch(pattern, module))


def _declared_loads(parsed):
    """The modules :mod:`stability.registry` loads: those each family's ``__init__`` names in
    its ``SCENES``, ``DATASETS`` and ``STUDIES`` (``"scene:HEAVY_TOP"``), the study kinds'
    when first asked for, the others as it is built."""
    for module, path, tree in parsed:
        if path.name != "__init__.py":
            continue
        for node in tree.body:
            if not (isinstance(node, ast.Assign) and any(
                    isinstance(target, ast.Name) and target.id in ("SCENES", "DATASETS", "STUDIES")
                    for target in node.targets)):
                continue
            for item in ast.walk(node.value):
                if isinstance(item, ast.Constant) and isinstance(item.value, str) \
                        and ":" in item.value:
                    yield f"{module}.{item.value.split(':')[0]}"


def import_graph() -> dict:
    """Each module of the package -> the modules its loading runs, as Python runs them: every
    import of :func:`internal_imports`; the ``__init__`` of each package above an imported
    module (``from stability.engine.scene import Scene`` runs ``stability/engine/__init__``
    first), but the importer's own packages, which are loaded before it; the names
    ``importlib.import_module`` loads (:func:`_loaded_names`); and the registry's loads of what
    the families declare (:func:`_declared_loads`)."""
    parsed = list(modules())
    known = {module for module, _, _ in parsed}
    edges = {module: set() for module in known}

    def add(importer, imported):
        parts = imported.split(".")
        for n in range(1, len(parts) + 1):
            target = ".".join(parts[:n])
            if target not in known or target == importer:
                continue
            above = n < len(parts)  # a package run on the way to the imported module
            if above and importer.startswith(target + "."):
                continue  # the importer's own package: already loaded
            edges[importer].add(target)

    for module, imported, *_ in internal_imports():
        add(module, imported)
    for module, _, tree in parsed:
        for imported in _loaded_names(tree, known):
            add(module, imported)
    for imported in _declared_loads(parsed):
        add("stability.registry", imported)
    return edges


def test_the_package_modules_import_each_other_without_a_circle():
    """Imports run one way, down the layers: a module imported back by a module it imports,
    however far round, is a circle; so is a submodule importing its own package's
    ``__init__``, which imports it. Counted as Python runs them (:func:`import_graph`): a
    package's ``__init__`` runs before any module inside it, and the modules loaded by name
    count as imports. The fix is never an import put inside a function (those count): move
    the shared code down, or pass it in."""
    found = circles(import_graph())
    assert found == [], "\n".join(
        f"{len(c)} modules import each other in a circle: {', '.join(c)}" for c in found)


def _private(name) -> bool:
    return name.startswith("_") and not name.startswith("__")


def test_no_module_imports_another_modules_private_names():
    """Neither ``from .x import _name`` nor ``x._name`` of a module ``x`` it imports: a helper
    two modules share is a public function of the lower one."""
    trees = {module: tree for module, _, tree in modules()}
    private, bound = set(), {}
    for module, imported, name, line, local in internal_imports():
        if imported == module:
            continue
        if name is not None and _private(name):
            private.add(f"{module}:{line} imports {imported}.{name}")
        if local is not None:
            bound.setdefault(module, {})[local] = imported
    for module, names in bound.items():
        for node in ast.walk(trees[module]):
            if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                    and node.value.id in names and _private(node.attr)):
                private.add(f"{module}:{node.lineno} uses {names[node.value.id]}.{node.attr}")
    assert sorted(private) == [], "\n".join(sorted(private))
