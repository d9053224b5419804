"""A tumbler's physics: its spin state from its two periods and moment ratios (and its periods
from a state), the mass properties of its shape model, and the linear theory of its relaxation.

**The spin state** (:func:`spin_states`, :func:`state_of`). Conventions (Samarasinha & A'Hearn, Icarus 93, 194 (1991); Kaasalainen, A&A 376, 302 (2001);
Pravec et al., Icarus 173, 108 (2005) and Icarus 233, 48 (2014)): moments I1 <= I2 <= I3 (I1 about
the long axis, I3 about the short axis), L the angular momentum, E the rotational kinetic
energy and E0 = L^2 / (2 I3) the lowest energy at that |L|, so 1 <= E/E0 <= I3/I1. z-x-z Euler
angles (phi, theta, psi) take space Z along L and body z along the reference axis:

- SAM (short-axis mode, 1 < E/E0 < I3/I2, the package's regime "major"): the reference axis is
  the short axis (I3). P_psi is the period of the rotation psi about it (psi turns backwards,
  psi' < 0, and P_psi is taken positive), P_phi the mean period of the precession phi of that
  axis about L. The long axis turns about L at 1/P_phi - 1/P_psi (Apophis: P1 of Pravec 2014).
- LAM (long-axis mode, I3/I2 < E/E0 < I3/I1, regime "minor"): the reference axis is the long
  axis (I1); P_psi is the period of the rotation about it (psi' > 0), P_phi the mean period of
  the precession of the long axis about L.

In both modes theta nutates with P_psi / 2. From the exact solution (:mod:`stability.free_body.
exact`), P_psi = 4 K(m) / nu, the period of the body's angular momentum along the polhode, and
the mean precession rate is, with Pi the complete integral of the third kind
(Landau & Lifshitz, *Mechanics*, section 37; derived from phi' = L (2E - m_z^2 / I_z) /
(L^2 - m_z^2) with m_z from the Jacobi solution):

    SAM:  <phi'> = L / I3 + L (I3 - I1) / (I1 I3) Pi(-n | m) / K,   n = I3 (I2 - I1) / (I1 (I3 - I2))
    LAM:  <phi'> = L / I1 - L (I3 - I1) / (I1 I3) Pi(-n | m) / K,   n = I1 (I3 - I2) / (I3 (I2 - I1))

and P_phi = 2 pi / <phi'>. Pi(-n | m) = R_F(0, 1 - m, 1) - (n / 3) R_J(0, 1 - m, 1, 1 + n)
(DLMF 19.25.2), R_F from :mod:`stability.core.elliptic`, R_J from SciPy.

The ratio P_psi / P_phi depends on E/E0 alone (at given moment ratios); :func:`spin_states`
solves it for E/E0 with brentq in each mode and returns every state the two periods fit (a
pair of periods can fit a SAM and a LAM state both), or only that of the mode asked for; |L|
then follows from P_psi.

**The shape model** (:func:`mass_properties`): a closed triangle mesh (OBJ, STL, PLY, OFF) of
uniform density -> volume, mass, centre of mass, inertia tensor, principal moments and axes, a
RigidBody.

The integrals are those of the divergence theorem over the facets, exact for a polyhedron
(Mirtich, J. Graphics Tools 1, 31 (1996); Eberly, "Polyhedral Mass Properties" (2002)), as
trimesh computes them (``Trimesh.mass_properties``); trimesh (the ``shapes`` extra, ``pip install
stability[shapes]``) also reads the file. A shape model is untrusted input: it is read as a mesh
and nothing else (no pickle, no scene graph of other files), and refused in one line when it is
missing, of another format, open (not watertight), with inconsistent or inward-facing facets, or
of zero or negative volume. trimesh has no test for self-intersection without python-fcl; a mesh
that crosses itself but is closed and consistently wound is not caught here.

**The relaxation** (:func:`wobble_rate`, :func:`damping_coefficient`): a tumbler whose interior
dissipates (:mod:`stability.asteroid.methods`, equation (1), the scene ``relaxing_tumbler``)
loses its wobble about the major axis at a rate the linearisation gives exactly, and gains one
about the minor axis; its axisymmetric motion is exact (:mod:`stability.asteroid.exact`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..core.body import RigidBody
from ..core.elliptic import carlson_rf, ellipk
from ..core.quaternions import matrix_to_quaternion, quaternion_to_matrix
from ..free_body.exact import MAJOR, MINOR, Q_K, Q_KIND, Q_M, Q_M1, Q_RATE, motion
from ..free_body.exact_attitude import exact_attitude
from ..integrators.spec import P_I1, P_I2, P_I3, P_INV1
from ..util.checks import positive_float, real_array, vectors3
from .methods import P_ALPHA, relaxation_params

#: The two modes of a tumbler, as the literature names them.
MODES = ("SAM", "LAM")

#: Grid of k'^2 = 1 - m on which the period ratio is scanned for its roots (log-spaced towards
#: the separatrix, where K diverges as ln(4 / k')).
_M1_GRID = np.unique(np.concatenate([np.logspace(-14, -1, 60), np.linspace(0.1, 0.9, 30),
                                     1.0 - np.logspace(-1, -12, 40)]))


@dataclass(frozen=True)
class SpinState:
    """A torque-free tumbling state, canonical frame (I1 <= I2 <= I3).

    Attributes
    ----------
    mode : str
        ``"SAM"`` or ``"LAM"`` (module docstring).
    moments : ndarray, shape (3,)
        Principal moments, ascending, in the units given (kg m^2, or ratios to I3).
    energy_ratio : float
        E/E0 = 2 E I3 / L^2.
    momentum : float
        |L| in (units of the moments) rad/s.
    period_psi, period_phi : float
        Rotation and mean precession periods, in the time unit of the input (s by default).
    w0 : ndarray, shape (3,)
        A body angular velocity of the state (at the phase where w2 = 0, w1, w3 > 0), canonical
        frame, in rad per time unit.
    """

    mode: str
    moments: np.ndarray
    energy_ratio: float
    momentum: float
    period_psi: float
    period_phi: float
    w0: np.ndarray

    @property
    def body(self) -> RigidBody:
        """The state's moments as a :class:`~stability.RigidBody` (axes canonical)."""
        return RigidBody(*self.moments, physical=False, name=f"{self.mode} tumbler")

    def attitude(self, t) -> np.ndarray:
        """The body-to-space rotations (n, 3, 3) at times ``t`` (n,), in the frame of L (space
        Z along the angular momentum; :func:`l_frame_start`): the free body's exact attitude
        (:func:`stability.free_body.exact_attitude.exact_attitude`)."""
        q0 = l_frame_start(self.w0, self.moments)
        return quaternion_to_matrix(exact_attitude(self.body, self.w0, np.atleast_1d(t), q0))

    @property
    def frequencies(self) -> tuple[float, float]:
        """(f_phi, f_psi) = (1 / P_phi, 1 / P_psi), cycles per time unit."""
        return 1.0 / self.period_phi, 1.0 / self.period_psi


