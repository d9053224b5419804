"""The tennis-racket study (stability.free_body.tennis_racket.study): its default run fits the
analytic growth rate."""

from pathlib import Path

import numpy as np
import pytest

import stability
from stability.cli import main

ROOT = Path(__file__).resolve().parents[3]
TENNIS = ROOT / "studies" / "tennis_racket.toml"


def test_default_study_fits_the_analytic_growth_rate(tmp_path, capsys):
    """The default study's members, seed, step and sampling; the horizon cut to 1.5 s (the
    fit window ends near 0.7 s, so the fitted number is the default run's own). The headline
    is what the accessor gives on the saved Dataset."""
    out = tmp_path / "rate"
    args = ["run", str(TENNIS), "--out", str(out), "--no-progress",
            "--set", "integration.t_end=1.5", "--set", "output.figures=false"]
    assert main(args) == 0
    capsys.readouterr()
    ds = stability.load(out / "tennis_racket.nc")
    assert ds.sizes["member"] == 10_000
    analytic = ds.attrs["growth_rate_analytic"]
    fitted = ds.attrs["growth_rate_fitted"]
    t0, t1 = ds.attrs["growth_fit_window"]
    assert 0.0 < t0 < t1 < 1.5
    # about the middle axis at 10 rad/s: sqrt(-Omega^2) = w sqrt((I2 - I1)(I3 - I2) / (I1 I3))
    i1, i2, i3 = np.sort(stability.RigidBody.preset("tennis_racket").moments)
    assert analytic == pytest.approx(10.0 * np.sqrt((i2 - i1) * (i3 - i2) / (i1 * i3)),
                                     rel=1e-14)
    assert analytic == pytest.approx(float(np.sqrt(-ds.attrs["omega_squared"])), rel=1e-15)
    assert abs(fitted - analytic) < 1e-3
    assert abs(fitted - analytic) / analytic < 1e-3
    assert float(ds.stability.measured_growth_rate().growth_rate) == fitted
