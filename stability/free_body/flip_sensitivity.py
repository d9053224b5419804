r"""The sensitivity of a free body's first flip to its moments and its start, by the tangent:
:func:`flip_sensitivities`.

A body spun near its middle axis flips when the middle component of its angular momentum
changes sign. The moments are carried as state that does not change (the scene
:data:`FREE_BODY_MOMENTS`: ``m' = m x I^-1 m``, ``I' = 0``), so the tangent scene of it
(:func:`stability.engine.tangent.tangent_scene`, RK4 of the state and six tangents, the exact
derivative of the computed RK4 map) carries the derivatives of the state with respect to the
moments beside those with respect to the start.

The computed flip time is the root of the cubic Hermite interpolant of ``m2`` over the step in
which it changes sign (from its values and slopes ``h m2'`` at both ends, error O(h^4) like
the method's), ``t* = t_n + s* h``. Its derivative along a direction q of the start
(``dx0 = q``) is that of the root, by the implicit function theorem:

.. math::

    \frac{dt^*}{dq} = -h \frac{\partial H / \partial q}{\partial H / \partial s}\Big|_{s^*},

``H(s) = y_0 h_{00}(s) + h y'_0 h_{10}(s) + y_1 h_{01}(s) + h y'_1 h_{11}(s)``, whose
coefficients' derivatives come from the tangents at both ends, ``dy = e_2 . X q`` and
``dy' = (J X q)_2`` (:func:`moments_jvp`, whose moments' columns give ``df_2/dI``). The
directions are those of the start's angular velocity ``w0`` (``dm0 = I dw0``) and of each
moment at a fixed ``w0`` (``dm0 = w0_k e_k``, ``dI = e_k``): a body made heavier about one axis
and tossed the same way.
"""

from __future__ import annotations

import numpy as np
import xarray as xr
from numba import njit

from ..engine.scene import Scene
from ..engine.tangent import Linearisation, tangent_scene
from ..ensemble.chunks import run_plan
from ..ensemble.options import run_options
from ..ensemble.plan import Plan
from ..integrators.spec import body_params
from ..output.dataset import header_attrs
from ..util import conventions as cv
from ..util.checks import positive_int, real_array
from .dispersion.measure import flip_intervals
from .scene import FREE_BODY, observe, tracked
from .schema import FLIP_SENSITIVITY


@njit(forceinline=True, error_model="numpy")
def moments_rhs(m1, m2, m3, I1, I2, I3, p):
    """``m' = m x I^-1 m`` with the moments read from the state, ``I' = 0``."""
    return ((I2 - I3) / (I2 * I3) * m2 * m3, (I3 - I1) / (I3 * I1) * m3 * m1,
            (I1 - I2) / (I1 * I2) * m1 * m2, 0.0, 0.0, 0.0)


@njit(forceinline=True, error_model="numpy")
def moments_jvp(m1, m2, m3, I1, I2, I3, v1, v2, v3, u1, u2, u3, p):
    """The Jacobian of :func:`moments_rhs` applied to ``(v, u)``, exactly: ``A_i`` =
    ``1/I_k - 1/I_j`` has ``dA_1 = u2 / I2^2 - u3 / I3^2`` and cyclic."""
    a1, a2, a3 = (I2 - I3) / (I2 * I3), (I3 - I1) / (I3 * I1), (I1 - I2) / (I1 * I2)
    s1, s2, s3 = u1 / (I1 * I1), u2 / (I2 * I2), u3 / (I3 * I3)
    return (a1 * (v2 * m3 + m2 * v3) + (s2 - s3) * m2 * m3,
            a2 * (v3 * m1 + m3 * v1) + (s3 - s1) * m3 * m1,
            a3 * (v1 * m2 + m1 * v2) + (s1 - s2) * m1 * m2, 0.0, 0.0, 0.0)


@njit(inline="always")
def moments_observe(m1, m2, m3, I1, I2, I3, p, ia, ib, ic):
    """The free body's ``observe`` of the angular-momentum part."""
    return observe(m1, m2, m3, p, ia, ib, ic)


def _moments_tracked(x, p, axes):
    return tracked(x[:, :3], p, axes)


def _params(moments, h=0.0):
    """The free body's row (its ``observe`` reads 1/I from it)."""
    return body_params(moments, h)


#: The free body with its moments as state: what the moments' derivatives are carried by.
FREE_BODY_MOMENTS = Scene(
    name="free_body_moments",
    module=__name__,
    title="free rigid body with its moments carried as state",
    equations="m' = m x I^-1 m, I' = 0",
    components=("m1", "m2", "m3", "I1", "I2", "I3"),
    units=(cv.UNITS_ANGULAR_MOMENTUM,) * 3 + (cv.UNITS_MOMENT_OF_INERTIA,) * 3,
    methods={},
    observe=moments_observe,
    tracked=_moments_tracked,
    tracked_units=cv.UNITS_ANGULAR_VELOCITY,
    linearisation=Linearisation(moments_rhs, moments_jvp, _params),
)


