"""Study files: a declarative schema per study kind, validation, and the resolved configuration.

A study file is TOML. The top-level key ``study`` names the kind (a key of
``stability.study.STUDIES``); the rest are sections (``[body]``, ``[spin]``, ``[ensemble]``,
``[integration]``, ``[output]`` ...) whose keys each kind declares as data: a :class:`Key` gives
the type, the default, the allowed values or range, the unit and a one-line description.
:func:`resolve` checks a parsed file against that schema and returns the *resolved*
configuration (every key present, defaults filled in), which is what a run uses and what is
stored, as TOML text (:func:`to_toml`), in the ``config_toml`` attribute of its Dataset.

Every problem is reported as one :class:`ConfigError` whose message is one line naming the file,
the section, the key and what is allowed, e.g.::

    studies/x.toml: [ensemble] members must be an integer >= 1, got -5

and nothing is run or written before the whole file has passed.
"""

from __future__ import annotations

import difflib
import json
import math
import os
import stat
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from ..core.body import RigidBody
from ..ensemble.memory import DEFAULT_MAX_MEMORY
from ..util.formatting import format_bytes
from ..integrators import METHODS
from ..ensemble.memory import memory_problem
from ..output.dataset import append_history, config_toml, software_attrs
from ..output.io import saving
from ..plotting.style import save
from ..util import conventions as cv
from ..util.threads import numba_threads

#: Default of a key that has no default: the file must set it.
REQUIRED = object()
#: Default of a key that may be left unset (it is then absent from the resolved configuration).
UNSET = None

_KINDS = ("int", "float", "str", "bool", "floats", "strs")


class ConfigError(ValueError):
    """A study file (or a command-line override of one) that does not fit its schema.

    ``str(error)`` is one line: ``<source>: [<section>] <key> <what is wrong>``.
    """

    def __init__(self, message: str, source: str = "", section: str = "", key: str = ""):
        self.source = source
        self.section = section
        self.key = key
        self.detail = message
        where = f"[{section}] " if section else ""
        prefix = f"{source}: " if source else ""
        super().__init__(f"{prefix}{where}{key + ' ' if key else ''}{message}")


