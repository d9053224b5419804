"""Rigid bodies described by their principal moments of inertia.

``RigidBody(I1, I2, I3)`` is the object every other part of the package takes. Moments are in
kg m^2 and may be given in any order: axis i of the body is the axis the caller calls i. Kernels
work in a *canonical frame* where the moments are sorted ascending; ``canonical_frame`` gives the
signed permutation (a proper rotation) that maps body components there and back, so Euler's
equations keep their form (an odd permutation alone would flip the sign of w x Iw).

Bodies can also be built from what one can measure: an inertia tensor (``RigidBody.from_tensor``),
a mass and the dimensions of a solid box, ellipsoid or cylinder (``RigidBody.box`` ...), or parts
joined by the parallel-axis theorem (``Part`` and ``RigidBody.composite``). ``RigidBody.preset``
gives bodies people know from the tennis-racket effect (``RigidBody.presets()`` lists them).
"""

from __future__ import annotations

import html
import math
import sys
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import NamedTuple

import numpy as np
from numba import njit

from ..util.checks import positive_float, real_array, real_number


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
        If a moment is not finite, is zero or negative, the products of two or three moments
        underflow or overflow a double, or (with ``physical=True``) the moments violate the
        triangle inequality.
    """

    I1: float
    I2: float
    I3: float
    physical: bool = True
    name: str = field(default="body", compare=False)

    def __post_init__(self):
        moments = []
        for label in ("I1", "I2", "I3"):
            value = real_number(label, getattr(self, label), "kg m^2")
            if not math.isfinite(value):
                raise ValueError(f"{label} must be finite, got {value}")
            if value <= 0.0:
                raise ValueError(
                    f"{label} must be > 0 kg m^2, got {value}: a principal moment of inertia "
                    "is a sum of m r^2 and is positive for any body with extent"
                )
            object.__setattr__(self, label, value)
            moments.append(value)
        _check_range(moments)
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

    # ------------------------------------------------------------------ constructors

    @classmethod
    def from_tensor(cls, J, physical: bool = True, name: str = "body"):
        """Principal moments and principal axes of a symmetric inertia tensor.

        Diagonalises ``J`` with ``numpy.linalg.eigh`` (LAPACK ``syevd``), so that
        ``J = axes @ diag(body.moments) @ axes.T``.

        Parameters
        ----------
        J : array_like, shape (3, 3)
            Inertia tensor about the centre of mass, in kg m^2, in any Cartesian frame (the
            "tensor frame"). It must be symmetric to a relative tolerance of
            ``SYMMETRY_RTOL`` = 1e-9 of its largest entry (the symmetric part is used) and
            positive definite.
        physical : bool, default True
            Require the triangle inequality of the principal moments (see :class:`RigidBody`).
            A violation by less than ``TRIANGLE_RTOL`` = 1e-12 of the largest moment is taken as
            round-off of an exactly flat body and the largest moment is set to the sum of the
            other two.
        name : str, default "body"
            Label of the returned body.

        Returns
        -------
        body : RigidBody
            Principal moments in ascending order, ``body.I1 <= body.I2 <= body.I3``.
        axes : ndarray, shape (3, 3)
            Proper rotation (``det(axes) = +1``): column i is the unit vector of principal axis
            i + 1 in the tensor frame. A vector ``v`` in the tensor frame has body components
            ``axes.T @ v``. Where moments are equal, any orthonormal basis of their plane is a
            set of principal axes; ``eigh`` picks one. Each of the first two columns is signed
            so that its largest-magnitude component is positive, the third makes the set right
            handed.

        Raises
        ------
        ValueError
            If ``J`` is not a 3x3 array of finite numbers, not symmetric, not positive definite
            (a zero or negative principal moment: a rod or a point mass has no extent in some
            direction), or (``physical=True``) its moments violate the triangle inequality.

        Examples
        --------
        >>> body, axes = RigidBody.from_tensor([[2.0, 0.5, 0.0], [0.5, 2.0, 0.0], [0.0, 0.0, 3.0]])
        >>> body.moments
        array([1.5, 2.5, 3. ])
        """
        J = _tensor("J", J)
        scale = float(np.max(np.abs(J)))
        if scale == 0.0:
            raise ValueError("inertia tensor J is all zeros; a body needs mass and extent")
        asymmetry = float(np.max(np.abs(J - J.T)))
        if asymmetry > SYMMETRY_RTOL * scale:
            raise ValueError(
                f"inertia tensor J is not symmetric: max |J - J.T| = {asymmetry:.3g} kg m^2 is "
                f"more than {SYMMETRY_RTOL:g} of its largest entry ({scale:.3g}); an inertia "
                "tensor satisfies J[i, j] = J[j, i], check the off-diagonal entries and their signs"
            )
        moments, axes = np.linalg.eigh(0.5 * (J + J.T))
        # eigh's eigenvalues carry an absolute error of a few eps * |J|; below that, zero.
        if moments[0] <= _EIGH_ZERO * moments[2]:
            raise ValueError(
                f"inertia tensor J is not positive definite: principal moments {tuple(moments)} "
                "kg m^2, the smallest is zero or negative (to round-off); every principal moment "
                "of a body with extent in all three directions is > 0 (a thin rod or a point mass "
                "has a zero moment), check the signs of the products of inertia "
                "(J[i, j] = -sum m x_i x_j)"
            )
        if physical:
            excess = moments[2] - (moments[0] + moments[1])
            if excess > TRIANGLE_RTOL * moments[2]:
                raise ValueError(
                    f"inertia tensor J has principal moments {tuple(moments)} kg m^2 that violate "
                    f"the triangle inequality I3 <= I1 + I2 ({moments[2]} > "
                    f"{moments[0] + moments[1]}), which every real mass distribution obeys; check "
                    "the tensor, or pass physical=False for a mathematical body"
                )
            if excess > 0.0:
                moments[2] = moments[0] + moments[1]
        for i in range(2):
            if axes[np.argmax(np.abs(axes[:, i])), i] < 0.0:
                axes[:, i] = -axes[:, i]
        axes[:, 2] = np.cross(axes[:, 0], axes[:, 1])
        body = cls(*moments, physical=physical, name=name)
        return body, axes

    @classmethod
    def box(cls, mass, a, b, c, name: str = "box"):
        """A solid rectangular box of uniform density.

        ``I1 = m (b^2 + c^2) / 12``, ``I2 = m (a^2 + c^2) / 12``, ``I3 = m (a^2 + b^2) / 12``
        about the centre (the standard table of moments in any mechanics text).

        Parameters
        ----------
        mass : float
            Mass in kg, finite and > 0.
        a, b, c : float
            Edge lengths along body axes 1, 2, 3, in m, finite and > 0.
        name : str, default "box"

        Returns
        -------
        RigidBody
            Moments in the order of the edges: axis i is the one along edge i.
        """
        return cls(*_box_moments(mass, a, b, c), name=name)

    @classmethod
    def ellipsoid(cls, mass, a, b, c, name: str = "ellipsoid"):
        """A solid ellipsoid of uniform density.

        ``I1 = m (b^2 + c^2) / 5`` and cyclic, about the centre.

        Parameters
        ----------
        mass : float
            Mass in kg, finite and > 0.
        a, b, c : float
            Semi-axes along body axes 1, 2, 3, in m, finite and > 0.
        name : str, default "ellipsoid"

        Returns
        -------
        RigidBody
        """
        return cls(*_ellipsoid_moments(mass, a, b, c), name=name)

    @classmethod
    def cylinder(cls, mass, radius, length, name: str = "cylinder"):
        """A solid circular cylinder of uniform density, its axis along body axis 3.

        ``I1 = I2 = m (3 r^2 + l^2) / 12``, ``I3 = m r^2 / 2`` about the centre. Axis 3 is
        stable; axes 1 and 2 have equal moments, so spin about them is neutral, not unstable
        (see :func:`stability.free_body.model.axis_stability`).

        Parameters
        ----------
        mass : float
            Mass in kg, finite and > 0.
        radius, length : float
            Radius and length in m, finite and > 0.
        name : str, default "cylinder"

        Returns
        -------
        RigidBody
        """
        return cls(*_cylinder_moments(mass, radius, length), name=name)

    @classmethod
    def composite(cls, parts, physical: bool = True, name: str = "composite"):
        """A body made of rigidly joined parts, by the parallel-axis theorem.

        The inertia tensor about the common centre of mass c is
        ``J = sum_k [J_k + m_k (|d_k|^2 E - d_k d_k^T)]`` with ``d_k = r_k - c`` (Steiner's
        theorem; e.g. Goldstein, Poole & Safko, *Classical Mechanics*, 3rd ed., section 5.3),
        then diagonalised by :meth:`from_tensor`.

        Parameters
        ----------
        parts : iterable of Part
            The parts, each with its mass, its inertia about its own centre of mass and the
            position of that centre, all in one assembly frame.
        physical : bool, default True
            Passed to :meth:`from_tensor`.
        name : str, default "composite"
            Label of the returned body.

        Returns
        -------
        Composite
            Named tuple ``(body, axes, centre_of_mass, mass, inertia)``: the body (moments
            ascending), its principal axes as columns in the assembly frame (a proper rotation),
            the centre of mass in m (shape (3,)), the total mass in kg and the inertia tensor
            about the centre of mass in the assembly frame in kg m^2 (shape (3, 3)).

        Raises
        ------
        ValueError
            If ``parts`` is empty or holds something that is not a :class:`Part`, or the
            assembly's tensor is rejected by :meth:`from_tensor` (e.g. point masses on one line).

        Examples
        --------
        A dumbbell: two 1 kg balls of radius 5 cm on the ends of a 0.5 kg rod 1 m long.

        >>> parts = [Part.ellipsoid(1.0, 0.05, 0.05, 0.05, position=(-0.5, 0, 0)),
        ...          Part.ellipsoid(1.0, 0.05, 0.05, 0.05, position=(0.5, 0, 0)),
        ...          Part.cylinder(0.5, 0.01, 1.0, axis=(1, 0, 0))]
        >>> dumbbell = RigidBody.composite(parts, name="dumbbell")
        >>> dumbbell.body.I3  # about an axis across the rod: 2 (2/5 m r^2 + m 0.5^2) + rod
        0.54367...
        """
        parts = list(parts) if isinstance(parts, Iterable) else parts
        if not isinstance(parts, list) or not parts:
            raise ValueError(f"parts must be a non-empty list of stability.Part, got {parts!r}")
        for k, part in enumerate(parts):
            if not isinstance(part, Part):
                raise ValueError(
                    f"parts[{k}] must be a stability.Part (e.g. Part.box(...)), got "
                    f"{type(part).__name__}"
                )
        masses = np.array([part.mass for part in parts])
        positions = np.array([part.position for part in parts])
        mass = float(masses.sum())
        centre = masses @ positions / mass
        inertia = np.zeros((3, 3))
        for part, m_k, r_k in zip(parts, masses, positions):
            d = r_k - centre
            inertia += part.inertia + m_k * (d @ d * np.eye(3) - np.outer(d, d))
        body, axes = cls.from_tensor(inertia, physical=physical, name=name)
        return Composite(body, axes, centre, mass, inertia)

    @classmethod
    def preset(cls, name: str):
        """A body that people know from the tennis-racket effect, by name.

        Each preset is built from parts (:data:`PRESETS`, whose descriptions state the
        dimensions and masses assumed) and returned in principal axes with moments ascending,
        so axis 2 is the intermediate, unstable one.

        Parameters
        ----------
        name : str
            One of :meth:`presets`: "book", "phone", "t_handle", "tennis_racket".

        Returns
        -------
        RigidBody
            Named ``name``. Its parts, centre of mass and principal axes:
            ``RigidBody.composite(PRESETS[name].parts())``.

        Raises
        ------
        ValueError
            For an unknown name, listing the known ones.
        """
        if not isinstance(name, str) or name not in PRESETS:
            raise ValueError(
                f"unknown preset {name!r}; known presets: {', '.join(sorted(PRESETS))}"
            )
        return cls.composite(PRESETS[name].parts(), name=name).body

    @staticmethod
    def presets() -> dict[str, str]:
        """The bodies :meth:`preset` builds, by name, each with what it is.

        Returns
        -------
        dict of str to str
            ``{name: description}``, names sorted: ``"book"``, ``"phone"``, ``"t_handle"``,
            ``"tennis_racket"``; each description gives the dimensions and masses assumed and
            which body axis is which.
        """
        return {name: PRESETS[name].description for name in sorted(PRESETS)}

    def __repr__(self) -> str:
        extra = "" if self.physical else ", physical=False"
        label = "" if self.name == "body" else f", name={self.name!r}"
        return f"RigidBody({self.I1!r}, {self.I2!r}, {self.I3!r}{extra}{label})"

    def axis_summary(self) -> list:
        """Per body axis: its moment, its rank and its linear stability at unit spin.

        Returns
        -------
        list of dict
            For axes 1, 2, 3: ``axis``, ``moment`` (kg m^2), ``rank`` ("smallest",
            "intermediate", "largest"; "equal" where two moments are equal),
            ``omega_squared``, Omega^2 / W^2 = (Ia - Ib)(Ia - Ic) / (Ib Ic)
            (:func:`stability.free_body.model.omega_squared` at W = 1 rad/s, s^-2), ``stability``
            ("stable" for Omega^2 > 0, "unstable" < 0, "neutral" = 0) and ``departure``, what
            a small departure from a spin W about the axis does, in words.
        """
        moments = [self.I1, self.I2, self.I3]
        rows = []
        for a in range(3):
            ia, ib, ic = moments[a], moments[(a + 1) % 3], moments[(a + 2) % 3]
            if ia in (ib, ic):
                rank = "equal"
            else:
                rank = ("smallest", "intermediate", "largest")[sum(ia > m for m in (ib, ic))]
            o2 = ((ia - ib) / ib) * ((ia - ic) / ic)
            if o2 < 0.0:
                stability, departure = "unstable", f"grows as exp({math.sqrt(-o2):.4g} W t)"
            elif o2 > 0.0:
                stability, departure = "stable", f"oscillates at {math.sqrt(o2):.4g} W"
            else:
                stability, departure = "neutral", "drifts, linearly in time"
            rows.append({"axis": a + 1, "moment": ia, "rank": rank, "omega_squared": o2,
                         "stability": stability, "departure": departure})
        return rows

    def describe(self) -> str:
        """A few lines for a person: the moments, which axis is unstable, and how fast a spin
        of W rad/s about it departs."""
        lines = [f"{self!r}"]
        lines += [f"  axis {r['axis']}: I = {r['moment']:.6g} kg m^2 ({r['rank']}), "
                  f"{r['stability']}: a departure {r['departure']}"
                  for r in self.axis_summary()]
        lines.append("  (W: the spin in rad/s, t in s)")
        return "\n".join(lines)

    def _repr_pretty_(self, printer, cycle):
        """IPython's text display: :meth:`describe`."""
        printer.text(repr(self) if cycle else self.describe())

    def _repr_html_(self) -> str:
        """A notebook's display: the moments and each axis's linear stability, as a table."""
        cells = [f"<tr><td>{r['axis']}</td><td>{r['moment']:.6g}</td><td>{r['rank']}</td>"
                 f"<td>{r['stability']}</td><td>{r['departure']}</td></tr>"
                 for r in self.axis_summary()]
        name = html.escape(self.name)
        return (f"<div><b>RigidBody</b> {name}<table><tr><th>axis</th><th>I (kg m²)</th>"
                "<th>moment</th><th>spin about it</th><th>a departure (W: spin, rad/s)</th>"
                f"</tr>{''.join(cells)}</table></div>")


