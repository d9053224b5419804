"""The bat study (stability.struck.studies.bat)."""

from pathlib import Path

from ...helpers import assert_cf_compliant, assert_declared, assert_readable


def test_bat_study_meets_its_claim_with_units_everywhere(tmp_path):
    import xarray as xr

    from stability.struck.figures import bat_figure
    from stability.study import run_study

    root = Path(__file__).resolve().parents[3]
    summary = run_study(root / "studies" / "bat.toml", tmp_path, quick=True, progress=False,
                        overrides=[("output.formats", "['png']")])
    v = summary.values
    assert v["max_error_held"] < v["claim"] and v["max_error_free"] < 1e-4
    assert v["max_error_sweet_zone"] < 1e-6 and v["members_failed"] == 0  # 16 RK4 steps
    assert sorted(p.name for p in summary.files) == ["bat.nc", "bat.png", "config.toml"]
    with xr.open_dataset(tmp_path / "bat.nc") as ds:
        for name, var in {**ds.data_vars, **ds.coords}.items():
            assert var.attrs.get("units") and var.attrs.get("long_name"), name
        assert_readable(bat_figure(ds))
    assert_cf_compliant(tmp_path / "bat.nc")
    assert_declared(tmp_path / "bat.nc", "bat")
    racket = run_study(root / "studies" / "bat.toml", tmp_path / "racket", quick=True,
                       progress=False, overrides=[("body.kind", '"tennis_racket"'),
                                                  ("hands.pivots", "[0.08]"),
                                                  ("output.figures", "false")])
    assert racket.values["max_error_held"] < 1e-9