def l_frame_start(w0, moments) -> np.ndarray:
    """The attitude q0 at t = 0 that puts L = I w0 along space Z (scalar-first quaternion)."""
    m = np.asarray(moments, float) * np.asarray(w0, float)
    z = m / np.linalg.norm(m)
    x = np.cross([0.0, 1.0, 0.0] if abs(z[1]) < 0.9 else [1.0, 0.0, 0.0], z)
    x /= np.linalg.norm(x)
    return matrix_to_quaternion(np.array([x, np.cross(z, x), z]))


def _pi_minus(n: float, m: float, m1: float) -> float:
    """Complete elliptic integral of the third kind Pi(-n | m), n > -1, via Carlson (DLMF 19.25.2)."""
    from scipy.special import elliprj

    return carlson_rf(0.0, m1, 1.0) - n / 3.0 * float(elliprj(0.0, m1, 1.0, 1.0 + n))


def _mean_precession(mode, I1, I2, I3, L, m, m1, K) -> float:
    """<phi'> of the reference axis about L (module docstring), rad per time unit."""
    c = L * (I3 - I1) / (I1 * I3)
    if mode == "SAM":
        n = I3 * (I2 - I1) / (I1 * (I3 - I2))
        return L / I3 + c * _pi_minus(n, m, m1) / K
    n = I1 * (I3 - I2) / (I3 * (I2 - I1))
    return L / I1 - c * _pi_minus(n, m, m1) / K


