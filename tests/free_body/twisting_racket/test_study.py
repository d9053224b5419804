"""The twisting-racket study (stability.free_body.twisting_racket.study): its quick run, Dataset and
figures."""

from pathlib import Path

import xarray as xr

from ...helpers import assert_cf_compliant, assert_declared, assert_readable

ROOT = Path(__file__).resolve().parents[3]


def test_study_twisting_racket_quick(tmp_path):
    from stability.free_body.twisting_racket.figures import flip_figure, twist_figure
    from stability.study import run_study

    summary = run_study(ROOT / "studies" / "twisting_racket.toml", tmp_path, quick=True,
                        progress=False, overrides=[("output.formats", "['png']")])
    v = summary.values
    assert v["max_montgomery_error"] < v["claim"] and v["max_twist_error"] < v["claim"]
    assert v["members_failed"] == 0 and 0.15 < v["twist_defect_member0"] < 0.3
    with xr.open_dataset(tmp_path / "twisting_racket.nc") as ds:
        for name, var in {**ds.data_vars, **ds.coords}.items():
            assert var.attrs.get("units") and var.attrs.get("long_name"), name
        assert_readable(twist_figure(ds))
        assert_readable(flip_figure(ds))
    assert_cf_compliant(tmp_path / "twisting_racket.nc")
    assert_declared(tmp_path / "twisting_racket.nc", "twisting_racket")
