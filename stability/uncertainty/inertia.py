"""The inertia tensor dispersed as a tensor: principal axes turned by a small rotation.

A member's tensor in the design's body frame is J = R diag(I) R^T, R the rotation by the
angle theta about the unit axis n (Rodrigues: R = 1 + sin(theta) K + (1 - cos(theta)) K^2,
K the cross-product matrix of n). J is symmetrised exactly ((J + J^T) / 2) and its principal
moments and axes re-derived (``numpy.linalg.eigh``): those are what a member's kernel runs
with, the axes the columns of the matrix from the principal frame to the design's.
"""

from __future__ import annotations

import numpy as np


def rotations(angle, axis) -> np.ndarray:
    """Rotation matrices by ``angle`` (N,) rad about unit ``axis`` (N, 3); shape (N, 3, 3)."""
    angle = np.asarray(angle, dtype=float)
    n = np.asarray(axis, dtype=float)
    K = np.zeros((angle.size, 3, 3))
    K[:, 0, 1], K[:, 0, 2], K[:, 1, 2] = -n[:, 2], n[:, 1], -n[:, 0]
    K -= np.transpose(K, (0, 2, 1))
    s, c = np.sin(angle)[:, None, None], np.cos(angle)[:, None, None]
    return np.eye(3) + s * K + (1.0 - c) * (K @ K)


def dispersed_tensor(moments, angle, axis):
    """Each member's tensor R diag(I) R^T and its principal moments and axes.

    Parameters
    ----------
    moments : array_like, shape (N, 3)
        Principal moments (kg m2) in the design's axes.
    angle : array_like, shape (N,)
        Misalignment angle, rad.
    axis : array_like, shape (N, 3)
        Unit rotation axes.

    Returns
    -------
    tensor : ndarray, shape (N, 3, 3)
        Symmetric, kg m2, in the design's frame.
    principal : ndarray, shape (N, 3)
        Its eigenvalues, the principal axis nearest design axis k in column k.
    axes : ndarray, shape (N, 3, 3)
        ``axes[j, :, k]``: member j's principal axis k in the design's frame, its
        component along design axis k >= 0.

    Raises
    ------
    ValueError
        If a tensor is not positive definite, or a rotation so large that two principal axes
        are nearest the same design axis.
    """
    moments = np.asarray(moments, dtype=float)
    R = rotations(angle, axis)
    J = (R * moments[:, None, :]) @ np.transpose(R, (0, 2, 1))
    J = 0.5 * (J + np.transpose(J, (0, 2, 1)))
    values, vectors = np.linalg.eigh(J)
    nearest = np.argmax(np.abs(vectors), axis=1)  # (N, 3): design axis of each eigenvector
    if not np.all(np.sort(nearest, axis=1) == np.arange(3)):
        raise ValueError("a misalignment so large that two principal axes are nearest the same "
                         "design axis; disperse the axes by a smaller angle")
    order = np.argsort(nearest, axis=1)
    principal = np.take_along_axis(values, order, axis=1)
    axes = np.take_along_axis(vectors, order[:, None, :], axis=2)
    axes *= np.where(np.diagonal(axes, axis1=1, axis2=2) < 0.0, -1.0, 1.0)[:, None, :]
    if not np.all(principal > 0.0):
        raise ValueError("a dispersed inertia tensor is not positive definite")
    return J, principal, axes


def physical(moments) -> np.ndarray:
    """Whether each row of ``moments`` (N, 3) is > 0 and obeys the triangle inequality (each at
    most the sum of the others, with the few ulps of slack :class:`stability.RigidBody` allows)."""
    I = np.asarray(moments, dtype=float)
    others = I.sum(axis=1, keepdims=True) - I
    return np.all((I > 0.0) & (I <= others * (1.0 + 4.0 * np.finfo(float).eps)), axis=1)