def flip_sensitivities(moments, w0, *, steps_per_flip: int = 400, h=None,
                       options=None) -> xr.Dataset:
    """Each member's first flip time and its derivatives with respect to the moments and the
    start (the module docstring), by RK4 and its tangent.

    Parameters
    ----------
    moments : array_like, shape (N, 3) or (3,)
        Ascending principal moments I1 < I2 < I3 of each member, or of all, kg m2.
    w0 : array_like, shape (N, 3)
        Starts near the middle axis, rad/s, in the same axes.
    steps_per_flip : int, default 400
        RK4 steps per exact flip interval 2K/nu of each member (its step h).
    h : float or array_like, shape (N,), optional
        The step of every member or of each, s, instead (what a finite difference of the
        computed map holds fixed).
    options : RunOptions, optional
        How and where the members run (:func:`stability.ensemble.chunks.run_plan`); the result
        is the same however they are cut.

    Returns
    -------
    xarray.Dataset
        As :data:`stability.free_body.schema.FLIP_SENSITIVITY` declares it.
    """
    w0 = real_array("w0", w0)
    if w0.ndim != 2 or w0.shape[1] != 3 or w0.shape[0] == 0:
        raise ValueError(f"w0 must be the starts of shape (N, 3), got shape {w0.shape}")
    n = w0.shape[0]
    moments = real_array("moments", moments)
    moments = np.broadcast_to(moments, (n, 3)).astype(float) if moments.shape in (
        (3,), (n, 3)) else moments
    if moments.shape != (n, 3) or not np.all(
            (0.0 < moments[:, 0]) & (moments[:, 0] < moments[:, 1])
            & (moments[:, 1] < moments[:, 2])):
        raise ValueError("moments must be (3,) or (N, 3) ascending and positive, "
                         "I1 < I2 < I3 for every member")
    if not np.all(np.abs(w0[:, 1]) > np.maximum(np.abs(w0[:, 0]), np.abs(w0[:, 2]))):
        raise ValueError("every start must turn mostly about the middle axis "
                         "(|w2| > |w1|, |w3|), whose first sign change of w2 is its flip")
    steps_per_flip = positive_int("steps_per_flip", steps_per_flip)
    interval = flip_intervals(moments, w0)
    if not np.all(np.isfinite(interval)):
        raise ValueError("a member does not flip (a start on the separatrix or about a stable "
                         "axis); start it near the middle axis")
    options = run_options(options)
    if h is None:
        h = interval / steps_per_flip
    else:
        h = np.broadcast_to(real_array("h", h), (n,)).astype(float)
        if not np.all(h > 0.0):
            raise ValueError("h must be > 0 s")
    sizes = np.ones(n, dtype=np.int64)
    rows = np.array([body_params(I) for I in moments])
    m0 = moments * w0
    # where the first flip is: the free body's own RK4, tracked, one flip interval and a bit
    located = run_plan(Plan(FREE_BODY, "rk4", m0, rows, sizes, h,
                            np.ceil(interval / h).astype(np.int64) + 2,
                            axes=[1, 0, 2], label="flip steps"), options.within("located"))
    first = located.extras["first_axis_crossing"]
    if not np.all(np.isfinite(first)):
        raise ValueError("a member's middle component did not change sign within a flip "
                         "interval; start it nearer the middle axis")
    steps = np.maximum(np.floor(first / h).astype(np.int64) - 1, 0)
    eye = np.eye(3)
    by_w = np.zeros((n, 6, 3))
    by_w[:, :3, :] = moments[:, :, None] * eye  # dm0 = I dw0
    by_I = np.zeros((n, 6, 3))
    by_I[:, :3, :] = w0[:, :, None] * eye  # dm0 = w0_k e_k at a fixed w0, dI = e_k
    by_I[:, 3:, :] = eye
    q = np.concatenate([by_I, by_w], axis=2)  # the six directions, carried together
    start = np.hstack([m0, moments, q.transpose(0, 2, 1).reshape(n, 36)])
    t, x0, x1 = _around_the_flip(tangent_scene(FREE_BODY_MOMENTS, 6), start, rows, h, steps,
                                 options.within("tangents"))
    flip, derivatives = _flip_and_derivatives(h, t, x0, x1)
    values = {"flip_time": flip, "dflip_dmoments": derivatives[:, :3],
              "dflip_dw0": derivatives[:, 3:], "moments": moments, "w0": w0, "step": h}
    coords = {cv.MEMBER: FLIP_SENSITIVITY.entry(cv.MEMBER, np.arange(n)),
              cv.AXIS: FLIP_SENSITIVITY.entry(cv.AXIS, np.arange(1, 4))}
    ds = xr.Dataset(FLIP_SENSITIVITY.entries(values), coords=coords)
    ds.attrs = header_attrs("first flip times of free bodies and their sensitivities",
                            "stability.free_body.flip_sensitivity.flip_sensitivities",
                            "Hairer, Norsett & Wanner, Solving ODEs I, II.6 (RK4 of the "
                            "variational equations)")
    return ds


