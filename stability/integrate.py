"""One trajectory, any registered method: ``integrate(body, w0, t_end, h, method)``."""

from __future__ import annotations

import numpy as np
import xarray as xr

from . import conventions as cv
from .body import RigidBody
from .checks import positive_float, positive_int, step_count, vectors3
from .dataset import provenance_attrs, storable_attrs
from .driver import propagate, untrusted
from .integrators import method_spec


def integrate(body: RigidBody, w0, t_end, h, method="rk4", save_every=1, progress=None):
    """Integrate the torque-free Euler equations from ``w0`` and return the trajectory.

    Parameters
    ----------
    body : RigidBody
    w0 : array_like, shape (3,)
        Initial body-frame angular velocity in rad/s.
    t_end : float
        Final time in s; must be a whole number of steps.
    h : float
        Step size in s.
    method : str, default "rk4"
        A name from ``stability.METHODS``.
    save_every : int, default 1
        Keep every ``save_every``-th step (the initial state is always kept).
    progress : bool, optional
        Progress bar; by default shown for runs expected to take more than 2 s.

    Returns
    -------
    xarray.Dataset
        Variable ``w`` (time, axis) in rad s-1; coordinates ``time`` (s) and ``axis`` (1, 2, 3);
        attributes naming the body, the method, its order, ``h`` and the run's status.
        After a non-finite state the remaining samples are NaN and ``status`` says so.
    """
    if not isinstance(body, RigidBody):
        raise ValueError(f"body must be a stability.RigidBody, got {type(body).__name__}")
    spec = method_spec(method)
    w0 = vectors3("w0", w0, "rad/s")
    if w0.ndim != 1:
        raise ValueError(f"w0 must have shape (3,) for integrate(), got {w0.shape}; "
                         "use run_ensemble for many starts")
    t_end = positive_float("t_end", t_end, "s")
    h = positive_float("h", h, "s")
    save_every = positive_int("save_every", save_every)
    n_steps = step_count(t_end, h)
    if n_steps % save_every:
        raise ValueError(
            f"save_every = {save_every} does not divide the {n_steps} steps of t_end / h, so the "
            f"final state would not be kept; choose save_every among the divisors of {n_steps}"
        )

    moments = body.moments
    result = propagate(spec, moments, (moments * w0)[None, :], h, n_steps, save_every, progress)

    m = np.concatenate([(moments * w0)[None, :], result.saved[0]], axis=0)
    w = m / moments
    steps = np.arange(m.shape[0]) * save_every
    status = int(result.status[0])
    if status != cv.STATUS_OK:
        w[untrusted(steps, result.fail_step)[0]] = np.nan
    ds = xr.Dataset(
        {
            "w": (
                (cv.TIME, cv.AXIS),
                w,
                {"long_name": "body-frame angular velocity", "units": cv.UNITS_ANGULAR_VELOCITY},
            )
        },
        coords={
            cv.TIME: (cv.TIME, steps * h, {"long_name": "time", "units": cv.UNITS_TIME}),
            cv.AXIS: (cv.AXIS, np.array(cv.AXES), {"long_name": "principal axis"}),
        },
        attrs=storable_attrs(
            {
                **provenance_attrs(
                    f"torque-free rotation of {body!r} by {spec.name}", body, spec, h,
                    f"stability.integrate({body!r}, w0={w0.tolist()}, t_end={t_end!r}, "
                    f"h={h!r}, method={spec.name!r}, save_every={save_every})",
                ),
                "save_every": save_every,
                "steps": result.steps_done,
                "status": cv.STATUS_MEANINGS.split()[status],
                "interrupted": int(result.interrupted),
            }
        ),
    )
    return ds
