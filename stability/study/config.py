"""The schema of study files: a declarative schema per study kind, validation against it, and the
resolved configuration (reading a file and its overrides is :mod:`.load`).

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

import json
import math
import sys
from dataclasses import dataclass, field
from typing import Any, Callable

from ..output.dataset import config_toml
from ..util.checks import did_you_mean

#: Default of a key that has no default: the file must set it.
REQUIRED = object()
#: Default of a key that may be left unset (it is then absent from the resolved configuration).
UNSET = None

_KINDS = ("int", "float", "str", "bool", "floats", "strs", "table")


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
        ``"floats"`` (a list of numbers), ``"strs"`` (a list of strings), ``"table"`` (a TOML
        table, whose keys the study kind's ``check`` reads), or a tuple of these when more
        than one type is allowed.
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
    suffix : str, optional
        Required ending of a string (a file name's extension, such as ``".nc"``).
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
    suffix: str | None = None

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
                    "table": "a table such as {distribution = \"uniform\", relative = 0.05}",
                }[kind]
            )
        text = " or ".join(words)
        if self.suffix is not None:
            text += f" ending in {self.suffix}"
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
            if self.suffix is not None and isinstance(item, str) and (
                    not item.endswith(self.suffix) or item == self.suffix):
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
    if kind == "table":
        return dict(value) if isinstance(value, dict) else _MISMATCH
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
                    f"unknown section [{name}]{did_you_mean(name, section_names)}; "
                    f"allowed sections: {', '.join(f'[{s}]' for s in section_names)}",
                    source,
                )
        elif name not in top_names:
            hint = did_you_mean(name, top_names)
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
                    f"unknown key {name!r}{did_you_mean(name, names)}; "
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


def to_toml(config: dict) -> str:
    """A resolved configuration as TOML text, as stored in a Dataset's ``config_toml``.

    The same writer as the Dataset's (:func:`stability.output.dataset.config_toml`), so the copy a
    run writes next to its Dataset and the attribute inside it are the same text.
    """

    return config_toml(config)