def canonical_frame(moments) -> tuple[np.ndarray, np.ndarray]:
    """Signed permutation sorting ``moments`` ascending; see :meth:`RigidBody.canonical_frame`.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments in kg m^2, any order; equal moments keep their order (stable sort).

    Returns
    -------
    perm : ndarray of int, shape (3,)
        ``perm[i]`` is the body axis (0-based) that becomes canonical axis i.
    signs : ndarray of float, shape (3,)
        +1 or -1 per canonical axis, chosen so that the map is a proper rotation.
    """
    moments = np.asarray(moments, dtype=float)
    perm = np.argsort(moments, kind="stable")
    parity = np.linalg.det(np.eye(3)[perm])  # +1 even, -1 odd permutation
    signs = np.array([1.0, 1.0, np.sign(parity)])
    return perm, signs


def to_canonical(x, perm, signs) -> np.ndarray:
    """Body components ``x[..., 3]`` to the canonical frame: ``signs * x[..., perm]``.

    Parameters
    ----------
    x : array_like, shape (..., 3)
        Components along body axes 1, 2, 3 (any vector: w, m, ...).
    perm : array_like of int, shape (3,)
        Body axis (0-based) of each canonical axis, from :func:`canonical_frame`.
    signs : array_like of float, shape (3,)
        +1 or -1 per canonical axis, from :func:`canonical_frame`.

    Returns
    -------
    ndarray, shape (..., 3)
        Canonical components, in the units of ``x``.
    """
    x = np.asarray(x, dtype=float)
    y = np.empty_like(x)
    for i in range(3):  # per axis: ~10x faster than fancy indexing on large ensembles
        np.multiply(x[..., perm[i]], signs[i], out=y[..., i])
    return y


