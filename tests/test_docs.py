"""The documentation: docstrings of the public API, and the site built with warnings as errors.

The build runs the gallery's examples and the work-precision study (quick mode) and writes the
pages generated from the code; the built HTML is then parsed, every internal link checked, and
nothing that a page loads by itself (script, style sheet, font, image) may come from the network:
the site, its equations included, works offline.
"""

import inspect
import os
import re
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urldefrag

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "docs" / "_ext"))

numpydoc = pytest.importorskip("numpydoc.docscrape", reason="the docs extra is not installed")

from stability_docs import (  # noqa: E402
    api_names, presets_page, scene_docstring)


def _object(dotted):
    import importlib

    module, _, name = dotted.rpartition(".")
    try:
        return getattr(importlib.import_module(module), name)
    except ModuleNotFoundError:  # a class attribute path
        parent, _, attr = module.rpartition(".")
        return getattr(getattr(importlib.import_module(parent), attr), name)


def test_every_source_compiles_without_a_warning():
    """No invalid escape such as "\\o" in a string that is not raw, where "\\t" or "\\n" would pass
    silently: a gallery page's docstring with "\\times" showed a tab and "imes" in its equations."""
    import warnings

    sources = [*ROOT.glob("stability/**/*.py"), *ROOT.glob("examples/*.py"),
               *ROOT.glob("docs/*.py")]
    assert len(sources) > 100
    for path in sources:
        text = path.read_text(encoding="utf-8")
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            compile(text, str(path), "exec")
        tree = __import__("ast").parse(text)
        doc = __import__("ast").get_docstring(tree, clean=False) or ""
        assert "\t" not in doc, f"{path}: a tab in the module docstring (make it r-prefixed)"


def test_the_examples_in_the_docstrings_of_the_package_namespace_run():
    """Every ``>>>`` example of what ``import stability`` gives (not marked to skip) runs and
    prints what it shows, with ``stability`` and ``np`` at hand as a reader has them."""
    import doctest

    import numpy as np

    import stability

    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    seen = set()
    for name in [n for n in dir(stability) if not n.startswith("_")]:
        for test in finder.find(getattr(stability, name), name,
                                extraglobs={"stability": stability, "np": np}):
            if test.name not in seen:
                seen.add(test.name)
                runner.run(test)
    results = runner.summarize(verbose=False)
    assert results.attempted >= 15 and results.failed == 0, results


def test_the_readme_python_example_runs_and_says_what_it_claims(tmp_path, monkeypatch):
    """The README's Python block runs as a reader copies it (its files go to a fresh folder),
    and the values its comments state hold."""
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), re.S)
    assert len(blocks) == 1
    monkeypatch.chdir(tmp_path)
    import numpy as np

    names = {}
    exec(compile(blocks[0], "README.md", "exec"), names)
    stability = names["stability"]
    assert f"{stability.growth_rate(names['body'], axis=2, spin=10.0):.3f}" == "9.048"
    one = names["one"]
    end = stability.exact_omega(names["body"], one.w.values[0], float(one.time[-1]))
    assert abs(one.w.values[-1] - end).max() < 1e-6 * 10.0
    w2 = one.w.values[:, 1]
    assert np.sum(np.signbit(w2[1:]) != np.signbit(w2[:-1])) == 4  # four flips
    assert {p.name for p in tmp_path.iterdir()} >= {"racket.nc", "flip.gif", "poinsot.png"}


def test_every_name_in_the_api_reference_has_a_numpydoc_summary():
    missing = []
    for name in api_names():
        obj = getattr(_object(name), "py_func", _object(name))
        doc = inspect.getdoc(obj)
        if not doc:
            missing.append(f"{name}: no docstring")
            continue
        parsed = (numpydoc.ClassDoc(obj) if inspect.isclass(obj) else numpydoc.FunctionDoc(obj))
        if not parsed["Summary"]:
            missing.append(f"{name}: no one-line summary")
    assert missing == []


def test_every_function_in_the_api_reference_documents_every_parameter():
    missing = []
    for name in api_names():
        obj = getattr(_object(name), "py_func", _object(name))
        if inspect.isclass(obj):
            target, doc = vars(obj).get("__init__"), numpydoc.ClassDoc(obj)
        else:
            target, doc = obj, numpydoc.FunctionDoc(obj)
        if not inspect.isfunction(target):
            continue
        documented = {part.strip() for p in doc["Parameters"] for part in p.name.split(",")}
        for param in inspect.signature(target).parameters.values():
            if param.name != "self" and param.kind not in (
                    param.VAR_POSITIONAL, param.VAR_KEYWORD) and param.name not in documented:
                missing.append(f"{name}({param.name})")
    assert missing == []


