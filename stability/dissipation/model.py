"""The damped bodies in closed form: steady spins, their linear theory, the energy sink, presets.

A steady spin ``w = W e_a`` about a principal axis a, with the damper at rest in the body (the
sphere turning with the shell; the mass on its spring at z = 0), is a state of both scenes
(:mod:`stability.dissipation.scene`). Its stability is that of the linearised equations
``dx' = M dx`` (``M`` the Jacobian of the right-hand side there):

- The spherical damper (state ``m = I w``, ``s = J w_s``): with ``hat(v)`` the matrix of
  ``v x``, ``w = W e_a``, ``m = I_a W e_a`` and ``s = J W e_a``::

      M = [[-hat(w) + hat(m) I^-1 - c I^-1,  (c / J) Id       ],
           [ hat(s) I^-1 + c I^-1,            -hat(w) - (c/J) Id]]                      (1)

  (:func:`sphere_jacobian`, closed form). The components along a decouple (an eigenvalue 0:
  the spin's size; and ``-r_a``); the four across it hold the nutation: :func:`growth_rate`
  is the largest real part of their eigenvalues. About an axis of symmetry (``I_b = I_c =
  I_t``, spin axis moment ``I_s``) they are the roots of one complex quadratic and their
  conjugates (:func:`axisymmetric_eigenvalues`, derived in the guide)::

      l^2 + (i (nu + W) + c (1/I_t + 1/J)) l - nu W + i nu c / J = 0,
      nu = W (I_t - I_s) / I_t.                                                        (2)

  For a weak damper the nutation root is ``-i nu + c (I_t - I_s) / (I_t I_s) + O(c^2)``: it
  grows about the minor axis (I_s < I_t) and decays about the major one.
- The whip antennas: the Jacobian of their right-hand side by complex-step differentiation
  (exact to round-off, :func:`whip_jacobian`); the eigenvalue of the steady spins' own family
  (0) is set aside.

**The energy sink** (Thomson & Reiter 1965; Kaplan, *Modern Spacecraft Dynamics and Control*
(1976), 5.3): treat the shell as rigid and the damper as a sink that drains its energy.
At fixed |m| the energy of a shell spinning about its symmetry axis at nutation angle theta is
``|m|^2 / 2 (cos^2 theta / I_s + sin^2 theta / I_t)``, so ``E' = -P`` makes
``theta' = P / (|m|^2 theta (1/I_s - 1/I_t))``; the sphere forced by the rigid nutation (body
rates ``w_t`` turning at ``-nu``) takes the relative rate ``|u| = nu w_t / sqrt((W I_s /
I_t)^2 + (c / J)^2)`` and dissipates ``P = c |u|^2``. Together::

    sigma_sink = c (I_t - I_s) I_s W^2 / (I_t ((W I_s)^2 + (c I_t / J)^2)),            (3)

largest at ``c* = J W I_s / I_t`` (:func:`energy_sink_rate`, :func:`energy_sink_optimum`). At
first order in c it is the root of (2); beyond, it drops the sphere's reaction on the shell.

**The end state**: with |H| kept and E falling, the motion ends in the state of least energy
at that |H|, a spin about the axis of greatest moment of the whole system (damper included,
``A``: :func:`~stability.dissipation.scene.sphere_moments`,
:func:`~stability.dissipation.scene.whip_moments`), having lost
``|H|^2 / 2 (1/A_start - 1/A_max)`` (:func:`energy_lost`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.axes import spin_axis
from .methods import whip_params, whip_rhs
from .scene import sphere_rigid_state, whip_rigid_state


def hat(v) -> np.ndarray:
    """The matrix of ``v x``: ``hat(v) x = v x x``.

    Parameters
    ----------
    v : array_like, shape (3,)
        A vector.
    """
    v1, v2, v3 = (float(x) for x in v)
    return np.array([[0.0, -v3, v2], [v3, 0.0, -v1], [-v2, v1, 0.0]])


def _across(axis: int) -> list:
    """State indices across the spin axis: the two other components of m and of s (or H)."""
    return [k for k in range(3) if k != axis]


def sphere_steady_spin(values, axis: int, spin: float) -> np.ndarray:
    """The state (6,) ``(m, s) = (I_a W e_a, J W e_a)`` of a steady spin ``W`` about body axis
    ``axis`` (0, 1, 2) with the sphere turning with the shell; ``values`` = (I1, I2, I3, J, c).

    Parameters
    ----------
    values : array_like
        The scene's parameter set: ``(I1, I2, I3, J, c)`` for the sphere,
        ``(I1, I2, I3, mu, b, k, c)`` for the whips.
    axis : int
        The spin's body axis, 0, 1 or 2.
    spin : float
        The spin W, rad s-1.
    """
    w = np.zeros(3)
    w[axis] = spin
    return sphere_rigid_state(values, w)[0]


def sphere_jacobian(values, axis: int, spin: float) -> np.ndarray:
    """Equation (1): the Jacobian (6, 6) of the spherical damper's equations at the steady spin
    :func:`sphere_steady_spin` (closed form).

    Parameters
    ----------
    values : array_like
        The scene's parameter set: ``(I1, I2, I3, J, c)`` for the sphere,
        ``(I1, I2, I3, mu, b, k, c)`` for the whips.
    axis : int
        The spin's body axis, 0, 1 or 2.
    spin : float
        The spin W, rad s-1.
    """
    I1, I2, I3, J, c = (float(v) for v in np.asarray(values, dtype=float))
    inv = np.diag([1.0 / I1, 1.0 / I2, 1.0 / I3])
    x = sphere_steady_spin(values, axis, spin)
    w = np.zeros(3)
    w[axis] = spin
    eye = np.eye(3)
    return np.block([[-hat(w) + hat(x[:3]) @ inv - c * inv, (c / J) * eye],
                     [hat(x[3:]) @ inv + c * inv, -hat(w) - (c / J) * eye]])


def sphere_eigenvalues(values, axis: int, spin: float) -> np.ndarray:
    """The four eigenvalues (s-1) of the nutation block of (1): the components across the spin
    axis, sorted by decreasing real part.

    Parameters
    ----------
    values : array_like
        The scene's parameter set: ``(I1, I2, I3, J, c)`` for the sphere,
        ``(I1, I2, I3, mu, b, k, c)`` for the whips.
    axis : int
        The spin's body axis, 0, 1 or 2.
    spin : float
        The spin W, rad s-1.
    """
    across = _across(axis)
    rows = across + [3 + k for k in across]
    lam = np.linalg.eigvals(sphere_jacobian(values, axis, spin)[np.ix_(rows, rows)])
    return lam[np.argsort(-lam.real, kind="stable")]


def axisymmetric_eigenvalues(spin_moment, transverse_moment, J, c, spin) -> np.ndarray:
    """Equation (2): the four nutation eigenvalues (s-1) of a spin ``W`` about the symmetry
    axis of a shell with moments ``I_s`` (that axis) and ``I_t`` (across), and a spherical
    damper (J, c); the roots of the quadratic and their conjugates, by decreasing real part.

    Parameters
    ----------
    spin_moment : float
        The shell's moment I_s about the spin axis, kg m2.
    transverse_moment : float
        The shell's moment I_t across it, kg m2.
    J : float
        The sphere's moment of inertia, kg m2.
    c : float or array_like
        The sphere's viscous coefficient, N m s.
    spin : float
        The spin W, rad s-1.
    """
    I_s, I_t, W = float(spin_moment), float(transverse_moment), float(spin)
    nu = W * (I_t - I_s) / I_t
    b = 1j * (nu + W) + c * (1.0 / I_t + 1.0 / J)
    q = -nu * W + 1j * nu * c / J
    root = np.sqrt(b * b - 4.0 * q)
    lam = np.array([(-b + root) / 2.0, (-b - root) / 2.0])
    lam = np.concatenate([lam, lam.conj()])
    return lam[np.argsort(-lam.real, kind="stable")]


def whip_steady_spin(values, axis: int, spin: float) -> np.ndarray:
    """The state (7,) of a steady spin ``W`` about body axis ``axis`` with the tips at rest in
    the body (:func:`~stability.dissipation.scene.whip_rigid_state`); ``values`` =
    (I1, I2, I3, mu, b, k, c).

    Parameters
    ----------
    values : array_like
        The scene's parameter set: ``(I1, I2, I3, J, c)`` for the sphere,
        ``(I1, I2, I3, mu, b, k, c)`` for the whips.
    axis : int
        The spin's body axis, 0, 1 or 2.
    spin : float
        The spin W, rad s-1.
    """
    w = np.zeros(3)
    w[axis] = spin
    return whip_rigid_state(values, w)[0]


def whip_jacobian(values, axis: int, spin: float, step: float = 1e-30) -> np.ndarray:
    """The Jacobian (7, 7) of the whip antennas' equations at :func:`whip_steady_spin`, by
    complex-step differentiation, ``M_ij = Im f_i(x + i eps e_j) / eps`` (no cancellation:
    exact to round-off at ``eps = 1e-30``).

    Parameters
    ----------
    values : array_like
        The scene's parameter set: ``(I1, I2, I3, J, c)`` for the sphere,
        ``(I1, I2, I3, mu, b, k, c)`` for the whips.
    axis : int
        The spin's body axis, 0, 1 or 2.
    spin : float
        The spin W, rad s-1.
    step : float
        The complex step eps.
    """
    p = whip_params(values)
    x = whip_steady_spin(values, axis, spin).astype(complex)
    out = np.empty((7, 7))
    for j in range(7):
        shifted = x.copy()
        shifted[j] += 1j * step
        out[:, j] = np.imag(whip_rhs(*shifted, p)) / step
    return out


def whip_eigenvalues(values, axis: int, spin: float) -> np.ndarray:
    """The eigenvalues (s-1) of :func:`whip_jacobian` but the 0 of the steady spins' own family
    (the one nearest 0 is set aside), by decreasing real part.

    Parameters
    ----------
    values : array_like
        The scene's parameter set: ``(I1, I2, I3, J, c)`` for the sphere,
        ``(I1, I2, I3, mu, b, k, c)`` for the whips.
    axis : int
        The spin's body axis, 0, 1 or 2.
    spin : float
        The spin W, rad s-1.
    """
    lam = np.linalg.eigvals(whip_jacobian(values, axis, spin))
    lam = np.delete(lam, np.argmin(np.abs(lam)))
    return lam[np.argsort(-lam.real, kind="stable")]


def moving_eigenvalues(eigenvalues, tolerance: float = 1e-9) -> np.ndarray:
    """``eigenvalues`` but those of size at most ``tolerance`` times the largest: the neutral
    directions a symmetric body has (spins about any axis of a plane of equal moments).

    Parameters
    ----------
    eigenvalues : array_like
        Eigenvalues, s-1.
    tolerance : float
        Relative size below which an eigenvalue counts as neutral.
    """
    lam = np.asarray(eigenvalues)
    return lam[np.abs(lam) > tolerance * np.abs(lam).max()]


def growth_rate(eigenvalues) -> float:
    """The nutation's growth rate (s-1): the largest real part of ``eigenvalues``; > 0 unstable,
    < 0 the rate at which a departure dies away.

    Parameters
    ----------
    eigenvalues : array_like
        Eigenvalues, s-1.
    """
    return float(np.max(np.real(eigenvalues)))


def energy_sink_rate(spin_moment, transverse_moment, J, c, spin):
    """Equation (3): the nutation's growth rate (s-1) by the energy-sink estimate, for a spin W
    about the symmetry axis (moments I_s, I_t of the shell) with a spherical damper (J, c).
    Array arguments broadcast.

    Parameters
    ----------
    spin_moment : float
        The shell's moment I_s about the spin axis, kg m2.
    transverse_moment : float
        The shell's moment I_t across it, kg m2.
    J : float
        The sphere's moment of inertia, kg m2.
    c : float or array_like
        The sphere's viscous coefficient, N m s.
    spin : float
        The spin W, rad s-1.
    """
    I_s, I_t = spin_moment, transverse_moment
    W = np.asarray(spin, dtype=float)
    c = np.asarray(c, dtype=float)
    return c * (I_t - I_s) * I_s * W**2 / (I_t * ((W * I_s) ** 2 + (c * I_t / J) ** 2))


def energy_sink_optimum(spin_moment, transverse_moment, J, spin) -> float:
    """The damping ``c* = J W I_s / I_t`` (N m s) that maximises (3).

    Parameters
    ----------
    spin_moment : float
        The shell's moment I_s about the spin axis, kg m2.
    transverse_moment : float
        The shell's moment I_t across it, kg m2.
    J : float
        The sphere's moment of inertia, kg m2.
    spin : float
        The spin W, rad s-1.
    """
    return float(J * spin * spin_moment / transverse_moment)


def optimum_damping(spin_moment, transverse_moment, J, spin) -> float:
    """The damping c (N m s) that makes the minor-axis nutation grow fastest by the linear
    theory (2): the maximum of the growth rate over log c (golden-section search, to 1e-12 in
    log c, over a factor 1000 either side of the energy sink's optimum, where it is
    unimodal).

    Parameters
    ----------
    spin_moment : float
        The shell's moment I_s about the spin axis, kg m2.
    transverse_moment : float
        The shell's moment I_t across it, kg m2.
    J : float
        The sphere's moment of inertia, kg m2.
    spin : float
        The spin W, rad s-1.
    """
    def rate(log_c):
        return growth_rate(axisymmetric_eigenvalues(spin_moment, transverse_moment, J,
                                                    math.exp(log_c), spin))

    return _largest(rate, energy_sink_optimum(spin_moment, transverse_moment, J, spin))


def equivalent_transverse_moment(moments) -> float:
    """The transverse moment I_t (kg m2) of the symmetric body whose rigid nutation about axis 1
    has the frequency of ``moments`` = (I_s, I_b, I_c):
    ``I_s / (1 - sqrt((I_b - I_s) (I_c - I_s) / (I_b I_c)))``, which is I_b when I_b = I_c; what
    the energy-sink estimate (3) takes for a body with unequal transverse moments.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments, the spin axis's first, kg m2.
    """
    I_s, I_b, I_c = (float(v) for v in moments)
    return I_s / (1.0 - math.sqrt((I_b - I_s) * (I_c - I_s) / (I_b * I_c)))


def nutation_growth_rate(moments, J, c, spin) -> float:
    """The growth rate (s-1) of the nutation of a spin ``W`` about body axis 1 of a shell of
    principal ``moments`` (I1, I2, I3; any, not only symmetric) with a spherical damper (J, c):
    the largest real part of the eigenvalues of (1).

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments, the spin axis's first, kg m2.
    J : float
        The sphere's moment of inertia, kg m2.
    c : float or array_like
        The sphere's viscous coefficient, N m s.
    spin : float
        The spin W, rad s-1.
    """
    return growth_rate(sphere_eigenvalues([*np.asarray(moments, dtype=float), J, c], 0, spin))


def best_damping(moments, J, spin) -> float:
    """The damping c (N m s) that turns a spin ``W`` about body axis 1 of a shell of any
    principal ``moments`` over fastest: the maximum of :func:`nutation_growth_rate` over log c
    (:func:`optimum_damping`, in closed form, for a symmetric shell).

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments, the spin axis's first, kg m2.
    J : float
        The sphere's moment of inertia, kg m2.
    spin : float
        The spin W, rad s-1.
    """
    I = np.asarray(moments, dtype=float)
    if I[1] == I[2]:
        return optimum_damping(I[0], I[1], J, spin)

    def rate(log_c):
        return nutation_growth_rate(I, J, math.exp(log_c), spin)

    return _largest(rate, energy_sink_optimum(I[0], equivalent_transverse_moment(I), J, spin))


def flat_spin_time(rate, angle, flat_angle=math.radians(80.0)):
    """The time (s) from a nutation angle ``angle`` (rad) to ``flat_angle`` (rad) at growth rate
    ``rate`` (s-1) by the linear law ``tan(theta) = tan(theta0) exp(rate t)``, which a turning
    body keeps almost to the end. Array arguments broadcast.

    Parameters
    ----------
    rate : float or array_like
        Growth rate of the nutation, s-1.
    angle : float or array_like
        Initial nutation angle, rad.
    flat_angle : float
        The nutation angle that counts as a flat spin, rad.
    """
    return np.log(math.tan(flat_angle) / np.tan(angle)) / np.asarray(rate, dtype=float)


def _largest(rate, guess) -> float:
    """The c > 0 at the largest ``rate(log c)`` (golden-section search, to 1e-12 in log c, over
    a factor 1000 either side of ``guess``, where it is unimodal)."""
    guess = math.log(guess)
    lo, hi = guess - 7.0, guess + 7.0
    inverse_golden = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = hi - inverse_golden * (hi - lo), lo + inverse_golden * (hi - lo)
    fa, fb = rate(a), rate(b)
    while hi - lo > 1e-12:
        if fa < fb:
            lo, a, fa = a, b, fb
            b = lo + inverse_golden * (hi - lo)
            fb = rate(b)
        else:
            hi, b, fb = b, a, fa
            a = hi - inverse_golden * (hi - lo)
            fa = rate(a)
    return float(math.exp(0.5 * (lo + hi)))


def tilted_rotation(moments, spin, angles, azimuths) -> np.ndarray:
    """Angular velocities (N, 3) of a body turning rigidly with spin ``W`` about axis 1 and its
    angular momentum ``H = A w`` tilted by ``angles`` (rad) from that axis, towards
    ``cos(azimuth) e2 + sin(azimuth) e3``: ``w = W (1, A1 tan(theta) cos(phi) / A2,
    A1 tan(theta) sin(phi) / A3)``, ``A`` the system's ``moments``.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments, the spin axis's first, kg m2.
    spin : float
        The spin W, rad s-1.
    angles : array_like, shape (N,)
        Tilts of H from axis 1, rad.
    azimuths : array_like, shape (N,)
        Their azimuths about axis 1, rad.
    """
    A = np.asarray(moments, dtype=float)
    tilt = np.tan(np.asarray(angles, dtype=float))
    phi = np.asarray(azimuths, dtype=float)
    return spin * np.column_stack([np.ones_like(tilt), A[0] * tilt * np.cos(phi) / A[1],
                                   A[0] * tilt * np.sin(phi) / A[2]])


def energy_lost(angular_momentum, start_moment, end_moment):
    """``|H|^2 / 2 (1/A_start - 1/A_end)`` (J): the energy a body sheds going from a steady spin
    about the axis of moment ``A_start`` to one about ``A_end`` at the same |H|.

    Parameters
    ----------
    angular_momentum : float or array_like
        |H|, kg m2 s-1.
    start_moment : float
        Moment of the axis spun about at the start, kg m2.
    end_moment : float
        Moment of the axis spun about at the end, kg m2.
    """
    H = np.asarray(angular_momentum, dtype=float)
    return 0.5 * H * H * (1.0 / start_moment - 1.0 / end_moment)


# --- presets ---------------------------------------------------------------------------------

#: Revolutions per minute to rad s-1.
RPM = 2.0 * math.pi / 60.0
#: 750 revolutions per minute, in rad s-1.
RPM_750 = 750.0 * 2.0 * math.pi / 60.0


@dataclass(frozen=True)
class Cylinder:
    """A spinning satellite modelled as a uniform solid cylinder.

    Parameters
    ----------
    length, diameter : float
        m.
    mass : float
        kg.
    spin : float
        The spin about the long axis at release, rad s-1.
    name : str
        For titles.
    sources : str
        Where the numbers come from, and what is assumed.
    """

    length: float
    diameter: float
    mass: float
    spin: float
    name: str = "cylinder"
    sources: str = ""

    @property
    def moments(self) -> np.ndarray:
        """``(I_s, I_t, I_t)`` (kg m2): ``M r^2 / 2`` about the long axis, ``M (3 r^2 + L^2) / 12``
        across it (r = diameter / 2), in the canonical order for a long cylinder."""
        r = 0.5 * self.diameter
        axial = 0.5 * self.mass * r * r
        transverse = self.mass * (3.0 * r * r + self.length**2) / 12.0
        return np.array([axial, transverse, transverse])


@dataclass(frozen=True)
class Spinner:
    """A spinning body given by its measured principal moments, spun about the first.

    The fields are the constructor's parameters and the instance's attributes.

    Parameters
    ----------
    moments : tuple of float
        ``(I_s, I_b, I_c)`` (kg m2): the spin axis's moment first, which must be the smallest
        (a damper turns a minor-axis spin over); :meth:`about` puts a body's moments so.
    spin : float
        The spin about the first axis at release, rad s-1.
    name : str
        For titles.
    sources : str
        Where the numbers come from.

    Raises
    ------
    ValueError
        A moment not finite or not positive, moments that no real body has (the triangle
        inequality), or a first moment not the smallest.
    """

    moments: tuple
    spin: float
    name: str = "body"
    sources: str = ""

    def __post_init__(self):
        I = tuple(float(v) for v in self.moments)
        if len(I) != 3 or not all(math.isfinite(v) and v > 0.0 for v in I):
            raise ValueError(f"moments must be three finite numbers > 0 (kg m2), got {I}")
        if max(I) > sum(I) - max(I):
            raise ValueError(f"the moments {I} violate the triangle inequality (the largest above "
                             "the sum of the other two), which every real body obeys; check "
                             "the numbers")
        if not I[0] < min(I[1:]):
            raise ValueError(f"the spin axis's moment {I[0]:g} kg m2 must be the smallest, "
                             f"below {I[1]:g} and {I[2]:g} (a damper turns a minor-axis spin "
                             "over); spin the body about its axis of least moment")
        object.__setattr__(self, "moments", I)

    @classmethod
    def about(cls, moments, axis, spin, name="body", sources=""):
        """The body of principal ``moments`` (I1, I2, I3) spun at ``spin`` (rad s-1) about
        ``axis`` (1, 2 or 3, or ``"smallest"``): its moments reordered with that axis first,
        the other two in their order.

        Parameters
        ----------
        moments : sequence of float
            Principal moments I1, I2, I3, kg m2.
        axis : int or str
            The spin axis: 1, 2, 3, or the name of its moment.
        spin : float
            rad s-1.
        name, sources : str
            As the class takes them.
        """
        I = [float(v) for v in moments]
        a = spin_axis(I, axis)
        if a not in (1, 2, 3):
            raise ValueError(f"axis must be 1, 2, 3 or the name of its moment, got {axis!r}")
        return cls((I[a - 1], *(I[k] for k in range(3) if k != a - 1)), spin, name, sources)


#: Explorer 1 (1958) as flown: the instrument section and the spent fourth-stage motor in one
#: cylinder.
EXPLORER_1 = Cylinder(
    length=2.03, diameter=0.152, mass=13.97, spin=RPM_750, name="Explorer 1",
    sources=(
        "length 2.03 m, diameter 0.152 m, mass 13.97 kg and spin 750 rpm about the long axis: "
        "NASA NSSDC Master Catalog, 1958-001A (Wikipedia gives 2.051 m, 80.75 in); the turn "
        "into a flat spin about an end-over-end axis within about one orbit (114.8 min): "
        "Bollay, Spin stability of the Explorer satellite, Stanford Engineering Case Library "
        "ECL 1006 (1967); the explanation by dissipation in the four whip antennas: Bracewell & "
        "Garriott, Nature 182, 760 (1958). Assumed: a uniform solid cylinder (the moments) and "
        "the damper standing for the antennas (its J and c)"
    ),
)
