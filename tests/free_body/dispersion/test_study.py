"""The free body's dispersion study (stability.free_body.dispersion.study): Morris screening from
its file, its Dataset and what dominates."""

import numpy as np
import tomli_w

import stability
from stability.study import run_study

from ...helpers import assert_cf_compliant, assert_declared
from .test_measure import SPEC


def test_morris_screening_from_the_study_file(tmp_path):
    """``[sensitivity] method = "morris"``: r (d + 1) members (the axes one group); the growth
    rate W sqrt((I2 - I1)(I3 - I2) / (I1 I3)) moves with the spin most (10 % against the
    moments' 2 %) and not with the start (mu* = 0) or the axes (round-off)."""
    raw = {"study": "dispersion", "dispersions": SPEC | {"truncate": True},
           "sensitivity": {"method": "morris", "trajectories": 20},
           "integration": {"members": 0},
           "output": {"dir": str(tmp_path / "out"), "formats": ["png"]}}
    study = tmp_path / "racket.toml"
    study.write_text(tomli_w.dumps(raw), encoding="utf-8")
    summary = run_study(study, progress=False)
    path = tmp_path / "out" / "dispersion.nc"
    assert_declared(path, "dispersion")
    assert_cf_compliant(path)
    ds = stability.load(path)
    assert ds.member.size == 20 * 7 and "mu_star" in ds and "first_order" not in ds
    growth = ds.mu_star.sel(output="growth_rate")
    assert str(growth.parameter.values[int(np.argmax(growth.values))]) == "rate"
    assert float(growth.sel(parameter="epsilon")) == 0.0
    assert float(growth.sel(parameter="axes")) < 1e-12  # re-diagonalised: round-off
    assert summary.values["dominant"] in ds.parameter.values
    assert (tmp_path / "out" / "indices.png").is_file()


def test_the_study_writes_its_dataset_and_names_what_dominates(tmp_path):
    raw = {"study": "dispersion", "dispersions": SPEC | {"truncate": True},
           "sensitivity": {"base": 128, "resamples": 20}, "integration": {"members": 3},
           "output": {"dir": str(tmp_path / "out"), "formats": ["png"]}}
    study = tmp_path / "racket.toml"
    study.write_text(tomli_w.dumps(raw), encoding="utf-8")
    summary = run_study(study, progress=False)
    path = tmp_path / "out" / "dispersion.nc"
    assert_declared(path, "dispersion")
    assert_cf_compliant(tmp_path / "out" / "dispersion.nc")
    ds = stability.load(path)
    n = 3
    assert np.array_equal(ds.run_parameters.values, ds.moments.values[:n])
    assert summary.values["dominant"] in ds.parameter.values
    assert summary.values["max_run_error"] < 1e-6
    assert (tmp_path / "out" / "indices.png").is_file()
    assert "Sobol' indices of the flip interval" in summary.table()