class _Links(HTMLParser):
    def __init__(self):
        super().__init__()
        self.links, self.ids = [], set()

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if "id" in attrs:
            self.ids.add(attrs["id"])
        for key in ("href", "src"):
            if tag in ("a", "img", "link", "script") and attrs.get(key):
                self.links.append(attrs[key])


# what a browser fetches by itself on opening a page (an <a href> is only followed when clicked)
_NETWORK = re.compile(r"^\s*(?:[a-z][a-z0-9+.-]*:)?//", re.IGNORECASE)  # https://, //host
_CSS_URL = re.compile(r"""@import\s+(?:url\(\s*)?['"]?([^'");\s]+)|url\(\s*['"]?([^'")\s]+)""",
                      re.IGNORECASE)
_LINK_RELS_NOT_LOADED = {"canonical", "alternate", "next", "prev", "index", "search", "author",
                         "license", "help", "top", "up", "first", "last", "bookmark"}


class _Loads(HTMLParser):
    """The URLs an HTML page loads when opened: scripts, style sheets, fonts, images, frames,
    media, and those in its inline styles (@import, url())."""

    def __init__(self):
        super().__init__()
        self.urls, self._in_style = [], False

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "link" and not set((attrs.get("rel") or "").lower().split()) <= \
                _LINK_RELS_NOT_LOADED:
            self.urls.append(attrs.get("href") or "")
        elif tag in ("script", "img", "iframe", "frame", "embed", "source", "track", "audio",
                     "video", "input"):
            self.urls += [attrs.get("src") or ""] + [
                part.split()[0] for part in (attrs.get("srcset") or "").split(",") if part.strip()]
            if tag == "video":
                self.urls.append(attrs.get("poster") or "")
        elif tag == "object":
            self.urls.append(attrs.get("data") or "")
        self.urls += _css_urls(attrs.get("style") or "")
        self._in_style = tag == "style"

    def handle_endtag(self, tag):
        self._in_style = False

    def handle_data(self, data):
        if self._in_style:
            self.urls += _css_urls(data)


def _css_urls(css):
    return [a or b for a, b in _CSS_URL.findall(css)]


def network_loads(site):
    """Every script, style sheet, font, image or other resource that a page of the built site
    (or one of its style sheets) loads from the network, as "file: URL"."""
    found = []
    for path in sorted(site.rglob("*")):
        if path.suffix == ".html":
            loads = _Loads()
            loads.feed(path.read_text(errors="replace"))
            urls = loads.urls
        elif path.suffix == ".css":
            urls = _css_urls(path.read_text(errors="replace"))
        else:
            continue
        found += [f"{path.relative_to(site)}: {url}" for url in urls if _NETWORK.match(url)]
    return found


