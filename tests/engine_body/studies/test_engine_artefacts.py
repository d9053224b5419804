"""The engine artefacts study (stability.engine_body.studies.engine_artefacts)."""

from pathlib import Path

import numpy as np

import stability

from ...helpers import assert_cf_compliant, assert_declared, assert_readable
from ..test_measure import RACKET, STARTS

ROOT = Path(__file__).resolve().parents[3]


def test_study_engine_artefacts_quick(tmp_path):
    from stability.engine_body.figures import artefacts_figure
    from stability.study import run_study

    summary = run_study(ROOT / "studies" / "engine_artefacts.toml", tmp_path, quick=True,
                        progress=False, overrides=[("output.formats", "['png']")])
    rules = summary.values["rules"]
    assert rules["no_gyroscopic"]["fraction_flipping"] == 0.0
    assert rules["exact"]["fraction_flipping"] == 1.0
    assert abs(rules["rk4"]["flip_interval_error"]) < 1e-4
    assert np.isnan(rules["no_gyroscopic"]["step_needed"])
    text = summary.table()  # one column per quantity, words where there is no number
    header = next(line for line in text.splitlines() if line.startswith("rule "))
    assert header.split("  ")[0] == "rule" and "step for energy" in header
    no_gyro = next(line for line in text.splitlines() if line.startswith("no_gyroscopic "))
    assert "no flip" in no_gyro and "not reached" in no_gyro and "nan" not in text
    ds = stability.load(tmp_path / "engine_artefacts.nc")
    for name, var in {**ds.data_vars, **ds.coords}.items():
        assert var.attrs.get("units") and var.attrs.get("long_name"), name
    assert_readable(artefacts_figure(ds))
    assert_cf_compliant(tmp_path / "engine_artefacts.nc")
    assert_declared(tmp_path / "engine_artefacts.nc", "engine_artefacts")


def test_progress_false_silences_every_bar_of_the_study(capfd):
    """``--no-progress`` reaches every run the study makes (they showed their bars)."""
    from stability.engine_body.measure import measure_artefacts

    args = (["rk4", "semi_implicit_euler"], RACKET, STARTS[:4], [1 / 60], 1.0)
    measure_artefacts(*args, halvings=1, search_members=4,
                      options=stability.RunOptions(progress=True))
    assert "step" in capfd.readouterr().err  # bars with units of steps, when asked for
    measure_artefacts(*args, halvings=1, search_members=4,
                      options=stability.RunOptions(progress=False))
    assert capfd.readouterr().err == ""
