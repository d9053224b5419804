"""Rigid bodies described by their principal moments of inertia.

``RigidBody(I1, I2, I3)`` is the object every other part of the package takes. Moments are in
kg m^2 and may be given in any order: axis i of the body is the axis the caller calls i. Kernels
work in a *canonical frame* where the moments are sorted ascending; ``canonical_frame`` gives the
signed permutation (a proper rotation) that maps body components there and back, so Euler's
equations keep their form (an odd permutation alone would flip the sign of w x Iw).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class RigidBody:
    """A rigid body given by its principal moments of inertia.

    Parameters
    ----------
    I1, I2, I3 : float
        Principal moments of inertia about body axes 1, 2, 3, in kg m^2; finite and > 0.
    physical : bool, default True
        Require the triangle inequality I_i <= I_j + I_k that every real mass distribution
        obeys. Pass ``False`` for a mathematical body (e.g. a textbook example with I = (1, 2, 4)).
    name : str, optional
        Label used in Dataset attributes and figure titles.

    Raises
    ------
    ValueError
        If a moment is not finite, is zero or negative, or (with ``physical=True``) the moments
        violate the triangle inequality.
    """

    I1: float
    I2: float
    I3: float
    physical: bool = True
    name: str = field(default="body", compare=False)

    def __post_init__(self):
        moments = []
        for label in ("I1", "I2", "I3"):
            value = getattr(self, label)
            try:
                value = float(value)
            except (TypeError, ValueError):
                raise ValueError(
                    f"{label} must be a number in kg m^2, got {value!r}"
                ) from None
            if not math.isfinite(value):
                raise ValueError(f"{label} must be finite, got {value}")
            if value <= 0.0:
                raise ValueError(
                    f"{label} must be > 0 kg m^2, got {value}: a principal moment of inertia "
                    "is a sum of m r^2 and is positive for any body with extent"
                )
            object.__setattr__(self, label, value)
            moments.append(value)
        if self.physical:
            total = sum(moments)
            for i, value in enumerate(moments):
                others = total - value
                # Relative slack of a few ulps so that exactly flat bodies (I3 = I1 + I2) pass.
                if value > others * (1.0 + 4.0 * np.finfo(float).eps):
                    raise ValueError(
                        f"moments {tuple(moments)} violate the triangle inequality "
                        f"I{i + 1} <= sum of the other two ({value} > {others}), which every real "
                        "body obeys; check the numbers, or pass physical=False for a "
                        "mathematical body"
                    )

    @property
    def moments(self) -> np.ndarray:
        """Principal moments ``(I1, I2, I3)`` as a float64 array of shape (3,), in kg m^2."""
        return np.array([self.I1, self.I2, self.I3])

    def canonical_frame(self) -> tuple[np.ndarray, np.ndarray]:
        """Signed permutation to the frame where the moments are sorted ascending.

        Returns
        -------
        perm : ndarray of int, shape (3,)
            ``perm[i]`` is the body axis (0-based) that becomes canonical axis i.
        signs : ndarray of float, shape (3,)
            +1 or -1 per canonical axis, chosen so that the map is a proper rotation.

        Notes
        -----
        The canonical components of a body vector ``x`` are ``signs * x[perm]``; see
        :func:`to_canonical` and :func:`from_canonical`.
        """
        return canonical_frame(self.moments)

    def __repr__(self) -> str:
        extra = "" if self.physical else ", physical=False"
        label = "" if self.name == "body" else f", name={self.name!r}"
        return f"RigidBody({self.I1!r}, {self.I2!r}, {self.I3!r}{extra}{label})"


def canonical_frame(moments) -> tuple[np.ndarray, np.ndarray]:
    """Signed permutation sorting ``moments`` ascending; see :meth:`RigidBody.canonical_frame`."""
    moments = np.asarray(moments, dtype=float)
    perm = np.argsort(moments, kind="stable")
    parity = np.linalg.det(np.eye(3)[perm])  # +1 even, -1 odd permutation
    signs = np.array([1.0, 1.0, np.sign(parity)])
    return perm, signs


def to_canonical(x, perm, signs) -> np.ndarray:
    """Body components ``x[..., 3]`` to the canonical frame: ``signs * x[..., perm]``."""
    x = np.asarray(x, dtype=float)
    return signs * x[..., perm]


def from_canonical(y, perm, signs) -> np.ndarray:
    """Inverse of :func:`to_canonical`."""
    y = np.asarray(y, dtype=float)
    x = np.empty_like(y)
    x[..., perm] = signs * y
    return x