@pytest.mark.slow
@pytest.mark.run_last
def test_the_site_builds_without_warnings_and_its_internal_links_resolve(tmp_path):
    out = tmp_path / "html"
    env = dict(os.environ, STABILITY_DOCS_QUICK="1", MPLBACKEND="Agg")
    done = subprocess.run(
        # -j 2: the pages read and written in two processes (the build runs last, when the
        # other tests are done)
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", "-j", "2",
         "-d", str(tmp_path / "doctrees"), "docs", str(out)],
        cwd=ROOT, env=env, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr[-4000:]
    pages = sorted(p for p in out.rglob("*.html")
                   if p.relative_to(out).parts[0] not in ("_static", "_sources"))
    assert (out / "index.html").exists() and (out / "gallery" / "index.html").exists()
    for needed in ("getting_started", "theory", "integrators", "dataset", "studies", "cli",
                   "scaling", "generated/api", "guide/twisting"):
        assert (out / f"{needed}.html").exists(), needed
    parsed = {}
    for page in pages:
        links = _Links()
        links.feed(page.read_text(errors="replace"))
        parsed[page] = links
    broken = []
    for page, links in parsed.items():
        for link in links.links:
            if re.match(r"^[a-z]+:", link) or link.startswith("//"):
                continue  # external: mailto, https, data
            target, anchor = urldefrag(unquote(link))
            target = target.split("?", 1)[0]  # a file's version query (?digest=...)
            path = (page.parent / target).resolve() if target else page
            if not path.exists():
                broken.append(f"{page.relative_to(out)} -> {link}")
            elif anchor and path.suffix == ".html" and path in parsed and \
                    anchor not in parsed[path].ids:
                broken.append(f"{page.relative_to(out)} -> {link} (no such anchor)")
    assert broken == []
    # the site works offline: nothing it loads comes from the network (MathJax is shipped in
    # _static/mathjax; sphinx-gallery's timing pages, which load CDN scripts, are not written)
    assert network_loads(out) == []
    assert (out / "_static" / "mathjax" / "tex-chtml.js").exists()
    theory = (out / "theory.html").read_text()
    assert re.search(r'<script [^>]*src="_static/mathjax/tex-chtml\.js', theory)
    # every cross-reference resolves: an unresolved one shows as its target ("python:None")
    unresolved = [f"{page.relative_to(out)}: {m.group(0)}" for page in pages
                  for m in re.finditer(r'<span class="pre">(?:python|numpy|xarray|numba|dask|'
                                       r'distributed):[^<]+</span>',
                                       page.read_text(errors="replace"))]
    assert unresolved == []
    # the gallery shows each example's code before what it printed and drew, and no object's
    # default repr ("<matplotlib.legend.Legend object at 0x...>")
    for page in sorted((out / "gallery").glob("plot_*.html")):
        html = page.read_text()
        shown = [i for i in (html.find("sphx-glr-script-out"), html.find("sphx-glr-single-img"))
                 if i >= 0]
        assert not shown or html.find("highlight-Python") < min(shown), page.name
        assert not re.search(r"object at 0x[0-9a-f]+", html), page.name
    # the generated pages carry what the code says: every study kind and every scene
    from stability.registry import SCENES
    from stability.study import STUDIES

    studies = (out / "studies.html").read_text()
    assert all(kind in studies for kind in STUDIES)
    guides = "".join((out / "guide" / f"{g}.html").read_text() for g in (
        "free_body", "torqued", "impacts_rolling", "twisting", "dissipation", "asteroids"))
    assert all("Scene <code" in guides and name in guides for name in SCENES)
    # each scene's equations are mathematics there (MathJax typesets them), not code
    assert all(scene.latex for scene in SCENES.values())
    assert guides.count('<div class="math') >= len(SCENES)
    api = (out / "generated" / "api.html").read_text()
    assert "run_ensemble" in api and "exact_attitude" in api


def test_the_gallerys_name_search_warns_of_nothing():
    """sphinx-gallery's search for the shortest path of each name the examples use asks every
    package above a name's module for that name (``stability.rolling`` for ``launch_formulas``
    of ``stability.rolling.model``): no package answers with a warning, so the build prints
    none, with no filter."""
    import ast
    import importlib
    import warnings

    from sphinx_gallery.backreferences import identify_names
    from sphinx_gallery.py_source_parser import split_code_and_text_blocks

    caught = []
    for path in sorted((ROOT / "examples").glob("plot_*.py")):
        blocks = split_code_and_text_blocks(str(path))[1]
        code = "\n".join(block.content for block in blocks if block.type == "code")
        for node in ast.walk(ast.parse(code)):  # sys.modules as after running the example
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("stability"):
                importlib.import_module(node.module)
        with warnings.catch_warnings(record=True) as found:
            warnings.simplefilter("always")
            identify_names(blocks, r":(?:func|class|meth|mod|data|attr|obj):`~?([\w.]+)`")
        caught += [f"{path.name}: {w.category.__name__}: {w.message}" for w in found]
    assert caught == []


def test_the_readme_and_getting_started_say_the_same_time_for_the_tennis_study():
    """One measured time (a run with the loop compiled: 8.0 s on two cores), said alike."""
    said = []
    for page in (ROOT / "README.md", ROOT / "docs" / "getting_started.md"):
        text = " ".join(page.read_text().split())
        found = re.search(r"tennis-racket study \(10,000 tossed rackets[^)]*\)", text)
        assert found, page
        said.append(found.group(0))
    assert said[0] == said[1] and "about 8 s on two cores" in said[0]


