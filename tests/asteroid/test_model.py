"""The tumbler's physics (stability.asteroid.model): spin states from published periods and moment
ratios, and back (the papers' numbers and modes reproduced, and the closed-form periods against
the state's own); the mass properties of shape meshes against exact moments, bad shape models
refused in one line (with the ``shapes`` extra)."""

import math

import numpy as np
import pytest

import stability
from stability.asteroid.lightcurve import ellipsoid_mesh, main_frequencies
from stability.asteroid.measure import lightcurve_peaks
from stability.asteroid.model import (
    damping_coefficient, energy_ratio_bounds, mass_properties, spin_state, spin_states, state_of,
    wobble_rate,
)

#: Pravec et al., "The tumbling spin state of (99942) Apophis", Icarus 233, 48 (2014). Abstract
#: (https://doczz.net/doc/4111739/the-tumbling-spin-state-of--99942--apophis): "a moderately
#: excited Short Axis Mode (SAM) state with ... E/E0 = 1.024 +- 0.013. (All quoted uncertainties
#: correspond to 3 sigma.)". Periods as cited from it (Wikipedia infobox; Durech et al., EPSC
#: 2024-257): P_phi = 27.38 +- 0.07 h (precession), P_psi = 263 +- 6 h (rotation), 30.56 +- 0.01 h
#: the "period of harmonic with strongest lightcurve amplitude" (P1 = (1/P_phi - 1/P_psi)^-1,
#: seen as P1/2). I1/I3 = 0.61, I2/I3 = 0.965: the paper's Table 2 as quoted in third-party
#: code (github.com/dusanmarceta/Tempestovsky); not seen in the paper's own text.
APOPHIS = {"moments": (0.61, 0.965, 1.0), "period_psi": 263.0, "period_phi": 27.38}
APOPHIS_E = (1.024, 0.013)  # E/E0 and its 3-sigma half-width
APOPHIS_P1 = (30.56, 0.01)  # h

#: Lee et al., "Refinement of the convex shape model and tumbling spin state of (99942) Apophis
#: using the 2020-2021 apparition data", A&A 661, L3 (2022), abstract (arXiv:2204.02540): "a
#: short axis mode with rotation and precession periods of 264.178 hours and 27.38547 hours",
#: "I_a:I_b:I_c = 0.64:0.97:1".
APOPHIS_LEE = {"moments": (0.64, 0.97, 1.0), "period_psi": 264.178, "period_phi": 27.38547}

#: Hudson & Ostro, "Shape and non-principal axis spin state of asteroid 4179 Toutatis",
#: Science 270, 84 (1995), abstract (https://science.sciencemag.org/content/270/5233/84): "a
#: long-axis mode characterized by periods of 5.41 days (rotation about the long axis) and 7.35
#: days (average for long-axis precession)", principal-axis extents 1.92, 2.40 and 4.60 km, the
#: density homogeneous to within the model's uncertainties. Its moment ratios are not in the
#: abstract: the tests use the uniform ellipsoid of those extents.
TOUTATIS_AXES = (4.60, 2.40, 1.92)
TOUTATIS = {"period_psi": 5.41, "period_phi": 7.35}  # days

#: Mueller, Belton & Samarasinha, DPS 2000, abstract 8.08 (BAAS 32; aas.org/archives/BAAS/v32n3/
#: dps2000/247.htm): Toutatis' light curve (Spencer et al. 1995) has lines at 0.135 +- 0.008 and
#: 0.271 +- 0.008 /day (long-axis precession) and 0.643 +- 0.008 /day (its combination with the
#: rotation, LAM), which "compares well with the values of 7.35 dy and 5.41 dy" of the radar.
TOUTATIS_LINES = (0.135, 0.271, 0.643)  # per day, each +- 0.008

