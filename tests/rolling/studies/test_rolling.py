"""The rolling study (stability.rolling.studies.rolling)."""

from pathlib import Path

from ...helpers import assert_cf_compliant, assert_declared, assert_readable


def test_rolling_study_meets_its_claim_with_units_everywhere(tmp_path):
    import stability
    from stability.rolling.figures import rolling_launch_figure, rolling_map_figure
    from stability.study import run_study

    root = Path(__file__).resolve().parents[3]
    summary = run_study(root / "studies" / "rolling.toml", tmp_path, quick=True,
                        progress=False, overrides=[("output.formats", "['png']")])
    v = summary.values
    assert v["cells_wrong_side"] == 0 and v["members_against_own_formula"] == 0
    for key in ("t_roll", "x_roll", "v_final", "heat", "acceleration", "spin_rate"):
        assert v[f"max_error_{key}"] < v["claim"], key
    assert v["members_failed"] == 0
    assert sorted(p.name for p in summary.files) == [
        "config.toml", "rolling.nc", "rolling_launch.png", "rolling_map.png"]
    ds = stability.load(tmp_path / "rolling.nc")
    for name, var in {**ds.data_vars, **ds.coords}.items():
        assert var.attrs.get("units") and var.attrs.get("long_name"), name
    assert_readable(rolling_map_figure(ds))
    assert_readable(rolling_launch_figure(ds))
    assert_cf_compliant(tmp_path / "rolling.nc")
    assert_declared(tmp_path / "rolling.nc", "rolling")