def test_a_family_guide_shows_each_paragraph_of_its_scenes_docstring_once():
    """The dissipation guide showed the module docstring of its three scenes three times, the
    torqued-body guide the Earth's twice: each scene's page now has its own part of it."""
    import importlib
    from collections import defaultdict

    from stability.registry import SCENES

    families = defaultdict(list)
    for scene in SCENES.values():
        families[scene.tracked.__module__].append(scene)
    shared = {module: scenes for module, scenes in families.items() if len(scenes) > 1}
    assert {"stability.dissipation.scene", "stability.earth.scene"} <= set(shared)
    for module, scenes in shared.items():
        doc = importlib.import_module(module).__doc__.strip()
        paragraphs = re.split(r"\n\s*\n", doc)
        shown = [re.split(r"\n\s*\n", scene_docstring(scene)) for scene in scenes]
        assert sum(shown, []) == paragraphs, module  # each once, in the docstring's order
        for scene, page in zip(scenes, shown):
            assert any(f"``{scene.name}``" in paragraph for paragraph in page), scene.name


def test_the_guide_lists_every_preset_as_rigidbody_presets_gives_it():
    """The free-body guide includes the generated table: one row per preset, its name,
    moments and description, and nothing else."""
    import stability

    assert "generated/presets.md" in (ROOT / "docs" / "guide" / "free_body.md").read_text()
    rows = [line for line in presets_page().splitlines() if line.startswith("| `")]
    listed = {}
    for row in rows:
        name, moments, description = (cell.strip() for cell in row.strip("|").split(" | "))
        listed[name.strip("`")] = (moments, description)
    presets = stability.RigidBody.presets()
    assert list(listed) == list(presets)
    for name, (moments, description) in listed.items():
        assert description == presets[name]
        assert [float(x) for x in moments.split(", ")] == pytest.approx(
            stability.RigidBody.preset(name).moments, rel=1e-3)


def test_the_api_reference_lists_the_dissipation_family():
    """stability.dissipation had no API pages: a user found its functions with dir()."""
    from stability_docs import API_MODULES, public_names

    listed = {m for _, modules in API_MODULES for m in modules}
    for module in ("model", "measure", "model_gyrostat", "measure_gyrostat", "figures"):
        assert f"dissipation.{module}" in listed and public_names(f"dissipation.{module}")
    names = set(api_names())
    for name in ("model.Spinner", "model.best_damping", "model.nutation_growth_rate",
                 "model.flat_spin_time", "model.sphere_eigenvalues", "measure.measure_explorer"):
        assert f"stability.dissipation.{name}" in names


def test_the_own_spinner_recipe_runs_as_a_script_and_prints_what_the_guide_says(tmp_path):
    """The dissipation guide's recipe, copied into a file and run with ``python file.py`` in a
    fresh folder, prints the numbers its text quotes."""
    text = (ROOT / "docs" / "guide" / "dissipation.md").read_text()
    recipe = text[text.index("## Your own spinner"):]
    recipe = recipe[:recipe.index("\n## ")]
    code = re.findall(r"```python\n(.*?)```", recipe, re.S)
    assert len(code) == 1
    (tmp_path / "spinner.py").write_text(code[0])
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
    done = subprocess.run([sys.executable, "spinner.py"], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "best damping 1.704 N m s (energy sink: c* = 1.702 N m s)" in done.stdout
    assert "flat spin after 88 min" in done.stdout and "flat spin after 441 min" in done.stdout
    assert "1.704" in recipe and "88 min" in recipe and "441" in recipe


def _run_as_script(folder, name, env_extra=None):
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), str(folder)]),
           "MPLBACKEND": "Agg", **(env_extra or {})}
    done = subprocess.run([sys.executable, name], cwd=folder, env=env, capture_output=True,
                          text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    return done


@pytest.mark.parametrize("source", ["examples/plot_08_dask.py", "docs/developers.md"])
def test_the_dask_examples_run_as_scripts_in_a_fresh_folder(tmp_path, source):
    """The examples that start a local dask cluster, copied as printed and run with
    ``python file.py`` in a fresh folder: the cluster's workers import the script again, which
    started the run once more in each ("Nanny failed to start worker process", then "store is
    in use by another run") before the examples were guarded."""
    path = ROOT / source
    if path.suffix == ".py":
        (tmp_path / "example.py").write_text(path.read_text())
        done = _run_as_script(tmp_path, "example.py")
        assert "bitwise equal: True" in done.stdout
        return
    module, script = re.findall(r"```python\n(.*?)```", path.read_text(), re.S)[:2]
    assert module.startswith("# spring.py") and 'scheduler="dask"' in script
    (tmp_path / "spring.py").write_text(module)
    (tmp_path / "run.py").write_text(script + "    print(sorted(ds.sizes.items()))\n")
    done = _run_as_script(tmp_path, "run.py")
    assert "('member', 1000)" in done.stdout
    assert "Nanny" not in done.stderr and "FolderBusy" not in done.stderr


def test_the_flip_and_the_toss_example_runs_as_a_script_and_measures_the_exact_interval(
        tmp_path):
    """The gallery's answer to "how does the flip depend on the toss?" (the phone by default)
    runs as a reader downloads it, in a fresh folder, and each toss's measured interval is its
    exact 2K/nu; the interval halves when the spin doubles and grows by steps in ln(1/epsilon)."""
    script = ROOT / "examples" / "plot_14_flip_and_the_toss.py"
    done = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True,
                          text=True, timeout=300,
                          env=dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=str(ROOT)))
    assert done.returncode == 0, done.stderr[-2000:]
    rows = re.findall(r"spin +([\d.]+) rad/s, epsilon ([\de.+-]+): flip interval +([\d.]+) s "
                      r"\(exact +([\d.]+) s\)", done.stdout)
    assert len(rows) == 11, done.stdout
    spin, eps, measured, exact = np.array(rows, dtype=float).T
    np.testing.assert_allclose(measured, exact, rtol=1e-3)
    by_spin, by_eps = exact[:5], exact[5:]  # spins 2 ... 32 rad/s; epsilons 1e-1 ... 1e-6
    assert np.all(np.diff(spin[:5]) > 0) and np.all(np.diff(eps[5:]) < 0)
    np.testing.assert_allclose(by_spin[:-1] / by_spin[1:], 2.0, rtol=1e-3)  # as 1/W
    steps = np.diff(by_eps)[1:]  # each decade of epsilon adds the same time, near 0
    assert np.all(steps > 0) and np.ptp(steps) < 0.01 * steps.mean()
    assert list(tmp_path.iterdir()) == []


