"""One trajectory, any registered method: ``integrate(body, w0, t_end, h, method)``; the
horizon and the step chosen from the physics where they are not given.

On scene ``free_body_attitude`` the body-to-space attitude quaternion comes too
(``stability.free_body.attitude``); on ``free_body`` the run goes through the 3-number member loop
of ``stability.free_body.propagate`` unchanged.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ..util import conventions as cv
from ..core.body import RigidBody
from ..util.checks import positive_float, positive_int, real_array, step_count, vectors3
from .attitude import attitude_spec, carries_attitude, propagate_attitude
from ..core.quaternions import IDENTITY
from ..output.dataset import provenance_attrs, storable_attrs
from .schema import TRAJECTORY
from .propagate import propagate
from ..engine.driver import untrusted
from .timescales import default_timescales
from .methods import method_spec


def integrate(
    body: RigidBody, w0, t_end=None, h=None, method="rk4", save_every=1, progress=None,
    scene="free_body", q0=None,
):
    """Integrate the torque-free Euler equations from ``w0`` and return the trajectory.

    Parameters
    ----------
    body : RigidBody
    w0 : array_like, shape (3,)
        Initial body-frame angular velocity in rad/s.
    t_end : float, optional
        Final time in s; must be a whole number of steps. By default four flip intervals 2K/nu
        of the exact motion, rounded up to whole saved steps
        (:func:`stability.free_body.timescales.default_horizon`).
    h : float, optional
        Step size in s. By default the step angle ``h max|w|`` is 0.02 rad, or a little less so
        that a ``t_end`` given is a whole number of saved steps
        (:func:`stability.free_body.timescales.default_step`).
    method : str, default "rk4"
        A name from ``stability.METHODS``.
    save_every : int, default 1
        Keep every ``save_every``-th step (the initial state is always kept).
    progress : bool, optional
        Progress bar; by default shown for runs expected to take more than 2 s.
    scene : {"free_body", "free_body_attitude"}, default "free_body"
        What is integrated: w alone, or w and the attitude, with the method's own attitude
        update (methods that can: ``stability.free_body.attitude.attitude_methods()``).
    q0 : array_like, shape (4,), optional
        Initial body-to-space attitude as a unit quaternion, scalar first; default the identity
        (body axes along the space axes). Only on scene ``free_body_attitude``.

    Returns
    -------
    xarray.Dataset
        Variable ``w`` (time, axis) in rad s-1; coordinates ``time`` (s) and ``axis`` (1, 2, 3);
        attributes naming the body, the method, its order, ``h``, the run's status and the
        nonlinear-solver iterations (``solver_iterations``, 0 for explicit methods).
        After a non-finite or failed state the remaining samples are NaN and ``status`` says so.
        A default step or horizon is said in ``h_rule`` or ``t_end_rule``.
        On scene ``free_body_attitude`` also ``q`` (time, quaternion_component), the unit
        quaternion of the body-to-space rotation (normalised on output), and ``q_norm_error``
        (time), the norm error ``|q| - 1`` of the quaternion the method carried (not
        renormalised in the loop; see ``stability.free_body.attitude``).

    Raises
    ------
    ValueError
        For a bad body, w0, t_end, h, save_every or scene; for scene ``free_body_attitude``
        with a method that cannot carry the attitude; for q0 that is not a finite unit
        quaternion.
    """
    if not isinstance(body, RigidBody):
        raise ValueError(f"body must be a stability.RigidBody, got {type(body).__name__}")
    spec = method_spec(method)
    w0 = vectors3("w0", w0, "rad/s")
    if w0.ndim != 1:
        raise ValueError(f"w0 must have shape (3,) for integrate(), got {w0.shape}; "
                         "use run_ensemble for many starts")
    save_every = positive_int("save_every", save_every)
    if t_end is not None:
        t_end = positive_float("t_end", t_end, "s")
    h, t_end, rules = default_timescales(body, w0[None, :], h, t_end, save_every)
    h = positive_float("h", h, "s")
    n_steps = step_count(t_end, h)
    if n_steps % save_every:
        raise ValueError(
            f"save_every = {save_every} does not divide the {n_steps} steps of t_end / h, so the "
            f"final state would not be kept; choose save_every among the divisors of {n_steps}"
        )

    attitude = carries_attitude(scene)
    if attitude:
        attitude_spec(spec)
        q0 = _unit_quaternion(q0)
    elif q0 is not None:
        raise ValueError("q0 is the initial attitude and needs scene='free_body_attitude'")

    moments = body.moments
    m0 = (moments * w0)[None, :]
    if attitude:
        result = propagate_attitude(spec, moments, m0, q0, h, n_steps, save_every, progress,
                                    partial=True)
    else:  # Ctrl-C: the steps done, marked interrupted
        result = propagate(spec, moments, m0, h, n_steps, save_every, progress, partial=True)

    m = np.concatenate([(moments * w0)[None, :], result.saved[0]], axis=0)
    w = m / moments
    steps = np.arange(m.shape[0]) * save_every
    status = int(result.status[0])
    mask = untrusted(steps, result.fail_step)[0] if status != cv.STATUS_OK else None
    if mask is not None:
        w[mask] = np.nan
    ds = xr.Dataset(
        TRAJECTORY.entries({"w": w}),
        coords=TRAJECTORY.entries({cv.TIME: steps * h, cv.AXIS: np.array(cv.AXES)}),
        attrs=storable_attrs(
            {
                **provenance_attrs(
                    f"torque-free rotation of {body!r} by {spec.name}", body, spec, h,
                    f"stability.integrate({body!r}, w0={w0.tolist()}, t_end={t_end!r}, "
                    f"h={h!r}, method={spec.name!r}, save_every={save_every}"
                    + (f", scene='free_body_attitude', q0={q0.tolist()})" if attitude else ")"),
                ),
                "save_every": save_every,
                "steps": result.steps_done,
                "status": cv.STATUS_MEANINGS.split()[status],
                "interrupted": int(result.interrupted),
                "solver_iterations": int(result.iterations[0]),
                **rules,
            }
        ),
    )
    if attitude:
        _add_attitude(ds, q0, result, mask)
    return ds


def _unit_quaternion(q0):
    """``q0`` as a float array of shape (4,) with norm 1 (to 1e-9); the identity if None."""
    if q0 is None:
        return IDENTITY.copy()
    q = real_array("q0 (a unit quaternion, scalar first)", q0)
    if q.shape != (4,) or not np.all(np.isfinite(q)):
        raise ValueError(
            f"q0 must be 4 finite numbers (a unit quaternion, scalar first), got {q0!r}"
        )
    norm = float(np.linalg.norm(q))
    if abs(norm - 1.0) > 1e-9:
        raise ValueError(
            f"q0 must be a unit quaternion, got |q0| = {norm!r}; divide it by its norm"
        )
    return q


def _add_attitude(ds, q0, result, mask):
    """Add ``q`` and ``q_norm_error`` (time) from an attitude run to ``ds`` in place."""
    q = np.concatenate([q0[None, :], result.extras["q_saved"][0]], axis=0)
    norm_error = np.concatenate(
        [[np.linalg.norm(q0) - 1.0], result.extras["q_norm_error_saved"][0]]
    )
    if mask is not None:
        q[mask] = np.nan
        norm_error[mask] = np.nan
    ds.update(TRAJECTORY.entries({"q": q, "q_norm_error": norm_error}))
    ds.coords.update(TRAJECTORY.entries({cv.QUATERNION: np.arange(4)}))
