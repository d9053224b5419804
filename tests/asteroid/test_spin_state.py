"""Spin states from published periods and moment ratios, and back: the papers' numbers and
modes reproduced, and the closed-form periods against the state's own."""

import numpy as np
import pytest

from stability.asteroid.lightcurve import main_frequencies
from stability.asteroid.measure import lightcurve_peaks
from stability.asteroid.spin_state import (
    energy_ratio_bounds, spin_state, spin_states, state_of,
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