@dataclass(frozen=True)
class Key:
    """One setting of a study file, declared as data.

    Attributes
    ----------
    name : str
        The key as written in the file.
    kind : str or tuple of str
        ``"int"``, ``"float"`` (an integer is accepted and converted), ``"str"``, ``"bool"``,
        ``"floats"`` (a list of numbers), ``"strs"`` (a list of strings), or a tuple of these
        when more than one type is allowed.
    default : object
        Value used when the file does not set the key; :data:`REQUIRED` if it must be set;
        :data:`UNSET` (None) if it may stay unset.
    doc : str
        One line saying what the key means (shown by ``stability run --help-study``).
    unit : str
        Unit of a number (UDUNITS spelling), "" if none.
    choices : tuple or callable, optional
        Allowed values (for lists: allowed elements), or a function returning them (for
        registries that may grow, such as the integrator names).
    minimum, maximum : float, optional
        Allowed range of a number (or of every element of a list of numbers).
    exclusive_minimum : bool
        The minimum itself is not allowed (``> minimum`` rather than ``>= minimum``).
    length : int, optional
        Required length of a list.
    """

    name: str
    kind: str | tuple[str, ...]
    default: Any
    doc: str
    unit: str = ""
    choices: tuple | Callable[[], tuple] | None = None
    minimum: float | None = None
    maximum: float | None = None
    exclusive_minimum: bool = False
    length: int | None = None

    def __post_init__(self):
        kinds = self.kinds
        if not kinds or any(k not in _KINDS for k in kinds):
            raise ValueError(f"Key {self.name!r}: kind must be among {_KINDS}, got {self.kind!r}")

    @property
    def kinds(self) -> tuple[str, ...]:
        return (self.kind,) if isinstance(self.kind, str) else tuple(self.kind)

    def allowed_choices(self) -> tuple | None:
        return self.choices() if callable(self.choices) else self.choices

    def allowed(self) -> str:
        """What the key accepts, in words: ``"an integer >= 1"``, ``"one of "rk4", "lp2""``."""
        choices = self.allowed_choices()
        unit = f" (in {self.unit})" if self.unit else ""
        if choices is not None:
            listed = ", ".join(toml_text(c) for c in choices)
            if set(self.kinds) & {"floats", "strs"}:
                size = f"{self.length} " if self.length else ""
                return f"a list of {size}values from {listed}"
            return f"one of {listed}"
        words = []
        for kind in self.kinds:
            words.append(
                {
                    "int": "an integer",
                    "float": "a number",
                    "str": "a string",
                    "bool": "true or false",
                    "floats": f"a list of {self.length or ''} numbers".replace("  ", " "),
                    "strs": f"a list of {self.length or ''} strings".replace("  ", " "),
                }[kind]
            )
        text = " or ".join(words)
        bounds = []
        if self.minimum is not None:
            bounds.append(f"{'>' if self.exclusive_minimum else '>='} {self.minimum:g}")
        if self.maximum is not None:
            bounds.append(f"<= {self.maximum:g}")
        if bounds:
            each = " each" if set(self.kinds) & {"floats"} else ""
            text += f"{each} " + " and ".join(bounds)
        return text + unit

    def check(self, value):
        """Return ``value`` converted to the key's type, or raise ``ValueError(self.allowed())``."""
        for kind in self.kinds:
            converted = _convert(kind, value, self.length)
            if converted is not _MISMATCH:
                break
        else:
            raise ValueError(self.allowed())
        choices = self.allowed_choices()
        items = converted if isinstance(converted, list) else [converted]
        for item in items:
            if choices is not None and item not in choices:
                raise ValueError(self.allowed())
            if isinstance(item, (int, float)) and not isinstance(item, bool):
                if not math.isfinite(item):
                    raise ValueError(self.allowed())
                if self.minimum is not None and (
                    item < self.minimum or (self.exclusive_minimum and item == self.minimum)
                ):
                    raise ValueError(self.allowed())
                if self.maximum is not None and item > self.maximum:
                    raise ValueError(self.allowed())
        return converted


_MISMATCH = object()


def _convert(kind, value, length):
    if kind == "bool":
        return value if isinstance(value, bool) else _MISMATCH
    if kind == "int":
        return value if isinstance(value, int) and not isinstance(value, bool) else _MISMATCH
    if kind == "float":
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            return _MISMATCH
        return float(value)
    if kind == "str":
        return value if isinstance(value, str) else _MISMATCH
    if kind in ("floats", "strs"):
        if not isinstance(value, list) or (length is not None and len(value) != length):
            return _MISMATCH
        element = "float" if kind == "floats" else "str"
        out = [_convert(element, v, None) for v in value]
        return _MISMATCH if any(v is _MISMATCH for v in out) else out
    raise AssertionError(kind)


@dataclass(frozen=True)
class Section:
    """A ``[section]`` of a study file: its keys and a one-line description.

    ``exclusive`` lists groups of keys of which a file may set at most one (e.g. a body given
    by ``preset`` or by ``moments``); when it sets one, the defaults of the others are dropped.
    """

    name: str
    doc: str
    keys: tuple[Key, ...]
    exclusive: tuple[tuple[str, ...], ...] = ()

    def key(self, name: str) -> Key:
        for k in self.keys:
            if k.name == name:
                return k
        raise KeyError(name)


@dataclass(frozen=True)
class Schema:
    """All sections of one study kind (the top-level ``study`` key is added by :func:`resolve`)."""

    sections: tuple[Section, ...]
    top: tuple[Key, ...] = field(default_factory=tuple)

    def section(self, name: str) -> Section:
        for s in self.sections:
            if s.name == name:
                return s
        raise KeyError(name)

    def describe(self) -> str:
        """The schema as an annotated TOML skeleton with defaults (for ``--help-study``)."""
        lines = []
        for key in self.top:
            lines.append(_describe_key(key))
        for section in self.sections:
            lines.append(f"\n[{section.name}]  # {section.doc}")
            for group in section.exclusive:
                lines.append(f"# set at most one of: {', '.join(group)}")
            for key in section.keys:
                lines.append(_describe_key(key))
        return "\n".join(lines).lstrip("\n")


