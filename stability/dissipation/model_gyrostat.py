"""The gyrostat (a dual-spin body) in closed form: its steady spins, their linear theory, and
the energy-sink criterion of Iorillo and Likins.

**The body** (scene ``gyrostat``, :mod:`stability.dissipation.scene`). A platform carries an
axisymmetric rotor (axial moment ``Jr``) on a frictionless bearing along its principal axis e3.
``A = diag(A1, A2, A3)`` are the whole body's principal moments with the rotor turning with the
platform (so ``A3 - Jr`` is the platform's own axial moment and A1, A2 hold the rotor's
transverse moment); the rotor spins at ``Omega`` relative to the platform. With the platform's
angular velocity w the angular momentum of platform and rotor, in the platform's frame, is::

    m = A w + Jr Omega e3,          the rotor's axial part  h_r = Jr (w3 + Omega).      (1)

A viscous spherical damper sits on the platform (a sphere of moment ``Jp`` in a fluid, torque
``cp u_p`` on the platform, ``u_p = w_p - w`` with ``w_p = p / Jp`` the sphere's rate) and one in
the rotor (``Jq``, ``cq``; ``u_q = q / Jq - w_r`` against the rotor's rate ``w_r = w + Omega
e3``). Each body's momentum changes by the torques on it: in the platform's frame (rotating at
w) Euler's equations of the gyrostat (Hughes, *Spacecraft Attitude Dynamics* (1986), ch. 7;
Likins, J. Spacecraft Rockets 4(12), 1638 (1967)) and the spheres' read::

    m' = m x w + cp u_p + cq u_q,    p' = p x w - cp u_p,    q' = q x w - cq u_q,
    h_r' = cq u_q3,                                                                    (2)

``h_r'`` because the rotor is axisymmetric and its bearing transmits no axial torque (a free
rotor: ``d(H_rotor . e3)/dt`` is the axial torque on it). The total ``H = m + p + q`` obeys
``H' = H x w``: constant in space, |H| kept. The energy ``E = (m1^2/A1 + m2^2/A2 + (m3 -
h_r)^2/(A3 - Jr) + h_r^2/Jr + |p|^2/Jp + |q|^2/Jq) / 2`` falls at ``cp |u_p|^2 + cq |u_q|^2``
(no motor holds the rotor's speed, so no work is done on the body).

**Steady spins.** With the bearing free, every spin of the platform at ``w_p`` about e3 with the
rotor at ``Omega`` relative to it and each sphere turning with its body is steady
(:func:`steady_spin`). The axial momentum of platform and rotor is ``h = A3 w_p + Jr Omega``,
and each body sees the nutation at its own frequency (the transverse rate, seen from that body,
turns at it)::

    lambda_p = h / A_t - w_p,    lambda_r = h / A_t - w_r = lambda_p - Omega,          (3)

``w_r = w_p + Omega`` the rotor's rate; ``h / A_t`` is the nutation's frequency in space.

**Linear theory.** About a steady spin the components along e3 decouple (the sizes of the spins,
and the spheres' axial relaxations) from those across it. For an axisymmetric platform
(``A1 = A2 = A_t``) write ``xi = dw1 + i dw2`` and ``eta_p``, ``eta_q`` the same for the spheres'
rates; (2) linearises to::

    xi'    = i lambda_p xi + (cp / A_t) (eta_p - xi) + (cq / A_t) (eta_q - xi),
    eta_p' = -i w_p eta_p + i w_p xi - (cp / Jp) (eta_p - xi),
    eta_q' = -i w_p eta_q + i w_r xi - (cq / Jq) (eta_q - xi),                        (4)

whose three eigenvalues and their conjugates are those of the Jacobian's transverse block
(:func:`axisymmetric_matrix`, :func:`axisymmetric_eigenvalues`; a damper with ``c = 0`` drops
out). With one damper, on body D (the platform or the rotor, ``w_D`` its rate), (4) is 2 x 2
and its eigenvalues are the roots of the quadratic (:func:`one_damper_eigenvalues`)::

    l^2 - (a + e) l + a e - b d = 0,   a = i lambda_p - c / A_t,   b = c / A_t,
                                       d = i w_D + c / J,   e = -i w_p - c / J.          (5)

At c = 0 the nutation root is ``i lambda_p``; its derivative in c gives::

    l = i lambda_p - c lambda_D / h + O(c^2),                                          (6)

so the nutation grows where the damper's body sees it turn backwards (``lambda_D < 0``) and
decays where forwards. On ``lambda_D = 0`` a mode with the sphere turning with its body
(``u = 0``, undamped, ``eta = xi``, frequency ``w_D - w_p``) solves (4) for every c: the growth
rate of one damper changes sign exactly there, whatever the damping (checked on fine maps in
``tests/dissipation/test_model_gyrostat.py``). A triaxial platform: :func:`eigenvalues` (the
Jacobian by complex-step differentiation, :func:`jacobian`).

**The energy sink** (Iorillo, *Nutation damping dynamics of axisymmetric rotor stabilized
satellites*, ASME Winter Annual Meeting (1965); Likins 1967; Hughes 1986, ch. 8). Treat the
nutation as the rigid gyrostat's (angle theta between e3 and H, the transverse rate ``w_t =
h theta / A_t`` turning at ``lambda_i`` in body i) and each damper as forced by it. The sphere
in body i lags by ``|u_i| = |lambda_i| w_t / sqrt((h / A_t)^2 + (c_i / J_i)^2)`` and dissipates
``D_i = c_i |u_i|^2``; averaged over a nutation period its sphere's axial momentum is steady, so
the axial torque it exerts on its body is ``J_i <u_1 w_2 - u_2 w_1> = D_i / lambda_i``. The sum
of those torques is the rate of ``H . e3 = |H| cos(theta)``, so::

    theta' = -(D_p / lambda_p + D_r / lambda_r) / (|H| sin(theta)):

the nutation decays iff ``D_p / lambda_p + D_r / lambda_r > 0`` (Likins' criterion; with the
free bearing, ``E' = -lambda_p h_p' - lambda_r h_r' = -(D_p + D_r)`` checks it). A damper on a
despun platform (``w_p = 0``, ``lambda_p = h / A_t > 0``) always stabilises; one in the rotor
(``lambda_r = w_r (Jr - A_t) / A_t`` there) destabilises unless the rotor alone is a major-axis
spinner (``Jr > A_t``). With the spheres' dissipation the growth rate is::

    sigma_sink = -h sum_i c_i lambda_i / (h^2 + (c_i A_t / J_i)^2),                    (7)

(:func:`energy_sink_rate`), the root (6) at first order in c; largest per damper at
``c*_i = J_i h / A_t`` (:func:`energy_sink_optimum`).

**Where the energy sink is good, and where it fails.** It drops the dampers' reaction on the
nutation (its frequency and shape), which is of order ``c / c*``: for weak damping,
``c << c*`` (the damper slow to drain energy against the nutation), (7) is the eigenvalue to
O(c^2) (relative differences of 1e-4 at ``c = 0.03 c*``), and with one damper its sign is exact
at any damping (above). It fails (5 to 25 per cent in the rate) when the damping is strong,
``c >~ c*``, and it can get the *sign* wrong near its own boundary when two dampers of different
strength pull against each other (``lambda_p > 0 > lambda_r``): there the two terms of (7)
nearly cancel, and the O(c^2) terms it drops decide. Nor does it hold for a platform far from
axisymmetric (elliptic nutation), for large nutation angles, or where the nutation is not slow
against the dampers' own relaxation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .methods import gyrostat_params, gyrostat_rhs
from .scene import gyrostat_rigid_state

#: Width of the gyrostat's state.
WIDTH = 10
#: State indices across e3: m1, m2, then p1, p2 (platform damper), q1, q2 (rotor damper).
_ACROSS = (0, 1)
_PLATFORM_SPHERE = (4, 5)
_ROTOR_SPHERE = (7, 8)


def steady_spin(values, platform_spin: float, relative_spin: float) -> np.ndarray:
    """The state (10,) of a steady spin: the platform at ``platform_spin`` (rad s-1) about e3,
    the rotor at ``relative_spin`` relative to it, each damper's sphere turning with its body;
    ``values`` = (A1, A2, A3, Jr, Jp, cp, Jq, cq).

    Parameters
    ----------
    values : array_like
        ``(A1, A2, A3, Jr, Jp, cp, Jq, cq)``: the whole body's moments (kg m2), the rotor's axial
        moment, each damper's J (kg m2) and c (N m s).
    platform_spin : float or array_like
        The platform's spin w_p about e3, rad s-1.
    relative_spin : float or array_like
        The rotor's speed relative to the platform, rad s-1.
    """
    return gyrostat_rigid_state(values, [[0.0, 0.0, platform_spin]], relative_spin)[0]


def axial_momentum(values, platform_spin, relative_spin):
    """``h = A3 w_p + Jr Omega`` (kg m2 s-1): the axial momentum of platform and rotor in a
    steady spin (the spheres' not included). Arrays broadcast.

    Parameters
    ----------
    values : array_like
        ``(A1, A2, A3, Jr, Jp, cp, Jq, cq)``: the whole body's moments (kg m2), the rotor's axial
        moment, each damper's J (kg m2) and c (N m s).
    platform_spin : float or array_like
        The platform's spin w_p about e3, rad s-1.
    relative_spin : float or array_like
        The rotor's speed relative to the platform, rad s-1.
    """
    A3, Jr = float(values[2]), float(values[3])
    return A3 * np.asarray(platform_spin, dtype=float) + Jr * np.asarray(relative_spin,
                                                                          dtype=float)


def nutation_frequencies(values, platform_spin, relative_spin):
    """Equation (3): ``(h, lambda_p, lambda_r)``, the axial momentum and the nutation's
    frequencies (rad s-1) seen by the platform and by the rotor, ``A_t = (A1 + A2) / 2``.
    Arrays broadcast.

    Parameters
    ----------
    values : array_like
        ``(A1, A2, A3, Jr, Jp, cp, Jq, cq)``: the whole body's moments (kg m2), the rotor's axial
        moment, each damper's J (kg m2) and c (N m s).
    platform_spin : float or array_like
        The platform's spin w_p about e3, rad s-1.
    relative_spin : float or array_like
        The rotor's speed relative to the platform, rad s-1.
    """
    A_t = 0.5 * (float(values[0]) + float(values[1]))
    h = axial_momentum(values, platform_spin, relative_spin)
    lam_p = h / A_t - np.asarray(platform_spin, dtype=float)
    return h, lam_p, lam_p - np.asarray(relative_spin, dtype=float)


def jacobian(values, platform_spin: float, relative_spin: float,
             step: float = 1e-30) -> np.ndarray:
    """The Jacobian (10, 10) of equations (2) at :func:`steady_spin`, by complex-step
    differentiation, ``M_ij = Im f_i(x + i eps e_j) / eps`` (exact to round-off).

    Parameters
    ----------
    values : array_like
        ``(A1, A2, A3, Jr, Jp, cp, Jq, cq)``: the whole body's moments (kg m2), the rotor's axial
        moment, each damper's J (kg m2) and c (N m s).
    platform_spin : float or array_like
        The platform's spin w_p about e3, rad s-1.
    relative_spin : float or array_like
        The rotor's speed relative to the platform, rad s-1.
    step : float
        The complex step eps.
    """
    p = gyrostat_params(values)
    x = steady_spin(values, platform_spin, relative_spin).astype(complex)
    out = np.empty((WIDTH, WIDTH))
    for j in range(WIDTH):
        shifted = x.copy()
        shifted[j] += 1j * step
        out[:, j] = np.imag(gyrostat_rhs.py_func(*shifted, p)) / step
    return out


def _present(values) -> list:
    """The transverse state indices that move: m1, m2 and the spheres of the dampers with
    c > 0 (a sphere without coupling is carried along, its modes neutral and without effect)."""
    rows = list(_ACROSS)
    if values[5] > 0:
        rows += _PLATFORM_SPHERE
    if values[7] > 0:
        rows += _ROTOR_SPHERE
    return rows


def eigenvalues(values, platform_spin: float, relative_spin: float) -> np.ndarray:
    """The nutation's eigenvalues (s-1): those of the Jacobian's block across e3 (the absent
    dampers' spheres left out), by decreasing real part. Any platform, triaxial too.

    Parameters
    ----------
    values : array_like
        ``(A1, A2, A3, Jr, Jp, cp, Jq, cq)``: the whole body's moments (kg m2), the rotor's axial
        moment, each damper's J (kg m2) and c (N m s).
    platform_spin : float or array_like
        The platform's spin w_p about e3, rad s-1.
    relative_spin : float or array_like
        The rotor's speed relative to the platform, rad s-1.
    """
    rows = _present(np.asarray(values, dtype=float))
    lam = np.linalg.eigvals(jacobian(values, platform_spin, relative_spin)[np.ix_(rows, rows)])
    return lam[np.argsort(-lam.real, kind="stable")]


def axisymmetric_matrix(values, platform_spin: float, relative_spin: float) -> np.ndarray:
    """The complex matrix of (4) on ``(xi, eta_p, eta_q)``, without the rows and columns of an
    absent damper (c = 0); ``A_t = A1`` (the platform must be axisymmetric, ``A1 = A2``).

    Parameters
    ----------
    values : array_like
        ``(A1, A2, A3, Jr, Jp, cp, Jq, cq)``: the whole body's moments (kg m2), the rotor's axial
        moment, each damper's J (kg m2) and c (N m s).
    platform_spin : float or array_like
        The platform's spin w_p about e3, rad s-1.
    relative_spin : float or array_like
        The rotor's speed relative to the platform, rad s-1.
    """
    A_t, _, _, _, Jp, cp, Jq, cq = (float(v) for v in values)
    w_p = float(platform_spin)
    w_r = w_p + float(relative_spin)
    _, lam_p, _ = nutation_frequencies(values, w_p, relative_spin)
    M = np.array([[1j * lam_p - (cp + cq) / A_t, cp / A_t, cq / A_t],
                  [1j * w_p + cp / Jp, -1j * w_p - cp / Jp, 0.0],
                  [1j * w_r + cq / Jq, 0.0, -1j * w_p - cq / Jq]])
    keep = [0] + [1] * (cp > 0) + [2] * (cq > 0)
    return M[np.ix_(keep, keep)]


def axisymmetric_eigenvalues(values, platform_spin: float, relative_spin: float) -> np.ndarray:
    """The eigenvalues of (4) and their conjugates (s-1), by decreasing real part: those of the
    Jacobian's transverse block for an axisymmetric platform.

    Parameters
    ----------
    values : array_like
        ``(A1, A2, A3, Jr, Jp, cp, Jq, cq)``: the whole body's moments (kg m2), the rotor's axial
        moment, each damper's J (kg m2) and c (N m s).
    platform_spin : float or array_like
        The platform's spin w_p about e3, rad s-1.
    relative_spin : float or array_like
        The rotor's speed relative to the platform, rad s-1.
    """
    lam = np.linalg.eigvals(axisymmetric_matrix(values, platform_spin, relative_spin))
    lam = np.concatenate([lam, lam.conj()])
    return lam[np.argsort(-lam.real, kind="stable")]


def one_damper_eigenvalues(transverse_moment, axial_moment, rotor_moment, J, c, platform_spin,
                           relative_spin, on_rotor: bool) -> np.ndarray:
    """Equation (5): the four nutation eigenvalues (s-1) of an axisymmetric gyrostat with one
    spherical damper (J, c) on the platform or (``on_rotor``) in the rotor, in closed form:
    the roots of the quadratic and their conjugates, by decreasing real part.

    Parameters
    ----------
    transverse_moment : float
        The transverse moment A_t, kg m2.
    axial_moment : float
        The axial moment A3 (rotor included), kg m2.
    rotor_moment : float
        The rotor's axial moment Jr, kg m2.
    J : float or array_like
        The sphere's moment of inertia, kg m2.
    c : float
        The sphere's viscous coefficient, N m s.
    platform_spin : float or array_like
        The platform's spin w_p about e3, rad s-1.
    relative_spin : float or array_like
        The rotor's speed relative to the platform, rad s-1.
    on_rotor : bool
        The damper is in the rotor (else on the platform).
    """
    A_t, A3, Jr = float(transverse_moment), float(axial_moment), float(rotor_moment)
    w_p, omega = float(platform_spin), float(relative_spin)
    lam_p = (A3 * w_p + Jr * omega) / A_t - w_p
    w_d = w_p + omega if on_rotor else w_p
    a, b = 1j * lam_p - c / A_t, c / A_t
    d, e = 1j * w_d + c / J, -1j * w_p - c / J
    trace, det = a + e, a * e - b * d
    root = np.sqrt(trace * trace - 4.0 * det)
    lam = np.array([(trace + root) / 2.0, (trace - root) / 2.0])
    lam = np.concatenate([lam, lam.conj()])
    return lam[np.argsort(-lam.real, kind="stable")]


def first_order_rate(values, platform_spin, relative_spin):
    """Equation (6) summed over the dampers: ``-(cp lambda_p + cq lambda_r) / h`` (s-1), the
    growth rate at first order in the damping. Arrays broadcast.

    Parameters
    ----------
    values : array_like
        ``(A1, A2, A3, Jr, Jp, cp, Jq, cq)``: the whole body's moments (kg m2), the rotor's axial
        moment, each damper's J (kg m2) and c (N m s).
    platform_spin : float or array_like
        The platform's spin w_p about e3, rad s-1.
    relative_spin : float or array_like
        The rotor's speed relative to the platform, rad s-1.
    """
    h, lam_p, lam_r = nutation_frequencies(values, platform_spin, relative_spin)
    return -(float(values[5]) * lam_p + float(values[7]) * lam_r) / h


def energy_sink_rate(values, platform_spin, relative_spin):
    """Equation (7): the nutation's growth rate (s-1) by the energy-sink estimate,
    ``-h sum_i c_i lambda_i / (h^2 + (c_i A_t / J_i)^2)``. Arrays broadcast.

    Parameters
    ----------
    values : array_like
        ``(A1, A2, A3, Jr, Jp, cp, Jq, cq)``: the whole body's moments (kg m2), the rotor's axial
        moment, each damper's J (kg m2) and c (N m s).
    platform_spin : float or array_like
        The platform's spin w_p about e3, rad s-1.
    relative_spin : float or array_like
        The rotor's speed relative to the platform, rad s-1.
    """
    A_t = 0.5 * (float(values[0]) + float(values[1]))
    Jp, cp, Jq, cq = (float(v) for v in values[4:8])
    h, lam_p, lam_r = nutation_frequencies(values, platform_spin, relative_spin)
    return -h * (cp * lam_p / (h * h + (cp * A_t / Jp) ** 2)
                 + cq * lam_r / (h * h + (cq * A_t / Jq) ** 2))


def energy_sink_stable(values, platform_spin, relative_spin):
    """Likins' criterion: True where ``D_p / lambda_p + D_r / lambda_r > 0`` (the energy sink
    says the nutation decays). Arrays broadcast.

    Parameters
    ----------
    values : array_like
        ``(A1, A2, A3, Jr, Jp, cp, Jq, cq)``: the whole body's moments (kg m2), the rotor's axial
        moment, each damper's J (kg m2) and c (N m s).
    platform_spin : float or array_like
        The platform's spin w_p about e3, rad s-1.
    relative_spin : float or array_like
        The rotor's speed relative to the platform, rad s-1.
    """
    return np.asarray(energy_sink_rate(values, platform_spin, relative_spin)) < 0.0


def energy_sink_optimum(J, transverse_moment, h):
    """``c* = J h / A_t`` (N m s): the damping of a sphere of moment J that drains the nutation
    fastest by (7). Arrays broadcast.

    Parameters
    ----------
    J : float or array_like
        The sphere's moment of inertia, kg m2.
    transverse_moment : float
        The transverse moment A_t, kg m2.
    h : float or array_like
        The axial momentum h, kg m2 s-1.
    """
    return np.asarray(J, dtype=float) * np.asarray(h, dtype=float) / float(transverse_moment)


def growth_rate(eigenvalues) -> float:
    """The largest real part (s-1) of ``eigenvalues``: > 0 the nutation grows.

    Parameters
    ----------
    eigenvalues : array_like
        Eigenvalues, s-1.
    """
    return float(np.max(np.real(eigenvalues)))


def tilted_spin(values, platform_spin, relative_spin, angles, azimuths) -> np.ndarray:
    """States (N, 10) of the gyrostat turning rigidly (the platform at ``w = (w1, w2, w_p)``,
    the rotor at ``Omega`` relative to it, each damper's sphere with its body) with its angular
    momentum tilted by ``angles`` (rad) from e3 towards ``cos(phi) e1 + sin(phi) e2``:
    ``H = (A1 w1 + S w1, A2 w2 + S w2, h + Jp w_p + Jq w_r)`` (S the spheres' moments that
    turn), ``tan(theta) = |H_t| / H_3``.

    Parameters
    ----------
    values : array_like
        ``(A1, A2, A3, Jr, Jp, cp, Jq, cq)``: the whole body's moments (kg m2), the rotor's axial
        moment, each damper's J (kg m2) and c (N m s).
    platform_spin : float or array_like
        The platform's spin w_p about e3, rad s-1.
    relative_spin : float or array_like
        The rotor's speed relative to the platform, rad s-1.
    angles : array_like, shape (N,)
        Tilts of H from e3, rad.
    azimuths : array_like, shape (N,)
        Their azimuths about e3, rad.
    """
    values = np.asarray(values, dtype=float)
    A1, A2, _, _, Jp, cp, Jq, cq = values
    spheres = (Jp if cp > 0 else 0.0) + (Jq if cq > 0 else 0.0)
    w_p, omega = float(platform_spin), float(relative_spin)
    axial = (axial_momentum(values, w_p, omega) + (Jp if cp > 0 else 0.0) * w_p
             + (Jq if cq > 0 else 0.0) * (w_p + omega))
    across = axial * np.tan(np.asarray(angles, dtype=float))
    phi = np.asarray(azimuths, dtype=float)
    w = np.column_stack([across * np.cos(phi) / (A1 + spheres),
                         across * np.sin(phi) / (A2 + spheres), np.full(across.shape, w_p)])
    return gyrostat_rigid_state(values, w, omega)


# --- The dual-spin map's body -------------------------------------------------------------------

@dataclass(frozen=True)
class DualSpinBody:
    """A gyrostat family for the map: an axisymmetric platform, a rotor, two spherical dampers.

    The fields are the constructor's parameters and the instance's attributes.

    Parameters
    ----------
    transverse_moment : float
        ``A_t``, the whole body's transverse moment (rotor included), kg m2.
    rotor_moment : float
        ``Jr``, the rotor's axial moment, kg m2.
    damper_moment : float
        ``J``, the moment of each damper's sphere, kg m2.
    platform_spin : float
        ``w_p``, the platform's spin about the rotor's axis, rad s-1.
    platform_damping, rotor_damping : float
        Each damper's viscous coefficient over its energy-sink optimum ``c* = J h / A_t``
        (``h = A3 w_p + Jr Omega``, per cell).
    """

    transverse_moment: float
    rotor_moment: float
    damper_moment: float
    platform_spin: float
    platform_damping: float
    rotor_damping: float

    def values(self, placement: str, ratio: float, speed: float) -> np.ndarray:
        """The scene's parameter set ``(A1, A2, A3, Jr, Jp, cp, Jq, cq)`` of a cell: ``A3 =
        ratio A_t``, the dampers of ``placement`` at their multiples of ``c*``, the other's
        ``c = 0``."""
        A_t, J = self.transverse_moment, self.damper_moment
        values = np.array([A_t, A_t, ratio * A_t, self.rotor_moment, J, 0.0, J, 0.0])
        star = float(energy_sink_optimum(J, A_t, axial_momentum(values, self.platform_spin,
                                                                 speed)))
        if placement in ("platform", "both"):
            values[5] = self.platform_damping * star
        if placement in ("rotor", "both"):
            values[7] = self.rotor_damping * star
        return values


def body_of(ds) -> DualSpinBody:
    """The gyrostat family of a dual-spin Dataset, from its attributes.

    Parameters
    ----------
    ds : xarray.Dataset
        The dual-spin study's Dataset.
    """
    a = ds.attrs
    return DualSpinBody(float(a["transverse_moment"]), float(a["rotor_moment"]),
                        float(a["damper_moment"]), float(a["platform_spin"]),
                        float(a["platform_damping"]), float(a["rotor_damping"]))


def linear_map(body, placement, ratios, speeds):
    """``(linear, sink)`` (R, S): the growth rate (s-1) by the eigenvalues and by the energy
    sink at every inertia ratio and relative speed, the dampers of ``placement``.

    Parameters
    ----------
    body : DualSpinBody
        The gyrostat family.
    placement : str
        Where the dampers sit, one of PLACEMENTS.
    ratios : array_like
        Inertia ratios A3 / A_t.
    speeds : array_like
        Relative speeds of the rotor, rad s-1.
    """
    ratios, speeds = np.asarray(ratios, dtype=float), np.asarray(speeds, dtype=float)
    linear, sink = np.empty((ratios.size, speeds.size)), np.empty((ratios.size, speeds.size))
    for i, ratio in enumerate(ratios):
        for j, speed in enumerate(speeds):
            values = body.values(placement, ratio, speed)
            linear[i, j] = axisymmetric_eigenvalues(values, body.platform_spin, speed)[0].real
            sink[i, j] = energy_sink_rate(values, body.platform_spin, speed)
    return linear, sink
