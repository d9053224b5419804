"""Loading a study file: read (a small regular file of UTF-8 TOML), overridden (``--quick``,
``--set``, ``--members``) and validated against its kind's schema, each problem one line
(:class:`~.config.ConfigError`): :func:`load_study`."""

from __future__ import annotations

import os
import stat
import sys
import tomllib
from pathlib import Path

from .config import ConfigError, toml_text, toml_type
from .kind import STUDIES, STUDY_KEY


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


def _check_dispersible(kind, raw: dict, source: str) -> None:
    """A ``[dispersions]`` section in a study whose kind draws none is one line naming the
    kinds that do."""
    names = [s.name for s in kind.schema.sections]
    if "dispersions" in raw and "dispersions" not in names:
        dispersed = [k for k, other in STUDIES.items()
                     if "dispersions" in [s.name for s in other.schema.sections]]
        raise ConfigError(
            f"study {kind.name!r} draws no dispersions; the studies that take [dispersions] "
            f"and report which uncertainty dominates are {', '.join(dispersed)}; or disperse "
            "any scene's named parameters with stability.uncertainty.scenes.run_dispersed",
            source)


def load_study(path, *, overrides=(), members=None, quick=False):
    """Read, override and validate a study file.

    Parameters
    ----------
    path : str or Path
        The TOML study file.
    overrides : sequence of (str, str)
        ``("section.key", "value")`` pairs (value in TOML syntax) applied on top of the file,
        as ``stability run --set`` does.
    members : int, optional
        Ensemble size, replacing the kind's members key (``--members``).
    quick : bool
        Apply the kind's quick-mode settings (``--quick``) before the overrides.

    Returns
    -------
    kind : StudyKind
    config : dict
        The resolved configuration (every key present, defaults filled in).
    source : str
        The file name, for messages.

    Raises
    ------
    ConfigError
        One line naming the file, section and key, and what is allowed.
    """
    source = str(path)
    raw = read(path)
    name = raw.get(STUDY_KEY, None)
    if name is None:
        raise ConfigError(
            "missing key 'study' at the top of the file; set study = one of "
            + ", ".join(toml_text(k) for k in STUDIES),
            source,
        )
    if not isinstance(name, str) or name not in STUDIES:
        kind = "" if isinstance(name, str) else f" (a {toml_type(name)})"
        raise ConfigError(
            f"study must be one of {', '.join(toml_text(k) for k in STUDIES)}, "
            f"got {toml_text(name)}{kind}",
            source,
        )
    kind = STUDIES[name]
    _check_dispersible(kind, raw, source)
    if quick:
        for section, values in kind.quick.items():
            raw.setdefault(section, {})
            if isinstance(raw[section], dict):
                raw[section].update(values)
    given = {}  # (section, key) -> the option that set it
    for dotted, text in overrides:
        set_value(raw, dotted, text, source=f"{source} (--set {dotted})")
        section, _, key = dotted.partition(".")
        given[(section, key)] = f"--set {dotted}"
    if members is not None:
        if kind.members_key is None:
            raise ConfigError(f"study kind {name!r} has no ensemble size; drop --members", source)
        section, key = kind.members_key
        raw.setdefault(section, {})[key] = members
        given[kind.members_key] = "--members"
    try:
        config = kind.resolve(raw, source)
    except ConfigError as exc:
        option = given.get((exc.section, exc.key))
        if option is None:
            raise
        raise ConfigError(exc.detail, f"{source} ({option})", exc.section, exc.key) from None
    return kind, config, source