#: Figure formats a study can write.
FIGURE_FORMATS = ("png", "pdf", "svg")


def preset_names() -> tuple:
    """The names of ``stability.RigidBody.presets()``, for a ``preset`` key's choices."""

    return tuple(RigidBody.presets())


def method_names() -> tuple:
    """The names of the registered integrators (``stability methods``), for a method key's
    choices."""

    return tuple(METHODS)


def tossed_body_sections(rate_default: float = 10.0) -> tuple:
    """The ``[body]`` section (a preset) of a study that tosses a body about its middle axis,
    and the spin key of its ``[toss]`` section."""
    return (
        Section("body", "the body tossed", (
            Key("preset", "str", "tennis_racket", "a body from RigidBody.presets()",
                choices=preset_names),
        )),
        Key("rate", "float", rate_default, "spin W about the middle axis", unit="rad/s",
            minimum=0.0, exclusive_minimum=True),
    )


#: Rough bytes one member of a run that keeps no time series holds at its peak (its start and
#: end states, parameters and summaries: about 64 numbers, copies included), for the memory
#: checks of kinds that keep no finer account.
MEMBER_BYTES = 512


def check_memory(schema: Schema, config: dict, source: str, nbytes: float, keys, what: str,
                 fix: str) -> None:
    """Refuse, before any work, a run that would not fit in memory: one line saying what it
    would take, what a run may hold and the machine has, and how to fix it.

    The one memory check of every study kind; each estimates its own ``nbytes`` (a rough
    upper bound of what it holds at its peak) from its keys, so that a huge count is refused
    at once rather than by NumPy's allocation error, perhaps after minutes of work.

    Parameters
    ----------
    schema : Schema
        The study kind's schema (the defaults the keys are compared with).
    config : dict
        The resolved configuration.
    source : str
        File name for the message.
    nbytes : float
        Bytes the run would hold.
    keys : sequence of (section, key)
        The settings the memory grows with; the message names the one raised most above its
        default (the first on a tie), as the one to lower.
    what : str
        What takes the memory, e.g. ``"the time series of 1000000 members"``.
    fix : str
        How to bring it down, e.g. ``"use fewer members or a larger [integration] save_every"``.

    Raises
    ------
    ConfigError
        If ``nbytes`` exceeds :data:`stability.ensemble.memory.DEFAULT_MAX_MEMORY` or the machine's
        memory.
    """

    problem = memory_problem(nbytes, what, fix)
    if problem is None:
        return
    section, key = max(keys, key=lambda k: _growth(schema, config, *k))
    raise ConfigError(f"= {toml_text(config[section][key])}: {problem}", source, section, key)


def _growth(schema: Schema, config: dict, section: str, key: str) -> float:
    """How many times its default a numeric key is (1 where there is no default to compare)."""
    value = config[section][key]
    default = schema.section(section).key(key).default
    if not isinstance(default, (int, float)) or isinstance(default, bool) or default <= 0:
        return 1.0
    return value / default


def output_section(name: str, figures, extra=()) -> Section:
    """The ``[output]`` section of a study: its folder ``results/<name>``, the Dataset
    ``<name>.nc``, the ``extra`` keys (more files), whether to draw ``figures`` (their stems)
    and in which formats."""
    what = "draw the figure" if len(figures) == 1 else f"draw the {len(figures)} figures"
    return Section("output", "where the results go", (
        Key("dir", "str", f"results/{name}", "output folder (relative to the current directory)"),
        Key("dataset", "str", f"{name}.nc", "file name of the Dataset (netCDF)"),
        *extra,
        Key("figures", "bool", True, what),
        Key("formats", "strs", ["png", "pdf"], "figure formats", choices=FIGURE_FORMATS),
    ))


