"""What in an HDF5 file reaches outside it, found without following anything: :func:`outside`.

An HDF5 file (a netCDF4 file is one) may hold external links (to an object of another file,
which the netCDF library follows, returning that file's contents as a variable, or waiting for
good on a FIFO), user-defined links, datasets stored in external raw files and virtual datasets
made of other files. :func:`outside` visits every link of the file (``H5Lvisit2``: into groups by
hard links only, each object once) and every dataset's creation properties, and names the first
such thing.

It uses the HDF5 library the netCDF library itself is linked to, through its C API (``ctypes``
on netCDF4's extension module, whose dependencies hold it), under xarray's HDF5 lock: a second
HDF5 library in the process (h5py's wheel carries its own) makes the netCDF library fail with
"HDF error" or crash, a known conflict of the two wheels.
"""

from __future__ import annotations

import ctypes
import functools
import gc
from pathlib import Path

import netCDF4
from xarray.backends.locks import HDF5_LOCK

_hid = ctypes.c_int64
_herr = ctypes.c_int
_P_DEFAULT = 0
_E_DEFAULT = 0
_F_ACC_RDONLY = 0
_INDEX_NAME = 0
_ITER_NATIVE = 2
_L_TYPE_HARD, _L_TYPE_SOFT, _L_TYPE_EXTERNAL = 0, 1, 64
_O_TYPE_DATASET = 1
_O_INFO_BASIC = 1
_D_VIRTUAL = 3
_T_VLEN = 9
#: Offsets in H5L_info2_t (type: int at 0; u.val_size: size_t at 24) and H5O_info2_t
#: (type: int after fileno and the 16-byte token), for LP64 platforms.
_LINK_TYPE, _LINK_VAL_SIZE, _OBJECT_TYPE = 0, 24, 24
_INFO_BYTES = 256  # room for either struct

_VISIT = ctypes.CFUNCTYPE(_herr, _hid, ctypes.c_char_p, ctypes.c_void_p, ctypes.c_void_p)


@functools.cache
def _library():
    """The HDF5 C API of the library netCDF4 is linked to, its signatures declared."""
    lib = ctypes.CDLL(netCDF4._netCDF4.__file__)
    signatures = {
        "H5open": (_herr, []),
        "H5Eset_auto2": (_herr, [_hid, ctypes.c_void_p, ctypes.c_void_p]),
        "H5Fis_accessible": (ctypes.c_int, [ctypes.c_char_p, _hid]),
        "H5Fopen": (_hid, [ctypes.c_char_p, ctypes.c_uint, _hid]),
        "H5Fclose": (_herr, [_hid]),
        "H5Lvisit2": (_herr, [_hid, ctypes.c_int, ctypes.c_int, _VISIT, ctypes.c_void_p]),
        "H5Lget_info2": (_herr, [_hid, ctypes.c_char_p, ctypes.c_void_p, _hid]),
        "H5Lget_val": (_herr, [_hid, ctypes.c_char_p, ctypes.c_void_p, ctypes.c_size_t, _hid]),
        "H5Lunpack_elink_val": (_herr, [ctypes.c_void_p, ctypes.c_size_t,
                                        ctypes.POINTER(ctypes.c_uint),
                                        ctypes.POINTER(ctypes.c_char_p),
                                        ctypes.POINTER(ctypes.c_char_p)]),
        "H5Oget_info_by_name3": (_herr, [_hid, ctypes.c_char_p, ctypes.c_void_p,
                                         ctypes.c_uint, _hid]),
        "H5Dopen2": (_hid, [_hid, ctypes.c_char_p, _hid]),
        "H5Dclose": (_herr, [_hid]),
        "H5Dget_create_plist": (_hid, [_hid]),
        "H5Pclose": (_herr, [_hid]),
        "H5Dget_type": (_hid, [_hid]),
        "H5Tget_class": (ctypes.c_int, [_hid]),
        "H5Tis_variable_str": (ctypes.c_int, [_hid]),
        "H5Tclose": (_herr, [_hid]),
        "H5Pget_layout": (ctypes.c_int, [_hid]),
        "H5Pget_external_count": (ctypes.c_int, [_hid]),
        "H5Pget_external": (_herr, [_hid, ctypes.c_uint, ctypes.c_size_t, ctypes.c_char_p,
                                    ctypes.POINTER(ctypes.c_int64),
                                    ctypes.POINTER(ctypes.c_uint64)]),
    }
    for name, (restype, argtypes) in signatures.items():
        function = getattr(lib, name)
        function.restype, function.argtypes = restype, argtypes
    lib.H5open()
    lib.H5Eset_auto2(_E_DEFAULT, None, None)  # as the netCDF library sets it: no printing
    return lib


class DamagedHDF5(ValueError):
    """An HDF5 file whose links or objects cannot be read."""


