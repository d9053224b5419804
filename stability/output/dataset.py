"""What a Dataset written by the package contains: variables, attributes, provenance, history.

Every variable's dims, units and long name are declared in :mod:`stability.ensemble.schema`, the
register of every Dataset kind (the documentation's Dataset reference is generated from it); this
module assembles the free body's ensemble Dataset (:data:`stability.ensemble.schema.ENSEMBLE`) and
the attributes every Dataset carries.

Ensemble Dataset (``run_ensemble``)
-----------------------------------
Dimensions: ``member`` (ensemble member, ``standard_name = "realization"``), ``time`` (float
seconds since the start, a CF time coordinate: ``standard_name = "time"``, ``axis = "T"``, units
``"s since 1970-01-01 00:00:00"``, the date a nominal origin, see
:data:`~stability.util.conventions.TIME_ORIGIN`), ``axis`` (principal axes 1, 2, 3 in the order the
body gives them) and ``level`` (perpendicular-amplitude levels, rad s-1). Per member: the start
``w0``, the ``status`` (int8 CF flags: ok, non_finite, diverged, not_converged,
step_too_large) and ``fail_time``, the summaries (:data:`SUMMARIES`: flips, crossings of the
perpendicular component, the largest perpendicular amplitude, the passage times of the levels,
the relative energy and |L| errors at the end); the time series ``w`` in runs that keep it, and
the attitude ``q``, ``q_norm_error`` and ``attitude_error`` in the scene
``free_body_attitude``.

Events are tracked at every step, times interpolated linearly within the step; the start
counts (a level the start reaches is passed at time 0). Times of events that did not happen
(no flip, a level never reached) are NaN for members whose ``status`` is ok. A member whose
status is not ok has every float variable NaN (``w`` included) except ``w0`` and
``fail_time``: its numbers are masked, never stored as valid data; counts are float64 so that
they can be masked too.

Global attributes: ``Conventions``, ``title``, ``source``, ``history`` (one timestamped line per
command that made or changed the Dataset, see :func:`append_history`), ``references``, the body
(``body``, ``body_name``, ``I1``, ``I2``, ``I3`` in kg m2), the method (``method``,
``method_order``, ``method_reference``, ``method_max_step_angle`` in rad), ``h``, the start
(``axis``, ``spin``, ``epsilon``, ``start_kind``), the seed (``seed_entropy``,
``seed_spawn_scheme``), the run (``steps``, ``steps_done``, ``interrupted``), the software
(``numba_version``, ``numba_threading_layer``...) and the whole resolved configuration as TOML
(``config_toml``). Every attribute is a str, a number or a numeric array, so the Dataset can be
written to netCDF.
"""

from __future__ import annotations

import datetime
import numbers
import platform
from collections.abc import Mapping

import numpy as np
import xarray as xr

from ..util import conventions as cv
from ..core.body import RigidBody
from ..ensemble.schema import ENSEMBLE, LEVEL
from ..version import __version__

#: Where the physics comes from; method references are added per Dataset.
REFERENCES = (
    "Landau & Lifshitz, Mechanics, 3rd ed., sec. 37 (free asymmetric top, exact solution); "
    "Euler's equations and the linear stability Omega^2 = (I3 - I1)(I3 - I2) W^2 / (I1 I2) "
    "with the sign as corrected in the package notes"
)

#: Per-member summary variables, in the order they appear in the Dataset.
SUMMARIES = (
    "flip_count", "first_flip_time", "last_flip_time", "mean_flip_interval",
    "perp_crossing_count", "first_perp_crossing", "last_perp_crossing",
    "max_perp_amplitude", "passage_time", "energy_error", "angular_momentum_error",
)


def variable_attrs(name: str) -> dict:
    """``long_name``, ``units`` (and CF standard name, comments, flags) of the ensemble's
    variable or coordinate ``name``, as the register declares them
    (:data:`stability.ensemble.schema.ENSEMBLE`)."""
    return ENSEMBLE.attrs(name)


# --- provenance -------------------------------------------------------------------------------


def utc_now() -> str:
    """The current UTC time as ISO 8601 to the second, e.g. ``2026-05-09T07:35:25Z``."""
    now = datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0)
    return now.strftime("%Y-%m-%dT%H:%M:%SZ")


def history_line(command: str, when: str | None = None) -> str:
    """One ``history`` line: ``"<UTC time>: <command>"`` (NCO/CF style)."""
    command = " ".join(str(command).split())  # one line, whatever the caller passed
    return f"{when or utc_now()}: {command}"


def append_history(ds: xr.Dataset, command: str) -> xr.Dataset:
    """Return ``ds`` with one timestamped line for ``command`` appended to its ``history``.

    Parameters
    ----------
    ds : xarray.Dataset
    command : str
        What changed the Dataset, e.g. the command line (``"stability run study.toml"``).

    Returns
    -------
    xarray.Dataset
        A shallow copy; the data are shared, the attributes are new.
    """
    out = ds.copy()
    previous = ds.attrs.get("history", "")
    line = history_line(command)
    out.attrs = {**ds.attrs, "history": f"{previous}\n{line}" if previous else line}
    return out


