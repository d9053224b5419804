"""The study protocol: :class:`StudyKind` (a kind's schema, checks, run and outputs), the
register of the kinds by name (:data:`STUDIES`), what a kind's run takes (:class:`StudyRun`),
what it returns (:class:`StudySummary`) and its printed table (:class:`SummaryTable`)."""

from __future__ import annotations

import functools
import textwrap
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from ..ensemble.options import RunOptions
from ..util.checks import registered
from .config import ConfigError, Schema, resolve, toml_text


#: The key every study file starts with: the kind of study it is.
STUDY_KEY = "study"


@dataclass(frozen=True)
class StudyKind:
    """A kind of study: its schema, how to run it, and what the generic options map to.

    Attributes
    ----------
    name : str
        The value of ``study = "..."`` in a study file, and the registry key.
    title : str
        One line saying what the study shows.
    schema : Schema
        Sections and keys of its study files.
    run : callable
        ``run(config, out_dir, options) -> StudySummary``: runs the resolved ``config`` as
        ``options`` (a :class:`StudyRun`) say and writes the outputs into ``out_dir`` (a Path
        that exists).
    outputs : callable
        ``outputs(config) -> list[str]``: the file names (relative to the output folder) a run
        writes, so that a run refuses to start rather than overwrite them after minutes of work.
    check : callable, optional
        ``check(config, source) -> config``: checks that involve several keys (raise
        :class:`ConfigError`); may complete the configuration (e.g. drop a default that another
        key replaces).
    quick : dict
        ``{section: {key: value}}`` overrides for ``--quick``: a small run for tests and demos.
    quick_note : str
        Where ``--quick`` changes more than the run's size and length (the physics, a part
        left out), and why; empty if it does not.
    members_key : tuple of str, optional
        ``(section, key)`` that ``--members`` sets; None if the kind has no such count.
    expected_bytes : callable, optional
        ``expected_bytes(config) -> int``: disk space a run needs at most, checked against the
        free space before it starts.
    resumable : bool
        ``run`` is given a store in its options (a folder for finished parts, kept when the run
        is stopped), ``resume`` and ``scheduler`` (``stability run --resume``, ``--scheduler``).
    """

    name: str
    title: str
    schema: Schema
    run: Callable
    outputs: Callable
    check: Callable | None = None
    quick: dict = field(default_factory=dict)
    quick_note: str = ""
    members_key: tuple[str, str] | None = None
    expected_bytes: Callable | None = None
    resumable: bool = False

    def resolve(self, raw: dict, source: str = "<study>") -> dict:
        """Validate a parsed study file of this kind; return the resolved configuration."""
        raw = dict(raw)
        kind = raw.pop(STUDY_KEY, self.name)
        if kind != self.name:
            raise ConfigError(f"study is {toml_text(kind)}, expected {toml_text(self.name)}",
                              source)
        config = {STUDY_KEY: self.name}
        config.update(resolve(raw, self.schema, source))
        if self.check is not None:
            config = self.check(config, source)
        return config

    def quick_lines(self, raw: dict | None = None, config: dict | None = None) -> list[str]:
        """What ``--quick`` sets, one line a key beside the value it replaces (that of ``raw``,
        a parsed study file, or else the default) and, where the resolved ``config`` holds
        another (``--set``, ``--members``), that one; then :attr:`quick_note`."""
        lines = []
        for section, values in self.quick.items():
            given = (raw or {}).get(section, {})
            for key, value in values.items():
                if isinstance(given, dict) and key in given:
                    before, where = given[key], "the file"
                else:
                    before, where = self.schema.section(section).key(key).default, "default"
                line = f"{section}.{key} = {toml_text(value)} ({where}: {toml_text(before)})"
                now = (config or {}).get(section, {}).get(key, value)
                if now != value:
                    line += f", then {toml_text(now)} by the options"
                lines.append(line)
        if self.quick_note:
            lines.append(f"note: {self.quick_note}")
        return lines


class StudyKinds(Mapping):
    """The register of study kinds by name, each loaded from its family when first asked for.

    The study framework imports no family (the kinds' modules import it):
    :mod:`stability.registry`, which reads what each family declares, declares the kinds here
    with the function that loads one. A kind's module is imported when the kind is first asked
    for, so that ``import stability`` stays free of the studies' modules and of matplotlib.
    """

    def __init__(self):
        self._loaders: dict[str, Callable[[], StudyKind]] = {}

    def declare(self, where: Mapping, load: Callable) -> None:
        """Register study kinds, each to be loaded when first asked for.

        Parameters
        ----------
        where : mapping of str to object
            Each kind's name -> where it is (:data:`stability.registry.STUDY_KINDS`: its
            module's path and the name of its :class:`StudyKind` there).
        load : callable
            ``load(where[name]) -> StudyKind`` (:func:`stability.registry.load`).
        """
        self._loaders.update({name: functools.partial(load, place)
                              for name, place in where.items()})

    def __getitem__(self, name) -> StudyKind:
        return self._loaders[name]()

    def __iter__(self):
        return iter(self._loaders)

    def __len__(self) -> int:
        return len(self._loaders)


