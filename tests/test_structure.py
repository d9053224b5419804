"""The package's shape, read from its source: layers that import one way, modules of one idea,
imports at the top, every module tested, a module's name meaning one thing.

The layers and their order are those of the design (``docs/developers.md``): ``util`` at the
bottom, then ``core``, then the shared machinery (``output``, ``plotting``, ...). A layer
imports only the layers below it. The package is moving to that layout; the layers checked here
are those it has reached.
"""

import ast
import importlib
from pathlib import Path

from .test_dependencies import internal_imports, modules

ROOT = Path(__file__).resolve().parents[1]

#: Each layer reached so far, and what it may import besides itself (module paths from
#: ``stability``). ``ensemble``, ``analysis``, ``output`` and ``plotting`` are one level of the
#: design: they may import each other (no module circle, which the test below forbids).
LAYERS = {
    "util": set(),
    "core": {"util"},
    "integrators": {"util", "core"},
    "engine": {"util", "core", "integrators"},
    "ensemble": {"util", "core", "integrators", "engine", "output", "version"},
    "analysis": {"util", "core", "ensemble"},
    "output": {"util", "core", "ensemble", "version"},
    "plotting": {"util", "core", "output"},
    "uncertainty": {"util", "core", "ensemble", "analysis", "plotting"},
    "tangents": {"util", "core", "integrators", "engine", "ensemble", "output", "plotting",
                 "version"},
}

#: Imports against the layer order still in the code, each with its reason, until it goes.
UPWARD: dict = {}

#: Where a family builds on another, each importing module with its reason: no other module of a
#: family imports another family, and the family's docstring names the modules it imports.
BUILDS_ON = {
    ("stability.asteroid.model", "free_body"): "the spin state from the periods inverts the "
                                               "free body's exact solution, and its attitude "
                                               "is the exact attitude",
    ("stability.earth.model", "free_body"): "Euler's wobble is the free body's oscillation "
                                            "about its stable axis",
    ("stability.earth.measure", "free_body"): "the wobble is run as a free-body ensemble and "
                                              "integration",
    ("stability.engine_body.scene", "free_body"): "the engines' state starts where the attitude "
                                                  "scene's does",
    ("stability.engine_body.measure", "free_body"): "the engines' flips against the exact "
                                                    "motion and the linear theory",
}

#: Lines a module may have; those over it hold two ideas (or more), but for these, each with
#: its reason, until they are split.
MAX_LINES = 800
LONG_MODULES = {
    "stability.core.body": "one public class with its constructors, parts and presets: 393 "
                           "lines of code, the rest the numpydoc of the API users call most",
}

#: Imports of the package's own modules inside functions, allowed at most: for the command
#: line's start-up time (the studies, matplotlib) and the optional GPU path (numba-cuda). The
#: count may only fall.
MAX_LOCAL_IMPORTS = 18

#: Modules that may have no test module of their own (:data:`COVERED_ELSEWHERE`); may only fall.
MAX_COVERED_ELSEWHERE = 20

#: Modules without a test module of their name, and the tests that exercise them: the figures,
#: drawn by their studies' tests; the scenes checked only by the registry-wide checks (and their
#: families' tests); and helpers exercised through the modules that use them. At most
#: MAX_COVERED_ELSEWHERE of them.
COVERED_ELSEWHERE = {
    "stability.asteroid.figures": "tests/asteroid/studies/test_tumbler.py",
    "stability.dissipation.figures": "tests/dissipation/studies/test_explorer.py, "
                                     "tests/dissipation/studies/test_dual_spin.py",
    "stability.earth.figures": "tests/earth/test_measure.py, tests/earth/studies/test_equinoxes.py",
    "stability.engine_body.figures": "tests/engine_body/studies/test_engine_artefacts.py",
    "stability.free_body.stability_map.figures": "tests/free_body/stability_map/test_study.py",
    "stability.free_body.twisting_racket.figures": "tests/free_body/twisting_racket/test_study.py",
    "stability.free_body.work_precision.figures": "tests/free_body/work_precision/test_study.py",
    "stability.heavy_top.figures": "tests/heavy_top/studies/test_gyroscope.py, "
                                   "tests/heavy_top/studies/test_sleeping_top.py",
    "stability.rolling.figures": "tests/rolling/studies/test_rolling.py",
    "stability.struck.figures": "tests/struck/studies/test_bat.py",
    "stability.uncertainty.figures": "tests/free_body/dispersion/test_study.py (its figure)",
    "stability.earth.scene": "tests/earth/studies/test_equinoxes.py, tests/test_registry.py",
    "stability.free_body.scene": "tests/test_registry.py",
    "stability.free_body.scene_attitude": "tests/test_registry.py",
    "stability.rolling.scene": "tests/test_registry.py",
    "stability.struck.scene": "tests/test_registry.py",
    "stability.engine.gpu.throughput": "tests/cli/test_gpu_bench.py "
                                       "(python -m stability.cli.gpu_bench)",
    "stability.engine.gpu.retarget": "tests/engine/gpu/test_kernels.py (each kernel's device twin)",
    "stability.integrators.munthe_kaas": "tests/integrators/test_geometric.py",
    "stability.util.interrupts": "tests/test_faults.py, tests/test_animation.py, "
                                 "tests/ensemble/test_chunks.py (real SIGINTs)",
}


