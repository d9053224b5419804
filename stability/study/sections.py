"""The sections and checks the study kinds share: the tossed body, the run (chunks, scheduler,
device), the output folder, and the one memory check before any work."""

from __future__ import annotations

import math
from dataclasses import replace

from ..core.body import RigidBody
from ..ensemble.memory import memory_problem
from ..output.io import COMPRESSIONS

from .config import ConfigError, Key, Schema, Section, toml_text
from .kind import StudyRun
from ..ensemble.options import RunOptions


#: Figure formats a study can write.
FIGURE_FORMATS = ("png", "pdf", "svg")


def preset_names() -> tuple:
    """The names of ``stability.RigidBody.presets()``, for a ``preset`` key's choices."""

    return tuple(RigidBody.presets())


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
    """How many times its default a numeric key is (1 where there is no default or no number to
    compare; ``"all"`` of a count that allows it: without bound)."""
    value = config[section][key]
    default = schema.section(section).key(key).default
    if not isinstance(default, (int, float)) or isinstance(default, bool) or default <= 0:
        return 1.0
    if isinstance(value, str):
        return math.inf if value == "all" else 1.0
    return value / default


def output_section(name: str, figures, extra=(), dataset: Key | None = None) -> Section:
    """The ``[output]`` section of a study: its folder ``results/<name>``, the Dataset
    (``dataset``, default the key of the file name ``<name>.nc``), the ``extra`` keys (more
    files), whether to draw ``figures`` (their stems), in which formats, and the Dataset's
    compression (:data:`stability.output.io.COMPRESSIONS`)."""
    what = "draw the figure" if len(figures) == 1 else f"draw the {len(figures)} figures"
    if dataset is None:
        dataset = Key("dataset", "str", f"{name}.nc", "file name of the Dataset (netCDF)",
                      suffix=".nc")
    return Section("output", "where the results go", (
        Key("dir", "str", f"results/{name}", "output folder (relative to the current directory)"),
        dataset,
        *extra,
        Key("figures", "bool", True, what),
        Key("formats", "strs", ["png", "pdf"], "figure formats", choices=FIGURE_FORMATS),
        Key("compression", "str", "zlib",
            "how the Dataset is compressed: zlib (every netCDF-4 reader has it), zstd (about 8 "
            "times as fast to write, a little larger; needs netCDF-C 4.9 with its plugins to "
            "read) or none", choices=tuple(COMPRESSIONS)),
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


def study_run_options(config: dict, options: StudyRun) -> RunOptions:
    """The run options (:class:`~stability.ensemble.options.RunOptions`) of a study's run:
    those it is given (``options.run``: its chunks in the store, ``--resume``, ``--threads``),
    on the scheduler given (``--scheduler``) or else the file's, in chunks of the file's
    ``[run] chunk_members``."""
    run = options.run
    return replace(run, scheduler=run.scheduler or config["run"]["scheduler"] or None,
                   chunk_members=config["run"]["chunk_members"] or None)
