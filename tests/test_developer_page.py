"""What the developer page and the package's checklists name exists: every path, module,
function and table they quote in backticks, so that a rename or a move that forgets them fails
here rather than misleading the next reader."""

import ast
import importlib
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: The texts a developer follows: the page, and the module docstrings that hold checklists.
TEXTS = ("docs/developers.md", "stability/engine/scene.py", "stability/integrators/spec.py",
         "stability/registry.py")

PATH = re.compile(r"(?:stability|tests|docs|studies|examples|\.ci)/[\w./-]*")
FILE = re.compile(r"\w+\.py|\w+/")
DOTTED = re.compile(r"stability(?:\.\w+)+")
TABLE = re.compile(r"[A-Z][A-Z0-9]*_[A-Z0-9_]+|[A-Z]{3,}")
CLASS = re.compile(r"[A-Z][a-z]+(?:[A-Z][a-z]+)+|[A-Z][a-z]{3,}")

#: Names the texts quote that belong to other programs: dask's, Python's.
OTHERS = {"LocalCluster", "PYTHONPATH"}


def _quoted(relative: str) -> list[str]:
    """The spans in backticks (single or double) of a page, or of a module's docstring."""
    text = (ROOT / relative).read_text(encoding="utf-8")
    if relative.endswith(".py"):
        text = ast.get_docstring(ast.parse(text)) or ""
    return re.findall(r"`+([^`\n]+?)`+", text)


def _top_level_names() -> set[str]:
    """Every name bound at the top level of a module of the package or of the tests, the
    environment variables the package reads (``STABILITY_*`` strings in its source) and
    :data:`OTHERS`."""
    names = set(OTHERS)
    for path in [*ROOT.glob("stability/**/*.py"), *ROOT.glob("tests/**/*.py")]:
        source = path.read_text(encoding="utf-8")
        names.update(re.findall(r"[\"'](STABILITY_[A-Z_]+)[\"']", source))
        for node in ast.parse(source).body:
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
                names.add(node.name)
            elif isinstance(node, (ast.Assign, ast.AnnAssign)):
                targets = node.targets if isinstance(node, ast.Assign) else [node.target]
                names.update(t.id for t in targets if isinstance(t, ast.Name))
    return names


def _resolves(dotted: str) -> bool:
    """``stability.a.b.c``: a module, or a name found in the longest module it starts with."""
    parts = dotted.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            value = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        for name in parts[cut:]:
            if not hasattr(value, name):
                return False
            value = getattr(value, name)
        return True
    return False


def _missing(span: str, names: set[str], files: set[str]) -> str | None:
    span = span.strip()
    if PATH.fullmatch(span):
        return None if (ROOT / span).exists() else f"{span}: no such path"
    if FILE.fullmatch(span):
        return None if span.rstrip("/") in files else f"{span}: no file or folder of that name"
    match = DOTTED.match(span)
    if match:
        return None if _resolves(match.group(0)) else f"{match.group(0)}: does not resolve"
    if TABLE.fullmatch(span) or CLASS.fullmatch(span):
        return None if span in names else f"{span}: defined nowhere in the package or tests"
    return None


@pytest.mark.parametrize("text", TEXTS)
def test_every_path_module_and_table_the_developer_texts_name_exists(text):
    names = _top_level_names()
    files = {path.name for path in [*ROOT.glob("stability/**/*"), *ROOT.glob("tests/**/*")]}
    missing = sorted({problem for span in _quoted(text)
                      if (problem := _missing(span, names, files))})
    assert missing == [], f"{text} names what is not there:\n" + "\n".join(missing)


def test_the_check_finds_a_stale_name():
    names, files = {"SCENES"}, {"scene.py"}
    assert _missing("stability/no_such_module.py", names, files) == \
        "stability/no_such_module.py: no such path"
    assert _missing("old.py", names, files) == "old.py: no file or folder of that name"
    assert _missing("stability.engine.no_such_name", names, files) == \
        "stability.engine.no_such_name: does not resolve"
    assert _missing("OLD_TABLE", names, files) == "OLD_TABLE: defined nowhere in the package or tests"
    assert _missing("stability.engine.scene.Scene", names, files) is None
    assert _missing("scene.py", names, files) is None