def from_canonical(y, perm, signs) -> np.ndarray:
    """Inverse of :func:`to_canonical`.

    Parameters
    ----------
    y : array_like, shape (..., 3)
        Components along the canonical axes.
    perm : array_like of int, shape (3,)
        Body axis (0-based) of each canonical axis, from :func:`canonical_frame`.
    signs : array_like of float, shape (3,)
        +1 or -1 per canonical axis, from :func:`canonical_frame`.

    Returns
    -------
    ndarray, shape (..., 3)
        Components along body axes 1, 2, 3, in the units of ``y``.
    """
    y = np.asarray(y, dtype=float)
    x = np.empty_like(y)
    for i in range(3):
        np.multiply(y[..., i], signs[i], out=x[..., perm[i]])
    return x


@njit(cache=True, error_model="numpy")
def canonical_m_to_w(m, perm, signs, moments, out) -> None:
    """Canonical angular momenta ``m`` (K, 3) to body-frame angular velocities ``out`` (K, 3):
    ``out[k, perm[i]] = (m[k, i] signs[i]) / moments[perm[i]]``, compiled.

    The operations of :func:`from_canonical` and then the division by the body's moments, in
    that order, so the numbers are bitwise those of the two steps.

    Parameters
    ----------
    m : ndarray, shape (K, 3)
        Angular momenta along the canonical axes, kg m2 s-1.
    perm : ndarray of int64, shape (3,)
        Body axis (0-based) of each canonical axis, from :func:`canonical_frame`.
    signs : ndarray of float, shape (3,)
        +1 or -1 per canonical axis, from :func:`canonical_frame`.
    moments : ndarray, shape (3,)
        Principal moments in the body's order, kg m2.
    out : ndarray, shape (K, 3)
        Filled with the body-frame angular velocities, rad/s.
    """
    for k in range(m.shape[0]):
        for i in range(3):
            out[k, perm[i]] = (m[k, i] * signs[i]) / moments[perm[i]]