def run_section(chunk_members: Key | None = None, extra=(),
                title="how the members are cut into chunks, and where they run") -> Section:
    """The ``[run]`` section of a study that resumes and scales (:func:`run_keys`), then the
    ``extra`` keys. Check it with :func:`check_run`."""
    return Section("run", title, (*run_keys(chunk_members), *extra))


def run_keys(chunk_members: Key | None = None) -> tuple:
    """The keys of a study that resumes and scales: members per chunk (each finished chunk is
    kept at once, so a stopped run continues with ``--resume``) and the scheduler the chunks
    run on; for a ``[run]`` section of a study's own (:func:`run_section`)."""
    if chunk_members is None:
        chunk_members = Key("chunk_members", "int", 0,
                            "members per chunk: each finished chunk is kept at once, so a "
                            "stopped run continues from there (stability run --resume); 0 cuts "
                            "a run into at most 8 chunks of at least 1e7 member-steps each",
                            minimum=0)
    return chunk_members, scheduler_key()


def scheduler_key(what: str = "the chunks") -> Key:
    """The ``scheduler`` key of a ``[run]`` section: where ``what`` run."""
    return Key("scheduler", "str", "",
               f"where {what} run: '' this machine, 'dask' a local dask.distributed "
               "cluster, or a scheduler address such as 'tcp://host:8786'")


def check_run(config: dict, source: str) -> None:
    """Refuse a ``[run] scheduler`` that is neither this machine, a local cluster nor an
    address."""
    scheduler = config["run"]["scheduler"]
    if scheduler not in ("", "dask") and "://" not in scheduler:
        raise ConfigError(
            f"must be '' (this machine), 'dask' (a local cluster) or a scheduler address such "
            f"as 'tcp://host:8786', got {scheduler!r}", source, "run", "scheduler")


def stored_run(config: dict, work, resume: bool, scheduler, threads) -> dict:
    """Keyword arguments of :func:`stability.ensemble.chunks.propagate_stored` for a study's
    run: its chunks in ``work``, the scheduler given (``--scheduler``) or the file's."""
    return {"store": work, "resume": resume,
            "scheduler": scheduler or config["run"]["scheduler"] or None,
            "chunk_members": config["run"]["chunk_members"] or None, "threads": threads}


def output_files(config: dict, figures, extra=()) -> list[str]:
    """The files a run of ``config`` writes into its folder: the Dataset, the files named by the
    ``extra`` keys of ``[output]``, ``config.toml`` and the ``figures`` in every format."""
    out = config["output"]
    names = [out["dataset"], *(out[key] for key in extra), "config.toml"]
    if out["figures"]:
        names += [f"{stem}.{fmt}" for stem in figures for fmt in out["formats"]]
    return names


def write_outputs(ds, config: dict, out_dir, name: str, figures: dict, *, overwrite=False,
                  history=None, attrs=None, threads=None, texts=None):
    """Label ``ds`` and write what ``[output]`` asks for: the Dataset, ``config.toml`` and the
    figures, published together (:func:`stability.output.io.saving`: the write runs while the
    figures draw; an interruption publishes nothing).

    Parameters
    ----------
    ds : xarray.Dataset
        The study's result; gets ``Conventions`` (the CF version every study's Dataset
        follows), the title, the study kind, the configuration (``config_toml``), ``attrs``, a
        history line, and the software versions and threads where it does not record them
        already (a run records them where it ran).
    config : dict
        The resolved configuration.
    out_dir : Path
        The output folder (it exists).
    name : str
        The study kind.
    figures : dict
        ``{stem: draw}``, ``draw(ds) -> Figure`` for each figure the study draws.
    history : str or False, optional
        The command to record (default ``stability run (<name>)``); False where ``ds`` already
        records the run that made it (a streamed ensemble does).
    threads : int, optional
        The Numba threads the run used (``stability run --threads``), recorded where ``ds``
        does not record them.
    texts : dict, optional
        ``{file name: text}``: more files written beside ``config.toml`` (a report, say).

    Returns
    -------
    ds : xarray.Dataset
        As written.
    files : list of Path
    """

    with numba_threads(threads):  # what the run recorded where it ran is kept
        software = {k: v for k, v in software_attrs().items() if k not in ds.attrs}
    ds.attrs.update({"Conventions": cv.CONVENTIONS, "title": config["title"], "study": name,
                     **(attrs or {}),
                     "config_toml": config_toml(config), **software})
    if history is not False:
        ds = append_history(ds, history or f"stability run ({name})")
    out = config["output"]
    files = [out_dir / out["dataset"]]
    with saving(ds, files[0], overwrite=overwrite):
        for file, text in {**(texts or {}), "config.toml": to_toml(config)}.items():
            (out_dir / file).write_text(text, encoding="utf-8")
            files.append(out_dir / file)
        if out["figures"]:
            for stem, draw in figures.items():
                files += save(draw(ds), out_dir, stem, out["formats"])
    return ds, files