#: Module names found in more than one folder of the package, each with its one meaning: the
#: shape every family (or study) repeats, and a loop's CUDA twin named as the CPU's. Any other
#: name is one module's, so that a name says which module it is.
REPEATED_NAMES = {
    "scene": "a family's scenes (stability.engine.scene: the Scene they are)",
    "methods": "a family's METHODS: its step kernels and their MethodSpecs",
    "model": "a family's formulas and presets, nothing that runs members",
    "exact": "a family's exact solution",
    "measure": "a family's or a study's runs and what is measured in them",
    "schema": "the declarations of the Datasets a family, a study or a layer writes",
    "figures": "a family's or a study's figures, drawn from its Datasets",
    "study": "a study kind in its study's own sub-package",
    "common": "what the study kinds in a family's studies/ share (its one module besides them)",
    "animation": "an animation: a family's of its body, written by stability.plotting.animation",
    "adaptive": "the adaptive member loop: the engine's, and its CUDA twin in stability.engine.gpu",
    "driver": "the engine's Python driver of the member loop, and its CUDA twin's",
}


def layer(module: str) -> str:
    """The first part of a module path below ``stability`` ('' for the package itself)."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


def test_each_layer_imports_only_the_layers_below_it():
    wrong = []
    for module, imported, *_ in internal_imports():
        own = layer(module)
        if own not in LAYERS or layer(imported) == own:
            continue
        target = layer(imported)
        if target not in LAYERS[own] and (own, target) not in UPWARD:
            wrong.append(f"{module} imports {imported} ({own} may import "
                         f"{', '.join(sorted(LAYERS[own])) or 'nothing of the package'})")
    assert wrong == [], "\n".join(wrong)


def test_no_module_serves_names_from_elsewhere():
    """A name is imported from the module that defines it or re-exports it: no module-level
    ``__getattr__`` hands out another module's names, but the package's own, which imports the
    matplotlib names of ``ON_FIRST_USE`` when first used; and no module puts a finder on
    ``sys.meta_path``."""
    serving = []
    for module, _, tree in modules():
        for node in tree.body:
            names = ([node.name] if isinstance(node, ast.FunctionDef) else
                     [t.id for t in node.targets if isinstance(t, ast.Name)]
                     if isinstance(node, ast.Assign) else [])
            if "__getattr__" in names and module != "stability":
                serving.append(f"{module} has a module __getattr__")
        serving += [f"{module} uses sys.meta_path" for node in ast.walk(tree)
                    if isinstance(node, ast.Attribute) and node.attr == "meta_path"]
    assert serving == [], "\n".join(serving)


def _defined(tree) -> set:
    """The names a module's own top-level statements bind (``try``/``if`` bodies included), not
    those it imports."""
    names, todo = set(), list(tree.body)
    while todo:
        node = todo.pop()
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            names.update(n.id for t in targets for n in ast.walk(t) if isinstance(n, ast.Name))
        elif isinstance(node, (ast.Try, ast.If)):
            todo += [*node.body, *node.orelse, *getattr(node, "finalbody", []),
                     *(b for h in getattr(node, "handlers", []) for b in h.body)]
    return names


def test_a_name_is_imported_from_the_module_that_defines_it():
    """No module but a package's ``__init__`` passes on a name it imported: every ``from m
    import name`` of the package's own modules names the module whose code binds it, so that a
    reader who follows an import finds the definition, and a family's module imported for a
    generic helper does not stand for the layer below it."""
    defined = {module: None if path.name == "__init__.py" else _defined(tree)
               for module, path, tree in modules()}
    relayed = [f"{module}:{line} takes {name} from {source}"
               for module, source, name, line, _ in internal_imports()
               if name is not None and defined[source] is not None
               and name not in defined[source]]
    assert relayed == [], "\n".join(relayed)


def test_no_module_is_longer_than_one_idea_but_those_listed():
    lines = {module: len(path.read_text(encoding="utf-8").splitlines())
             for module, path, _ in modules()}
    long = {module for module, n in lines.items() if n > MAX_LINES}
    assert long - set(LONG_MODULES) == set(), {m: lines[m] for m in long - set(LONG_MODULES)}
    assert set(LONG_MODULES) - long == set(), "split now: strike them from LONG_MODULES"


def _local_imports(tree) -> int:
    count = 0

    def visit(node, inside):
        nonlocal count
        for child in ast.iter_child_nodes(node):
            if inside and isinstance(child, ast.ImportFrom) and (
                    child.level or (child.module or "").startswith("stability")):
                count += 1
            elif inside and isinstance(child, ast.Import):
                count += sum(a.name.startswith("stability") for a in child.names)
            visit(child, inside or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)))

    visit(tree, False)
    return count


def test_imports_sit_at_the_top_of_their_modules_but_a_few():
    counts = {module: _local_imports(tree) for module, _, tree in modules()}
    total = sum(counts.values())
    assert total <= MAX_LOCAL_IMPORTS, sorted(counts.items(), key=lambda kv: -kv[1])[:10]


def test_every_module_has_a_test_module_or_is_listed_as_covered_elsewhere():
    def tested(path) -> bool:  # tests/<folders>/test_<name>.py, or flat tests/test_<name>.py
        folders = path.relative_to(ROOT / "stability").parent
        return any((ROOT / "tests" / where / f"test_{path.stem}.py").is_file()
                   for where in (folders, Path()))

    untested = set()
    for module, path, _ in modules():
        if path.name in ("__init__.py", "__main__.py") or tested(path):
            continue
        untested.add(module)
    assert untested - set(COVERED_ELSEWHERE) == set()
    assert len(COVERED_ELSEWHERE) <= MAX_COVERED_ELSEWHERE
    assert set(COVERED_ELSEWHERE) - untested == set(), "tested by name now: strike them"
    named = [f.strip(",") for where in COVERED_ELSEWHERE.values()
             for f in where.split(" (")[0].split()]
    missing = [f for f in named if not (ROOT / f).is_file()]
    assert missing == []


def _families() -> tuple:
    import stability.registry

    return stability.registry.FAMILIES


def test_a_family_imports_another_only_where_it_builds_on_it():
    """Every import from one family into another is a module of :data:`BUILDS_ON`, which holds
    no stale entry, and the importing family's docstring names each module it imports; the
    families that build on none import none."""
    families = _families()
    found, named = set(), {}
    for module, imported, *_ in internal_imports():
        own, target = layer(module), layer(imported)
        if own in families and target in families and own != target:
            found.add((module, target))
            named.setdefault(own, set()).add(imported)
    assert sorted(found - set(BUILDS_ON)) == [], "imports between families not in BUILDS_ON"
    assert sorted(set(BUILDS_ON) - found) == [], "BUILDS_ON entries no module needs"
    assert len(BUILDS_ON) <= 8
    for family in ("heavy_top", "dissipation", "struck", "rolling", "free_body"):
        assert family not in named, f"{family} imports another family: {sorted(named[family])}"
    for family, imported in named.items():
        doc = ast.get_docstring(ast.parse((ROOT / "stability" / family / "__init__.py")
                                          .read_text(encoding="utf-8"))) or ""
        unnamed = sorted(m for m in imported if f":mod:`{m}`" not in doc.replace("\n", " "))
        assert unnamed == [], f"stability/{family}/__init__.py does not name {unnamed}"


#: What runs members: a family's model holds its formulas and none of these.
RUNS_MEMBERS = ("stability.ensemble.chunks", "stability.ensemble.plan", "stability.engine",
                "stability.engine.driver", "stability.ensemble.scene_run")


def test_no_familys_model_runs_an_ensemble():
    """A family's ``model.py`` holds its formulas and presets; the runs and their measurement
    are its ``measure.py`` (the struck body and rolling had theirs in the model)."""
    families = _families()
    running = sorted({module for module, imported, *_ in internal_imports()
                      if module.endswith(".model") and layer(module) in families
                      and imported in RUNS_MEMBERS})
    assert running == [], f"models that run members: {running}"


#: The modules every family has: the scene it registers (its ``SCENES``) and its METHODS table,
#: its physics, its per-member measurement, its Datasets' declarations and its figures (with
#: ``__init__.py``, which declares what it registers).
FAMILY_MODULES = ("scene", "methods", "model", "measure", "schema", "figures")
#: The file of a study kind's module in a study of several modules (a sub-package of the
#: family), and the one module ``studies/`` may hold besides the kinds.
STUDY_MODULE, STUDIES_COMMON = "study", "common"


def test_every_family_has_the_same_shape():
    """Every family of :data:`stability.registry.FAMILIES` has the same shape, so that a family
    copied from the smallest (``stability/struck/``) has every part the others have:

    - ``model.py`` (the physics: equations, parameters, presets, starts; no runs),
      ``measure.py`` (the runs and what is measured per member), ``schema.py`` (its Datasets'
      declarations) and ``figures.py``;
    - ``scene.py`` (the scenes it registers: at least one) and ``methods.py`` (its METHODS
      table); ``exact.py`` where there is an exact solution (optional: the free body, the heavy
      top and the asteroid);
    - its study kinds (its ``STUDIES``) each ``studies/<kind>.py``, a module of the package
      ``studies/`` named after the kind, or, for a study of several modules (its own measure,
      schema and figures), a sub-package of the family whose ``study.py`` is the kind (the free
      body's ``tennis_racket/`` and the others: the free body has no ``studies/``, the
      dissipation family has both); ``studies/`` holds the kinds' modules and at most
      ``common.py`` (what its kinds share), and every other sub-package of a family is a study;
    - no ``studies.py`` or ``study.py`` beside ``model.py``: a kind is never at the top.

    Further modules are allowed, each of one idea (the structure test above holds the length):
    the families differ in how much physics they carry (the free body's exact attitude, GPU and
    streamed runs; the heavy top's animation; the gyrostat's model and measurement beside the
    damped body's, ``model_gyrostat.py`` and ``measure_gyrostat.py``), and a closed list would
    push unrelated ideas into one module past the length. What is fixed is what every family
    has, where a reader looks first."""
    import stability.registry

    wrong = []
    for family in stability.registry.FAMILIES:
        folder = ROOT / "stability" / family
        package = importlib.import_module(f"stability.{family}")
        modules_here = {p.stem for p in folder.glob("*.py")}
        packages_here = {p.name for p in folder.iterdir()
                         if p.is_dir() and (p / "__init__.py").is_file()}
        needed = set(FAMILY_MODULES) | {"__init__"}
        wrong += [f"{family} has no {m}.py" for m in sorted(needed - modules_here)]
        wrong += [f"{family} registers no scene"] * (not package.SCENES)
        wrong += [f"{family} has {m}.py at its top" for m in ("studies", STUDY_MODULE)
                  if m in modules_here]
        kinds_in_studies, study_packages = set(), set()
        for kind, where in package.STUDIES.items():
            module, attribute = where.split(":")
            parts = module.split(".")
            if parts == ["studies", kind]:
                kinds_in_studies.add(kind)
            elif len(parts) == 2 and parts[1] == STUDY_MODULE and parts[0] != "studies":
                study_packages.add(parts[0])
            else:
                wrong.append(f"{family}'s kind {kind} is at {where}, not studies.{kind}:STUDY "
                             f"or <sub-package>.{STUDY_MODULE}:STUDY")
                continue
            path = folder.joinpath(*parts).with_suffix(".py")
            if attribute != "STUDY" or not path.is_file():
                wrong.append(f"{family}'s kind {kind}: no STUDY in {path.relative_to(ROOT)}")
        if kinds_in_studies:
            present = {p.stem for p in (folder / "studies").glob("*.py")} - {"__init__"}
            wrong += [f"{family}/studies/{m}.py is no kind of {family}'s STUDIES"
                      for m in sorted(present - kinds_in_studies - {STUDIES_COMMON})]
        elif "studies" in packages_here:
            wrong.append(f"{family} has studies/ but registers no kind there")
        wrong += [f"{family}/{p}/ is neither studies/ nor a study registered as "
                  f"{p}.{STUDY_MODULE}:STUDY"
                  for p in sorted(packages_here - study_packages - {"studies"})]
    assert wrong == [], "\n".join(wrong)


def test_a_module_name_means_one_thing():
    """A module's name appears in one folder of the package, but the names of
    :data:`REPEATED_NAMES`, which mean one thing wherever they appear."""
    folders = {}
    for _, path, _ in modules():
        if path.name not in ("__init__.py", "__main__.py"):
            folders.setdefault(path.stem, []).append(path.relative_to(ROOT).as_posix())
    repeated = {stem: paths for stem, paths in folders.items() if len(paths) > 1}
    wrong = [f"{stem}.py means two things: {' and '.join(paths)}"
             for stem, paths in sorted(repeated.items()) if stem not in REPEATED_NAMES]
    assert wrong == [], "\n".join(wrong)
    assert set(REPEATED_NAMES) - set(repeated) == set(), "one module each now: strike them"