def check_moments(moments) -> np.ndarray:
    """Three distinct principal moments (or ratios) in ascending order, physical; else one line.

    Parameters
    ----------
    moments : array_like, shape (3,)
        I1 < I2 < I3, e.g. ``(I1/I3, I2/I3, 1)``.

    Returns
    -------
    ndarray, shape (3,)
    """
    I = vectors3("moments", moments)
    if I.ndim != 1 or not np.all(np.isfinite(I)) or np.any(I <= 0.0):
        raise ValueError(f"moments must be three finite positive numbers I1 < I2 < I3, got "
                         f"{np.asarray(moments).tolist()}")
    if not (I[0] < I[1] < I[2]):
        raise ValueError(f"moments must be distinct and ascending, I1 < I2 < I3 (I1 about the "
                         f"long axis), got {I.tolist()}; sort them, or perturb equal ones")
    if I[2] > I[0] + I[1]:
        raise ValueError(f"moments {I.tolist()} violate the triangle inequality I3 <= I1 + I2 "
                         "that every real body obeys (ratios I1/I3 + I2/I3 must be >= 1)")
    return I


def check_mode(mode) -> str:
    """``"SAM"`` or ``"LAM"`` (any case); else ValueError."""
    if not isinstance(mode, str) or mode.upper() not in MODES:
        raise ValueError(f"mode must be 'SAM' (short-axis mode) or 'LAM' (long-axis mode), "
                         f"got {mode!r}")
    return mode.upper()


def _elliptic(mode, I, e):
    """(m, m1, nu / L) of the state E/E0 = e at |L| = 1 (module docstring of exact.py)."""
    I1, I2, I3 = I
    d1, d2, d3 = 1.0 - e * I1 / I3, 1.0 - e * I2 / I3, e - 1.0  # D1, D2, D3 over L^2
    if mode == "SAM":
        m = (I2 - I1) * d3 / ((I3 - I2) * d1)
        m1 = (I3 - I1) * d2 / ((I3 - I2) * d1)
        nu = math.sqrt((I3 - I2) * d1 / (I1 * I2 * I3))
    else:
        m = (I3 - I2) * d1 / ((I2 - I1) * d3)
        m1 = (I3 - I1) * (-d2) / ((I2 - I1) * d3)
        nu = math.sqrt((I2 - I1) * d3 / (I1 * I2 * I3))
    return m, m1, nu


def _energy_ratio(mode, I, m1) -> float:
    """E/E0 of the state whose k'^2 is ``m1`` (the inverse of :func:`_elliptic`)."""
    I1, I2, I3 = I
    m = 1.0 - m1
    if mode == "SAM":  # m (I3 - I2)(1 - e r1) = (I2 - I1)(e - 1)
        a, b = (I3 - I2), (I2 - I1)
        return (a * m + b) / (a * m * I1 / I3 + b)
    a, b = (I2 - I1), (I3 - I2)  # m (I2 - I1)(e - 1) = (I3 - I2)(1 - e r1)
    return (a * m + b) / (a * m + b * I1 / I3)