def outside(path) -> str:
    """What in the HDF5 file ``path`` reaches outside it, as the middle of a line (``"holds an
    external link /a to 'other.h5':/data"``), or "" if nothing; "" too for a file that is not
    HDF5 (a netCDF classic file has none of these).

    Raises
    ------
    DamagedHDF5
        If the file is HDF5 but cannot be opened or walked.
    """
    name = str(Path(path)).encode()
    with HDF5_LOCK:
        lib = _library()
        if lib.H5Fis_accessible(name, _P_DEFAULT) <= 0:
            return ""
        file_id = lib.H5Fopen(name, _F_ACC_RDONLY, _P_DEFAULT)
        if file_id < 0:
            raise DamagedHDF5("its superblock or root group cannot be read")
        try:
            return _first_outside(lib, file_id)
        finally:
            lib.H5Fclose(file_id)


def _first_outside(lib, file_id: int) -> str:
    """:func:`outside` of the open file ``file_id``. The links are listed first, the callback
    only noting each (no HDF5 call from inside HDF5's iteration, and no garbage collection,
    whose finalizers may close a netCDF file, which would enter HDF5 again), then looked at."""
    links: list[tuple[bytes, int]] = []

    def note(_group, link, info, _data):
        links.append((link, ctypes.c_int.from_address(info + _LINK_TYPE).value))
        return 0

    visit = _VISIT(note)
    collecting = gc.isenabled()
    gc.disable()
    try:
        failed = lib.H5Lvisit2(file_id, _INDEX_NAME, _ITER_NATIVE, visit, None) < 0
    finally:
        if collecting:
            gc.enable()
    if failed:
        raise DamagedHDF5("its links cannot be read")
    for link, kind in links:
        where = "/" + link.decode("utf-8", "replace")
        if kind == _L_TYPE_EXTERNAL:
            return f"holds an external link {where}{_target(lib, file_id, link)}"
        if kind not in (_L_TYPE_HARD, _L_TYPE_SOFT):
            return f"holds a user-defined link {where}"
    for link, kind in links:
        if kind == _L_TYPE_HARD:
            problem = _dataset_problem(lib, file_id, link, "/" + link.decode("utf-8", "replace"))
            if problem:
                return problem
    return ""


def _target(lib, group: int, name: bytes) -> str:
    """`` to 'file':object`` of an external link, or "" where it cannot be read."""
    info = ctypes.create_string_buffer(_INFO_BYTES)
    if lib.H5Lget_info2(group, name, info, _P_DEFAULT) < 0:
        return ""
    size = ctypes.c_size_t.from_buffer(info, _LINK_VAL_SIZE).value
    if not 0 < size < 1 << 16:
        return ""
    buffer = ctypes.create_string_buffer(size)
    flags, filename, obj = ctypes.c_uint(), ctypes.c_char_p(), ctypes.c_char_p()
    if (lib.H5Lget_val(group, name, buffer, size, _P_DEFAULT) < 0 or lib.H5Lunpack_elink_val(
            buffer, size, ctypes.byref(flags), ctypes.byref(filename), ctypes.byref(obj)) < 0):
        return ""
    return (f" to {(filename.value or b'').decode('utf-8', 'replace')!r}:"
            f"{(obj.value or b'').decode('utf-8', 'replace')}")


def _variable_length(lib, dataset: int) -> bool:
    """Whether the dataset holds variable-length data (netCDF strings): HDF5 keeps it in the
    file's global heap, and copying such a dataset's creation properties (its fill value) while
    the netCDF library has the same file open crashes the library."""
    dtype = lib.H5Dget_type(dataset)
    if dtype < 0:
        return False
    try:
        return lib.H5Tget_class(dtype) == _T_VLEN or lib.H5Tis_variable_str(dtype) > 0
    finally:
        lib.H5Tclose(dtype)


def _dataset_problem(lib, group: int, name: bytes, where: str) -> str:
    """What in the dataset ``name`` (if it is one) reads outside the file, or ""."""
    info = ctypes.create_string_buffer(_INFO_BYTES)
    if lib.H5Oget_info_by_name3(group, name, info, _O_INFO_BASIC, _P_DEFAULT) < 0:
        raise DamagedHDF5(f"its object {where} cannot be read")
    if ctypes.c_int.from_buffer(info, _OBJECT_TYPE).value != _O_TYPE_DATASET:
        return ""
    dataset = lib.H5Dopen2(group, name, _P_DEFAULT)
    if dataset < 0:
        raise DamagedHDF5(f"its variable {where} cannot be opened")
    try:
        if _variable_length(lib, dataset):
            return ""  # stored in the file's heap: never external, never virtual
        plist = lib.H5Dget_create_plist(dataset)
        try:
            if lib.H5Pget_external_count(plist) > 0:
                first = ctypes.create_string_buffer(4096)
                offset, size = ctypes.c_int64(), ctypes.c_uint64()
                lib.H5Pget_external(plist, 0, 4096, first, ctypes.byref(offset),
                                    ctypes.byref(size))
                return (f"stores its variable {where} in external files (first "
                        f"{first.value.decode('utf-8', 'replace')!r})")
            if lib.H5Pget_layout(plist) == _D_VIRTUAL:
                return f"holds a virtual dataset {where}, made of other files"
        finally:
            lib.H5Pclose(plist)
    finally:
        lib.H5Dclose(dataset)
    return ""


__all__ = ["DamagedHDF5", "outside"]