#: The study kinds by name (declared by :mod:`stability.registry`).
STUDIES: Mapping[str, StudyKind] = StudyKinds()


def study_kind(name) -> StudyKind:
    """The registered kind ``name``; ``ValueError`` listing the known kinds if there is none."""
    return registered(STUDIES, name, "study kind", "kinds")


def quick_notes(kind: StudyKind, raw: dict | None = None, config: dict | None = None
                ) -> list[str]:
    """The lines saying what ``--quick`` sets for ``kind`` (:meth:`StudyKind.quick_lines`):
    printed by ``stability studies KIND`` and after a quick run's summary."""
    if not kind.quick:
        return ["--quick changes nothing in this kind"]
    lines = ["--quick sets (a small, fast run):"]
    for line in kind.quick_lines(raw, config):
        lines += textwrap.wrap(line, 94, initial_indent="  ", subsequent_indent="    ")
    return lines


@dataclass(frozen=True)
class StudyRun:
    """How a study kind's ``run`` goes: the run options it passes on to the package, and how
    it writes its outputs; the fields are the constructor's parameters.

    Parameters
    ----------
    run : RunOptions, optional
        How the members run (:class:`~stability.ensemble.options.RunOptions`): ``threads`` and
        ``progress`` for every kind; for a resumable kind also ``store`` (the work folder its
        finished parts are kept in), ``resume`` and ``scheduler`` (the file's ``[run]
        scheduler`` where None). Default: in this process, with the default options.
    overwrite : bool, default False
        Replace output files that exist.
    history : str, optional
        The command line, appended to the Dataset's ``history`` attribute.

    Examples
    --------
    >>> StudyRun(RunOptions(threads=2, progress=False), overwrite=True).run.threads
    2
    """

    run: RunOptions = field(default_factory=RunOptions)
    overwrite: bool = False
    history: str | None = None

    def __post_init__(self):
        if not isinstance(self.run, RunOptions):
            raise ValueError(f"run must be a stability.RunOptions, got {type(self.run).__name__}")
        if not isinstance(self.overwrite, bool):
            raise ValueError(f"overwrite must be True or False, got {self.overwrite!r:.80}")


@dataclass
class StudySummary:
    """What a study run reports: headline numbers and the files it wrote.

    Attributes
    ----------
    study : str
        Study kind.
    out_dir : Path
        Folder the files were written to.
    files : list of Path
        Files written.
    rows : list of (str, str, str)
        ``(quantity, value, unit)`` for the summary table printed at the end of a run.
    values : dict
        The same numbers as floats, keyed by short names (for tests and scripts).
    tables : list of SummaryTable
        Tables printed after the rows.
    notes : list of str
        Lines printed last (what ``--quick`` set, :meth:`StudyKind.quick_lines`).
    """

    study: str
    out_dir: Path
    files: list = field(default_factory=list)
    rows: list = field(default_factory=list)
    values: dict = field(default_factory=dict)
    tables: list = field(default_factory=list)
    notes: list = field(default_factory=list)

    def table(self) -> str:
        """The rows as an aligned plain-text table, then each of ``tables``, then ``notes``."""
        parts = []
        if self.rows:
            w0 = max(len(r[0]) for r in self.rows)
            w1 = max(len(r[1]) for r in self.rows)
            parts.append("\n".join(f"{q:<{w0}}  {v:>{w1}}  {u}".rstrip()
                                   for q, v, u in self.rows))
        parts += [table.text() for table in self.tables]
        if self.notes:
            parts.append("\n".join(self.notes))
        return "\n\n".join(parts)


def run_rows(values: dict, wall: float) -> list:
    """The closing rows of a summary of stored runs: the members not ok, the wall time (all, and
    the integration's) and the member-steps, from ``values`` (``members_failed``,
    ``integration_time``, ``member_steps``) and ``wall`` (s)."""
    return [("members not ok", f"{values['members_failed']}", ""),
            ("wall time (all) / integration", f"{wall:.1f} / {values['integration_time']:.1f}",
             "s"),
            ("member-steps", f"{values['member_steps']:.3g}", "")]


@dataclass
class SummaryTable:
    """A table of a study's summary with one column per quantity (:attr:`StudySummary.tables`).

    Attributes
    ----------
    title : str
        One line above the table.
    columns : list of (str, str)
        ``(name, unit)`` of each column; the unit is printed under the name, in parentheses
        (none for an empty unit).
    rows : list of tuple of str
        The cells, formatted; the first column is left-aligned, the others right-aligned.
    """

    title: str
    columns: list
    rows: list = field(default_factory=list)

    def text(self) -> str:
        """The title, a header of names over units, and the rows, in aligned columns."""
        names = [name for name, _ in self.columns]
        units = [f"({unit})" if unit else "" for _, unit in self.columns]
        widths = [max(len(names[k]), len(units[k]), *(len(row[k]) for row in self.rows))
                  for k in range(len(self.columns))]

        def line(cells):
            first = f"{cells[0]:<{widths[0]}}"
            rest = [f"{cell:>{width}}" for cell, width in zip(cells[1:], widths[1:])]
            return "  ".join([first, *rest]).rstrip()

        return "\n".join([self.title, line(names), line(units), *map(line, self.rows)])
