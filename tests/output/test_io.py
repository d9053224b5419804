"""save / load: netCDF4 round trip, compression, atomic writes, overwrite refusal, history."""

import tomllib

import netCDF4
import numpy as np
import pytest
import xarray as xr

import stability
from stability.output.io import COMPRESSIONS
from stability.util import conventions as cv
from stability.output import io
from stability.output.dataset import append_history, check_storable, config_toml

from ..helpers import assert_cf_compliant, assert_declared

BODY = stability.RigidBody(1.0, 2.0, 3.0, name="test body")


@pytest.fixture(scope="module")
def series():
    """A time-series ensemble with flagged members (RK4 at h W from 0.3 to 6)."""
    spins = np.geomspace(1.0, 20.0, 20)
    starts = np.column_stack([0.01 * spins, spins, 0.02 * spins])
    ds = stability.run_ensemble(BODY, 2, starts=starts, method="rk4", h=0.3, t_end=30.0)
    assert set(np.unique(ds.status.values)) > {0}  # some members are masked (NaN)
    return ds


@pytest.fixture(scope="module")
def summaries():
    return stability.run_ensemble(BODY, 2, 1.0, 1e-3, 300, h=0.05, t_end=50.0,
                                  keep=stability.Keep(save_every=0), seed=None)


@pytest.mark.parametrize("name", ["series", "summaries"])
def test_round_trip_is_identical(name, request, tmp_path):
    ds = request.getfixturevalue(name)
    path = stability.save(ds, tmp_path / "run.nc")
    back = stability.load(path)
    xr.testing.assert_identical(back, ds)
    for var in ds.variables:
        assert back[var].dtype == ds[var].dtype, var


def test_time_stays_float_seconds_and_is_cf_time(series, tmp_path):
    path = stability.save(series, tmp_path / "run.nc")
    back = stability.load(path)
    assert back.time.dtype == np.float64
    assert back.time.attrs["units"] == "s since 1970-01-01 00:00:00" == cv.UNITS_TIME_COORDINATE
    np.testing.assert_array_equal(back.time.values, series.time.values)
    with netCDF4.Dataset(path) as nc:  # what other tools see
        assert nc["time"].dtype == np.float64 and nc["time"].units == cv.UNITS_TIME_COORDINATE
        assert nc["time"].standard_name == "time" and nc["time"].axis == "T"
        assert "_FillValue" not in nc["time"].ncattrs()
    # A CF reader decodes the seconds to instants from the nominal origin.
    with xr.open_dataset(path) as opened:
        seconds = (opened.time.values - np.datetime64(cv.TIME_ORIGIN)) / np.timedelta64(1, "s")
        np.testing.assert_allclose(seconds, series.time.values, rtol=0, atol=1e-9)


@pytest.mark.parametrize("name", ["series", "summaries"])
def test_saved_runs_follow_cf(name, request, tmp_path):
    path = stability.save(request.getfixturevalue(name), tmp_path / "run.nc")
    assert_cf_compliant(path)
    assert_declared(path, "ensemble")


def test_saved_integration_with_attitude_follows_cf(tmp_path):
    ds = stability.integrate(BODY, [0.01, 1.0, 0.02], 1.0, 0.1, "rk4", scene="free_body_attitude")
    path = stability.save(ds, tmp_path / "run.nc")
    assert_cf_compliant(path)
    assert_declared(path, "trajectory")
    xr.testing.assert_identical(stability.load(path), ds)


def test_time_is_the_last_dimension_on_disk_and_back_in_place_on_load(series, tmp_path):
    """CF 2.4 wants time right of every other dimension; the package keeps each member's samples
    of one instant together, w (member, time, axis): the file holds w (member, axis, time),
    plain xarray reads it so, and load (and a store's Dataset) puts it back."""
    path = stability.save(series, tmp_path / "run.nc")
    with netCDF4.Dataset(path) as nc:
        assert nc["w"].dimensions == (cv.MEMBER, cv.AXIS, cv.TIME)
    with xr.open_dataset(path) as opened:
        assert opened.w.dims == (cv.MEMBER, cv.AXIS, cv.TIME)
    back = stability.load(path)
    assert back.w.dims == series.w.dims == (cv.MEMBER, cv.TIME, cv.AXIS)
    np.testing.assert_array_equal(back.w.values, series.w.values)


def test_file_is_compressed_and_chunked_along_member(series, tmp_path):
    path = stability.save(series, tmp_path / "run.nc")
    with netCDF4.Dataset(path) as nc:
        assert nc.Conventions == "CF-1.10"
        for name in ("w", "status", "passage_time", "energy_error"):
            filters = nc[name].filters()
            assert filters["zlib"] and filters["complevel"] == 1, name
            assert filters["shuffle"], name
            chunks = nc[name].chunking()
            assert chunks != "contiguous"
            assert list(chunks[1:]) == list(nc[name].shape[1:]), name  # whole members
        assert nc["status"].dtype == np.int8


@pytest.mark.parametrize("codec", sorted(COMPRESSIONS))
def test_each_compression_reads_back_identical_and_as_cf_readers_see_it(series, tmp_path,
                                                                       codec):
    """Every compression of COMPRESSIONS gives back the Dataset saved, is the filter netCDF
    reports, and passes the CF checker; anything else is refused before a file is made."""
    path = stability.save(series, tmp_path / f"{codec}.nc", compress=codec)
    xr.testing.assert_identical(stability.load(path), series)
    with netCDF4.Dataset(path) as nc:
        filters = nc["w"].filters()
        assert filters["zlib"] == (codec == "zlib") and filters["zstd"] == (codec == "zstd")
        assert filters["shuffle"] == (codec == "zlib")
    assert_cf_compliant(path)
    with pytest.raises(ValueError, match="compression must be one of zlib, zstd, none"):
        stability.save(series, tmp_path / "other.nc", compress="lz5")
    assert not (tmp_path / "other.nc").exists()


