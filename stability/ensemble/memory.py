"""How much memory a run may hold: the one check every run makes before any work.

A run that would not fit is refused at once, in one line, rather than by NumPy's allocation
error, perhaps after minutes of work. Each caller estimates its own bytes (a rough upper bound
of what it holds at its peak) and words the refusal as its settings are named (a study's keys,
a function's arguments); the limit and the line's middle are here:
:func:`stability.study.sections.check_memory` for the study kinds, :func:`stability.run_scene`
for a run of any scene. The machine's memory is what this process may have: the physical
memory, or its cgroup's limit where that is less (a container, a batch job), so that a
``max_memory`` above it is refused in words too rather than by NumPy.
"""

from __future__ import annotations

import os
from pathlib import Path, PurePosixPath

from ..util.formatting import format_bytes

#: Default limit (bytes) on what one run may hold in memory (and on the Dataset of
#: :func:`stability.run_ensemble`, its ``max_memory``).
DEFAULT_MAX_MEMORY = 4 * 2**30


#: Where Linux mounts the cgroup file systems, and where a process finds its own cgroups.
CGROUP_ROOT = Path("/sys/fs/cgroup")
PROC_CGROUP = Path("/proc/self/cgroup")

#: A cgroup limit at or above this many bytes is no limit (cgroup v1 writes 2^63 - 4096).
NO_LIMIT = 2**60


def machine_memory() -> int | None:
    """Bytes of memory this process may use: the machine's physical memory, or its cgroup's
    limit where that is less (a container, a batch job); None where the system says neither."""
    try:
        physical = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):
        physical = None
    limits = [n for n in (physical, cgroup_limit()) if n is not None and n > 0]
    return min(limits, default=None)


def cgroup_limit() -> int | None:
    """The smallest memory limit of this process's cgroups and the cgroups above them
    (v2 ``memory.max``, v1 ``memory.limit_in_bytes``); None where there is none."""
    try:
        lines = PROC_CGROUP.read_text(encoding="utf-8", errors="replace").splitlines()
    except OSError:
        lines = []
    files = {CGROUP_ROOT / "memory.max", CGROUP_ROOT / "memory" / "memory.limit_in_bytes"}
    for line in lines:
        _, controllers, where = (line.split(":", 2) + ["", ""])[:3]
        if controllers == "":
            base, name = CGROUP_ROOT, "memory.max"
        elif "memory" in controllers.split(","):
            base, name = CGROUP_ROOT / "memory", "memory.limit_in_bytes"
        else:
            continue
        parts = PurePosixPath(where).parts[1:]
        files.update(base.joinpath(*parts[:k], name) for k in range(len(parts) + 1))
    limits = []
    for file in files:
        try:
            text = file.read_text(encoding="ascii", errors="replace").strip()
        except OSError:  # not there, or not readable
            continue
        if text.isdigit() and int(text) < NO_LIMIT:
            limits.append(int(text))
    return min(limits, default=None)


def limit_words(max_memory: float) -> str:
    """The limit a run holds to, as a message names it: ``"max_memory = 4.0 GiB"``, or where
    the machine has less, ``"the memory of this machine (it has 16.0 GiB; max_memory =
    909.5 TiB is above it)"``."""
    machine = machine_memory()
    if machine is not None and machine < max_memory:
        return (f"the memory of this machine (it has {machine_words(machine)}; max_memory = "
                f"{format_bytes(max_memory)} is above it)")
    return f"max_memory = {format_bytes(max_memory)}"


def machine_words(machine: int) -> str:
    """What this machine has, ``"16.0 GiB"``, or ``"1.0 GiB for this process (its cgroup's
    limit)"``."""
    cgroup = " for this process (its cgroup's limit)" if machine == cgroup_limit() else ""
    return f"{format_bytes(machine)}{cgroup}"


def memory_problem(nbytes: float, what: str, fix: str,
                   max_memory: float = DEFAULT_MAX_MEMORY, holder: str = "a run") -> str | None:
    """Why a run holding ``nbytes`` would not fit, as the end of a one-line refusal; None if
    it fits.

    Parameters
    ----------
    nbytes : float
        Bytes the run would hold at its peak.
    what : str
        What takes the memory, e.g. ``"the time series of 1000000 members"``.
    fix : str
        How to bring it down, e.g. ``"use fewer members or a larger save_every"``.
    max_memory : float, default :data:`DEFAULT_MAX_MEMORY`
        The most a run may hold; the machine's memory where that is less.
    holder : str, default "a run"
        What may hold that much, as the line names it.

    Returns
    -------
    str or None
        ``"<what> would take about <size> in memory, above the <limit> <holder> may hold;
        this machine has <size>; <fix>"``.
    """
    machine = machine_memory()
    limit = min(max_memory, machine or max_memory)
    if nbytes <= limit:
        return None
    has = f"; this machine has {machine_words(machine)}" if machine else ""
    return (f"{what} would take about {format_bytes(nbytes)} in memory, above the "
            f"{format_bytes(limit)} {holder} may hold{has}; {fix}")