# ---------------------------------------------------------------------------------- tolerances

#: Largest asymmetry ``max |J - J.T|`` accepted by ``RigidBody.from_tensor``, relative to the
#: largest entry of J. Tensors computed as R D R.T are symmetric to ~1e-16; 1e-9 still admits a
#: tensor typed in with 9-10 significant digits but rejects a sign slip in a product of inertia.
SYMMETRY_RTOL = 1e-9

#: Violations of the triangle inequality below this fraction of the largest principal moment are
#: taken as round-off of an exactly flat body (eigh's error is ~1e-15) and are clipped.
TRIANGLE_RTOL = 1e-12

# Principal moments at or below this fraction of the largest are zero to eigh's round-off
# (its absolute eigenvalue error is a few eps times the norm of J).
_EIGH_ZERO = 8.0 * np.finfo(float).eps

# Orthogonality tolerance for rotation matrices given to Part: max |R.T R - E|.
_ORTHOGONAL_ATOL = 1e-9


# ------------------------------------------------------------------------ shapes (kg, m -> kg m^2)


def _box_moments(mass, a, b, c) -> tuple[float, float, float]:
    """Principal moments of a solid box with edges a, b, c along axes 1, 2, 3."""
    mass = positive_float("mass", mass, "kg")
    a, b, c = (positive_float(label, x, "m") for label, x in zip("abc", (a, b, c)))
    return (
        mass * (b * b + c * c) / 12.0,
        mass * (a * a + c * c) / 12.0,
        mass * (a * a + b * b) / 12.0,
    )