def _ratio(mode, I, m1) -> float:
    """P_psi / P_phi at k'^2 = m1 (independent of |L|)."""
    m = 1.0 - m1
    e = _energy_ratio(mode, I, m1)
    _, _, nu = _elliptic(mode, I, e)
    K = ellipk(m1)
    return _mean_precession(mode, *I, 1.0, m, m1, K) * 4.0 * K / (2.0 * math.pi * nu)


def _state(mode, I, e, period_psi) -> SpinState:
    """The state of mode ``mode`` at E/E0 = e whose rotation period is ``period_psi``."""
    I1, I2, I3 = I
    m, m1, nu1 = _elliptic(mode, I, e)
    K = ellipk(m1)
    L = 4.0 * K / (period_psi * nu1)
    phi = _mean_precession(mode, I1, I2, I3, L, m, m1, K)
    w0 = np.array([math.sqrt(L * L * (e - 1.0) / (I1 * (I3 - I1))), 0.0,
                   math.sqrt(L * L * (1.0 - e * I1 / I3) / (I3 * (I3 - I1)))])
    return SpinState(mode, I.copy(), float(e), float(L), float(period_psi),
                     float(2.0 * math.pi / phi), w0)


def spin_states(moments, period_psi, period_phi, mode=None) -> list[SpinState]:
    """Every torque-free state with these moment ratios and periods (module docstring).

    Parameters
    ----------
    moments : array_like, shape (3,)
        I1 < I2 < I3, any scale (ratios ``(I1/I3, I2/I3, 1)`` give |L| per unit I3).
    period_psi, period_phi : float
        Rotation period P_psi and mean precession period P_phi, > 0, one time unit.
    mode : str, optional
        ``"SAM"`` or ``"LAM"``: only that mode's states; default both.

    Returns
    -------
    list of SpinState
        SAM states first, each mode's by increasing E/E0; empty if none fits.
    """
    I = check_moments(moments)
    p_psi = positive_float("period_psi", period_psi)
    p_phi = positive_float("period_phi", period_phi)
    modes = MODES if mode is None else (check_mode(mode),)
    from scipy.optimize import brentq

    target = p_psi / p_phi
    out = []
    for md in modes:
        f = np.array([_ratio(md, I, x) for x in _M1_GRID]) - target
        roots = []
        for j in np.flatnonzero(np.sign(f[:-1]) * np.sign(f[1:]) < 0):
            x = brentq(lambda x: _ratio(md, I, x) - target, _M1_GRID[j], _M1_GRID[j + 1],
                       xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=200)
            roots.append(_energy_ratio(md, I, x))
        out += [_state(md, I, e, p_psi) for e in sorted(roots)]
    return out


def spin_state(moments, period_psi, period_phi, mode) -> SpinState:
    """The one state of ``mode`` these periods fit; ValueError if none or several.

    Parameters are those of :func:`spin_states`, ``mode`` required.
    """
    states = spin_states(moments, period_psi, period_phi, mode)
    if len(states) != 1:
        what = "no" if not states else f"{len(states)}"
        raise ValueError(f"{what} {check_mode(mode)} states fit P_psi = {period_psi:g} and "
                         f"P_phi = {period_phi:g} at moments {np.asarray(moments).tolist()}; "
                         "check which period is which, or use spin_states() for all")
    return states[0]


