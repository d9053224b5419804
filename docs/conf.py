"""Sphinx configuration of the stability documentation.

Build: ``sphinx-build -W -b html docs docs/_build/html`` (the README's command). The reference
pages in ``docs/generated/`` are written from the code at every build (``_ext/stability_docs``);
the gallery (``examples/``) is executed by sphinx-gallery. ``STABILITY_DOCS_QUICK=1`` runs the
work-precision study in quick mode (CI).
"""

import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS.parent))
sys.path.insert(0, str(DOCS / "_ext"))

import stability  # noqa: E402

project = "stability"
author = "the stability developers"
copyright = "2026, the stability developers"
release = stability.__version__
version = release

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.intersphinx",
    "sphinx.ext.mathjax",
    # MathJax 3 shipped with the site (_static/mathjax), so that equations render offline
    "sphinx-mathjax-offline",
    "numpydoc",
    "myst_parser",
    "sphinx_gallery.gen_gallery",
    "stability_docs",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
# sg_execution_times: sphinx-gallery's timing pages, which load their table scripts and styles
# from the network (not written, see below; excluded should an older build have left them)
exclude_patterns = ["_build", "generated/*.md", "generated/work_precision", "**/*.ipynb",
                    "sg_execution_times.rst", "gallery/sg_execution_times.rst"]
myst_enable_extensions = ["dollarmath"]
myst_heading_anchors = 3
# Pages made from README sections start their subsections at any level.
suppress_warnings = ["myst.header"]

html_theme = "pydata_sphinx_theme"
html_title = f"stability {release}"
html_theme_options = {"navigation_with_keys": False, "show_toc_level": 2}

autosummary_generate = True
autodoc_default_options = {"members": False}
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False

# Online the inventories come from the projects' sites; offline (a build machine without
# network access) from the small ones in _inventories, made by _ext/inventories.py.
_INV = DOCS / "_inventories"
intersphinx_mapping = {
    "python": ("https://docs.python.org/3", (None, str(_INV / "python.inv"))),
    "numpy": ("https://numpy.org/doc/stable", (None, str(_INV / "numpy.inv"))),
    "xarray": ("https://docs.xarray.dev/en/stable", (None, str(_INV / "xarray.inv"))),
    "numba": ("https://numba.readthedocs.io/en/stable", (None, str(_INV / "numba.inv"))),
    "dask": ("https://docs.dask.org/en/stable", (None, str(_INV / "dask.inv"))),
    "distributed": ("https://distributed.dask.org/en/stable",
                    (None, str(_INV / "distributed.inv"))),
}
intersphinx_timeout = 5

sphinx_gallery_conf = {
    "examples_dirs": str(DOCS.parent / "examples"),
    "gallery_dirs": "gallery",
    "filename_pattern": r"/plot_",
    "abort_on_example_error": True,
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "matplotlib_animations": False,
    # the timing pages load jQuery, DataTables and Bootstrap from CDNs: the site stays offline
    "write_computation_times": False,
    # a cell's last expression is shown only where it has an HTML view (a Dataset), not as
    # "<matplotlib.legend.Legend object at 0x...>"
    "capture_repr": ("_repr_html_",),
    # the names of these families link to the module that defines them
    # (stability.rolling.model.launch_formulas), with no search for a shorter path
    "prefer_full_module": {r"^stability\.(earth|struck|rolling)\."},
}

import inventories  # noqa: E402

inventories.write(_INV)
numpydoc_xref_param_type = True
numpydoc_xref_aliases = {
    "ndarray": "numpy.ndarray",
    "Dataset": "xarray.Dataset",
    "DataArray": "xarray.DataArray",
    "Path": "pathlib.Path",
}
numpydoc_xref_ignore = "all"


def setup(app):
    # sphinx-mathjax-offline only sets mathjax_path and copies MathJax once the build has
    # finished: safe for parallel reading and writing (sphinx-build -j), which it does not
    # declare, so that -j would warn and read serially
    mathjax = app.extensions.get("sphinx-mathjax-offline")
    if mathjax is not None:
        mathjax.parallel_read_safe = mathjax.parallel_write_safe = True
