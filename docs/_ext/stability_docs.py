"""Pages generated from the code when the documentation is built, so that they cannot drift.

When the configuration is read this writes ``docs/generated/``:

- ``scene_<name>.md``: each registered scene's equations, state and units, methods, invariants
  and exact solution (``stability.registry.SCENES``);
- ``methods.md``: the registered integrators and what they declare (``stability.METHODS``);
- ``presets.md``: the preset bodies, their moments and descriptions
  (``stability.RigidBody.presets()``);
- ``dataset_schema.md``: every Dataset kind's variables, dims, units, long names and notes
  (``stability.ensemble.schema.SCHEMAS``, the register the code that writes them reads);
- ``studies.md``: every study kind's keys, defaults, units and allowed values (the schemas that
  validate study files);
- ``cli.md``: the help of every ``stability`` command (the argument parser);
- ``work_precision.md``: the work-precision study, run at build time (``--quick`` when the
  environment variable ``STABILITY_DOCS_QUICK`` is 1), its report and figures;

and it removes from ``docs/api`` the pages autosummary wrote for names no longer listed.
"""

from __future__ import annotations

import importlib
import math
import os
import re
import shutil
import textwrap
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1]
ROOT = DOCS.parent
OUT = DOCS / "generated"
API = DOCS / "api"