#: Belton et al., "The excited spin state of 1I/2017 U1 'Oumuamua", ApJL 856, L21 (2018),
#: doi:10.3847/2041-8213/aab370, abstract: light-curve frequencies 2.77 +- 0.11 (double minimum)
#: and 6.42 +- 0.18 cycles/day; "the long axis precesses around the total angular momentum
#: vector with an average period of (8.67 +- 0.34) hr. For the three LAMs we have found, the
#: possible rotation periods around the long axis are 6.58, 13.15, or 54.48 hr, with 54.48 hr
#: being the most likely." No moment ratios in the abstract.
OUMUAMUA_P_PHI = 8.67  # h
OUMUAMUA_LAM_P_PSI = (6.58, 13.15, 54.48)  # h


def ellipsoid_moments(a, b, c):
    return np.array([b * b + c * c, a * a + c * c, a * a + b * b]) / (a * a + b * b)


def within(value, centre, half_width):
    return abs(value - centre) <= half_width


def p1_hours(state):
    """The period 2 / f of each of the state's strongest light-curve lines (SAM: P1)."""
    return 2.0 / main_frequencies(state)


def test_apophis_is_the_short_axis_mode_of_pravec_2014_with_its_energy():
    """Pravec et al. 2014: of the two states the periods fit, the SAM one has the paper's
    E/E0 = 1.024 to its three decimals and the strongest light-curve line at P1 = 30.56 h to
    its two; the LAM one lies outside the 3-sigma interval of E/E0 and has no line at P1."""
    states = spin_states(**APOPHIS)
    assert [s.mode for s in states] == ["SAM", "LAM"]
    sam, lam = states
    assert round(sam.energy_ratio, 3) == APOPHIS_E[0]
    assert not within(lam.energy_ratio, *APOPHIS_E)
    assert 1.0 < sam.energy_ratio < energy_ratio_bounds(APOPHIS["moments"])[1]
    f_phi, f_psi = sam.frequencies  # the long axis turns about L at f_phi - f_psi
    assert round(1.0 / (f_phi - f_psi), 2) == APOPHIS_P1[0]
    assert [round(p, 2) for p in p1_hours(sam)] == [APOPHIS_P1[0]]
    assert not any(within(p, *APOPHIS_P1) for p in p1_hours(lam))


@pytest.mark.parametrize("period_psi", [263.0 - 6.0, 263.0 + 6.0])
@pytest.mark.parametrize("period_phi", [27.38 - 0.07, 27.38 + 0.07])
def test_apophis_energy_stays_in_its_interval_over_the_periods_ranges(period_psi, period_phi):
    """Pravec et al. 2014: at the nominal moment ratios, every corner of the periods' 3-sigma
    ranges (263 +- 6 h, 27.38 +- 0.07 h) gives a SAM with E/E0 in 1.024 +- 0.013."""
    sam = spin_state(APOPHIS["moments"], period_psi, period_phi, "SAM")
    assert within(sam.energy_ratio, *APOPHIS_E)


def test_apophis_sam_state_is_what_the_mode_argument_returns():
    sam = spin_state(mode="sam", **APOPHIS)
    assert sam.mode == "SAM"
    assert sam.period_psi == pytest.approx(263.0, rel=1e-14)
    assert sam.period_phi == pytest.approx(27.38, rel=1e-13)


def test_apophis_state_of_lee_2022_is_the_sam_pravec_2014_saw():
    """Lee et al. 2022 (2020-21 data, their own moment ratios): their periods fit a SAM and a
    LAM; only the SAM, the mode they give, has its strongest line at Pravec et al.'s P1
    (30.56 +- 0.01 h) and E/E0 in Pravec et al.'s 1.024 +- 0.013. The free body keeps both
    between the apparitions."""
    sam, lam = spin_states(**APOPHIS_LEE)
    assert (sam.mode, lam.mode) == ("SAM", "LAM")
    assert [within(p, *APOPHIS_P1) for p in p1_hours(sam)] == [True]
    assert not any(within(p, *APOPHIS_P1) for p in p1_hours(lam))
    assert within(sam.energy_ratio, *APOPHIS_E)
    assert not within(lam.energy_ratio, *APOPHIS_E)