def _around_the_flip(tscene, start, rows, h, steps, options):
    """The time and the states (with tangents) at both ends of the step in which the middle
    component changes sign: run to ``steps`` (the step before the one the tracking located,
    whose last bits may differ), then step by step to the sign change."""
    n = start.shape[0]
    x = start.copy()
    t = np.zeros(n)
    todo = steps > 0
    if todo.any():
        moved = run_plan(Plan(tscene, "rk4", start[todo], rows[todo],
                              np.ones(int(todo.sum()), dtype=np.int64), h[todo], steps[todo],
                              label="flip tangents"), options)
        x[todo] = moved.x_final
        t[todo] = steps[todo] * h[todo]
    ends = np.zeros_like(x)
    found = np.zeros(n, dtype=bool)
    for _ in range(4):
        nxt = _one_step(tscene, x, rows, h)
        change = (~found) & (np.sign(nxt[:, 1]) != np.sign(x[:, 1]))
        ends[change] = nxt[change]
        found |= change
        if found.all():
            return t, x, ends
        keep = ~found
        x[keep], t[keep] = nxt[keep], t[keep] + h[keep]
    raise RuntimeError("the sign change of the middle component was not found next to the "
                       "step the tracking located it in")


def _one_step(tscene, x, rows, h) -> np.ndarray:
    """One RK4 step of the tangent scene for every member (its own step)."""
    n = x.shape[0]
    run = Plan(tscene, "rk4", np.ascontiguousarray(x), rows, np.ones(n, dtype=np.int64), h, 1,
               label="")
    return run.propagate().x_final


def _slope_and_products(x, V):
    """``f_2`` at states ``x`` (N, >= 6) and ``(J v)_2`` of each tangent ``v`` (the columns of
    ``V``, (N, 6, k)): the scene's own :func:`moments_rhs` and :func:`moments_jvp`, evaluated
    in NumPy over the members (neither reads its parameter row)."""
    state = [x[:, i] for i in range(6)]
    f2 = moments_rhs.py_func(*state, None)[1]
    jv2 = moments_jvp.py_func(*(c[:, None] for c in state), *(V[:, i, :] for i in range(6)),
                              None)[1]
    return f2, jv2


def _hermite_root(y0, d0, y1, d1):
    """The root s in [0, 1] of the cubic Hermite H(s) (values y, slopes d = h y'), by Newton's
    method from the secant's; with H's derivatives in its four coefficients and in s."""
    s = np.clip(y0 / (y0 - y1), 0.0, 1.0)
    for _ in range(50):
        h00, h10, h01, h11 = _basis(s)
        value = y0 * h00 + d0 * h10 + y1 * h01 + d1 * h11
        slope = _slope(y0, d0, y1, d1, s)
        step = value / slope
        s = s - step
        if np.all(np.abs(step) <= 1e-16):
            break
    return s, _basis(s), _slope(y0, d0, y1, d1, s)


def _basis(s):
    s2, s3 = s * s, s * s * s
    return 2 * s3 - 3 * s2 + 1, s3 - 2 * s2 + s, -2 * s3 + 3 * s2, s3 - s2


def _slope(y0, d0, y1, d1, s):
    s2 = s * s
    return (y0 * (6 * s2 - 6 * s) + d0 * (3 * s2 - 4 * s + 1) + y1 * (-6 * s2 + 6 * s)
            + d1 * (3 * s2 - 2 * s))


def _flip_and_derivatives(h, t, x0, x1):
    """The flip time and its derivatives along the tangents, from the states and tangents at
    both ends of the step of the sign change."""
    n = x0.shape[0]
    V0 = x0[:, 6:].reshape(n, -1, 6).transpose(0, 2, 1)  # column j: tangent j
    V1 = x1[:, 6:].reshape(n, -1, 6).transpose(0, 2, 1)
    f0, jv0 = _slope_and_products(x0, V0)
    f1, jv1 = _slope_and_products(x1, V1)
    y0, y1, d0, d1 = x0[:, 1], x1[:, 1], h * f0, h * f1
    s, (h00, h10, h01, h11), slope = _hermite_root(y0, d0, y1, d1)
    dy0, dy1 = V0[:, 1, :], V1[:, 1, :]
    dd0, dd1 = h[:, None] * jv0, h[:, None] * jv1
    dH = dy0 * h00[:, None] + dd0 * h10[:, None] + dy1 * h01[:, None] + dd1 * h11[:, None]
    return t + s * h, -h[:, None] * dH / slope[:, None]
