"""Studies: a parameter file in, a Dataset and figures out.

A study file (TOML, ``studies/*.toml``) names its kind with ``study = "..."``; ``STUDIES`` maps
each kind to its :class:`~.kind.StudyKind` (declared by :mod:`stability.registry`): the schema
its files are checked against and the ``run`` function that does the work by calling the
package. ``run_study`` (:mod:`.runner`) is what ``stability run`` calls. The framework:
:mod:`.config` (the schema: keys, sections, validation, the resolved configuration),
:mod:`.load` (a study file read, overridden and validated), :mod:`.sections` (the sections and
checks the kinds share), :mod:`.outputs` (what a run writes into its folder) and :mod:`.kind`
(the protocol and the register of kinds). This module only gathers their public names.

To add a kind of study: write its module in its family's package with its ``SCHEMA``,
``outputs`` and ``run`` (see :mod:`stability.heavy_top.studies.gyroscope`), name it in the
family's ``STUDIES``, and declare the Dataset it writes in the family's ``schema.py`` under the
kind's name, named in its ``DATASETS`` (the tests hold its file to it). A study orchestrates: its
``run`` reads the resolved file, calls the package (references, sweeps, estimators, shape grids
live there, once), saves the Dataset, draws the figures and summarises; figures draw the Dataset.
"""

from .config import REQUIRED, UNSET, ConfigError, Key, Schema, Section, resolve, to_toml
from .kind import STUDIES, StudyKind, StudyRun, StudySummary, quick_notes, study_kind
from .load import load_study
from .runner import run_study

__all__ = [
    "REQUIRED",
    "STUDIES",
    "UNSET",
    "ConfigError",
    "Key",
    "Schema",
    "Section",
    "StudyKind",
    "StudyRun",
    "StudySummary",
    "load_study",
    "quick_notes",
    "resolve",
    "run_study",
    "study_kind",
    "to_toml",
]