def test_toutatis_is_a_long_axis_mode_as_in_hudson_ostro_1995():
    """A homogeneous ellipsoid of Toutatis' extents, with its two periods, fits only LAM."""
    states = spin_states(ellipsoid_moments(*TOUTATIS_AXES), **TOUTATIS)
    assert [s.mode for s in states] == ["LAM"]
    lo, boundary, hi = energy_ratio_bounds(ellipsoid_moments(*TOUTATIS_AXES))
    assert boundary < states[0].energy_ratio < hi


@pytest.mark.parametrize("period_psi, period_phi", [(5.38, 7.40), (5.38, 7.41)])
def test_toutatis_later_periods_fit_the_long_axis_mode_too(period_psi, period_phi):
    """Zhao, Hu & Ji, IAU Symp. 318, 156 (2016), abstract (arXiv:1511.04357): 5.38 +- 0.03 d
    about the long axis and 7.40 +- 0.03 d precession of it; Mueller et al. 2000: 5.38 and
    7.41 d for an assumed LAM. With the same ellipsoid both fit one state, a LAM."""
    states = spin_states(ellipsoid_moments(*TOUTATIS_AXES), period_psi, period_phi)
    assert [s.mode for s in states] == ["LAM"]


def test_toutatis_long_axis_mode_has_the_light_curve_lines_mueller_2000_found():
    """Mueller, Belton & Samarasinha 2000 found Toutatis' lines at 0.135, 0.271 and 0.643
    /day (+- 0.008). The LAM state of Hudson & Ostro's periods puts its two main lines,
    2 f_phi and 2 (f_phi + f_psi), on the last two, and the three strongest lines of its
    synthetic light curve (uniform ellipsoid, exact attitude) on all three."""
    lam = spin_state(ellipsoid_moments(*TOUTATIS_AXES), mode="LAM", **TOUTATIS)
    theory = main_frequencies(lam)
    assert within(theory[0], TOUTATIS_LINES[1], 0.008)
    assert within(theory[1], TOUTATIS_LINES[2], 0.008)
    assert within(lam.frequencies[0], TOUTATIS_LINES[0], 0.008)
    peaks, _ = lightcurve_peaks(lam, (1.0, 0.0, 0.3), (1.0, 0.2, 0.3), samples=4096, count=3)
    assert np.all(np.abs(np.sort(peaks) - TOUTATIS_LINES) <= 0.008)


def test_oumuamua_lam_whose_main_lines_are_belton_2018s_is_its_most_likely_one():
    """Belton et al. 2018: three LAMs with P_phi = 8.67 h, P_psi = 6.58, 13.15 or 54.48 h. Each
    puts 2 f_phi on the double minimum at 2.77 +- 0.11 c/d; only 54.48 h, the paper's most
    likely, puts 2 (f_phi + f_psi) on 6.42 +- 0.18 c/d. The lines depend on the periods and the
    mode alone; the body (a uniform 6 : 1.2 : 1 cigar) only has to admit the three LAMs."""
    moments = ellipsoid_moments(6.0, 1.2, 1.0)
    hits = []
    for p_psi in OUMUAMUA_LAM_P_PSI:
        lam = spin_state(moments, p_psi, OUMUAMUA_P_PHI, "LAM")
        per_day = 24.0 * main_frequencies(lam)
        assert within(per_day[0] / 2.0, 2.77, 0.11)
        hits.append(within(per_day[1], 6.42, 0.18))
    assert hits == [False, False, True]


@pytest.mark.parametrize("w", [(0.3, 0.2, 1.0), (1.0, 0.4, 0.2), (0.8, -0.3, 0.5)])
def test_state_to_periods_to_state_round_trips(w):
    I = np.array([1.0, 2.0, 2.6])
    s = state_of(I, w)
    back = spin_states(I, s.period_psi, s.period_phi, s.mode)
    match = min(back, key=lambda b: abs(b.energy_ratio - s.energy_ratio))
    assert match.energy_ratio == pytest.approx(s.energy_ratio, rel=1e-11)
    assert match.momentum == pytest.approx(s.momentum, rel=1e-11)
    again = state_of(I, match.w0)
    assert again.period_phi == pytest.approx(s.period_phi, rel=1e-11)
    assert again.mode == s.mode