def _describe_key(key: Key) -> str:
    if key.default is REQUIRED:
        value = "<required>"
    elif key.default is UNSET:
        value = "<unset>"
    else:
        value = toml_text(key.default)
    return f"{key.name} = {value}  # {key.doc}; {key.allowed()}"


def toml_text(value) -> str:
    """A value as it would be written in TOML (strings quoted, booleans lowercase)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, int) and _beyond_a_float(value):  # its digits would drown the line
        return f"an integer of {math.floor(math.log10(abs(value))) + 1} digits"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_text(v) for v in value) + "]"
    return str(value)


def _beyond_a_float(value) -> bool:
    """Whether ``value`` (or an element of it) is an integer no float can hold (above about
    1.8e308): TOML integers have no limit, and such a one cannot be a number, a count or a seed."""
    if isinstance(value, list):
        return any(_beyond_a_float(v) for v in value)
    return (isinstance(value, int) and not isinstance(value, bool)
            and abs(value) > sys.float_info.max)


def toml_type(value) -> str:
    """The TOML name of a value's type (``"integer"``, ``"table"``, ...), for messages."""
    return {bool: "boolean", int: "integer", float: "number", str: "string", list: "list",
            dict: "table"}.get(type(value), type(value).__name__)


#: The largest study file read (bytes): a study file is a page of settings; anything larger
#: is a wrong path (a data file, a device) and is refused before it is read.
MAX_STUDY_BYTES = 2**20


def read(path) -> dict:
    """Parse a study file; a missing, unreadable or oversized file or bad TOML is a one-line
    :class:`ConfigError`.

    Only a regular file of at most :data:`MAX_STUDY_BYTES` is read (``/dev/zero``, a FIFO or
    a folder would be read for ever, wait for ever, or fail obscurely). A UTF-8 byte-order
    mark, which Windows editors write, is skipped.
    """
    path = Path(path)
    source = str(path)
    try:
        with open(path, "rb", opener=_open_without_waiting) as f:
            info = os.fstat(f.fileno())
            if not stat.S_ISREG(info.st_mode):
                raise ConfigError(f"is {_file_kind(info.st_mode)}, not a study file; give the "
                                  "path of a .toml file", source)
            data = f.read(MAX_STUDY_BYTES + 1)  # its size may change as it is read
    except FileNotFoundError:
        raise ConfigError("no such file", source) from None
    except IsADirectoryError:
        raise ConfigError("is a folder, not a study file; give the path of a .toml file",
                          source) from None
    except OSError as exc:
        raise ConfigError(f"cannot read the file ({exc.strerror or exc})", source) from None
    if len(data) > MAX_STUDY_BYTES:
        raise ConfigError(f"is larger than the {MAX_STUDY_BYTES // 2**20} MiB a study file may "
                          "have; give the path of a .toml study file", source)
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ConfigError(f"is not UTF-8 text (byte {exc.start}); save it as UTF-8", source
                          ) from None
    return parse(text, source)


