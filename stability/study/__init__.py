"""Studies: a parameter file in, a Dataset and figures out.

A study file (TOML, ``studies/*.toml``) names its kind with ``study = "..."``; ``STUDIES`` maps
each kind to its :class:`~.config.StudyKind`: the schema its files are checked against and the
``run`` function that does the work by calling the package. ``run_study`` is what
``stability run`` calls.

To add a kind of study: write one module here with its ``SCHEMA``, ``outputs`` and ``run``
(see :mod:`.tennis_racket`), and add one line to ``STUDIES``. A study orchestrates: its ``run``
reads the resolved file, calls the package (references, sweeps, estimators, shape grids live
there, once), saves the Dataset, draws the figures and summarises; figures draw the Dataset.
"""

from __future__ import annotations

from pathlib import Path

from . import stability_map, tennis_racket, work_precision
from .config import (
    REQUIRED,
    STUDY_KEY,
    UNSET,
    ConfigError,
    _show,
    _type_name,
    Key,
    Schema,
    Section,
    StudyKind,
    StudySummary,
    read,
    resolve,
    set_value,
    to_toml,
)

STUDIES: dict[str, StudyKind] = {
    "stability_map": stability_map.STUDY,
    "tennis_racket": tennis_racket.STUDY,
    "work_precision": work_precision.STUDY,
}


def study_kind(name) -> StudyKind:
    """The registered kind ``name``; ``ValueError`` listing the known kinds if there is none."""
    try:
        return STUDIES[name]
    except (KeyError, TypeError):
        raise ValueError(
            f"unknown study kind {name!r}; known kinds: {', '.join(STUDIES)}"
        ) from None


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
            + ", ".join(_show(k) for k in STUDIES),
            source,
        )
    if not isinstance(name, str) or name not in STUDIES:
        kind = "" if isinstance(name, str) else f" (a {_type_name(name)})"
        raise ConfigError(
            f"study must be one of {', '.join(_show(k) for k in STUDIES)}, got {_show(name)}"
            f"{kind}",
            source,
        )
    kind = STUDIES[name]
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


def run_study(
    study,
    out_dir=None,
    *,
    members=None,
    threads=None,
    overwrite=False,
    quick=False,
    progress=None,
    overrides=(),
    history=None,
    source=None,
) -> StudySummary:
    """Run a study and write its outputs; return its summary.

    Parameters
    ----------
    study : str, Path or dict
        A study file, or a configuration already resolved by :func:`load_study`.
    out_dir : str or Path, optional
        Output folder; default ``[output] dir`` of the configuration.
    members, quick, overrides
        As in :func:`load_study` (only when ``study`` is a file).
    threads : int, optional
        Numba threads for the run (default: all that Numba was started with).
    overwrite : bool
        Replace output files that exist; otherwise refuse before running anything.
    progress : bool, optional
        Progress bar; by default shown for runs expected to take more than a few seconds.
    history : str, optional
        The command line, appended to the Dataset's ``history`` attribute.

    Returns
    -------
    StudySummary
    """
    if isinstance(study, dict):
        kind = study_kind(study.get(STUDY_KEY))
        source = source or "<config>"
        config = kind.resolve(study, source)  # a resolved configuration resolves to itself
    else:
        kind, config, source = load_study(
            study, overrides=overrides, members=members, quick=quick
        )
    if threads is not None:
        threads = _check_threads(threads)
    out = Path(out_dir if out_dir is not None else config["output"]["dir"])
    if out.exists() and not out.is_dir():
        raise ValueError(f"output folder {out} exists and is not a folder")
    existing = [out / name for name in kind.outputs(config) if (out / name).exists()]
    if existing and not overwrite:
        shown = ", ".join(str(p) for p in existing[:2]) + (" ..." if len(existing) > 2 else "")
        raise ValueError(
            f"{shown} already exists; pass --overwrite to replace it, "
            "or --out DIR for another folder"
        )
    out.mkdir(parents=True, exist_ok=True)
    return kind.run(
        config, out, overwrite=overwrite, threads=threads, progress=progress, history=history
    )


def _check_threads(threads) -> int:
    import numba

    most = numba.config.NUMBA_NUM_THREADS
    if isinstance(threads, bool) or not isinstance(threads, int) or not 1 <= threads <= most:
        raise ValueError(
            f"threads must be a whole number from 1 to {most} (the cores Numba started with; "
            f"set NUMBA_NUM_THREADS to change that), got {threads!r}"
        )
    return threads


__all__ = [
    "REQUIRED",
    "STUDIES",
    "UNSET",
    "ConfigError",
    "Key",
    "Schema",
    "Section",
    "StudyKind",
    "StudySummary",
    "load_study",
    "resolve",
    "run_study",
    "study_kind",
    "to_toml",
]