def state_of(moments, w) -> SpinState:
    """The mode, E/E0, |L| and periods of the state ``w`` of a body (the inverse direction).

    Parameters
    ----------
    moments : array_like, shape (3,)
        I1 < I2 < I3 (canonical frame).
    w : array_like, shape (3,)
        Body angular velocity, canonical frame, rad per time unit; off the separatrix.

    Returns
    -------
    SpinState
        With ``w0 = w`` as given.
    """
    I = check_moments(moments)
    w = vectors3("w", w)
    if w.ndim != 1 or not np.all(np.isfinite(w)) or not np.any(w):
        raise ValueError(f"w must be a finite, non-zero angular velocity of shape (3,), got "
                         f"{np.asarray(w).tolist()}")
    q = motion(*I, *w)
    kind = int(q[Q_KIND])
    if kind not in (MAJOR, MINOR):
        raise ValueError("the state lies on the separatrix (L^2 = 2 E I2): it has no periods "
                         "(neither SAM nor LAM); perturb it")
    mode = "SAM" if kind == MAJOR else "LAM"
    L = float(np.linalg.norm(I * w))
    e = float(np.dot(I * w, w) * I[2] / L**2)
    K, nu = float(q[Q_K]), abs(float(q[Q_RATE]))
    phi = _mean_precession(mode, *I, L, float(q[Q_M]), float(q[Q_M1]), K)
    return SpinState(mode, I, e, L, 4.0 * K / nu, 2.0 * math.pi / phi, w.copy())


def energy_ratio_bounds(moments) -> tuple[float, float, float]:
    """(1, I3/I2, I3/I1): the lowest E/E0, the SAM/LAM boundary (separatrix) and the highest."""
    I = check_moments(moments)
    return 1.0, float(I[2] / I[1]), float(I[2] / I[0])


# --- The shape model ----------------------------------------------------------------------------

#: The file formats read (trimesh's loaders for them).
FORMATS = ("obj", "stl", "ply", "off")


@dataclass(frozen=True)
class MassProperties:
    """Mass properties of a uniform solid, in the units of its mesh (length L, density rho).

    Attributes
    ----------
    volume : float
        L^3.
    mass : float
        rho L^3.
    center_of_mass : ndarray, shape (3,)
        L, in the mesh's frame.
    inertia : ndarray, shape (3, 3)
        Inertia tensor about the centre of mass, mesh axes, rho L^5.
    moments : ndarray, shape (3,)
        Principal moments, ascending, rho L^5.
    axes : ndarray, shape (3, 3)
        Principal axes as columns (a proper rotation), ``inertia = axes diag(moments) axes^T``.
    """

    volume: float
    mass: float
    center_of_mass: np.ndarray
    inertia: np.ndarray
    moments: np.ndarray
    axes: np.ndarray

    def body(self, name: str = "shape model") -> RigidBody:
        """The :class:`~stability.RigidBody` of the principal moments (axes ascending)."""
        return RigidBody(*self.moments, name=name)


def _trimesh():
    try:
        import trimesh
    except ImportError:
        raise ImportError("reading shape models needs trimesh: pip install 'stability[shapes]'"
                          ) from None
    return trimesh


def load_mesh(path):
    """A shape model file read as one triangle mesh (a ``trimesh.Trimesh``), checked.

    Parameters
    ----------
    path : str or Path
        An OBJ, STL, PLY or OFF file.
    """
    trimesh = _trimesh()
    p = Path(path)
    kind = p.suffix.lower().lstrip(".")
    if kind not in FORMATS:
        raise ValueError(f"{p}: a shape model must be one of {', '.join(FORMATS)} (by its "
                         f"suffix), got {p.suffix or 'no suffix'!r}")
    if not p.is_file():
        raise ValueError(f"{p}: no such file")
    try:
        with open(p, "rb") as stream:
            mesh = trimesh.load(stream, file_type=kind, force="mesh", process=True)
    except Exception as exc:  # a parser's error, whatever its type, is the file's fault
        raise ValueError(f"{p}: not a readable {kind.upper()} mesh ({type(exc).__name__}: "
                         f"{str(exc).splitlines()[0] if str(exc) else 'no detail'})") from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise ValueError(f"{p}: holds no triangles; a shape model is a closed triangle mesh")
    return _checked(mesh, str(p))