def _open_without_waiting(path, flags):
    """``os.open`` that does not wait for a writer (a FIFO), so that the kind of file can be
    checked before anything is read."""
    return os.open(path, flags | getattr(os, "O_NONBLOCK", 0))


def _file_kind(mode: int) -> str:
    """What a file that is not a regular file is, in words."""
    for test, words in ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                        (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                        (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return words
    return "not a regular file"


def parse(text: str, source: str = "<study>") -> dict:
    """Parse TOML text; a syntax error becomes a one-line :class:`ConfigError`."""
    try:
        return tomllib.loads(text.removeprefix("\ufeff"))
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"not valid TOML: {exc}", source) from None
    except ValueError:  # tomllib's only other error: an integer too long for int()
        raise ConfigError(_TOO_LONG, source) from None


#: What an integer of more digits than Python converts to int is told.
_TOO_LONG = (f"holds an integer of more than {sys.get_int_max_str_digits()} digits, beyond the "
             "range of any number a key takes")


def resolve(raw: dict, schema: Schema, source: str = "<study>") -> dict:
    """Check a parsed study file against ``schema`` and fill in the defaults.

    Parameters
    ----------
    raw : dict
        The parsed TOML (top-level keys and one dict per section).
    schema : Schema
        The study kind's schema.
    source : str
        File name used in error messages.

    Returns
    -------
    dict
        ``{top-level key: value, section: {key: value}}`` with every declared key present
        (keys whose default is :data:`UNSET` and that the file leaves out are omitted).

    Raises
    ------
    ConfigError
        For the first unknown section or key, wrong type, value out of range, or missing
        required key; the message is one line naming the key and what is allowed.
    """
    top_names = [k.name for k in schema.top]
    section_names = [s.name for s in schema.sections]
    resolved: dict = {}
    for name, value in raw.items():
        if isinstance(value, dict):
            if name not in section_names:
                raise ConfigError(
                    f"unknown section [{name}]{_did_you_mean(name, section_names)}; "
                    f"allowed sections: {', '.join(f'[{s}]' for s in section_names)}",
                    source,
                )
        elif name not in top_names:
            hint = _did_you_mean(name, top_names)
            if name in section_names:
                raise ConfigError(
                    f"[{name}] must be a section (a TOML table), got {toml_text(value)}", source
                )
            raise ConfigError(
                f"unknown top-level key {name!r}{hint}; allowed: "
                + ", ".join(top_names + [f"[{s}]" for s in section_names]),
                source,
            )
    for key in schema.top:
        resolved_value = _resolve_key(key, raw, source, "")
        if resolved_value is not UNSET:
            resolved[key.name] = resolved_value
    for section in schema.sections:
        given = raw.get(section.name, {})
        names = [k.name for k in section.keys]
        for name in given:
            if name not in names:
                raise ConfigError(
                    f"unknown key {name!r}{_did_you_mean(name, names)}; "
                    f"allowed keys: {', '.join(names)}",
                    source,
                    section.name,
                )
        dropped = set()
        for group in section.exclusive:
            chosen = [name for name in group if name in given]
            if len(chosen) > 1:
                raise ConfigError(
                    f"give only one of {', '.join(group)}, got {', '.join(chosen)}",
                    source, section.name,
                )
            if chosen:
                dropped.update(name for name in group if name != chosen[0])
        out = {}
        for key in section.keys:
            if key.name in dropped:
                continue
            value = _resolve_key(key, given, source, section.name)
            if value is not UNSET:
                out[key.name] = value
        resolved[section.name] = out
    return resolved


def _resolve_key(key: Key, given: dict, source: str, section: str):
    if key.name not in given:
        if key.default is REQUIRED:
            raise ConfigError(f"is required: set it to {key.allowed()}", source, section, key.name)
        default = key.default
        return list(default) if isinstance(default, tuple) else default
    value = given[key.name]
    if _beyond_a_float(value):
        raise ConfigError(f"must be {key.allowed()}, got {toml_text(value)}, beyond the range of "
                          f"a number (about {sys.float_info.max:.1e})", source, section, key.name)
    try:
        return key.check(value)
    except ValueError as exc:
        raise ConfigError(
            f"must be {exc}, got {toml_text(value)}{_type_hint(key, value)}",
            source, section, key.name,
        ) from None


def _type_hint(key: Key, value) -> str:
    """`` (a string)`` when the type is wrong, so "got 5" vs "got "5"" is not a puzzle."""
    for kind in key.kinds:
        if _convert(kind, value, None) is not _MISMATCH:
            return ""
    return f" (a {toml_type(value)})"


def _did_you_mean(name: str, options) -> str:
    close = difflib.get_close_matches(name, list(options), n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


def set_value(raw: dict, dotted: str, text: str, source: str = "--set") -> None:
    """Apply a command-line override ``section.key=value`` (value in TOML syntax) to ``raw``.

    ``text`` is parsed as a TOML value, so ``5``, ``1e-4``, ``"lp2"`` and ``[1, 2, 3]`` mean what
    they mean in the file; a bare word that is not TOML (``lp2``) is taken as a string.
    """
    section, _, key = dotted.partition(".")
    if not key or not section:
        raise ConfigError(
            f"override {dotted!r} must name a section and a key, as in ensemble.members=100",
            source,
        )
    try:
        value = tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        value = text
    except ValueError:  # an integer too long for int()
        raise ConfigError(_TOO_LONG, source) from None
    table = raw.setdefault(section, {})
    if not isinstance(table, dict):
        raise ConfigError(f"[{section}] is not a section", source)
    table[key] = value


def to_toml(config: dict) -> str:
    """A resolved configuration as TOML text, as stored in a Dataset's ``config_toml``.

    The same writer as the Dataset's (:func:`stability.output.dataset.config_toml`), so the copy a
    run writes next to its Dataset and the attribute inside it are the same text.
    """

    return config_toml(config)


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
        ``run(config, out_dir, *, overwrite, threads, progress, history) -> StudySummary``:
        runs the resolved ``config`` and writes the outputs into ``out_dir`` (a Path that exists).
    outputs : callable
        ``outputs(config) -> list[str]``: the file names (relative to the output folder) a run
        writes, so that a run refuses to start rather than overwrite them after minutes of work.
    check : callable, optional
        ``check(config, source) -> config``: checks that involve several keys (raise
        :class:`ConfigError`); may complete the configuration (e.g. drop a default that another
        key replaces).
    quick : dict
        ``{section: {key: value}}`` overrides for ``--quick``: a small run for tests and demos.
    members_key : tuple of str, optional
        ``(section, key)`` that ``--members`` sets; None if the kind has no such count.
    expected_bytes : callable, optional
        ``expected_bytes(config) -> int``: disk space a run needs at most, checked against the
        free space before it starts.
    resumable : bool
        ``run`` also takes ``work`` (a folder for finished parts, kept when the run is
        stopped), ``resume`` and ``scheduler`` (``stability run --resume``, ``--scheduler``).
    """

    name: str
    title: str
    schema: Schema
    run: Callable
    outputs: Callable
    check: Callable | None = None
    quick: dict = field(default_factory=dict)
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
    """

    study: str
    out_dir: Path
    files: list = field(default_factory=list)
    rows: list = field(default_factory=list)
    values: dict = field(default_factory=dict)
    tables: list = field(default_factory=list)

    def table(self) -> str:
        """The rows as an aligned plain-text table, then each of ``tables``."""
        parts = []
        if self.rows:
            w0 = max(len(r[0]) for r in self.rows)
            w1 = max(len(r[1]) for r in self.rows)
            parts.append("\n".join(f"{q:<{w0}}  {v:>{w1}}  {u}".rstrip()
                                   for q, v, u in self.rows))
        parts += [table.text() for table in self.tables]
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
