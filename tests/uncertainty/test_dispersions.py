"""Bad dispersions are one line before any work; truncation keeps the moments physical (the
distributions' maps: tests/uncertainty/test_distributions.py)."""

import math

import numpy as np
import pytest

from stability.free_body.dispersion.measure import nominal
from stability.free_body.dispersion.study import STUDY
from stability.study.config import ConfigError
from stability.uncertainty.designs import unit_design
from stability.uncertainty.dispersions import dispersions

NOMINAL = nominal((1.0, 2.0, 2.5), 10.0, 1e-3)
UNIFORM = {"distribution": "uniform", "relative": 0.05}
BAD = [
    ({"rate": {"distribution": "uniform", "relative": -0.1}}, "relative \\(a spread\\) must be > 0"),
    ({"rate": {"distribution": "normal", "sigma": -1.0}}, "sigma \\(a spread\\) must be > 0"),
    ({"damping": UNIFORM}, "unknown parameter 'damping' to disperse; known: I1"),
    ({"I1": {"distribution": "normal", "relative": 0.01}}, "can give a moment <= 0"),
    ({"rate": {"distribution": "uniform", "lower": 11.0, "upper": 10.0}}, "lower must be < upper"),
    ({"rate": {"distribution": "uniform", "lower": 1.0, "upper": math.inf}}, "must be a finite"),
    ({"rate": {"distribution": "gamma", "sigma": 1.0}}, "distribution must be one of uniform"),
    ({"epsilon": {"distribution": "log-uniform", "lower": -1.0, "upper": 1.0}}, "needs lower > 0"),
    ({"moments": {"distribution": "uniform", "relative": 0.2}}, "break the triangle inequality"),
    ({"axes": {"distribution": "uniform", "lower": 0.0, "upper": 4.0}}, "within \\[-pi, pi\\]"),
]


@pytest.mark.parametrize("spec, message", BAD)
def test_a_bad_dispersion_is_one_line(spec, message):
    with pytest.raises(ValueError, match=message) as info:
        dispersions(spec, NOMINAL)
    assert "\n" not in str(info.value)


def test_a_bad_dispersion_in_a_study_file_names_its_key_before_any_work():
    raw = {"dispersions": {"moments": {"distribution": "normal", "relative": 0.01}}}
    with pytest.raises(ConfigError, match=r"^x.toml: \[dispersions\] .*moment <= 0") as info:
        STUDY.resolve(raw, "x.toml")
    assert "\n" not in str(info.value)
    with pytest.raises(ConfigError, match=r"\[dispersions\] unknown key 'spin'"):
        STUDY.resolve({"dispersions": {"spin": {"distribution": "uniform"}}}, "x.toml")
    with pytest.raises(ConfigError, match=r"\[dispersions\] rate must be a table"):
        STUDY.resolve({"dispersions": {"rate": 0.1}}, "x.toml")


def test_truncation_keeps_every_member_physical_and_is_refused_where_it_leaves_nothing():
    racket = nominal((0.00129072, 0.01443074, 0.01569281), 10.0, 1e-3)
    spec = {"moments": {"distribution": "uniform", "relative": 0.02}}
    with pytest.raises(ValueError, match="truncate = true"):
        dispersions(spec, racket)
    disp = dispersions(spec, racket, truncate=True)
    unit = unit_design("sobol", 1024, 3, 2)
    x = disp.draw(unit)
    assert np.all(x["I3"] <= x["I1"] + x["I2"]) and np.all(x["I3"] >= abs(x["I1"] - x["I2"]))
    free = disp.distributions["I3"].ppf(unit[:, 2])
    assert np.mean(free > x["I1"] + x["I2"]) > 0.2  # untruncated, many would break it
    with pytest.raises(ValueError, match="needs the largest moment I3 dispersed"):
        dispersions({"I1": spec["moments"], "I2": spec["moments"]}, racket, truncate=True)