def _checked(mesh, where: str):
    """``mesh`` if it bounds a solid; else a one-line ValueError saying what to fix."""
    if not np.all(np.isfinite(mesh.vertices)):
        raise ValueError(f"{where}: vertices that are not finite numbers; fix the file")
    if not mesh.is_watertight:
        raise ValueError(f"{where}: the mesh is open or has edges shared by more than two "
                         f"facets (not watertight: {len(mesh.faces)} facets); close its holes "
                         "(e.g. trimesh.repair.fill_holes) or export a closed solid")
    if not mesh.is_winding_consistent:
        raise ValueError(f"{where}: facets wound inconsistently (neighbours disagree on which "
                         "side is out); fix the normals (trimesh.repair.fix_winding)")
    if not mesh.volume > 0.0:
        raise ValueError(f"{where}: the facets face inwards (signed volume {mesh.volume:.6g} "
                         "<= 0); invert them (trimesh.repair.fix_inversion)")
    return mesh


def mesh_from_arrays(vertices, faces):
    """A checked ``trimesh.Trimesh`` from vertices (V, 3) and triangles (F, 3)."""
    trimesh = _trimesh()
    v = real_array("vertices", vertices)
    f = np.asarray(faces)
    if v.ndim != 2 or v.shape[1] != 3 or f.ndim != 2 or f.shape[1] != 3 or len(f) == 0:
        raise ValueError(f"a mesh is vertices (V, 3) and faces (F, 3), got {v.shape} and "
                         f"{f.shape}")
    if not np.issubdtype(f.dtype, np.integer) or f.min() < 0 or f.max() >= len(v):
        raise ValueError(f"faces must index the {len(v)} vertices with integers")
    return _checked(trimesh.Trimesh(v, f, process=True), "mesh")


def mass_properties(shape, density: float = 1.0) -> MassProperties:
    """Mass properties of a closed mesh of uniform ``density`` (module docstring).

    Parameters
    ----------
    shape : str, Path, (vertices, faces) or trimesh.Trimesh
        A shape-model file, arrays, or a mesh.
    density : float
        Mass per unit volume (kg m^-3 for a mesh in metres).

    Returns
    -------
    MassProperties
    """
    rho = positive_float("density", density)
    if isinstance(shape, (str, Path)):
        mesh = load_mesh(shape)
    elif isinstance(shape, tuple) and len(shape) == 2:
        mesh = mesh_from_arrays(*shape)
    else:
        mesh = _checked(shape, "mesh") if hasattr(shape, "is_watertight") else None
        if mesh is None:
            raise ValueError(f"shape must be a file, (vertices, faces) or a trimesh.Trimesh, "
                             f"got {type(shape).__name__}")
    props = mesh.mass_properties  # unit density, inertia about the centre of mass
    J = np.asarray(props["inertia"], float) * rho
    J = 0.5 * (J + J.T)
    moments, axes = np.linalg.eigh(J)
    if np.linalg.det(axes) < 0.0:
        axes[:, 2] = -axes[:, 2]
    return MassProperties(float(props["volume"]), float(props["volume"]) * rho,
                          np.asarray(props["center_mass"], float), J, moments, axes)


def _relaxation_body(moments, alpha) -> np.ndarray:
    """The kernel parameters of ``moments`` (three numbers) and ``alpha``, checked."""
    values = real_array("moments", moments).reshape(-1)
    if values.size != 3:
        raise ValueError(f"moments must be three numbers (I1, I2, I3), got {values.size}")
    return relaxation_params([*values, alpha])


def _linear_terms(p, axis, length):
    """(a, b, k) of :func:`wobble_rate`'s linearisation about ``L e_axis``."""
    inv = p[P_INV1:P_INV1 + 3]
    a, b = (length * (inv[k] - inv[axis]) for k in range(3) if k != axis)
    return a, b, p[P_ALPHA] * length


