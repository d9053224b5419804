"""A netCDF file handed in is untrusted: real hostile files, each refused in one line.

Each case builds the file for real (an HDF5 external link made with h5py, in a process of its
own, since h5py's HDF5 beside netCDF's in one process breaks the netCDF library; a variable stored in
an external file, a virtual dataset, a file declaring 1e12 members in a few kB, a data chunk
damaged by flipped bytes, a FIFO, a device or a folder at the path) and checks that
``stability.load`` and the readers of a run's chunk folder refuse it with one line that names
the file and says what to do, read nothing outside it, allocate nothing of the declared size,
and never open a FIFO (a thread beside each such case releases a reader that waits on it,
and counts it).
"""

import importlib.util
import json
import os
import subprocess
import sys
import textwrap
import threading
from pathlib import Path

import netCDF4
import numpy as np
import pytest
import xarray as xr

import stability
from stability.ensemble.chunks import summed_attrs
from stability.free_body.stability_map.measure import read_batch
from stability.output.store import ChunkStore, open_store


def small_dataset(members=4) -> xr.Dataset:
    return xr.Dataset({"w": (("member", "axis"), np.arange(3.0 * members).reshape(members, 3))},
                      coords={"member": np.arange(members)})


def one_line(exc_info, path) -> str:
    """The refusal's message, checked to be one line naming ``path``."""
    message = str(exc_info.value)
    assert "\n" not in message and str(path) in message, message
    return message