def test_energy_and_momentum_of_the_state_are_those_of_its_angular_velocity():
    s = spin_state(mode="LAM", **APOPHIS)
    I = s.moments
    L = np.linalg.norm(I * s.w0)
    assert L == pytest.approx(s.momentum, rel=1e-14)
    assert np.dot(I * s.w0, s.w0) * I[2] / L**2 == pytest.approx(s.energy_ratio, rel=1e-13)


# --- The shape model -------------------------------------------------------------------------


@pytest.fixture
def trimesh():
    """trimesh (the ``shapes`` extra), which reads and integrates the meshes; the shape's tests
    are skipped without it."""
    return pytest.importorskip("trimesh")


#: An L-shaped (non-convex) outline in the x-y plane, counter-clockwise, and its split into
#: two rectangles (x0, x1, y0, y1) for the exact moments.
L_OUTLINE = [(0, 0), (3, 0), (3, 1), (1, 1), (1, 2.5), (0, 2.5)]
L_PARTS = [(0, 3, 0, 1), (0, 1, 1, 2.5)]
L_CAP = [(0, 1, 2), (0, 2, 3), (0, 3, 4), (0, 4, 5)]  # a fan inside the L


def prism(outline, cap, height):
    """Closed mesh of a prism over a polygon, z in [0, height], outward facets."""
    n = len(outline)
    v = np.array([(x, y, 0.0) for x, y in outline] + [(x, y, height) for x, y in outline])
    faces = [(a, c, b) for a, b, c in cap] + [(a + n, b + n, c + n) for a, b, c in cap]
    for i in range(n):
        j = (i + 1) % n
        faces += [(i, j, j + n), (i, j + n, i + n)]
    return v, np.array(faces)


def box_tensor(x0, x1, y0, y1, z0, z1, rho):
    """Inertia tensor of a box about the origin, and its mass and centroid."""
    m = rho * (x1 - x0) * (y1 - y0) * (z1 - z0)
    c = np.array([x0 + x1, y0 + y1, z0 + z1]) / 2
    d = np.array([x1 - x0, y1 - y0, z1 - z0])
    J = m / 12 * np.diag([d[1]**2 + d[2]**2, d[0]**2 + d[2]**2, d[0]**2 + d[1]**2])
    return J + m * (c @ c * np.eye(3) - np.outer(c, c)), m, c


def test_cube_moments_are_exact(trimesh):
    box = trimesh.creation.box(extents=(2.0, 2.0, 2.0))
    p = mass_properties((box.vertices, box.faces), density=3.0)
    exact = 3.0 * 8.0 * (4.0 + 4.0) / 12.0
    assert p.mass == pytest.approx(24.0, rel=1e-14)
    assert np.abs(p.moments / exact - 1.0).max() < 1e-12


def test_l_shaped_solid_matches_its_two_boxes_to_round_off(trimesh):
    h, rho = 0.7, 2.5
    p = mass_properties(prism(L_OUTLINE, L_CAP, h), density=rho)
    parts = [box_tensor(x0, x1, y0, y1, 0.0, h, rho) for x0, x1, y0, y1 in L_PARTS]
    mass = sum(m for _, m, _ in parts)
    com = sum(m * c for _, m, c in parts) / mass
    J = sum(j for j, _, _ in parts) - mass * (com @ com * np.eye(3) - np.outer(com, com))
    assert abs(p.mass / mass - 1.0) < 1e-12
    assert np.abs(p.center_of_mass - com).max() < 1e-12
    assert np.abs(p.inertia - J).max() < 1e-12 * np.abs(J).max()
    exact = np.linalg.eigvalsh(J)
    assert np.abs(p.moments / exact - 1.0).max() < 1e-12
    assert np.allclose(p.axes @ np.diag(p.moments) @ p.axes.T, p.inertia, atol=1e-12)
    assert p.body().moments.tolist() == p.moments.tolist()