#: The pages' Python blocks that another test runs as a script, or that need what CI lacks.
BLOCKS_RUN_ELSEWHERE = {
    ("docs/developers.md", 0): "the user's module of the next block",
    ("docs/developers.md", 1): "test_the_dask_examples_run_as_scripts_in_a_fresh_folder",
    ("docs/guide/dissipation.md", 0): "test_the_own_spinner_recipe_runs_as_a_script_...",
}
#: What a block reads, made first in its folder: the study run quick (its Dataset there).
BLOCK_FILES = {("docs/dataset.md", 0): ("bat.toml", "bat.nc"),
               ("docs/dataset.md", 1): ("tennis_racket.toml", "tennis_racket.nc")}


def _doc_blocks():
    pages = [*sorted((ROOT / "docs").glob("*.md")),
             *sorted((ROOT / "docs" / "guide").glob("*.md"))]
    for page in pages:
        name = str(page.relative_to(ROOT))
        for k, block in enumerate(re.findall(r"```python\n(.*?)```", page.read_text(), re.S)):
            if (name, k) not in BLOCKS_RUN_ELSEWHERE:
                yield pytest.param(name, k, block, id=f"{name}[{k}]")


@pytest.mark.parametrize("page, k, block", list(_doc_blocks()))
def test_every_python_block_of_the_docs_runs_as_a_script(tmp_path, page, k, block):
    """Each Python block of the documentation's pages, copied as printed into a file and run
    with ``python file.py`` in a fresh folder (the file it reads made first by the study that
    writes it): the developer page's read a variable its run never kept, and two blocks were
    fragments (``...`` for the arguments, ``body`` never defined)."""
    if "stability.engine.gpu" in block:
        pytest.importorskip("numba.cuda")
        from numba import cuda
        if not cuda.is_available():
            pytest.skip("the GPU's block needs a CUDA GPU")
    if (page, k) in BLOCK_FILES:
        study, dataset = BLOCK_FILES[page, k]
        done = subprocess.run(
            [sys.executable, "-m", "stability", "run", str(ROOT / "studies" / study), "--quick",
             "--out", str(tmp_path / "made"), "--no-progress", "--set", "output.figures=false"],
            cwd=tmp_path, capture_output=True, text=True, timeout=600,
            env={**os.environ, "PYTHONPATH": str(ROOT)})
        assert done.returncode == 0, done.stderr[-2000:]
        (tmp_path / "made" / dataset).rename(tmp_path / dataset)
    (tmp_path / "example.py").write_text(block)
    _run_as_script(tmp_path, "example.py")
