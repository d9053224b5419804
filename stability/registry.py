"""The problem families, in one list: :data:`FAMILIES`. Each family's package declares its
scenes and study kinds (its ``SCENES`` and ``STUDIES``); here they become :data:`SCENES` by name
and :data:`STUDY_KINDS`, declared to the study framework's register
(:data:`stability.study.STUDIES`, which loads each kind when first asked for).

To add a family: copy a family's folder (the smallest is ``stability/struck/``; every family has
its shape: ``scene.py``, ``methods.py``, ``model.py``, ``measure.py``, ``schema.py``,
``figures.py`` and a study kind per ``studies/<kind>.py``, or per sub-package with its
``study.py`` for a study of several modules; ``tests/test_structure.py`` holds it), declare its
scenes and study kinds in its ``__init__.py``, and add its name to :data:`FAMILIES`. The generic
tests, the docs' scene pages and Dataset reference, ``stability methods`` and
``stability studies`` pick it up from here. A scene in a module of the user's own comes from
:func:`stability.define_scene` (:mod:`stability.engine.user_scene`, which refuses a name
registered here) and is passed as it is.
"""

import importlib

from .engine.scene import Scene
from .engine.user_scene import RESERVED_NAMES
from .ensemble.schema import DatasetSchema, register
from .study.kind import STUDIES
from .tangents.schema import TANGENTS
from .uncertainty.schema import MORRIS_SCREENING, SOBOL_INDICES
from .util.checks import registered

#: The families, each a package ``stability.<name>``, in the order their scenes are listed.
FAMILIES = ("free_body", "heavy_top", "earth", "rolling", "struck", "engine_body", "dissipation",
            "asteroid")


def declared(family: str, kind: str) -> dict:
    """What a family's package declares it registers.

    Parameters
    ----------
    family : str
        A name of :data:`FAMILIES`.
    kind : str
        ``"SCENES"``, ``"STUDIES"`` or ``"DATASETS"``.

    Returns
    -------
    dict
        Each study kind's name (or each scene's or Dataset's position) -> (module path,
        attribute name).
    """
    package = f"stability.{family}"
    table = getattr(importlib.import_module(package), kind)
    items = table.items() if isinstance(table, dict) else enumerate(table)
    out = {}
    for key, where in items:
        module, attribute = where.split(":")
        out[key] = (f"{package}.{module}", attribute)
    return out


def load(where):
    """What a declaration names, imported.

    Parameters
    ----------
    where : tuple of str
        (module path, attribute), as :func:`declared` gives it.

    Returns
    -------
    object
        The scene or study kind.
    """
    module, attribute = where
    return getattr(importlib.import_module(module), attribute)


SCENES: dict[str, Scene] = {
    s.name: s for s in (load(where) for family in FAMILIES
                        for where in declared(family, "SCENES").values())}
RESERVED_NAMES.update(SCENES)  # define_scene refuses them

#: Each family's Dataset declarations by name, added to the register
#: (:data:`stability.ensemble.schema.SCHEMAS`).
DATASETS: dict[str, DatasetSchema] = {
    s.name: s for s in (load(where) for family in FAMILIES
                        for where in declared(family, "DATASETS").values())}
register(*DATASETS.values())
register(SOBOL_INDICES, MORRIS_SCREENING)  # the sensitivity analyses of stability.uncertainty
register(TANGENTS)  # the finite-time Lyapunov exponents of stability.tangents

#: Each study kind's name -> (module, attribute) of its StudyKind, imported when first used.
STUDY_KINDS: dict[str, tuple] = dict(sorted(
    (name, where) for family in FAMILIES for name, where in declared(family, "STUDIES").items()))
STUDIES.declare(STUDY_KINDS, load)  # the register the study framework reads


def scene(name) -> Scene:
    """The scene registered under ``name``; ValueError listing the known ones if none.

    Parameters
    ----------
    name : str or Scene
        A key of :data:`SCENES`; a Scene is returned as it is.

    Returns
    -------
    Scene
    """
    if isinstance(name, Scene):
        return name
    return registered(SCENES, name, "scene")


__all__ = ["DATASETS", "FAMILIES", "SCENES", "STUDY_KINDS", "declared", "load", "scene"]
