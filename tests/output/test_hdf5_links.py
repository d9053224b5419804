"""What in an HDF5 file reaches outside it (stability.output.hdf5_links), for real hostile files: an
external link (to a file or a FIFO), external storage, a virtual dataset and a link inside a group
are each refused in one line, nothing outside read (the files and helpers of
tests/output/test_untrusted.py)."""

import os

import netCDF4
import numpy as np
import pytest

import stability

from .test_untrusted import one_line, refused_beside, small_dataset, with_external_link, with_h5py


def test_an_external_link_is_refused_and_the_other_file_never_read(tmp_path):
    secret = tmp_path / "secret.h5"
    with_h5py("""
        with h5py.File(secret, "w") as f:
            f["data"] = np.array([3.14, 2.72])
        """, secret=secret)
    path = with_external_link(tmp_path / "linked.nc", secret)
    with pytest.raises(ValueError) as caught:
        stability.load(path)
    message = one_line(caught, path)
    assert "external link /stolen" in message and "secret.h5" in message
    assert "reads nothing outside the file" in message and "stability.save" in message


def test_an_external_link_to_a_fifo_is_refused_without_blocking(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    path = with_external_link(tmp_path / "linked.nc", fifo)
    caught, readers = refused_beside(fifo, lambda: stability.load(path))
    assert "external link" in one_line(caught, path)
    assert readers == 0, "the FIFO was opened for reading"


def test_a_variable_in_external_storage_is_refused(tmp_path):
    raw = tmp_path / "raw.bin"
    raw.write_bytes(np.arange(10.0).tobytes())
    path = tmp_path / "external.nc"
    with netCDF4.Dataset(path, "w") as nc:
        nc.createDimension("n", 10)
    with_h5py("""
        with h5py.File(path, "a") as f:
            f.create_dataset("v", shape=(10,), dtype="f8", external=[(raw, 0, 80)])
        """, path=path, raw=raw)
    with pytest.raises(ValueError) as caught:
        stability.load(path)
    message = one_line(caught, path)
    assert "stores its variable /v in external files" in message and "raw.bin" in message


def test_a_virtual_dataset_made_of_other_files_is_refused(tmp_path):
    source = tmp_path / "source.h5"
    path = tmp_path / "virtual.nc"
    with_h5py("""
        with h5py.File(source, "w") as f:
            f["data"] = np.arange(4.0)
        layout = h5py.VirtualLayout(shape=(4,), dtype="f8")
        layout[:] = h5py.VirtualSource(source, "data", shape=(4,))
        with h5py.File(path, "w") as f:
            f.create_virtual_dataset("v", layout)
        """, source=source, path=path)
    with pytest.raises(ValueError) as caught:
        stability.load(path)
    assert "virtual dataset /v" in one_line(caught, path)


def test_a_link_inside_a_group_is_found_too(tmp_path):
    path = tmp_path / "grouped.nc"
    stability.save(small_dataset(), path)
    with_h5py("""
        with h5py.File(path, "a") as f:
            f.create_group("inner/deeper")["link"] = h5py.ExternalLink("/etc/hostname", "/")
        """, path=path)
    with pytest.raises(ValueError) as caught:
        stability.load(path)
    assert "external link /inner/deeper/link" in one_line(caught, path)
