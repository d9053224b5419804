"""The dispersed Explorer study end to end, with Sobol' indices and with Morris screening: the
linear estimates against integrated members, what dominates, and its bad dispersions one line
before any work."""

import numpy as np
import pytest
import tomli_w

import stability
from stability.dissipation.dispersion.study import STUDY
from stability.study import run_study
from stability.study.config import ConfigError

from ...helpers import assert_cf_compliant, assert_declared
from .test_measure import SPEC, UNIFORM


def study_file(tmp_path, **sections):
    raw = {"study": "explorer_dispersion", "damper": {"inertia": 1e-3},
           "dispersions": SPEC, "output": {"dir": str(tmp_path / "out"), "formats": ["png"]},
           **sections}
    path = tmp_path / "explorer.toml"
    path.write_text(tomli_w.dumps(raw), encoding="utf-8")
    return path


def test_the_study_integrates_members_and_finds_the_start_dominates_the_flat_spin(tmp_path):
    """Integrated members reach the flat spin within 1.5 % of the linear estimate, their fitted
    rates within 1e-3 of the eigenvalue, and start from the angle drawn; over two decades of
    the start, it dominates the time to the flat spin, J the growth rate, and c (at the energy
    sink's optimum, where the rate is stationary in c) matters least of the damper."""
    summary = run_study(study_file(tmp_path, sensitivity={"base": 64, "resamples": 20},
                                   integration={"members": 3}), progress=False)
    path = tmp_path / "out" / "explorer_dispersion.nc"
    assert_declared(path, "explorer_dispersion")
    assert_cf_compliant(tmp_path / "out" / "explorer_dispersion.nc")
    ds = stability.load(path)
    assert ds.member.size == 64 * 7
    n = ds.run.size
    assert np.all(ds.run_status.values == 0)
    assert np.max(np.abs(ds.run_flat_time.values / ds.flat_time.values[:n] - 1.0)) < 0.015
    assert np.max(np.abs(ds.run_growth_rate.values / ds.growth_rate.values[:n] - 1.0)) < 1e-3
    assert ds.run_start_angle.values == pytest.approx(ds.angle.values[:n], rel=1e-12)
    assert summary.values["dominant"] == "angle"
    assert summary.values["dominant_growth_rate"] == "inertia"
    total = ds.total.sel(output="growth_rate")
    assert float(total.sel(parameter="damping")) < float(total.sel(parameter="inertia")) / 10
    assert (tmp_path / "out" / "indices.png").is_file()
    assert "Sobol' indices of the flat time" in summary.table()


def test_morris_screening_from_the_study_file_ranks_as_the_indices_do(tmp_path):
    """``method = "morris"``: r (d + 1) members, mu* over sd in the Dataset; the start does
    not move the growth rate (mu* ~ 0) and J moves it most."""
    summary = run_study(study_file(tmp_path, sensitivity={"method": "morris",
                                                          "trajectories": 12},
                                   integration={"members": 0}), progress=False)
    path = tmp_path / "out" / "explorer_dispersion.nc"
    assert_declared(path, "explorer_dispersion")
    assert_cf_compliant(tmp_path / "out" / "explorer_dispersion.nc")
    ds = stability.load(path)
    assert ds.member.size == 12 * 6 and "total" not in ds and "run" not in ds.dims
    mu = ds.mu_star.sel(output="growth_rate")
    assert float(mu.sel(parameter="angle")) < 1e-3 * float(mu.max())
    assert summary.values["dominant_growth_rate"] == "inertia"
    assert summary.values["analysis"].startswith("Morris")
    assert "Morris screening (over sd) of the growth rate" in summary.table()


BAD = [
    ({"dispersions": {"damping": {"distribution": "normal", "relative": 0.2}}},
     r"\[dispersions\] damping .*can give a value <= 0 N m s"),
    ({"dispersions": {"length": {"distribution": "uniform", "lower": 0.1, "upper": 2.0}}},
     r"\[dispersions\] length .*sqrt\(3\)/2 times the diameter"),
    ({"dispersions": {"angle": {"distribution": "uniform", "lower": 1.0, "upper": 85.0}}},
     r"\[dispersions\] angle must stay below \[analysis\] flat_angle = 80"),
    ({"dispersions": {"rotor": UNIFORM}}, r"\[dispersions\] unknown key 'rotor'"),
    ({"dispersions": {"mass": UNIFORM}, "sensitivity": {"base": 100}},
     r"\[sensitivity\] base must be a power of 2"),
    ({"dispersions": {"mass": UNIFORM}, "sensitivity": {"method": "morris", "levels": 5}},
     r"\[sensitivity\] levels must be even"),
    ({"dispersions": {"mass": UNIFORM}, "sensitivity": {"method": "sobolev"}},
     r"\[sensitivity\] method"),
    ({"dispersions": {"mass": UNIFORM}, "integration": {"members": 4, "step_angle": 1.5},
      "damper": {"inertia": 1e-6, "damping": 3000.0}},
     r"\[integration\] step_angle makes h times the damper's fastest relaxation rate"),
]


@pytest.mark.parametrize("raw, message", BAD)
def test_a_bad_dispersion_is_one_line_before_any_work(raw, message):
    with pytest.raises(ConfigError, match=message) as info:
        STUDY.resolve(raw, "x.toml")
    assert "\n" not in str(info.value)