def _ellipsoid_moments(mass, a, b, c) -> tuple[float, float, float]:
    """Principal moments of a solid ellipsoid with semi-axes a, b, c along axes 1, 2, 3."""
    mass = positive_float("mass", mass, "kg")
    a, b, c = (positive_float(label, x, "m") for label, x in zip("abc", (a, b, c)))
    return (
        mass * (b * b + c * c) / 5.0,
        mass * (a * a + c * c) / 5.0,
        mass * (a * a + b * b) / 5.0,
    )


def _cylinder_moments(mass, radius, length) -> tuple[float, float, float]:
    """Principal moments of a solid cylinder whose axis is axis 3."""
    mass = positive_float("mass", mass, "kg")
    r = positive_float("radius", radius, "m")
    length = positive_float("length", length, "m")
    across = mass * (3.0 * r * r + length * length) / 12.0
    return across, across, 0.5 * mass * r * r


def _tensor(name: str, J) -> np.ndarray:
    """``J`` as a finite float64 array of shape (3, 3), else ValueError."""
    J = real_array(name, J, "kg m^2")
    if J.shape != (3, 3):
        raise ValueError(f"{name} must have shape (3, 3) (an inertia tensor), got shape {J.shape}")
    if not np.all(np.isfinite(J)):
        raise ValueError(f"{name} must be finite, got {J.tolist()}")
    return J


