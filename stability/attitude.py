"""The attitude: a unit quaternion per member, advanced with m by the method's own update.

Convention: ``q = (q0, q1, q2, q3)``, scalar first, Hamilton product; ``R(q)`` is the
*body-to-space* rotation (space components of a body vector x are ``R(q) x``), and the attitude
obeys ``R' = R hat(w)``, i.e. ``q' = q (0, w) / 2``. The spatial angular momentum ``R(q) m`` is
constant for the free body.

Each method advances q by its own rule (``MethodSpec.attitude_step``, or the twins in
``stability.integrators.kinematics``): the Lie-Poisson sub-flows turn the attitude by the same
angles as m, ``Q <- Q R_k(+theta)``, and the Casimir part by ``Q <- Q exp(h hat(m) / I2)``; DMV,
the LGVI and the implicit midpoint rule multiply by their Cayley rotation F; RKMK4 by
``exp(-hat v)``; RK4 integrates the kinematics. Every one of these is a right multiplication
``q <- q r_n`` by a quaternion r_n that depends on m only, so the *direction* of q (the rotation)
never depends on its norm. Renormalisation policy, therefore: none inside the loop; q is carried
with compensated summation like m, normalised only on output, and its norm error ``|q| - 1`` is
reported. For the methods whose r_n is a unit quaternion (all but RK4) that error is round-off
(at most 1.5e-14 after 1e5 steps in the tests); for RK4 it is its truncation error,
O((h |w|)^6) per step.

A run without attitude stays 3 numbers per member and goes through ``stability.driver``
unchanged; ``propagate_attitude`` is the same loop layout with 7 numbers per member: blocks of
``BLOCK`` members in ``prange``, time outside, stages, members innermost, Kahan updates, status
codes and never an exception. Its block body is a separate (non-parallel) function called from
the ``prange`` loop, which keeps compilation short for the large implicit kernels.

Reference used by the tests: scipy ``solve_ivp`` DOP853 on (m, q) at rtol = atol = 1e-13, a
very-high-accuracy numerical reference (the exact attitude of Celledoni, Fasso, Safstrom & Zanna,
SIAM J. Sci. Comput. 30, 2084 (2008) is not implemented here).
"""

from __future__ import annotations

import functools
import time

import numpy as np
from numba import njit, prange

from .body import canonical_frame, from_canonical, to_canonical
from .conventions import STATUS_NONFINITE, STATUS_NOT_CONVERGED, STATUS_OK
from .driver import BLOCK, Propagation, _kahan_add, run_in_chunks
from .integrators import METHODS, method_spec
from .integrators.kinematics import ATTITUDE_TWINS

#: Initial attitude when none is given: the body axes coincide with the space axes.
IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])


# --- quaternion helpers (NumPy, any leading shape) ---------------------------------------------


