"""A free-body run's members as a Dataset (stability.free_body.results): members that fail are
flagged and masked, each by its own status."""

import numpy as np

import stability
from stability.free_body.spin_ensembles import run_ensemble
from stability.ensemble.starts import perturbed_starts
from stability.util import conventions as cv

BODY = stability.RigidBody(1.0, 2.0, 3.0, name="I=(1,2,3)")


def _float_vars(ds):
    return [name for name, var in ds.data_vars.items() if var.dtype.kind == "f" and name != "w0"]


def _assert_masked_exactly_where_not_ok(ds):
    bad = ds.status.values != cv.STATUS_OK
    for name in _float_vars(ds) + ["w"] * ("w" in ds):
        values = ds[name].values.reshape(ds.member.size, -1)
        if name not in ("fail_time",):
            assert np.all(np.isnan(values[bad])), name  # every non-ok member is masked
    # No NaN presented as valid data: an ok member has finite states, errors and amplitudes.
    for name in ("w", "energy_error", "angular_momentum_error", "max_perp_amplitude"):
        values = ds[name].values.reshape(ds.member.size, -1)
        assert np.all(np.isfinite(values[~bad])), name
        assert np.all(np.isnan(values).any(axis=1) <= bad), name
    assert np.all(np.isnan(ds.fail_time.values) == ~bad)


def test_absurd_step_flags_every_member_as_non_finite():
    # One slow member keeps the run from being refused up front; the 70 others blow up.
    starts = np.vstack([[0.0, 0.01, 0.0], perturbed_starts(2, 1.0, 0.1, 70)])
    ds = run_ensemble(BODY, 2, starts=starts, method="rk4", h=5.0, t_end=1000.0)
    assert ds.status.values[0] == cv.STATUS_OK
    assert np.all(ds.status.values[1:] == cv.STATUS_NONFINITE)
    _assert_masked_exactly_where_not_ok(ds)
    assert np.all(ds.fail_time.values[1:] <= 1000.0)


def test_large_step_flags_diverged_members():
    # RK4 at h W = 1 stays finite but loses far more than 1e-2 of the energy.
    ds = run_ensemble(BODY, 2, 1.0, 0.1, 8, method="rk4", h=1.0, t_end=200.0)
    assert np.all(ds.status.values == cv.STATUS_DIVERGED)
    _assert_masked_exactly_where_not_ok(ds)
    np.testing.assert_array_equal(ds.fail_time.values, 200.0)


def test_mixed_ensemble_is_masked_per_member():
    # Spins from 0.1 to 20 rad/s at h = 0.3 s: h W from 0.03 (fine) to 6 (blows up).
    spins = np.geomspace(0.1, 20.0, 40)
    starts = np.column_stack([0.01 * spins, spins, 0.02 * spins])
    ds = run_ensemble(BODY, 2, starts=starts, method="rk4", h=0.3, t_end=60.0,
                      keep=stability.Keep(save_every=2))
    counts = np.bincount(ds.status.values, minlength=5)
    assert counts[cv.STATUS_OK] > 0 and counts[cv.STATUS_NONFINITE] > 0
    assert counts[cv.STATUS_OK] + counts[cv.STATUS_NONFINITE] + counts[cv.STATUS_DIVERGED] \
        + counts[cv.STATUS_STEP_TOO_LARGE] == 40
    _assert_masked_exactly_where_not_ok(ds)
    ok = ds.status.values == cv.STATUS_OK
    assert np.all(np.abs(ds.energy_error.values[ok]) <= 1e-2)
    assert np.all(ok[: ok.sum()])  # the slow spins are the ones that stay ok


def test_divergence_tolerance_is_a_keyword():
    strict = run_ensemble(BODY, 3, 1.0, 0.1, 4, method="rk4", h=0.5, t_end=500.0,
                          keep=stability.Keep(divergence_tolerance=1e-6))
    loose = run_ensemble(BODY, 3, 1.0, 0.1, 4, method="rk4", h=0.5, t_end=500.0)
    assert np.all(strict.status.values == cv.STATUS_DIVERGED)
    assert np.all(loose.status.values == cv.STATUS_OK)
    assert np.all(np.abs(loose.energy_error.values) > 1e-6)