def with_h5py(code: str, **names):
    """Run ``code`` with h5py and NumPy in a new process, ``names`` (paths) bound as strings;
    what it prints as JSON, if anything. h5py carries an HDF5 library of its own, which must
    not meet the netCDF library's in one process (the netCDF library then fails or crashes)."""
    if importlib.util.find_spec("h5py") is None:  # not imported here: its HDF5 stays out
        pytest.skip("h5py (the test extra) makes the hostile files")
    bound = "".join(f"{key} = {str(value)!r}\n" for key, value in names.items())
    done = subprocess.run([sys.executable, "-c", "import json, h5py, numpy as np\n" + bound
                           + textwrap.dedent(code)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout) if done.stdout.strip() else None


def with_external_link(path: Path, target: Path) -> Path:
    """``path``: a file stability.save wrote, with an external link to ``target``'s /data."""
    stability.save(small_dataset(), path)
    with_h5py("""
        with h5py.File(path, "a") as f:
            f["stolen"] = h5py.ExternalLink(target, "/data")
        """, path=path, target=target)
    return path


def refused_beside(fifo: Path, call):
    """``call()``'s ValueError, and how often ``call`` opened ``fifo`` for reading.

    Meanwhile a thread opens the FIFO for writing whenever a reader waits on it (an open that
    succeeds only then), which releases that reader: a call that would wait for good returns,
    and is seen to have opened the FIFO.
    """
    stop, readers = threading.Event(), []

    def release():
        while not stop.is_set():
            try:
                os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
                readers.append(1)
            except OSError:  # ENXIO: no reader waits
                pass
            stop.wait(0.01)

    thread = threading.Thread(target=release, daemon=True)
    thread.start()
    try:
        with pytest.raises(ValueError) as caught:
            call()
    finally:
        stop.set()
        thread.join()
    return caught, len(readers)


def huge_file(path: Path, members=10**12) -> Path:
    """A netCDF file of a few kB declaring ``members`` members (no data written)."""
    with netCDF4.Dataset(path, "w") as nc:
        nc.createDimension("member", members)
        nc.createDimension("axis", 3)
        nc.createVariable("member", "i8", ("member",), chunksizes=(1024,))
        nc.createVariable("w", "f8", ("member", "axis"), chunksizes=(1024, 3))
    return path


def test_a_tiny_file_declaring_1e12_members_is_refused_before_any_allocation(tmp_path):
    path = huge_file(tmp_path / "huge.nc")
    assert path.stat().st_size < 64 * 1024
    with pytest.raises(ValueError) as caught:
        stability.load(path)
    message = one_line(caught, path)
    assert "would take about 29.1 TiB in memory, above the" in message
    assert "open it lazily" in message and "xarray.open_dataset" in message
    assert "open_store" in message


def test_a_file_above_max_memory_is_refused_and_one_within_it_read(tmp_path):
    path = stability.save(small_dataset(1000), tmp_path / "run.nc")
    with pytest.raises(ValueError) as caught:
        stability.load(path, max_memory=10_000)
    assert "31.2 KiB in memory, above the 9.8 KiB" in one_line(caught, path)
    xr.testing.assert_identical(stability.load(path, max_memory=10**6), small_dataset(1000))


def damaged_file(path: Path) -> Path:
    """A saved file whose first compressed chunk of ``w`` has 100 bytes flipped."""
    values = np.random.default_rng(0).normal(size=20000)
    stability.save(xr.Dataset({"w": (("member",), values)}), path)
    offset, size = with_h5py("""
        with h5py.File(path, "r") as f:
            chunk = f["w"].id.get_chunk_info(0)
        print(json.dumps([chunk.byte_offset, chunk.size]))
        """, path=path)
    assert size > 1000
    data = bytearray(path.read_bytes())
    for i in range(offset + 200, offset + 300):
        data[i] ^= 0xFF
    path.write_bytes(bytes(data))
    return path


def test_a_damaged_chunk_is_one_line_naming_the_file_and_variable(tmp_path, capfd):
    path = damaged_file(tmp_path / "damaged.nc")
    with pytest.raises(ValueError) as caught:
        stability.load(path)
    message = one_line(caught, path)
    assert "is damaged: its variable 'w' cannot be read" in message
    assert "write it again, or use an intact copy" in message
    assert "HDF5" not in capfd.readouterr().err  # no diagnostics of the library printed


def test_a_fifo_at_the_path_is_refused_without_blocking(tmp_path):
    fifo = tmp_path / "run.nc"
    os.mkfifo(fifo)
    link = tmp_path / "link.nc"
    link.symlink_to(fifo)
    for path in (fifo, link):
        caught, readers = refused_beside(fifo, lambda: stability.load(path))
        assert "is a FIFO (named pipe), not a regular file" in one_line(caught, path)
        assert readers == 0, "the FIFO was opened for reading"


@pytest.mark.parametrize("path, kind", [("/dev/null", "a character device"),
                                        ("/dev/zero", "a character device")])
def test_a_device_at_the_path_is_refused(path, kind):
    if not os.path.exists(path):
        pytest.skip(f"{path} is not on this system")
    with pytest.raises(ValueError) as caught:
        stability.load(path)
    assert f"is {kind}, not a regular file" in one_line(caught, path)


def store_of_two_chunks(folder: Path) -> ChunkStore:
    """A complete store of 4 members in chunks of 2, its lock given back."""
    store = ChunkStore(folder, {"case": "untrusted"}, 4, 2)
    for k in range(2):
        part = small_dataset(2).assign_coords(member=np.arange(2 * k, 2 * k + 2))
        part.attrs["wall_time"] = 1.0
        store.write(k, part)
    store.complete({"title": "two chunks"})
    store.close()
    return store


def test_a_store_whose_chunk_links_outside_is_refused_naming_the_chunk(tmp_path):
    store = store_of_two_chunks(tmp_path / "store")
    assert open_store(store.dir).w.shape == (4, 3)
    with_h5py("""
        with h5py.File(path, "a") as f:
            f["stolen"] = h5py.ExternalLink("/etc/hostname", "/")
        """, path=store.path(1))
    for read in (open_store, lambda _: summed_attrs(store, 0.0)):
        with pytest.raises(ValueError) as caught:
            read(store.dir)
        assert "external link /stolen" in one_line(caught, store.path(1))


def test_a_store_whose_chunk_is_a_fifo_is_refused_without_blocking(tmp_path):
    store = store_of_two_chunks(tmp_path / "store")
    store.path(0).unlink()
    os.mkfifo(store.path(0))
    caught, readers = refused_beside(store.path(0), lambda: open_store(store.dir))
    assert "is a FIFO" in one_line(caught, store.path(0))
    assert readers == 0, "the FIFO was opened for reading"


def test_a_store_chunk_declaring_a_huge_coordinate_is_refused_before_reading_it(tmp_path):
    store = store_of_two_chunks(tmp_path / "store")
    store.path(1).unlink()
    with netCDF4.Dataset(store.path(1), "w") as nc:
        nc.createDimension("member", 2)
        nc.createDimension("axis", 10**12)
        nc.createVariable("axis", "i8", ("axis",), chunksizes=(1024,))
        nc.createVariable("w", "f8", ("member", "axis"), chunksizes=(1, 1024))
    with pytest.raises(ValueError) as caught:
        open_store(store.dir)
    assert "the coordinates of" in one_line(caught, store.path(1))


def test_a_stability_map_batch_file_is_checked_as_load_checks_a_file(tmp_path):
    path = with_external_link(tmp_path / "batch.nc", Path("/etc/hostname"))
    with pytest.raises(ValueError) as caught:
        read_batch(path, 1)
    assert "external link" in one_line(caught, path)
    with pytest.raises(ValueError) as caught:
        read_batch(damaged_file(tmp_path / "damaged.nc"), 1)
    assert "is damaged" in one_line(caught, tmp_path / "damaged.nc")