def _vector(name: str, x, unit: str) -> np.ndarray:
    """``x`` as a finite float64 array of shape (3,), else ValueError."""
    x = real_array(name, x, unit)
    if x.shape != (3,):
        raise ValueError(f"{name} must have shape (3,) (x, y, z in {unit}), got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError(f"{name} must be finite, got {x.tolist()}")
    return x


def _rotated(moments, rotation) -> np.ndarray:
    """Tensor ``R diag(moments) R.T`` of a part whose axes are the columns of ``rotation``."""
    if rotation is None:
        return np.diag(moments)
    R = _tensor("rotation", rotation)
    error = float(np.max(np.abs(R.T @ R - np.eye(3))))
    if error > _ORTHOGONAL_ATOL:
        raise ValueError(
            f"rotation must be orthogonal (columns = the part's axes 1, 2, 3 as unit vectors in "
            f"the assembly frame), but max |R.T R - E| = {error:.3g}"
        )
    return R @ np.diag(moments) @ R.T


# ------------------------------------------------------------------------------------ composite


@dataclass(frozen=True, eq=False)
class Part:
    """One rigid piece of a composite body, placed in the assembly frame.

    Parameters
    ----------
    mass : float
        Mass in kg, finite and > 0.
    inertia : array_like, shape (3, 3)
        Inertia tensor about the part's own centre of mass, in the assembly frame, in kg m^2:
        symmetric and positive semi-definite (zero for a point mass).
    position : array_like, shape (3,)
        The part's centre of mass in the assembly frame, in m.
    name : str, default "part"
        Label, for messages.

    Notes
    -----
    The constructors ``Part.point``, ``Part.box``, ``Part.ellipsoid``, ``Part.cylinder`` and
    ``Part.from_body`` build the tensor from a shape; join parts with
    :meth:`RigidBody.composite`.
    """

    mass: float
    inertia: np.ndarray
    position: np.ndarray
    name: str = "part"

    def __post_init__(self):
        mass = positive_float(f"mass of part {self.name!r}", self.mass, "kg")
        J = _tensor(f"inertia of part {self.name!r}", self.inertia)
        scale = float(np.max(np.abs(J)))
        if float(np.max(np.abs(J - J.T))) > SYMMETRY_RTOL * scale:
            raise ValueError(
                f"inertia of part {self.name!r} is not symmetric (J[i, j] must equal J[j, i]): "
                f"{J.tolist()}"
            )
        J = 0.5 * (J + J.T)
        if scale > 0.0 and np.linalg.eigvalsh(J)[0] < -_EIGH_ZERO * scale:
            raise ValueError(
                f"inertia of part {self.name!r} has a negative principal moment "
                f"({np.linalg.eigvalsh(J)[0]:.3g} kg m^2); an inertia tensor is positive "
                "semi-definite, check the signs of the products of inertia"
            )
        r = _vector(f"position of part {self.name!r}", self.position, "m")
        J.setflags(write=False)
        r.setflags(write=False)
        object.__setattr__(self, "mass", mass)
        object.__setattr__(self, "inertia", J)
        object.__setattr__(self, "position", r)

    @classmethod
    def point(cls, mass, position, name: str = "point"):
        """A point mass: zero inertia about itself.

        Parameters
        ----------
        mass : float
            Mass in kg, finite and > 0.
        position : array_like, shape (3,)
            Position in the assembly frame, in m.
        name : str, default "point"
        """
        return cls(mass, np.zeros((3, 3)), position, name)

    @classmethod
    def box(cls, mass, a, b, c, position=(0.0, 0.0, 0.0), rotation=None, name: str = "box"):
        """A solid box of uniform density; moments as in :meth:`RigidBody.box`.

        Parameters
        ----------
        mass : float
            Mass in kg, finite and > 0.
        a, b, c : float
            Edge lengths along the box's own axes 1, 2, 3, in m, finite and > 0.
        position : array_like, shape (3,), default (0, 0, 0)
            Centre of the box in the assembly frame, in m.
        rotation : array_like, shape (3, 3), optional
            Orthogonal matrix whose columns are the box's axes 1, 2, 3 as unit vectors in the
            assembly frame (tensor ``R diag(I) R^T``); by default along the assembly's x, y, z.
        name : str, default "box"
        """
        return cls(mass, _rotated(_box_moments(mass, a, b, c), rotation), position, name)

    @classmethod
    def ellipsoid(
        cls, mass, a, b, c, position=(0.0, 0.0, 0.0), rotation=None, name: str = "ellipsoid"
    ):
        """A solid ellipsoid of uniform density; moments as in :meth:`RigidBody.ellipsoid`.

        Parameters
        ----------
        mass : float
            Mass in kg, finite and > 0.
        a, b, c : float
            Semi-axes along the ellipsoid's own axes 1, 2, 3, in m, finite and > 0.
        position : array_like, shape (3,), default (0, 0, 0)
            Centre in the assembly frame, in m.
        rotation : array_like, shape (3, 3), optional
            As in :meth:`box`.
        name : str, default "ellipsoid"
        """
        return cls(mass, _rotated(_ellipsoid_moments(mass, a, b, c), rotation), position, name)

    @classmethod
    def cylinder(
        cls, mass, radius, length, position=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0),
        name: str = "cylinder",
    ):
        """A solid cylinder of uniform density, its symmetry axis along ``axis``.

        The tensor is ``J = I_across E + (I_along - I_across) n n^T``, with ``n`` the unit
        vector of ``axis`` and the moments of :meth:`RigidBody.cylinder`.

        Parameters
        ----------
        mass : float
            Mass in kg, finite and > 0.
        radius, length : float
            In m, finite and > 0.
        position : array_like, shape (3,), default (0, 0, 0)
            Centre in the assembly frame, in m.
        axis : array_like, shape (3,), default (0, 0, 1)
            Direction of the symmetry axis in the assembly frame (any non-zero length).
        name : str, default "cylinder"
        """
        across, _, along = _cylinder_moments(mass, radius, length)
        n = _vector(f"axis of part {name!r}", axis, "any unit")
        norm = float(np.linalg.norm(n))
        if norm == 0.0:
            raise ValueError(f"axis of part {name!r} must be a non-zero vector, got {n.tolist()}")
        n = n / norm
        return cls(mass, across * np.eye(3) + (along - across) * np.outer(n, n), position, name)

    @classmethod
    def frustum(
        cls, mass, radius0, radius1, length, base=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0),
        name: str = "frustum",
    ):
        """A solid truncated cone of uniform density (a cone when one radius is 0).

        With the radius ``r(z) = r0 + (r1 - r0) z / L`` along the axis from the base (z = 0) and
        density rho = M / (pi int r^2 dz): centre ``z_c = int z r^2 dz / int r^2 dz``, moment
        about the axis ``rho pi int r^4 / 2 dz`` and across it, about the centre,
        ``rho pi int (r^4 / 4 + (z - z_c)^2 r^2) dz`` (thin disks; the integrals are exact
        polynomial ones). Equal radii give :meth:`cylinder`.

        Parameters
        ----------
        mass : float
            Mass in kg, finite and > 0.
        radius0, radius1 : float
            Radii of the base and of the far face, in m, finite and >= 0, not both 0.
        length : float
            In m, finite and > 0.
        base : array_like, shape (3,), default (0, 0, 0)
            Centre of the base face (radius0) in the assembly frame, in m.
        axis : array_like, shape (3,), default (0, 0, 1)
            Direction from the base to the far face (any non-zero length).
        name : str, default "frustum"
        """
        mass = positive_float(f"mass of part {name!r}", mass, "kg")
        length = positive_float(f"length of part {name!r}", length, "m")
        r0, r1 = (real_number(f"{label} of part {name!r}", r, "m")
                  for label, r in (("radius0", radius0), ("radius1", radius1)))
        if not (math.isfinite(r0) and math.isfinite(r1) and min(r0, r1) >= 0.0
                and max(r0, r1) > 0.0):
            raise ValueError(f"radii of part {name!r} must be finite and >= 0, not both 0 "
                             f"(in m), got {radius0!r} and {radius1!r}")
        n = _vector(f"axis of part {name!r}", axis, "any unit")
        norm = float(np.linalg.norm(n))
        if norm == 0.0:
            raise ValueError(f"axis of part {name!r} must be a non-zero vector, got {n.tolist()}")
        n = n / norm
        radius = np.polynomial.Polynomial([r0, (r1 - r0) / length])
        z = np.polynomial.Polynomial([0.0, 1.0])

        def integral(poly):
            antiderivative = poly.integ()
            return float(antiderivative(length) - antiderivative(0.0))

        volume = integral(radius**2)  # / pi
        rho = mass / volume
        centre = integral(z * radius**2) / volume
        along = rho * integral(radius**4) / 2.0
        across = rho * integral(radius**4 / 4.0 + (z - centre) ** 2 * radius**2)
        base = _vector(f"base of part {name!r}", base, "m")
        tensor = across * np.eye(3) + (along - across) * np.outer(n, n)
        return cls(mass, tensor, base + centre * n, name)

    @classmethod
    def from_body(cls, body: RigidBody, mass, position, rotation=None, name: str | None = None):
        """A part with the principal moments of a body, turned by ``rotation``.

        Parameters
        ----------
        body : RigidBody
            Principal moments in kg m^2 about the part's centre of mass.
        mass : float
            Mass in kg, finite and > 0 (given separately: a RigidBody holds moments only).
        position : array_like, shape (3,)
            Centre of mass in the assembly frame, in m.
        rotation : array_like, shape (3, 3), optional
            As in :meth:`box`: columns are the body's axes 1, 2, 3 in the assembly frame.
        name : str, optional
            Defaults to ``body.name``.
        """
        if not isinstance(body, RigidBody):
            raise ValueError(f"body must be a stability.RigidBody, got {type(body).__name__}")
        label = body.name if name is None else name
        return cls(mass, _rotated(body.moments, rotation), position, label)


