"""How much memory a run may hold: the one check every run makes before any work.

A run that would not fit is refused at once, in one line, rather than by NumPy's allocation
error, perhaps after minutes of work. Each caller estimates its own bytes (a rough upper bound
of what it holds at its peak) and words the refusal as its settings are named (a study's keys,
a function's arguments); the limit and the line's middle are here:
:func:`stability.study.sections.check_memory` for the study kinds, :func:`stability.run_scene`
for a run of any scene.
"""

from __future__ import annotations

import os

from ..util.formatting import format_bytes

#: Default limit (bytes) on what one run may hold in memory (and on the Dataset of
#: :func:`stability.run_ensemble`, its ``max_memory``).
DEFAULT_MAX_MEMORY = 4 * 2**30


def machine_memory() -> int | None:
    """Bytes of physical memory of this machine; None where the system does not say."""
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):
        return None


def memory_problem(nbytes: float, what: str, fix: str,
                   max_memory: float = DEFAULT_MAX_MEMORY) -> str | None:
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

    Returns
    -------
    str or None
        ``"<what> would take about <size> in memory, above the <limit> a run may hold; this
        machine has <size>; <fix>"``.
    """
    machine = machine_memory()
    limit = min(max_memory, machine or max_memory)
    if nbytes <= limit:
        return None
    has = f"; this machine has {format_bytes(machine)}" if machine else ""
    return (f"{what} would take about {format_bytes(nbytes)} in memory, above the "
            f"{format_bytes(limit)} a run may hold{has}; {fix}")