@pytest.mark.parametrize("rings", [32, 64])
def test_meshed_ellipsoid_matches_its_moments_to_the_mesh_resolution(trimesh, rings):
    """The mesh is the affine image of a latitude-longitude sphere mesh whose cells span
    delta = pi / rings: its facets lie within cos(delta / sqrt 2) of the centre, so the solid
    holds the ellipsoid scaled by lambda = cos(delta / sqrt 2) and lies inside it, and each
    moment is within 1 - lambda^5 of the exact one (below); it falls as rings^-2."""
    a, b, c = 3.0, 2.0, 1.0
    exact = 4 / 3 * math.pi * a * b * c / 5 * np.array([b*b + c*c, a*a + c*c, a*a + b*b])
    tol = 1.0 - math.cos(math.pi / rings / math.sqrt(2.0)) ** 5
    p = mass_properties(ellipsoid_mesh(a, b, c, rings))
    err = np.abs(p.moments / np.sort(exact) - 1.0)
    assert np.all(p.moments < np.sort(exact)) and err.max() < tol
    coarse = mass_properties(ellipsoid_mesh(a, b, c, rings // 2))
    ratio = np.abs(coarse.moments / np.sort(exact) - 1.0) / err
    assert np.all(np.abs(ratio - 4.0) < 0.1)  # second order in the resolution
    assert np.allclose(np.abs(p.axes), np.eye(3), atol=1e-12)


def test_stl_and_obj_files_read_as_the_same_solid(trimesh, tmp_path):
    v, f = prism(L_OUTLINE, L_CAP, 1.0)
    mesh = trimesh.Trimesh(v, f)
    arrays = mass_properties((v, f))
    for kind in ("stl", "obj"):
        mesh.export(tmp_path / f"l.{kind}")
        p = mass_properties(tmp_path / f"l.{kind}")
        assert p.volume == pytest.approx(3.0 * 1.0 + 1.0 * 1.5, rel=1e-6)  # float32 in STL
        assert np.allclose(p.moments, arrays.moments, rtol=1e-6)


def one_line(call):
    with pytest.raises(ValueError) as info:
        call()
    message = str(info.value)
    assert "\n" not in message, message
    return message


def test_bad_shape_models_are_refused_in_one_line(trimesh, tmp_path):
    v, f = prism(L_OUTLINE, L_CAP, 1.0)
    assert "not watertight" in one_line(lambda: mass_properties((v, f[:-1])))
    assert "facets face inwards" in one_line(lambda: mass_properties((v, f[:, ::-1])))
    assert "no such file" in one_line(lambda: mass_properties(tmp_path / "none.stl"))
    (tmp_path / "x.pkl").write_bytes(b"\x80\x04")
    assert "must be one of obj, stl" in one_line(lambda: mass_properties(tmp_path / "x.pkl"))
    (tmp_path / "bad.stl").write_bytes(b"\x00" * 40)
    assert "bad.stl" in one_line(lambda: mass_properties(tmp_path / "bad.stl"))


def test_the_damping_coefficient_gives_the_damping_time_it_was_made_from():
    """alpha from a damping time tau, then the major axis's wobble rate from alpha: -1 / tau
    to 1e-15; at alpha = 0 every rate is the free body's (0 about the stable axes,
    sqrt(-Omega^2) about the intermediate one)."""
    moments, length = (0.61, 0.965, 1.0), 3.0
    for tau in (1e3, 4.2e7, 3.1e16):
        alpha = damping_coefficient(moments, length, tau)
        assert wobble_rate(moments, 2, length, alpha) == pytest.approx(-1.0 / tau, rel=1e-15)
    free = float(stability.growth_rate(stability.RigidBody(*moments, physical=False), 2,
                                       length / moments[1]))
    assert wobble_rate(moments, 1, length, 0.0) == pytest.approx(free, rel=1e-14)
    assert wobble_rate(moments, 0, length, 0.0) == wobble_rate(moments, 2, length, 0.0) == 0.0

