"""Every study says where its time went: the summary's table of the member loop, compilation,
measuring, figures and the write, adding up to the wall time."""

from pathlib import Path

import pytest

from stability.study import run_study
from stability.study.timing import STAGE_NAMES, time_table

ROOT = Path(__file__).resolve().parents[2]


def test_the_table_adds_up_to_the_wall_time_and_names_every_stage():
    table, values = time_table(10.0, {"integration": 4.0, "compile": 1.0, "figures": 2.5})
    assert [row[0] for row in table.rows[:5]] == list(STAGE_NAMES.values())
    assert values["time_other"] == pytest.approx(2.5)
    assert sum(float(row[1]) for row in table.rows[:-1]) == pytest.approx(10.0)
    assert table.rows[0][2] == "40" and table.rows[-1] == ("wall time", "10.00", "100")
    assert "where the time went" in table.text()


@pytest.mark.parametrize("kind", ["bat"])
def test_a_study_run_ends_with_where_its_time_went(tmp_path, kind):
    """A quick run through the pipeline: its member loop's seconds are booked (> 0), the figures
    and the write too, and the rows add up to the wall time."""
    summary = run_study(ROOT / "studies" / f"{kind}.toml", quick=True, progress=False,
                        out_dir=tmp_path, overrides=[("output.formats", "['png']")])
    v = summary.values
    assert v["time_integration"] > 0 and v["time_figures"] > 0 and v["time_write"] > 0
    parts = sum(v[f"time_{stage}"] for stage in STAGE_NAMES) + v["time_other"]
    assert parts == pytest.approx(v["time_wall"], rel=1e-9)
    assert v["time_wall"] >= v["wall_time"]  # the kind's own wall time is inside it
    assert "where the time went" in summary.table()
