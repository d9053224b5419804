"""The Earth's wobble study (stability.earth.studies.earth_wobble)."""

from pathlib import Path

import xarray as xr

from stability.study import run_study

from ...helpers import assert_cf_compliant, assert_declared

ROOT = Path(__file__).resolve().parents[3]


def test_study_runs_from_its_file(tmp_path):
    summary = run_study(ROOT / "studies" / "earth_wobble.toml", tmp_path, quick=True,
                        progress=False, overrides=[("output.formats", "['png']")])
    assert abs(summary.values["relative_error"]) < 1e-9
    with xr.open_dataset(tmp_path / "earth_wobble.nc") as ds:
        for name, var in ds.data_vars.items():
            assert var.attrs.get("units") and var.attrs.get("long_name"), name
    assert (tmp_path / "earth_wobble.png").exists()
    assert_cf_compliant(tmp_path / "earth_wobble.nc")
    assert_declared(tmp_path / "earth_wobble.nc", "earth_wobble")