class Composite(NamedTuple):
    """What :meth:`RigidBody.composite` returns.

    Attributes
    ----------
    body : RigidBody
        Principal moments, ascending, in kg m^2.
    axes : ndarray, shape (3, 3)
        Principal axes of ``body`` as columns in the assembly frame (a proper rotation).
    centre_of_mass : ndarray, shape (3,)
        In the assembly frame, in m.
    mass : float
        Total mass in kg.
    inertia : ndarray, shape (3, 3)
        Inertia tensor about the centre of mass, in the assembly frame, in kg m^2.
    """

    body: RigidBody
    axes: np.ndarray
    centre_of_mass: np.ndarray
    mass: float
    inertia: np.ndarray


# -------------------------------------------------------------------------------------- presets


@dataclass(frozen=True)
class Preset:
    """A named body: a one-line description (dimensions assumed) and a function giving its parts.

    The fields are the constructor's parameters and the instance's attributes.

    Parameters
    ----------
    name : str
        Registry key (``"tennis_racket"``).
    description : str
        One line: what the body is, its dimensions and which axis is 1, 2, 3.
    parts : callable
        ``parts() -> list of Part``: the parts, for :meth:`RigidBody.composite`.
    """

    name: str
    description: str
    parts: Callable[[], list[Part]]


def _tennis_racket_parts() -> list[Part]:
    """A strung 100 sq in tennis racket, 0.69 m long, about 0.30 kg.

    Assembly frame: x along the handle from the butt (x = 0) to the tip (x = 0.69 m), y across
    the head in the string plane, z normal to the strings. Dimensions assumed, typical of modern
    rackets and inside the ITF limits (Rules of Tennis, rule 4: length <= 73.7 cm, hitting
    surface <= 39.4 x 29.2 cm):

    - grip and shaft: a box 0.19 x 0.030 x 0.026 m, 0.110 kg, from the butt;
    - throat: two beams, 0.17 x 0.012 x 0.022 m, 0.0175 kg each, 3.5 cm either side of the axis;
    - head frame: an elliptical hoop with centreline semi-axes 0.165 m (x) and 0.125 m (y),
      0.140 kg, cross-section 0.024 m deep in z, as 48 segments weighted by arc length;
    - strings: an elliptical lamina with semi-axes 0.155 x 0.115 m, 0.017 kg.

    The result, 0.302 kg with the balance point 0.34 m from the butt, has a swingweight (about
    the y axis 0.10 m from the butt) of 0.031 kg m^2 and a twistweight (about the handle's axis)
    of 13 kg cm^2, in the range racket makers publish (~0.030-0.033 kg m^2 and 13-15 kg cm^2).
    """
    parts = [
        Part.box(0.110, 0.19, 0.030, 0.026, position=(0.095, 0.0, 0.0), name="grip"),
        Part.box(0.0175, 0.17, 0.012, 0.022, position=(0.275, 0.035, 0.0), name="throat +y"),
        Part.box(0.0175, 0.17, 0.012, 0.022, position=(0.275, -0.035, 0.0), name="throat -y"),
    ]
    a, b, depth, frame_mass, centre = 0.165, 0.125, 0.024, 0.140, 0.525
    theta = (np.arange(48) + 0.5) * (2.0 * np.pi / 48)
    arc = np.hypot(a * np.sin(theta), b * np.cos(theta))  # |dr/dtheta|: mass per unit angle
    segment_masses = frame_mass * arc / arc.sum()
    for k, (t, m_k) in enumerate(zip(theta, segment_masses)):
        # A segment's depth along z gives it m d^2 / 12 about the in-plane axes.
        J_k = m_k * depth**2 / 12.0 * np.diag([1.0, 1.0, 0.0])
        r_k = (centre + a * np.cos(t), b * np.sin(t), 0.0)
        parts.append(Part(m_k, J_k, r_k, name=f"frame segment {k}"))
    sa, sb, m_s = 0.155, 0.115, 0.017  # elliptical lamina: m b^2/4, m a^2/4, m (a^2 + b^2)/4
    J_strings = m_s / 4.0 * np.diag([sb**2, sa**2, sa**2 + sb**2])
    parts.append(Part(m_s, J_strings, (centre, 0.0, 0.0), name="strings"))
    return parts


