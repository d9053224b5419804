"""Where a study's time went: the table every study's summary ends with (:func:`time_table`).

The seconds come from the time ledger (:mod:`stability.util.ledger`) that the study runner
opens around the kind's run: the member loop, Numba's compilation and the per-chunk measurement
of every run through the pipeline, and the figures and the Dataset's write. What is left of the
wall time (set-up, the measurement after the run, reading chunk files, joining them) is shown as
the rest, so the rows add up to the wall time.
"""

from __future__ import annotations

from .kind import StudySummary, SummaryTable

#: The ledger's stages as the table names them.
STAGE_NAMES = {"integration": "integration (member loop)", "compile": "Numba compile",
               "measuring": "measuring, per chunk where it ran", "figures": "figures",
               "write": "the Dataset's write after the figures"}


def time_table(wall: float, spent: dict) -> tuple[SummaryTable, dict]:
    """The table of where ``wall`` seconds went, from the ledger's ``spent`` seconds by stage,
    and the same numbers by name (``time_<stage>``, ``time_other``, ``time_wall``).

    Parameters
    ----------
    wall : float
        The study run's wall time, s.
    spent : dict
        ``{stage: seconds}`` of :data:`stability.util.ledger.STAGES`.

    Returns
    -------
    SummaryTable, dict
    """
    values = {f"time_{stage}": float(spent.get(stage, 0.0)) for stage in STAGE_NAMES}
    rest = max(0.0, wall - sum(values.values()))
    rows = [(name, f"{values[f'time_{stage}']:.2f}", f"{_share(values[f'time_{stage}'], wall)}")
            for stage, name in STAGE_NAMES.items()]
    rows.append(("the rest (set-up, measuring after the run, files)", f"{rest:.2f}",
                 _share(rest, wall)))
    rows.append(("wall time", f"{wall:.2f}", "100"))
    values.update({"time_other": rest, "time_wall": float(wall)})
    return SummaryTable("where the time went", [("stage", ""), ("time", "s"), ("share", "%")],
                        rows), values


def _share(seconds: float, wall: float) -> str:
    return f"{100.0 * seconds / wall:.0f}" if wall > 0 else "-"


def add_time_table(summary: StudySummary, wall: float, spent: dict) -> None:
    """End ``summary`` with :func:`time_table`, and its values with the same numbers, unless
    its kind states its own breakdown of every stage (its values hold ``figures_time``: the
    tennis racket's, the stability map's)."""
    if "figures_time" in summary.values:
        return
    table, values = time_table(wall, spent)
    summary.tables.append(table)
    summary.values.update(values)