#: What runs the member loop's blocks at the same time, recorded as ``numba_threading_layer``:
#: the package's own threads (:func:`stability.engine.driver.run_blocks`); the loop has no parallel
#: region of Numba's, so no Numba threading layer is used.
LOOP_THREADS = "none: the member loop's blocks run on the package's threads, GIL released"


def threading_layer() -> str:
    """What runs the member loop in parallel (:data:`LOOP_THREADS`)."""
    return LOOP_THREADS


def software_attrs() -> dict:
    """Versions of the package, Python and the numerical libraries, and Numba's threading."""
    import numba

    return {
        "source": f"stability {__version__}",
        "stability_version": __version__,
        "python_version": platform.python_version(),
        "numpy_version": np.__version__,
        "xarray_version": xr.__version__,
        "numba_version": numba.__version__,
        "numba_threading_layer": threading_layer(),
        "numba_num_threads": int(numba.get_num_threads()),
    }


def provenance_attrs(title: str, body, spec, h: float, command: str) -> dict:
    """Global attributes every Dataset of the package carries.

    Parameters
    ----------
    title : str
        One-line description of the Dataset.
    body : RigidBody
    spec : MethodSpec
        The integrator used.
    h : float
        Step in s.
    command : str
        What made the Dataset; the first line of ``history``.

    Returns
    -------
    dict
        ``Conventions``, ``title``, ``source`` and versions, ``history``, ``references``,
        ``date_created``, the body (``body``, ``body_name``, ``I1``, ``I2``, ``I3``), the method
        (``method``, ``method_title``, ``method_order``, ``method_reference``) and ``h``.
    """
    attrs = header_attrs(title, command,
                         f"{REFERENCES}; method: {spec.reference}" if spec.reference
                         else REFERENCES)
    attrs.update({
        "body": repr(body),
        "body_name": body.name,
        "I1": body.I1,
        "I2": body.I2,
        "I3": body.I3,
        "moments_units": cv.UNITS_MOMENT_OF_INERTIA,
        **method_attrs(spec),
        "h": float(h),
    })
    return attrs


def header_attrs(title: str, command: str, references: str = "") -> dict:
    """The first global attributes of a Dataset of the package: ``Conventions``, ``title``,
    the software (:func:`software_attrs`), ``history`` (``command`` its first line),
    ``references`` (where given) and ``date_created``."""
    now = utc_now()
    return {
        "Conventions": cv.CONVENTIONS,
        "title": title,
        **software_attrs(),
        "history": history_line(command, now),
        **({"references": references} if references else {}),
        "date_created": now,
    }


def method_attrs(spec) -> dict:
    """The method of a run as global attributes: ``method``, ``method_title``,
    ``method_order``, ``method_reference`` and, where it has one, ``method_max_step_angle``."""
    return {
        "method": spec.name,
        "method_title": spec.title,
        "method_order": "exact" if spec.is_exact else int(spec.order),
        "method_reference": spec.reference,
        **({"method_max_step_angle": float(spec.max_step_angle)}
           if spec.max_step_angle is not None else {}),
    }


# --- configuration as TOML --------------------------------------------------------------------


def body_from_attrs(attrs):
    """The body named by a Dataset's attributes (``I1``, ``I2``, ``I3`` in kg m2 and
    ``body_name``, as :func:`provenance_attrs` writes them), as a mathematical body
    (``physical=False``: the moments are taken as recorded)."""
    return RigidBody(attrs["I1"], attrs["I2"], attrs["I3"], physical=False,
                     name=attrs.get("body_name", "body"))


def config_toml(config: Mapping) -> str:
    """The configuration ``config`` as a TOML document (written with ``tomli_w``).

    NumPy scalars and arrays become plain numbers and lists, tuples become lists and keys whose
    value is ``None`` are left out (TOML has no null).

    Raises
    ------
    ValueError
        If ``config`` is not a mapping or holds a value TOML cannot represent.
    """
    import tomli_w

    if not isinstance(config, Mapping):
        raise ValueError(f"config must be a dict (a TOML table), got {type(config).__name__}")
    try:
        return tomli_w.dumps(_plain(config))
    except TypeError as error:
        raise ValueError(f"config cannot be written as TOML: {error}") from None


def _plain(value):
    """``value`` with NumPy types, tuples and ``None`` turned into what TOML can hold."""
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items() if v is not None}
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, numbers.Integral) and not isinstance(value, bool):
        # TOML integers are 64-bit; larger ones (e.g. 128-bit seed entropy) go as strings.
        return int(value) if -(2**63) <= value < 2**63 else str(value)
    return value


# --- attributes netCDF can store --------------------------------------------------------------