def wobble_rate(moments, axis: int, momentum: float, alpha: float) -> float:
    """The growth rate (1/s) of a small wobble about a spin about ``axis`` of the relaxing
    tumbler (:mod:`stability.asteroid.methods`, equation (1)): negative where it dies out.

    Linearised about ``m = L e_j``, the two components across the axis, in the cyclic order
    ``(j, b, c)``, obey ``x' = -k a x - b y``, ``y' = a x - k b y`` with ``k = alpha L``,
    ``a = L (1/I_b - 1/I_j)`` and ``b = L (1/I_c - 1/I_j)``, whose eigenvalues are
    ``-k (a + b) / 2 +- sqrt(k^2 (a - b)^2 / 4 - a b)``. About the major axis a, b > 0 and the
    wobble decays at ``k (a + b) / 2`` while it turns at ``sqrt(a b - k^2 (a - b)^2 / 4)`` (at
    alpha = 0, the free body's Omega); about the minor axis a, b < 0 and the same dissipation
    makes it grow (Bloch, Krishnaprasad, Marsden & Ratiu, Comm. Math. Phys. 175, 1 (1996): the
    instability a dissipation induces); about the intermediate axis a b < 0 and it grows at
    ``sqrt(-a b)`` shifted by about ``-k (a + b) / 2`` (slower where 1/I1 + 1/I3 > 2/I2).

    Parameters
    ----------
    moments : array_like, shape (3,)
        Canonical moments I1 <= I2 <= I3 (kg m^2).
    axis : {0, 1, 2}
        The spin axis.
    momentum : float
        |L| (kg m^2/s), > 0.
    alpha : float
        The damping coefficient (kg^-1 m^-2 s), >= 0.

    Returns
    -------
    float
        The largest real part of the two eigenvalues.
    """
    p = _relaxation_body(moments, alpha)
    if isinstance(axis, bool) or not isinstance(axis, (int, np.integer)) or axis not in (0, 1, 2):
        raise ValueError(f"axis must be 0, 1 or 2 (canonical, I1 <= I2 <= I3), got {axis!r}")
    a, b, k = _linear_terms(p, int(axis), positive_float("momentum", momentum, "kg m2 s-1"))
    disc = 0.25 * k * k * (a - b) ** 2 - a * b
    return float(-0.5 * k * (a + b) + (math.sqrt(disc) if disc > 0.0 else 0.0))


def damping_coefficient(moments, momentum: float, damping_time: float) -> float:
    """The alpha of equation (1) (kg^-1 m^-2 s) with which a small wobble about the major axis
    dies out in ``damping_time``: ``alpha = 2 / (tau L^2 (1/I1 + 1/I2 - 2/I3))``, the inverse
    of :func:`wobble_rate` while the wobble still turns; a damping time too short for that
    (``tau <= |a - b| / ((a + b) sqrt(a b))``), or a body without one major axis (I2 = I3), is
    refused.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Canonical moments I1 <= I2 < I3 (kg m^2).
    momentum : float
        |L| (kg m^2/s), > 0.
    damping_time : float
        The e-folding time tau (s) of the wobble's amplitude, > 0.

    Returns
    -------
    float
    """
    p = _relaxation_body(moments, 0.0)
    length = positive_float("momentum", momentum, "kg m2 s-1")
    tau = positive_float("damping_time", damping_time, "s")
    if not p[P_I2] < p[P_I3]:
        raise ValueError(f"the moments {tuple(float(x) for x in p[P_I1:P_I1 + 3])} have no "
                         "single major axis (I2 = I3): a wobble about it does not die out")
    a, b, _ = _linear_terms(p, 2, length)
    shortest = abs(a - b) / ((a + b) * math.sqrt(a * b))
    if not tau > shortest:
        raise ValueError(f"damping_time = {tau:g} s is too short for these moments and |L|: "
                         f"the wobble would no longer turn; give more than {shortest:.6g} s")
    return 2.0 / (tau * length * (a + b))


__all__ = ["MODES", "SpinState", "check_mode", "check_moments", "energy_ratio_bounds",
           "l_frame_start",
           "spin_state", "spin_states", "state_of",
           "FORMATS", "MassProperties", "load_mesh", "mass_properties", "mesh_from_arrays",
           "damping_coefficient", "wobble_rate"]