def _cell(text) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def _table(header, rows) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(_cell(c) for c in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def scene_page(scene) -> str:
    """Equations, state, methods, invariants and exact solution of one scene."""
    state = _table(("component", "units"), zip(scene.components, scene.units))
    methods = ", ".join(f"`{name}`" for name in scene.methods)
    invariants = ", ".join(f"`{name}` ({_kept(scene, name)})" for name in scene.invariants)
    exact = "yes" if scene.exact is not None else "none in closed form"
    doc = scene_docstring(scene)
    doc = re.sub(r":(func|mod|class|meth|data|attr):`([^`]+)`", r"{py:\1}`\2`", doc)  # to MyST
    doc = _math_to_myst(doc)
    equations = (f"Equations:\n\n$$\n{scene.latex.strip()}\n$$" if scene.latex
                 else f"Equations: `{scene.equations}`")
    return (f"## Scene `{scene.name}`: {scene.title}\n\n"
            f"{equations}\n\n{doc}\n\n"
            f"State ({scene.width} numbers a member, in the kernels' frame):\n\n{state}\n"
            f"Methods: {methods}. Invariants checked: {invariants or 'none'}. "
            f"Exact solution: {exact}.\n")


def scene_docstring(scene) -> str:
    """The part of the docstring of the module that defines ``scene`` about it: where the
    module holds several scenes, each described from a paragraph that starts with its name
    (``Scene ``name``:`` or ````name``,``), the paragraphs from its own up to the next scene's,
    the module's opening ones on its first scene's page and its closing ones on its last's, so
    that a guide that shows every scene of a family shows each paragraph once."""
    from stability.registry import SCENES

    module = scene.tracked.__module__
    doc = (importlib.import_module(module).__doc__ or "").strip()
    names = [s.name for s in SCENES.values() if s.tracked.__module__ == module]
    paragraphs = re.split(r"\n\s*\n", doc)
    starts = {}
    for k, paragraph in enumerate(paragraphs):
        found = re.match(r"(?:Scene )?``(\w+)``", paragraph)
        if found and found.group(1) in names and found.group(1) not in starts:
            starts[found.group(1)] = k
    if scene.name not in starts:
        return doc
    order = sorted(starts.values())
    lo = starts[scene.name]
    hi = next((k for k in order if k > lo), len(paragraphs))
    if lo == order[0]:
        lo = 0  # the module's opening paragraphs
    return "\n\n".join(paragraphs[lo:hi])


def _math_to_myst(doc: str) -> str:
    """A docstring's mathematics in MyST: ``:math:`x``` roles and ``.. math::`` blocks."""
    doc = re.sub(r":math:`([^`]+)`", r"{math}`\1`", doc)
    lines, out, i = doc.split("\n"), [], 0
    while i < len(lines):
        if lines[i].strip() != ".. math::":
            out.append(lines[i])
            i += 1
            continue
        i, block = i + 1, []
        while i < len(lines) and (not lines[i].strip() or lines[i].startswith(" ")):
            block.append(lines[i])
            i += 1
        out += ["```{math}", textwrap.dedent("\n".join(block)).strip(), "```", ""]
    return "\n".join(out)


def _kept(scene, invariant) -> str:
    """Which of the scene's methods keep ``invariant`` to round-off (``Scene.kept_by``)."""
    kept = [name for name in scene.methods if scene.keeps(invariant, name)]
    if any(scene.keeps(invariant, name) is None for name in scene.methods):
        return "not conserved along a whole motion"
    if not kept:
        return "to each method's order"
    if len(kept) == len(scene.methods):
        return "to round-off by every method"
    names = ", ".join(f"`{name}`" for name in kept)
    return f"to round-off by {names}; by the others to their order"


def presets_page() -> str:
    """The bodies ``RigidBody.preset(name)`` builds, with their moments and descriptions."""
    from stability import RigidBody

    rows = []
    for name, description in RigidBody.presets().items():
        I1, I2, I3 = RigidBody.preset(name).moments
        rows.append((f"`{name}`", f"{I1:.4g}, {I2:.4g}, {I3:.4g}", description))
    return ("Every preset body, `stability.RigidBody.preset(name)` (in a study file "
            "`[body] preset = \"name\"`; `RigidBody.presets()` lists them), principal "
            "moments ascending:\n\n"
            + _table(("preset", "I1, I2, I3 (kg m²)", "what it is"), rows))


def methods_page() -> str:
    from stability import METHODS

    rows = []
    for spec in METHODS.values():
        keeps = [name for name, flag in (("|L|", spec.preserves_casimir),
                                         ("energy", spec.preserves_energy)) if flag]
        order = "exact" if math.isinf(spec.order) else f"{spec.order:g}"
        rows.append((f"`{spec.name}`", spec.title, order, spec.family,
                     ", ".join(keeps) or "-", "yes" if spec.attitude else "no",
                     spec.evaluations, spec.note))
    return ("Every registered integrator and what it declares (`stability.METHODS`, the "
            "registry the tests and the command `stability methods` read):\n\n"
            + _table(("name", "method", "order", "family", "keeps", "attitude",
                      "cost units a step", "when to use it"), rows))


def dataset_page() -> str:
    """Every Dataset kind of the register (``stability.ensemble.schema.SCHEMAS``): one table each."""
    from stability.ensemble.schema import KINDS, SCHEMAS
    from stability.study import STUDIES

    api = set(api_names())
    out = []
    for schema in SCHEMAS.values():
        writers = " and ".join(f"{{py:func}}`{name}`" if name in api else f"`{name}`"
                               for name in schema.written_by)
        if schema.name in STUDIES:
            where = (f"The study kind `{schema.name}` writes it to `{schema.file}` "
                     f"(`stability run studies/{schema.name}.toml`); built by {writers}.")
        else:
            where = f"Built by {writers}; `stability.save` writes it."
        if getattr(schema, "note", ""):  # a template, its variables named from a scene
            where += f" {schema.note}."
        rows = []
        for name, var in schema.variables.items():
            extra = dict(var.extra)
            notes = ["coordinate"] if var.coordinate else []
            if var.optional:
                notes.append(f"only in {var.optional}")
            notes += [f"`{key} = \"{extra[key]}\"`" for key in ("standard_name", "axis")
                      if key in extra]
            for key in ("flag_values", "flag_masks"):
                if key in extra:
                    pairs = zip(extra[key], extra["flag_meanings"].split())
                    notes.append(f"{key}: " + ", ".join(f"{v} `{m}`" for v, m in pairs))
            if "comment" in extra:
                notes.append(extra["comment"])
            rows.append((f"`{name}`", ", ".join(var.dims) or "(scalar)", var.units,
                         KINDS[var.kind], var.long_name, "; ".join(notes)))
        title = schema.title[0].upper() + schema.title[1:]
        out.append(f"### `{schema.name}`\n\n{title}. {where}\n\n"
                   + _table(("name", "dims", "units", "type", "long name", "notes"), rows))
    return "\n".join(out)


def _default(key) -> str:
    from stability.study.config import REQUIRED

    if key.default is REQUIRED:
        return "(required)"
    if key.default is None:
        return "(unset)"
    return f"`{key.default!r}`".replace("'", '"')


def studies_page() -> str:
    from stability.study import STUDIES

    out = []
    for kind in STUDIES.values():
        out.append(f"## `{kind.name}`: {kind.title}\n\n"
                   f"A study file starts with `study = \"{kind.name}\"`; its file in `studies/` "
                   f"is `studies/{kind.name}.toml` where one ships.\n")
        rows = [("(top)", f"`{k.name}`", _default(k), k.unit, k.allowed(), k.doc)
                for k in kind.schema.top]
        for section in kind.schema.sections:
            rows += [(f"`[{section.name}]`", f"`{k.name}`", _default(k), k.unit, k.allowed(),
                      k.doc) for k in section.keys]
        out.append(_table(("section", "key", "default", "unit", "allowed", "meaning"), rows))
    return "\n".join(out)


def cli_page() -> str:
    import argparse

    from stability.cli.main import build_parser

    parser = build_parser()
    parser.prog = "stability"
    out = ["```text", parser.format_help().rstrip(), "```", ""]
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                sub.prog = f"stability {name}"
                out += [f"### `stability {name}`", "", "```text", sub.format_help().rstrip(),
                        "```", ""]
    return "\n".join(out)


def work_precision_page(quick: bool) -> str:
    """Run the work-precision study and return its report, with its figures beside it."""
    from stability.study import run_study

    folder = OUT / "work_precision"
    if folder.exists():
        shutil.rmtree(folder)
    folder.mkdir(parents=True)
    run_study(ROOT / "studies" / "work_precision.toml", folder, quick=quick, progress=False,
              overrides=[("output.formats", "['png']")])
    report = (folder / "work_precision.md").read_text()
    report = report.replace("\n# ", "\n### ").replace("\n## ", "\n### ")
    if report.startswith("# "):
        report = "###" + report[1:]
    mode = ("in quick mode (`--quick`: fewer members and steps)" if quick
            else "with the study file as it is")
    return (f"Run {mode} on the machine that built these pages, by "
            "`stability run studies/work_precision.toml`; times are that machine's.\n\n"
            + report
            + "\n![speed against error of every integrator]"
              "(generated/work_precision/work_precision.png)\n"
            + "\n![invariant drift over long runs](generated/work_precision/invariant_drift.png)\n")


#: Modules whose public functions and classes the API reference lists (beside the top level).
API_MODULES = (
    ("Bodies and linear theory", ("core.body", "core.quaternions", "free_body.model",
                                  "heavy_top.model")),
    ("Exact solutions", ("free_body.exact", "free_body.exact_attitude", "heavy_top.exact",
                         "core.elliptic")),
    ("Ensembles, runs and files", ("free_body.spin_ensembles", "ensemble.starts",
                                   "free_body.ensemble_plan", "free_body.streamed",
                                   "free_body.integrate", "free_body.attitude", "output.io",
                                   "output.plain", "output.stream", "util.formatting",
                                   "ensemble.schema")),
    ("Measures and estimators", ("analysis.members", "analysis.fits", "analysis.regimes",
                                 "analysis.estimates", "free_body.measure",
                                 "free_body.tennis_racket.measure",
                                 "free_body.twisting_racket.geometric_phase",
                                 "analysis.periodic", "core.roots",
                                 "free_body.work_precision.drift", "free_body.accuracy")),
    ("Scenes, integrators and the engine", ("registry", "engine.scene", "engine.user_scene",
                                            "integrators", "free_body.methods", "engine")),
    ("Studies' library functions", ("free_body.twisting_racket.measure", "engine_body.measure",
                                     "struck.model", "struck.measure", "rolling.model",
                                     "rolling.measure", "heavy_top.measure",
                                     "earth.measure", "earth.model",
                                     "free_body.stability_map.measure",
                                     "free_body.work_precision.measure",
                                     "free_body.work_precision.sweeps",
                                     "free_body.stability_map.shapes",
                                     "free_body.tennis_racket.flipsweep", "free_body.polhodes")),
    ("Energy dissipation: damped bodies and dual spin", (
        "dissipation.model", "dissipation.measure", "dissipation.model_gyrostat",
        "dissipation.measure_gyrostat", "dissipation.figures")),
    ("Figures and animations", ("plotting.animation", "free_body.animation",
                                "heavy_top.animation", "free_body.figures")),
)


def public_names(module_name: str) -> list[str]:
    """Public functions and classes of ``stability.<module_name>``: its ``__all__``, else those
    defined in it whose names do not start with an underscore; those the top level exports are
    listed there only."""
    import inspect

    import stability

    top = {id(getattr(stability, n)) for n in stability.__all__}
    module = importlib.import_module(f"stability.{module_name}")
    if hasattr(module, "__all__"):
        names = list(module.__all__)
    else:
        names = [name for name, obj in vars(module).items()
                 if not name.startswith("_") and getattr(obj, "__module__", None) == module.__name__
                 and (inspect.isfunction(obj) or inspect.isclass(obj)
                      or hasattr(obj, "py_func"))]
    return [n for n in names if callable(getattr(module, n)) and id(getattr(module, n)) not in top]


def api_names() -> list[str]:
    """Every name the API reference lists, dotted from ``stability``."""
    import stability

    names = [f"stability.{n}" for n in stability.__all__ if callable(getattr(stability, n))]
    for _, modules in API_MODULES:
        names += [f"stability.{m}.{n}" for m in modules for n in public_names(m)]
    return names


def api_page() -> str:
    import stability

    out = ["API reference", "=" * 13, "",
           "Every public function and class, with its shapes and units (numpydoc docstrings).",
           "", "Top level", "---------", "", ".. currentmodule:: stability", "",
           ".. autosummary::", "   :toctree: ../api", ""]
    out += [f"   {n}" for n in stability.__all__ if callable(getattr(stability, n))]
    for title, modules in API_MODULES:
        out += ["", title, "-" * len(title), ""]
        for m in modules:
            out += [f"``stability.{m}``: {_first_line(m)}", "", ".. autosummary::",
                    "   :toctree: ../api", ""]
            out += [f"   {m}.{n}" for n in public_names(m)]
            out.append("")
    return "\n".join(out) + "\n"


def _first_line(module_name) -> str:
    doc = importlib.import_module(f"stability.{module_name}").__doc__ or ""
    line = doc.strip().splitlines()[0].rstrip(".") + "." if doc.strip() else ""
    return _escape_bars(line)


def generate(app=None) -> None:
    """Write every generated page (see the module docstring)."""
    from stability.registry import SCENES

    OUT.mkdir(exist_ok=True)
    for scene in SCENES.values():
        (OUT / f"scene_{scene.name}.md").write_text(scene_page(scene))
    (OUT / "methods.md").write_text(methods_page())
    (OUT / "presets.md").write_text(presets_page())
    (OUT / "dataset_schema.md").write_text(dataset_page())
    (OUT / "studies.md").write_text(studies_page())
    (OUT / "cli.md").write_text(cli_page())
    (OUT / "api.rst").write_text(api_page())
    drop_stale_api_pages()
    quick = os.environ.get("STABILITY_DOCS_QUICK") == "1"
    (OUT / "work_precision.md").write_text(work_precision_page(quick))


def drop_stale_api_pages() -> None:
    """autosummary writes a page per listed name into ``docs/api`` and never removes one: drop
    the pages of names no longer listed (a function renamed or removed), whose import would
    fail the build in a tree that built the documentation before."""
    if API.is_dir():
        keep = set(api_names())
        for page in API.glob("stability.*.rst"):
            if page.stem not in keep:
                page.unlink()


_LITERAL = re.compile(r"(``.*?``)")


def _escape_bars(line: str) -> str:
    """The docstrings write norms as |L| (plain text, as the terminal shows them); outside
    literals, escape the bars so that reStructuredText does not read substitutions."""
    return "".join(p if p.startswith("``") else p.replace("|", "\\|")
                   for p in _LITERAL.split(line))


def escape_bars(app, what, name, obj, options, lines) -> None:
    """Autodoc hook: :func:`_escape_bars` on every docstring line."""
    lines[:] = [_escape_bars(line) for line in lines]


def setup(app):
    app.connect("config-inited", lambda app, config: generate(app))  # before any page is read
    app.connect("autodoc-process-docstring", escape_bars, priority=400)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