def test_existing_file_is_not_overwritten_unless_asked(series, summaries, tmp_path):
    path = stability.save(series, tmp_path / "run.nc")
    before = path.read_bytes()
    with pytest.raises(FileExistsError, match="overwrite=True"):
        stability.save(summaries, path)
    assert path.read_bytes() == before
    stability.save(summaries, path, overwrite=True)
    xr.testing.assert_identical(stability.load(path), summaries)


@pytest.mark.parametrize("error, raised", [(RuntimeError("NetCDF: HDF error"), OSError),
                                           (KeyboardInterrupt(), KeyboardInterrupt)])
def test_interrupted_write_leaves_no_file(series, tmp_path, monkeypatch, error, raised):
    real = io._write

    def write_then_fail(ds, path, encoding):
        real(ds, path, encoding)  # the temporary file is complete on disk ...
        assert path.exists() and path.parent == tmp_path
        raise error  # ... and the write is interrupted before the rename

    monkeypatch.setattr(io, "_write", write_then_fail)
    with pytest.raises(raised):  # a library's error is an OSError naming the path
        stability.save(series, tmp_path / "run.nc")
    assert list(tmp_path.iterdir()) == []  # neither the target nor the temporary file


def test_interrupted_overwrite_keeps_the_old_file(series, summaries, tmp_path, monkeypatch):
    path = stability.save(summaries, tmp_path / "run.nc")
    before = path.read_bytes()

    def fail(ds, path, encoding):
        path.write_bytes(b"CDF half-written")
        raise OSError("interrupted")

    monkeypatch.setattr(io, "_write", fail)
    with pytest.raises(OSError):
        stability.save(series, path, overwrite=True)
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["run.nc"]


def test_unstorable_attributes_are_refused_before_writing(summaries, tmp_path):
    for bad, message in [(True, "bool"), (None, "NoneType"), ([1, 2], "list"),
                         (np.array([1.0]), "one-element"), ({"a": 1}, "dict")]:
        ds = summaries.copy()
        ds.attrs = {**summaries.attrs, "flag": bad}
        with pytest.raises(ValueError, match=f"attribute 'flag' of the Dataset .*{message}"):
            stability.save(ds, tmp_path / "bad.nc")
    ds = summaries.copy()
    ds["energy_error"].attrs["ok"] = False
    with pytest.raises(ValueError, match="variable 'energy_error'"):
        stability.save(ds, tmp_path / "bad.nc")
    assert list(tmp_path.iterdir()) == []


def test_history_appends_one_timestamped_line(summaries, tmp_path):
    changed = append_history(summaries, "stability plot run.nc\n--format png")
    lines = changed.attrs["history"].split("\n")
    assert lines[0] == summaries.attrs["history"]
    assert len(lines) == 2 and lines[1].endswith(": stability plot run.nc --format png")
    assert lines[1][:4].isdigit() and lines[1][19] == "Z"  # 2026-01-01T00:00:00Z: ...
    assert "\n" not in summaries.attrs["history"]  # the original is unchanged
    back = stability.load(stability.save(changed, tmp_path / "run.nc"))
    assert back.attrs["history"] == changed.attrs["history"]
    check_storable(back)


def test_config_toml_round_trips_through_toml_and_netcdf(summaries, tmp_path):
    config = {"study": {"members": np.int64(300), "eps": [1e-3, 1e-4], "skip": None},
              "seed": 2**100}
    text = config_toml(config)
    assert tomllib.loads(text) == {"study": {"members": 300, "eps": [1e-3, 1e-4]},
                                   "seed": str(2**100)}
    entropy = int(summaries.attrs["seed_entropy"])  # fresh 128-bit entropy, kept exactly
    assert entropy > 2**64
    back = stability.load(stability.save(summaries, tmp_path / "run.nc"))
    assert tomllib.loads(back.attrs["config_toml"])["run_ensemble"]["seed"] == str(entropy)


def test_load_and_save_errors(summaries, tmp_path):
    with pytest.raises(FileNotFoundError, match="no such file"):
        stability.load(tmp_path / "missing.nc")
    text = tmp_path / "notes.nc"
    text.write_text("not a netCDF file\n")
    with pytest.raises(ValueError, match=r"notes.nc is not a netCDF file stability can read "
                                         r"\(.*Unknown file format.*\); give a .nc file"):
        stability.load(text)
    with pytest.raises(ValueError, match="is a folder; give a .nc file written by "
                                         "stability.save"):
        stability.load(tmp_path)
    with pytest.raises(ValueError, match="does not exist"):
        stability.save(summaries, tmp_path / "nowhere" / "run.nc")
    with pytest.raises(ValueError, match="xarray.Dataset"):
        stability.save(summaries.energy_error, tmp_path / "run.nc")


def test_integrate_dataset_round_trips_too(tmp_path):
    ds = stability.integrate(BODY, [0.01, 1.0, 0.0], t_end=5.0, h=0.1, method="rk4")
    assert ds.attrs["Conventions"] == "CF-1.10" and "integrate" in ds.attrs["history"]
    back = stability.load(stability.save(ds, tmp_path / "one.nc"))
    xr.testing.assert_identical(back, ds)

