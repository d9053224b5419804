"""Where a run's time goes: seconds by stage, kept for the run under way (:func:`time_ledger`).

The one pipeline (:func:`stability.ensemble.chunks.run_plan`) books the member loop's seconds
(``integration``), Numba's compilation (``compile``) and the per-chunk measurement
(``measuring``) of every run it makes, wherever the chunks ran (a chunk's own times travel in
its file); a study's outputs book ``figures`` and ``write`` (the Dataset's write after the
figures). A study run (:func:`stability.study.run_study`) opens a ledger around its kind's run
and prints what it holds, so that every study says where its time went without each kind
timing itself. Outside a ledger, booking does nothing.
"""

from __future__ import annotations

import contextvars
from collections import defaultdict
from contextlib import contextmanager

#: The stages booked, in the order a summary lists them.
STAGES = ("integration", "compile", "measuring", "figures", "write")

_LEDGER: contextvars.ContextVar = contextvars.ContextVar("stability_time_ledger", default=None)


@contextmanager
def time_ledger():
    """Book the seconds of the runs made inside the block; yields the ``{stage: seconds}``
    dict they are added to (a ledger opened inside another books to the inner one only)."""
    spent = defaultdict(float)
    token = _LEDGER.set(spent)
    try:
        yield spent
    finally:
        _LEDGER.reset(token)


def book(stage: str, seconds) -> None:
    """Add ``seconds`` to ``stage`` (one of :data:`STAGES`) of the open ledger, if any."""
    if stage not in STAGES:
        raise ValueError(f"stage must be one of {', '.join(STAGES)}, got {stage!r}")
    spent = _LEDGER.get()
    if spent is not None:
        spent[stage] += float(seconds)
