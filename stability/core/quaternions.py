"""Quaternions of attitudes: products, conjugates, rotation matrices, errors, frames.

Convention: ``q = (q0, q1, q2, q3)``, scalar first, Hamilton product; ``R(q)`` is the
*body-to-space* rotation (space components of a body vector x are ``R(q) x``). NumPy functions over
any leading shape; :mod:`stability.free_body.attitude` carries attitudes through runs with them.
"""

from __future__ import annotations

import numpy as np

from .body import canonical_frame
from ..util.checks import real_array

#: Initial attitude when none is given: the body axes coincide with the space axes.
IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])


# --- quaternion helpers (NumPy, any leading shape) ---------------------------------------------


def quaternion_multiply(a, b) -> np.ndarray:
    """Hamilton product ``a b`` of quaternions, arrays of shape (..., 4), scalar first.

    Parameters
    ----------
    a, b : array_like, shape (..., 4)
        Quaternions, scalar first; the leading shapes broadcast.

    Returns
    -------
    ndarray, shape (..., 4)
        The product ``a b``.
    """
    a = real_array("a", a)
    b = real_array("b", b)
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
    """``(q0, -q1, -q2, -q3)``; the inverse of a unit quaternion.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Quaternions, scalar first.

    Returns
    -------
    ndarray, shape (..., 4)
        The conjugates (a new array; ``q`` is not modified).
    """
    q = real_array("q", q)
    q[..., 1:] *= -1.0
    return q


def quaternion_to_matrix(q) -> np.ndarray:
    """Rotation matrices R(q / |q|), shape (..., 3, 3), from quaternions of shape (..., 4).

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Quaternions, scalar first, nonzero; normalised before use.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        The body-to-space rotation matrices.
    """
    q = real_array("q", q)
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

    Parameters
    ----------
    R : array_like, shape (3, 3)
        A rotation matrix.

    Returns
    -------
    ndarray, shape (4,)
        The unit quaternion, scalar first, with q0 >= 0.

    Raises
    ------
    ValueError
        If R does not have shape (3, 3).
    """
    R = real_array("R", R)
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

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Body-to-space quaternions, scalar first (normalised before use).
    m : array_like, shape (..., 3)
        Body angular momenta, body frame, kg m^2/s.

    Returns
    -------
    ndarray, shape (..., 3)
        Space components of the angular momentum, kg m^2/s.
    """
    R = quaternion_to_matrix(q)
    return np.einsum("...ij,...j->...i", R, real_array("m", m, "kg m2/s"))


def attitude_error(q, q_ref) -> np.ndarray:
    """Angle in rad of the rotation from ``R(q_ref)`` to ``R(q)``; shapes (..., 4) -> (...).

    Insensitive to the sign of either quaternion (q and -q are the same rotation) and to their
    norms.

    Parameters
    ----------
    q, q_ref : array_like, shape (..., 4)
        Quaternions, scalar first; the leading shapes broadcast.

    Returns
    -------
    ndarray, shape (...)
        Rotation angles in rad, in [0, pi].
    """
    d = quaternion_multiply(quaternion_conjugate(q_ref), q)
    return 2.0 * np.arctan2(np.linalg.norm(d[..., 1:], axis=-1), np.abs(d[..., 0]))


def frame_along(n, hint=None) -> np.ndarray:
    """A right-handed orthonormal frame whose third axis is along ``n``: columns (x, y, z).

    z = n / |n|; x is the part of ``hint`` perpendicular to z, normalised (by default the space
    axis least aligned with z, so x is never ill-defined); y = z x x. ``frame.T`` maps space
    components into the frame, e.g. with z along the angular momentum L.

    Parameters
    ----------
    n : array_like, shape (3,)
        Direction of the third axis, non-zero.
    hint : array_like, shape (3,), optional
        Direction for the first axis; used where it is not parallel to ``n``.

    Returns
    -------
    ndarray, shape (3, 3)
        A rotation matrix whose columns are the unit vectors x, y, z.
    """
    z = real_array("n", n)
    norm = float(np.linalg.norm(z))
    if z.shape != (3,) or not norm > 0.0:
        raise ValueError(f"n must be a non-zero vector of shape (3,), got {n!r}")
    z = z / norm
    x = None
    if hint is not None:
        h = real_array("hint", hint)
        h = h - (h @ z) * z
        if np.linalg.norm(h) > 1e-9 * max(float(np.linalg.norm(hint)), 1e-300):
            x = h
    if x is None:
        e = np.eye(3)[int(np.argmin(np.abs(z)))]
        x = e - (e @ z) * z
    x = x / np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def canonical_quaternion(moments) -> np.ndarray:
    """Unit quaternion c of the rotation C taking body components to the canonical frame.

    ``m_canonical = C m``; an attitude q (body to space) is ``q c*`` in the canonical frame
    (R(q) C^T), and ``q_canonical c`` back in the body frame.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments (I1, I2, I3) in kg m^2, any order.

    Returns
    -------
    ndarray, shape (4,)
        The unit quaternion c, scalar first, with c0 >= 0.
    """
    perm, signs = canonical_frame(moments)
    C = np.zeros((3, 3))
    C[np.arange(3), perm] = signs
    return matrix_to_quaternion(C)