def storable_attrs(attrs: Mapping, where: str = "the Dataset") -> dict:
    """``attrs`` converted to what netCDF stores and reads back unchanged.

    Bools become 0/1, NumPy scalars plain numbers, lists and tuples arrays, one-element arrays
    numbers (netCDF reads them back as scalars); ``None`` and other types are refused.

    Raises
    ------
    ValueError
        Naming the attribute, where it is and what to store instead.
    """
    out = {}
    for key, value in attrs.items():
        if isinstance(value, (bool, np.bool_)):
            value = int(value)
        elif isinstance(value, np.generic):
            value = value.item()
        elif isinstance(value, (list, tuple)):
            value = np.asarray(value)
        if isinstance(value, np.ndarray) and value.size == 1 and value.ndim <= 1:
            value = value.reshape(-1)[0].item()
        problem = _attr_problem(value)
        if problem:
            raise ValueError(f"attribute {key!r} of {where} {problem}")
        out[key] = value
    return out


def check_storable(ds: xr.Dataset) -> None:
    """Raise ``ValueError`` unless every attribute of ``ds`` and of its variables, and every
    variable's dtype, is stored by netCDF and read back unchanged."""
    places = [("the Dataset", ds.attrs)]
    places += [(f"variable {name!r}", var.attrs) for name, var in ds.variables.items()]
    for where, attrs in places:
        for key, value in attrs.items():
            problem = _attr_problem(value)
            if problem:
                raise ValueError(f"attribute {key!r} of {where} {problem}")
    for name, var in ds.variables.items():
        if var.dtype == bool:
            raise ValueError(
                f"variable {name!r} is boolean; netCDF has no bool type, store it as int8"
            )


def _attr_problem(value) -> str | None:
    """Why netCDF would not give ``value`` back unchanged, or None if it would."""
    if isinstance(value, (bool, np.bool_)):
        return f"is a bool ({value}); netCDF has no bool type: store 0 or 1"
    if isinstance(value, str):
        return None
    if isinstance(value, (numbers.Real, np.number)):
        return None
    if isinstance(value, np.ndarray):
        if value.ndim != 1 or value.dtype.kind not in "iuf" or value.size < 2:
            return (
                f"is an array of shape {value.shape} and dtype {value.dtype}; netCDF gives "
                "back only 1-D numeric arrays of two or more elements (store a number instead "
                "of a one-element array)"
            )
        return None
    if isinstance(value, (list, tuple)):
        return f"is a {type(value).__name__}; store a numpy array"
    return (
        f"is a {type(value).__name__} ({value!r}); netCDF stores only str, numbers and 1-D "
        "numeric arrays"
    )


# --- the ensemble Dataset ---------------------------------------------------------------------


def ensemble_dataset(w0, status, fail_time, summaries, levels, attrs, time=None, w=None):
    """Assemble the ensemble Dataset described in the module docstring.

    Parameters
    ----------
    w0 : ndarray, shape (N, 3)
        Initial angular velocities in rad/s.
    status : ndarray of int8, shape (N,)
    fail_time : ndarray, shape (N,)
        Seconds; NaN for members that are ok.
    summaries : dict of ndarray
        Every name in :data:`SUMMARIES`: shape (N,), ``passage_time`` (N, n_levels).
    levels : ndarray, shape (n_levels,)
        Amplitude levels in rad/s.
    attrs : dict
        Global attributes (made storable here).
    time : ndarray, shape (n_time,), optional
        Sample times in s, for a time-series run.
    w : ndarray, shape (N, n_time, 3), optional
        Angular velocity samples in rad/s (with ``time``).

    Returns
    -------
    xarray.Dataset
    """
    n = w0.shape[0]
    coords = {
        cv.MEMBER: np.arange(n, dtype=np.int64),
        cv.AXIS: np.array(cv.AXES, dtype=np.int64),
        LEVEL: np.asarray(levels, dtype=float),
    }
    data = {}
    if w is not None:
        coords[cv.TIME] = np.asarray(time, dtype=float)
        data["w"] = w
    data["w0"] = w0
    data["status"] = np.asarray(status, dtype=np.int8)
    data["fail_time"] = fail_time
    for name in SUMMARIES:
        data[name] = np.asarray(summaries[name], dtype=float)
    return xr.Dataset(ENSEMBLE.entries(data), coords=ENSEMBLE.entries(coords),
                      attrs=storable_attrs(attrs))


def add_attitude(ds: xr.Dataset, q, norm_error, error) -> None:
    """Add the attitude series ``q`` (member, time, 4), ``q_norm_error`` and ``attitude_error``
    (member, time) to an ensemble Dataset in place."""
    ds.coords[cv.QUATERNION] = ENSEMBLE.entry(cv.QUATERNION, np.arange(4))
    ds["q"] = ENSEMBLE.entry("q", q)
    ds["q_norm_error"] = ENSEMBLE.entry("q_norm_error", norm_error)
    ds["attitude_error"] = ENSEMBLE.entry("attitude_error", error)


def summary_bytes(n_levels: int) -> int:
    """Bytes per member of the ensemble Dataset without the time series."""
    floats = 3 + 1 + (len(SUMMARIES) - 1) + n_levels  # w0, fail_time, scalar summaries, levels
    return 8 * floats + 1 + 8  # + status (int8) + member coordinate (int64)
