"""The dispersed Explorer's members: its linear growth rate against the closed form of the
axisymmetric body, and its time to the flat spin at that rate."""

import math

import numpy as np
import pytest

from stability.dissipation.dispersion import measure as M
from stability.dissipation.model import axisymmetric_eigenvalues
from stability.uncertainty.designs import unit_design
from stability.uncertainty.dispersions import dispersions

UNIFORM = {"distribution": "uniform", "relative": 0.2}
SPEC = {"length": {"distribution": "uniform", "relative": 0.02}, "inertia": UNIFORM,
        "damping": UNIFORM, "spin": {"distribution": "uniform", "relative": 0.05},
        "angle": {"distribution": "log-uniform", "lower": 0.01, "upper": 1.0}}
#: The quick study's nominal body: Explorer 1 with a sphere 10 times heavier than its study's.
NOMINAL = M.nominal(2.03, 0.152, 13.97, 750.0, 1e-3, 1.0, 0.1)


def test_the_linear_growth_rate_is_the_axisymmetric_closed_form():
    """The leading eigenvalue of the Jacobian about the long axis (each member's cylinder,
    damper and spin |H| / A_s) equals the roots of the axisymmetric body's quadratic."""
    disp = dispersions(SPEC, NOMINAL)
    draws = M.members(disp, unit_design("random", 40, len(disp.columns()), 3))
    got = M.linear(draws, math.radians(80.0))
    for k in range(40):
        I_s, I_t, _, J, c = draws["values"][k]
        spin = draws["W"][k] / math.cos(draws["theta0"][k])  # |H| / A_s of the tilted start
        want = axisymmetric_eigenvalues(I_s, I_t, J, c, spin)[0].real
        assert got["growth_rate"][k] == pytest.approx(want, rel=1e-9)
    assert np.all(got["growth_rate"] > 0.0)  # a minor-axis spin with a damper always turns
    flat = np.log(math.tan(math.radians(80.0)) / np.tan(draws["theta0"])) / got["growth_rate"]
    assert np.array_equal(got["flat_time"], flat)
