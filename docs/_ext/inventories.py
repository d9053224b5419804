"""Small intersphinx inventories of the libraries the documentation links to, for offline builds.

A build machine without network access cannot fetch the projects' ``objects.inv``; these list
the objects the pages and docstrings refer to, at their pages on the projects' sites (the same
addresses the full inventories give). Online builds use the projects' own inventories first.
"""

from __future__ import annotations

import zlib
from pathlib import Path

#: project -> [(name, role, path on the project's site[, title])]
OBJECTS = {
    "python": [
        ("float", "py:class", "library/functions.html#float"),
        ("int", "py:class", "library/functions.html#int"),
        ("str", "py:class", "library/stdtypes.html#str"),
        ("bool", "py:class", "library/functions.html#bool"),
        ("dict", "py:class", "library/stdtypes.html#dict"),
        ("list", "py:class", "library/stdtypes.html#list"),
        ("tuple", "py:class", "library/stdtypes.html#tuple"),
        ("pathlib.Path", "py:class", "library/pathlib.html#pathlib.Path"),
        ("ValueError", "py:exception", "library/exceptions.html#ValueError"),
        ("KeyboardInterrupt", "py:exception", "library/exceptions.html#KeyboardInterrupt"),
        ("sequence", "std:term", "glossary.html#term-sequence"),
        ("iterable", "std:term", "glossary.html#term-iterable"),
        ("mapping", "std:term", "glossary.html#term-mapping"),
        ("bltin-boolean-values", "std:label", "library/stdtypes.html#boolean-values",
         "Boolean Values"),
        ("bltin-none", "std:label", "library/constants.html#None", "None"),
        # numpydoc refers to None, True, False and callable in parameter types
        ("None", "py:data", "library/constants.html#None"),
        ("True", "py:data", "library/constants.html#True"),
        ("False", "py:data", "library/constants.html#False"),
        ("callable", "py:function", "library/functions.html#callable"),
    ],
    "numpy": [
        ("numpy.ndarray", "py:class", "reference/generated/numpy.ndarray.html#numpy.ndarray"),
        ("array_like", "std:term", "glossary.html#term-array_like"),
        ("arrays.scalars", "std:label", "reference/arrays.scalars.html#arrays-scalars",
         "Scalars"),
        ("numpy.random.SeedSequence", "py:class",
         "reference/random/bit_generators/generated/numpy.random.SeedSequence.html"
         "#numpy.random.SeedSequence"),
        ("numpy.random.Generator", "py:class",
         "reference/random/generator.html#numpy.random.Generator"),
    ],
    "xarray": [
        ("xarray.Dataset", "py:class", "generated/xarray.Dataset.html#xarray.Dataset"),
        ("xarray.DataArray", "py:class", "generated/xarray.DataArray.html#xarray.DataArray"),
        ("xarray.open_dataset", "py:function",
         "generated/xarray.open_dataset.html#xarray.open_dataset"),
        ("xarray.open_mfdataset", "py:function",
         "generated/xarray.open_mfdataset.html#xarray.open_mfdataset"),
    ],
    "numba": [
        ("numba.njit", "py:function", "reference/jit-compilation.html#numba.njit"),
        ("numba.prange", "py:function", "reference/jit-compilation.html#numba.prange"),
    ],
    "dask": [
        ("dask.array.Array", "py:class", "generated/dask.array.Array.html#dask.array.Array"),
    ],
    "distributed": [
        ("distributed.Client", "py:class", "api.html#distributed.Client"),
        ("distributed.LocalCluster", "py:class", "api.html#distributed.LocalCluster"),
    ],
}


def write(folder) -> None:
    """Write ``<project>.inv`` for every project of :data:`OBJECTS` into ``folder``."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    for project, objects in OBJECTS.items():
        head = (f"# Sphinx inventory version 2\n# Project: {project}\n# Version: \n"
                "# The remainder of this file is compressed using zlib.\n").encode()
        body = "".join(f"{entry[0]} {entry[1]} {-1 if entry[1] == 'std:label' else 1} "
                       f"{entry[2]} {entry[3] if len(entry) > 3 else '-'}\n"
                       for entry in objects)
        (folder / f"{project}.inv").write_bytes(head + zlib.compress(body.encode()))