def _t_handle_parts() -> list[Part]:
    """A steel T-handle, the shape of the wing nut in Dzhanibekov's 1985 observation.

    Crossbar: a steel cylinder 100 mm long, 10 mm in diameter, along y; stem: a steel cylinder
    50 mm long, 12 mm in diameter, along x, its end touching the crossbar's middle. Steel
    density 7850 kg/m^3.
    """
    rho = 7850.0
    bar_r, bar_l = 0.005, 0.100
    stem_r, stem_l = 0.006, 0.050
    return [
        Part.cylinder(
            rho * np.pi * bar_r**2 * bar_l, bar_r, bar_l, axis=(0.0, 1.0, 0.0), name="crossbar"
        ),
        Part.cylinder(
            rho * np.pi * stem_r**2 * stem_l, stem_r, stem_l,
            position=(bar_r + stem_l / 2, 0.0, 0.0), axis=(1.0, 0.0, 0.0), name="stem",
        ),
    ]


def _phone_parts() -> list[Part]:
    """A 6.1-inch smartphone as a uniform box 147 x 71.5 x 7.8 mm, 0.17 kg."""
    return [Part.box(0.17, 0.147, 0.0715, 0.0078, name="phone")]


def _book_parts() -> list[Part]:
    """A hardback book as a uniform box 240 x 160 x 30 mm, 0.80 kg (paper ~0.7 g/cm^3)."""
    return [Part.box(0.80, 0.240, 0.160, 0.030, name="book")]


#: The presets by name (read-only). ``RigidBody.preset(name)`` builds one; every preset has a
#: clearly intermediate axis 2: min(I2 - I1, I3 - I2) >= 0.08 (I3 - I1).
PRESETS: Mapping[str, Preset] = MappingProxyType({
    "tennis_racket": Preset(
        "tennis_racket",
        "strung tennis racket, 0.69 m, 0.30 kg (grip, throat, elliptical head frame 0.33 x "
        "0.25 m, strings); axis 1 along the handle, 2 across the head, 3 normal to the strings",
        _tennis_racket_parts,
    ),
    "t_handle": Preset(
        "t_handle",
        "steel T-handle (Dzhanibekov's wing nut): crossbar 100 x 10 mm, stem 50 x 12 mm; "
        "axis 1 along the crossbar, 2 along the stem, 3 normal to the T",
        _t_handle_parts,
    ),
    "phone": Preset(
        "phone",
        "smartphone, uniform box 147 x 71.5 x 7.8 mm, 0.17 kg; axis 1 along the length, "
        "2 along the width, 3 normal to the screen",
        _phone_parts,
    ),
    "book": Preset(
        "book",
        "hardback book, uniform box 240 x 160 x 30 mm, 0.80 kg; axis 1 along the "
        "spine (240 mm), 2 along the 160 mm edge, 3 normal to the cover",
        _book_parts,
    ),
})


def _check_range(moments) -> None:
    """Refuse moments whose products, which the kernels form (``I_j I_k`` in the Euler
    coefficients, ``I1 I2 I3`` in Moser-Veselov), underflow or overflow a double."""
    I1, I2, I3 = moments
    low, high = sys.float_info.min, sys.float_info.max
    products = (I1 * I2, I2 * I3, I3 * I1, I1 * I2 * I3)
    if not all(low <= x <= high for x in products):
        raise ValueError(
            f"moments {tuple(moments)} kg m^2 are out of a double's range: the kernels form "
            f"products of two and of three moments, which must lie between {low:.3g} and "
            f"{high:.3g}; w(t) depends only on the ratios of the moments, so divide all three "
            "by one factor (by I2, say)")
