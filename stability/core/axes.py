"""Which principal axis carries which moment: the names study files and the API take an axis
by (``"smallest"``, ``"intermediate"``, ``"largest"``), and the moments of a body checked.

``body`` is a :class:`~stability.core.body.RigidBody` or an array of principal moments of shape
(..., 3) in kg m^2, in any order; axis labels 1, 2, 3 are the caller's.
"""

from __future__ import annotations

import numpy as np

from .body import RigidBody
from ..util.checks import real_array

__all__ = ["MOMENT_NAMES", "principal_moments", "intermediate_axis", "principal_axis",
           "moment_name", "spin_axis"]

#: Names of the axes by their moment, in ascending order of the moment.
MOMENT_NAMES = ("smallest", "intermediate", "largest")


def principal_moments(body) -> np.ndarray:
    """Principal moments (..., 3) of a RigidBody or an array of moments, validated."""
    if isinstance(body, RigidBody):
        return body.moments
    I = real_array("body (principal moments, or a stability.RigidBody)", body, "kg m^2")
    if I.ndim == 0 or I.shape[-1] != 3:
        raise ValueError(
            f"body must be a stability.RigidBody or principal moments of shape (..., 3) in "
            f"kg m^2, got an array of shape {I.shape}"
        )
    if not np.all(np.isfinite(I)) or np.any(I <= 0.0):
        raise ValueError(
            f"principal moments must be finite and > 0 kg m^2, got {body!r}"
        )
    return I


def intermediate_axis(body):
    """Label (1, 2 or 3) of the axis with the intermediate moment, the unstable one.

    Parameters
    ----------
    body : RigidBody or array_like, shape (..., 3)

    Returns
    -------
    int, or ndarray of int with the moments' leading shape
        With equal moments the tie is broken by label order (stable sort), and the axis is
        neutral rather than unstable; see :func:`axis_stability`.
    """
    I = principal_moments(body)
    label = np.argsort(I, axis=-1, kind="stable")[..., 1] + 1
    return int(label) if label.ndim == 0 else label


def principal_axis(body, which: str) -> int:
    """Label (1, 2 or 3) of the axis with the ``"smallest"``, ``"intermediate"`` or
    ``"largest"`` moment (:data:`MOMENT_NAMES`); equal moments are ranked by label.

    Parameters
    ----------
    body : RigidBody or array_like, shape (3,)
        Principal moments in kg m^2, any order.
    which : {"smallest", "intermediate", "largest"}
        The moment wanted.

    Returns
    -------
    int
        The axis label, 1, 2 or 3.

    Raises
    ------
    ValueError
        If ``which`` is not one of :data:`MOMENT_NAMES`.
    """
    if which not in MOMENT_NAMES:
        raise ValueError(f"which must be one of {', '.join(MOMENT_NAMES)}, got {which!r}")
    order = np.argsort(principal_moments(body), kind="stable")
    return int(order[MOMENT_NAMES.index(which)]) + 1


def spin_axis(body, axis):
    """Body axis of ``axis``: the name of its moment (``"smallest"``, ``"intermediate"``,
    ``"largest"``) as its label 1, 2 or 3 (:func:`principal_axis`), anything else as it is (for
    the caller's own check); how study files and :func:`stability.run_ensemble` read it.

    Parameters
    ----------
    body : RigidBody or array_like, shape (3,)
        Principal moments in kg m^2, any order.
    axis : int or str
        A label 1, 2, 3, or a name of :data:`MOMENT_NAMES`.

    Returns
    -------
    int or object
        The label of the named axis, or ``axis`` as given.

    Raises
    ------
    ValueError
        A string that names no moment.
    """
    if not isinstance(axis, str):
        return axis
    if axis not in MOMENT_NAMES:
        raise ValueError(f"axis must be the principal axis 1, 2 or 3, or the name of its "
                         f"moment ({', '.join(MOMENT_NAMES)}), got {axis!r}")
    return principal_axis(body, axis)


def moment_name(body, axis: int) -> str:
    """Which moment body axis ``axis`` (1, 2, 3) carries: ``"smallest"``, ``"intermediate"`` or
    ``"largest"``; the inverse of :func:`principal_axis`.

    Parameters
    ----------
    body : RigidBody or array_like, shape (3,)
        Principal moments in kg m^2, any order.
    axis : int
        The axis label, 1, 2 or 3.

    Returns
    -------
    str
        One of :data:`MOMENT_NAMES`; equal moments are ranked by label.
    """
    rank = int(np.argsort(np.argsort(principal_moments(body), kind="stable"))[axis - 1])
    return MOMENT_NAMES[rank]