def quaternion_multiply(a, b) -> np.ndarray:
    """Hamilton product ``a b`` of quaternions, arrays of shape (..., 4), scalar first."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    a0, a1, a2, a3 = np.moveaxis(a, -1, 0)
    b0, b1, b2, b3 = np.moveaxis(b, -1, 0)
    return np.stack(
        [
            a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
            a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
            a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
            a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0,
        ],
        axis=-1,
    )


def quaternion_conjugate(q) -> np.ndarray:
    """``(q0, -q1, -q2, -q3)``; the inverse of a unit quaternion."""
    q = np.array(q, dtype=float)
    q[..., 1:] *= -1.0
    return q


def quaternion_to_matrix(q) -> np.ndarray:
    """Rotation matrices R(q / |q|), shape (..., 3, 3), from quaternions of shape (..., 4)."""
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    w, x, y, z = np.moveaxis(q, -1, 0)
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        axis=-2,
    )


def matrix_to_quaternion(R) -> np.ndarray:
    """Unit quaternion (scalar first, q0 >= 0) of a rotation matrix R, shape (3, 3).

    Shepperd's method: the largest of 4 q0^2, 4 q1^2, 4 q2^2, 4 q3^2 (read off the trace and
    the diagonal) is taken as the pivot, so no division by a small number [Shepperd, J.
    Guidance Control 1, 223 (1978)].
    """
    R = np.asarray(R, dtype=float)
    if R.shape != (3, 3):
        raise ValueError(f"R must have shape (3, 3), got {R.shape}")
    t = np.trace(R)
    pivots = [1.0 + t, 1.0 + 2 * R[0, 0] - t, 1.0 + 2 * R[1, 1] - t, 1.0 + 2 * R[2, 2] - t]
    k = int(np.argmax(pivots))
    r = 0.5 * np.sqrt(pivots[k])
    s = 0.25 / r
    if k == 0:
        q = [r, (R[2, 1] - R[1, 2]) * s, (R[0, 2] - R[2, 0]) * s, (R[1, 0] - R[0, 1]) * s]
    elif k == 1:
        q = [(R[2, 1] - R[1, 2]) * s, r, (R[0, 1] + R[1, 0]) * s, (R[0, 2] + R[2, 0]) * s]
    elif k == 2:
        q = [(R[0, 2] - R[2, 0]) * s, (R[0, 1] + R[1, 0]) * s, r, (R[1, 2] + R[2, 1]) * s]
    else:
        q = [(R[1, 0] - R[0, 1]) * s, (R[0, 2] + R[2, 0]) * s, (R[1, 2] + R[2, 1]) * s, r]
    q = np.array(q)
    return q if q[0] >= 0.0 else -q


def spatial_angular_momentum(q, m) -> np.ndarray:
    """``R(q) m``: the space components of the body angular momentum m; shapes (..., 4), (..., 3).

    Constant along the exact free motion, so its drift measures the attitude's consistency with m.
    """
    R = quaternion_to_matrix(q)
    return np.einsum("...ij,...j->...i", R, np.asarray(m, dtype=float))


def attitude_error(q, q_ref) -> np.ndarray:
    """Angle in rad of the rotation from ``R(q_ref)`` to ``R(q)``; shapes (..., 4) -> (...).

    Insensitive to the sign of either quaternion (q and -q are the same rotation) and to their
    norms.
    """
    d = quaternion_multiply(quaternion_conjugate(q_ref), q)
    return 2.0 * np.arctan2(np.linalg.norm(d[..., 1:], axis=-1), np.abs(d[..., 0]))


def canonical_quaternion(moments) -> np.ndarray:
    """Unit quaternion c of the rotation C taking body components to the canonical frame.

    ``m_canonical = C m``; an attitude q (body to space) is ``q c*`` in the canonical frame
    (R(q) C^T), and ``q_canonical c`` back in the body frame.
    """
    perm, signs = canonical_frame(moments)
    C = np.zeros((3, 3))
    C[np.arange(3), perm] = signs
    return matrix_to_quaternion(C)


# --- which methods carry the attitude ----------------------------------------------------------


def attitude_kernel(method):
    """The (m, q) kernel of a method: its spec's ``attitude_step``, else its registered twin.

    Returns None when the method cannot carry the attitude.
    """
    spec = method_spec(method)
    if spec.attitude_step is not None:
        return spec.attitude_step
    return ATTITUDE_TWINS.get(spec.step)


def attitude_methods() -> tuple[str, ...]:
    """Names of the registered methods that can carry the attitude."""
    return tuple(name for name in METHODS if attitude_kernel(name) is not None)


# --- the loop ----------------------------------------------------------------------------------


@njit(inline="always")
def _bad(v):
    return 1 if v - v != 0.0 else 0  # inf or NaN


@functools.cache
def attitude_loop(kernel):
    """Compile (once per process) the (m, q) ensemble loop around the stage kernel ``kernel``.

    The returned function advances ``m`` (N, 3) and ``q`` (N, 4) in place by ``n_steps`` steps::

        advance(m, q, comp, p, h, n_stages, n_steps, save_every, saved_m, saved_q,
                status, fail_step, iterations, step0)

    ``comp`` (N, 7) carries the Kahan compensation of (m, q) between calls; ``saved_m`` (N, k, 3)
    and ``saved_q`` (N, k, 4), k = n_steps // save_every, receive the state after every
    ``save_every``-th step (0 saves nothing); ``status`` (N,) int8, ``fail_step`` (N,) int64 and
    ``iterations`` (N,) int64 are updated in place as in ``stability.driver.member_loop``
    (finiteness is checked every step here, so ``fail_step`` is the exact step count).
    """

    @njit(error_model="numpy")
    def advance_block(
        m, q, comp, p, h, n_stages, n_steps, save_every, saved_m, saved_q, status, fail_step,
        iterations, step0, lo, size,
    ):
        x1 = np.empty(BLOCK)
        x2 = np.empty(BLOCK)
        x3 = np.empty(BLOCK)
        y0 = np.empty(BLOCK)
        y1 = np.empty(BLOCK)
        y2 = np.empty(BLOCK)
        y3 = np.empty(BLOCK)
        cx1 = np.empty(BLOCK)
        cx2 = np.empty(BLOCK)
        cx3 = np.empty(BLOCK)
        cy0 = np.empty(BLOCK)
        cy1 = np.empty(BLOCK)
        cy2 = np.empty(BLOCK)
        cy3 = np.empty(BLOCK)
        d1 = np.zeros(BLOCK)
        d2 = np.zeros(BLOCK)
        d3 = np.zeros(BLOCK)
        g0 = np.zeros(BLOCK)
        g1 = np.zeros(BLOCK)
        g2 = np.zeros(BLOCK)
        g3 = np.zeros(BLOCK)
        bad = np.zeros(BLOCK, dtype=np.int64)
        nonconv = np.zeros(BLOCK, dtype=np.int64)
        first_bad = np.full(BLOCK, -1, dtype=np.int64)
        iters = np.zeros(BLOCK, dtype=np.int64)
        for j in range(size):
            x1[j], x2[j], x3[j] = m[lo + j, 0], m[lo + j, 1], m[lo + j, 2]
            y0[j], y1[j], y2[j], y3[j] = q[lo + j, 0], q[lo + j, 1], q[lo + j, 2], q[lo + j, 3]
            cx1[j], cx2[j], cx3[j] = comp[lo + j, 0], comp[lo + j, 1], comp[lo + j, 2]
            cy0[j], cy1[j] = comp[lo + j, 3], comp[lo + j, 4]
            cy2[j], cy3[j] = comp[lo + j, 5], comp[lo + j, 6]
        k = 0
        for n in range(n_steps):
            for j in range(size):
                d1[j] = 0.0
                d2[j] = 0.0
                d3[j] = 0.0
                g0[j] = 0.0
                g1[j] = 0.0
                g2[j] = 0.0
                g3[j] = 0.0
            for s in range(n_stages):
                for j in range(size):
                    e1, e2, e3, f0, f1, f2, f3, it = kernel(
                        x1[j] + d1[j], x2[j] + d2[j], x3[j] + d3[j],
                        y0[j] + g0[j], y1[j] + g1[j], y2[j] + g2[j], y3[j] + g3[j], h, p, s,
                    )
                    d1[j] += e1
                    d2[j] += e2
                    d3[j] += e3
                    g0[j] += f0
                    g1[j] += f1
                    g2[j] += f2
                    g3[j] += f3
                    iters[j] += it if it > 0 else 0
                    nonconv[j] |= 1 if it < 0 else 0
            for j in range(size):
                _kahan_add(x1, cx1, j, d1[j])
                _kahan_add(x2, cx2, j, d2[j])
                _kahan_add(x3, cx3, j, d3[j])
                _kahan_add(y0, cy0, j, g0[j])
                _kahan_add(y1, cy1, j, g1[j])
                _kahan_add(y2, cy2, j, g2[j])
                _kahan_add(y3, cy3, j, g3[j])
                now_bad = _bad(x1[j] + x2[j] + x3[j] + y0[j] + y1[j] + y2[j] + y3[j])
                first_bad[j] = n if (now_bad == 1 and bad[j] == 0) else first_bad[j]
                bad[j] |= now_bad
            if save_every > 0 and (n + 1) % save_every == 0:
                for j in range(size):
                    saved_m[lo + j, k, 0] = x1[j]
                    saved_m[lo + j, k, 1] = x2[j]
                    saved_m[lo + j, k, 2] = x3[j]
                    saved_q[lo + j, k, 0] = y0[j]
                    saved_q[lo + j, k, 1] = y1[j]
                    saved_q[lo + j, k, 2] = y2[j]
                    saved_q[lo + j, k, 3] = y3[j]
                k += 1
        for j in range(size):
            g = lo + j
            m[g, 0], m[g, 1], m[g, 2] = x1[j], x2[j], x3[j]
            q[g, 0], q[g, 1], q[g, 2], q[g, 3] = y0[j], y1[j], y2[j], y3[j]
            comp[g, 0], comp[g, 1], comp[g, 2] = cx1[j], cx2[j], cx3[j]
            comp[g, 3], comp[g, 4], comp[g, 5], comp[g, 6] = cy0[j], cy1[j], cy2[j], cy3[j]
            iterations[g] += iters[j]
            if bad[j] != 0 and status[g] == STATUS_OK:
                status[g] = STATUS_NONFINITE
                fail_step[g] = step0 + first_bad[j] + 1  # step count, as in the driver
            elif nonconv[j] != 0 and status[g] == STATUS_OK:
                status[g] = STATUS_NOT_CONVERGED
                fail_step[g] = step0

    @njit(parallel=True)
    def advance(
        m, q, comp, p, h, n_stages, n_steps, save_every, saved_m, saved_q, status, fail_step,
        iterations, step0,
    ):
        n_members = m.shape[0]
        n_blocks = (n_members + BLOCK - 1) // BLOCK
        for b in prange(n_blocks):
            lo = b * BLOCK
            advance_block(
                m, q, comp, p, h, n_stages, n_steps, save_every, saved_m, saved_q, status,
                fail_step, iterations, step0, lo, min(BLOCK, n_members - lo),
            )

    return advance


def _compiled(advance, p):
    """Compile ``advance`` for the standard argument types; return the seconds it took."""
    t0 = time.perf_counter()
    if not advance.signatures:
        advance(
            np.zeros((1, 3)), np.zeros((1, 4)), np.zeros((1, 7)), p, 0.0, 1, 0, 0,
            np.zeros((1, 0, 3)), np.zeros((1, 0, 4)), np.zeros(1, np.int8),
            np.full(1, -1, np.int64), np.zeros(1, np.int64), 0,
        )
    return time.perf_counter() - t0


def propagate_attitude(
    method, moments, m0, q0, h, n_steps, save_every=0, progress=None, chunk_steps=None
):
    """Advance body angular momenta and attitudes of an ensemble with a registered method.

    Parameters
    ----------
    method : str or MethodSpec
        A name from :func:`attitude_methods`.
    moments : array_like, shape (3,)
        Principal moments (I1, I2, I3) in kg m^2, any order.
    m0 : array_like, shape (N, 3)
        Initial body angular momenta m = I w (body frame), kg m^2 s^-1.
    q0 : array_like, shape (4,) or (N, 4)
        Initial body-to-space unit quaternions, scalar first.
    h : float
        Step in s, > 0.
    n_steps : int
        Number of steps.
    save_every : int, default 0
        Store the state every ``save_every`` steps; 0 stores only the final state.
    progress : bool or None
        Progress bar; ``None`` shows one when the run is expected to take > 2 s.
    chunk_steps : int, optional
        Steps per kernel call; by default about 0.25 s of work per call.

    Returns
    -------
    Propagation
        As from :func:`stability.driver.propagate` (body frame), with ``extras``:
        ``q_final`` (N, 4) and ``q_saved`` (N, n_saved, 4): unit quaternions (normalised on
        output); ``q_norm_error_final`` (N,) and ``q_norm_error_saved`` (N, n_saved): ``|q| - 1``
        of the carried, unnormalised quaternion.

    Raises
    ------
    ValueError
        If the method cannot carry the attitude, or q0 has the wrong shape.
    """
    spec = method_spec(method)
    kernel = attitude_kernel(spec)
    if kernel is None:
        raise ValueError(
            f"method {spec.name!r} cannot carry the attitude; methods that can: "
            + ", ".join(attitude_methods())
        )
    moments = np.asarray(moments, dtype=float)
    perm, signs = canonical_frame(moments)
    p = spec.params(moments[perm], h)
    m = np.ascontiguousarray(to_canonical(np.atleast_2d(m0), perm, signs))
    n_members = m.shape[0]
    q0 = np.asarray(q0, dtype=float)
    if q0.shape not in ((4,), (n_members, 4)):
        raise ValueError(f"q0 must have shape (4,) or ({n_members}, 4), got {q0.shape}")
    c = canonical_quaternion(moments)
    q = np.ascontiguousarray(
        quaternion_multiply(np.broadcast_to(q0, (n_members, 4)), quaternion_conjugate(c))
    )
    comp = np.zeros((n_members, 7))
    status = np.full(n_members, STATUS_OK, dtype=np.int8)
    fail_step = np.full(n_members, -1, dtype=np.int64)
    iterations = np.zeros(n_members, dtype=np.int64)
    n_saved = n_steps // save_every if save_every > 0 else 0
    saved_m = np.full((n_members, n_saved, 3), np.nan)
    saved_q = np.full((n_members, n_saved, 4), np.nan)

    advance = attitude_loop(kernel)
    compile_time = _compiled(advance, p)

    def run_chunk(steps_this, done, k_saved):
        k_this = steps_this // save_every if save_every > 0 else 0
        buffer_m = np.empty((n_members, k_this, 3))  # contiguous: one compiled signature
        buffer_q = np.empty((n_members, k_this, 4))
        advance(
            m, q, comp, p, h, spec.stages, steps_this, save_every, buffer_m, buffer_q, status,
            fail_step, iterations, done,
        )
        saved_m[:, k_saved : k_saved + k_this] = buffer_m
        saved_q[:, k_saved : k_saved + k_this] = buffer_q

    done, k_saved, wall, interrupted = run_in_chunks(
        run_chunk, n_steps, save_every, chunk_steps, progress, spec.name
    )

    norm_final = np.linalg.norm(q, axis=-1)  # of the carried quaternion, canonical frame
    norm_saved = np.linalg.norm(saved_q[:, :k_saved], axis=-1)
    q_final = quaternion_multiply(q, c)
    q_saved = quaternion_multiply(saved_q[:, :k_saved], c)
    return Propagation(
        m_final=from_canonical(m, perm, signs),
        saved=from_canonical(saved_m[:, :k_saved], perm, signs),
        status=status,
        fail_step=fail_step,
        iterations=iterations,
        steps_done=done,
        interrupted=interrupted,
        wall_time=wall,
        compile_time=compile_time,
        extras={
            "q_final": q_final / np.linalg.norm(q_final, axis=-1, keepdims=True),
            "q_saved": q_saved / np.linalg.norm(q_saved, axis=-1, keepdims=True),
            "q_norm_error_final": norm_final - 1.0,
            "q_norm_error_saved": norm_saved - 1.0,
        },
    )
