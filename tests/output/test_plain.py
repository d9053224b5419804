"""A file opened with plain xarray: ds.stability.in_seconds() gives what stability.load reads."""

import numpy as np
import xarray as xr

import stability


def test_a_plainly_opened_file_in_seconds_is_what_stability_load_reads(tmp_path):
    body = stability.RigidBody(1.0, 2.0, 3.0)
    ds = stability.run_ensemble(body, 2, 1.0, 0.1, 4, h=0.01, t_end=1.0,
                                keep=stability.Keep(save_every=10),
                                options=stability.RunOptions(progress=False))  # times 0.1 k, not whole nanoseconds
    path = stability.save(ds, tmp_path / "run.nc")
    with xr.open_dataset(path) as plain:  # xarray's defaults: dates, the file's order
        assert plain.time.dtype.kind == "M" and str(plain.time.values[1]).startswith("1970")
        assert plain.w.dims == ("member", "axis", "time")
        back = plain.stability.in_seconds()
        assert back.w.dims == ("member", "time", "axis")
        assert np.array_equal(back.time.values, ds.time.values)  # bit for bit
        assert back.time.attrs["units"] == "s since 1970-01-01 00:00:00"  # CF kept
        xr.testing.assert_identical(back.load(), stability.load(path))
    loaded = stability.load(path)
    assert loaded.stability.in_seconds().time.values.tolist() == loaded.time.values.tolist()
    assert np.array_equal(loaded.stability.in_seconds().w.values, loaded.w.values)
