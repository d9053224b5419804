"""Spin states from published periods and moment ratios, and back: the papers' numbers and
modes reproduced, and the closed-form periods against the state's own."""

import numpy as np
import pytest

from stability.asteroid.spin_state import (
    energy_ratio_bounds, spin_state, spin_states, state_of,
)

#: Pravec et al., "The tumbling spin state of (99942) Apophis", Icarus 233, 48 (2014), abstract
#: and section 5: P_phi = 27.38 +- 0.07 h, P_psi = 263 +- 6 h, I1/I3 = 0.61 (+0.11 -0.08),
#: I2/I3 = 0.965 (+0.009 -0.015), SAM with E/E0 = 1.024 +- 0.013 (3 sigma), the strongest
#: light-curve period P1 = (1/P_phi - 1/P_psi)^-1 = 30.56 +- 0.01 h.
APOPHIS = {"moments": (0.61, 0.965, 1.0), "period_psi": 263.0, "period_phi": 27.38}

#: Hudson & Ostro, "Shape and non-principal axis spin state of asteroid 4179 Toutatis",
#: Science 270, 84 (1995), abstract: a long-axis mode with 5.41 d (rotation about the long
#: axis) and 7.35 d (mean precession of the long axis), principal-axis extents 4.60, 2.40 and
#: 1.92 km, its density homogeneous to within the model's uncertainties.
TOUTATIS_AXES = (4.60, 2.40, 1.92)


def ellipsoid_moments(a, b, c):
    return np.array([b * b + c * c, a * a + c * c, a * a + b * b]) / (a * a + b * b)


def test_apophis_is_the_short_axis_mode_of_pravec_2014_with_its_energy():
    """Of the two states the periods fit, the SAM one has the paper's E/E0 to its three
    decimals and the LAM one lies outside the paper's 3-sigma interval."""
    states = spin_states(**APOPHIS)
    assert [s.mode for s in states] == ["SAM", "LAM"]
    sam, lam = states
    assert round(sam.energy_ratio, 3) == 1.024
    assert abs(lam.energy_ratio - 1.024) > 0.013
    assert 1.0 < sam.energy_ratio < energy_ratio_bounds(APOPHIS["moments"])[1]
    # the long axis turns about L with P1 = (1/P_phi - 1/P_psi)^-1 = 30.56 h
    f_phi, f_psi = sam.frequencies
    assert round(1.0 / (f_phi - f_psi), 2) == 30.56


def test_apophis_sam_state_is_what_the_mode_argument_returns():
    sam = spin_state(mode="sam", **APOPHIS)
    assert sam.mode == "SAM"
    assert sam.period_psi == pytest.approx(263.0, rel=1e-14)
    assert sam.period_phi == pytest.approx(27.38, rel=1e-13)


def test_toutatis_is_a_long_axis_mode_as_in_hudson_ostro_1995():
    """A homogeneous ellipsoid of Toutatis' extents, with its two periods, fits only LAM."""
    states = spin_states(ellipsoid_moments(*TOUTATIS_AXES), 5.41, 7.35)
    assert [s.mode for s in states] == ["LAM"]
    lo, boundary, hi = energy_ratio_bounds(ellipsoid_moments(*TOUTATIS_AXES))
    assert boundary < states[0].energy_ratio < hi


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
