"""Finite-time Lyapunov exponents from tangents against the linear theory of each scene.

- Free body, spin W = 2 about the intermediate axis of I = (1, 2, 3): the linear rate is
  sigma = sqrt(-Omega^2) = W sqrt((I2 - I1)(I3 - I2) / (I1 I3)) = 2 / sqrt(3). A start
  eps = 1e-10 off the axis stays in the linear phase (amplitude eps e^(sigma t) < 1e-3) for
  t < 14 s; the leading tangent's rate departs from sigma there by the decaying mode,
  O(e^(-2 sigma t)) (< 1e-7 beyond t = 7), the amplitude, O(eps^2 e^(2 sigma t)) (< 1e-6), and
  RK4's error on the rate, (h sigma)^4 / 120 (1e-11 at h = 0.005): within 1e-6 relative.
- About the smallest and the largest axes the motion is periodic: the tangent oscillates
  (bounded by the linearised ellipse) and shears, growing at most linearly in t (the period
  depends on the orbit), so log|v(t)| <= log(2 (1 + t / P)) and the FTLE -> 0 like log(t) / t;
  exponential growth at even 1 % of the intermediate axis's rate would give log|v| = 6.3 over
  the 100 periods run.
- Spherical damper (1, 2, 3, J = 0.2, c = 0.1) spun at W = 2 about its minor axis, started
  on the steady spin: the tangent across the axis grows at the real part of the leading
  eigenvalue of the linearisation (:func:`stability.dissipation.model.sphere_eigenvalues`),
  measured over a whole nutation period 2 pi / Im(lambda) (the oscillation of |v| cancels
  there) after 8 periods (the other pair, 0.62 s-1 slower, is down by e^-27): within 1e-6
  relative (RK4's error on it ~5e-9).
"""

import numpy as np
import pytest
import xarray as xr

import stability
from stability import RunOptions
from stability.dissipation.model import sphere_eigenvalues, sphere_steady_spin
from stability.engine import propagate_groups
from stability.engine.tangent import tangent_scene
from stability.free_body.model import growth_rate, oscillation_frequency
from stability.registry import SCENES
from stability.tangents.ftle import run_tangents

from ..helpers import assert_cf_compliant, assert_declared

FREE_BODY = SCENES["free_body"]
SPHERE = SCENES["sphere_damper"]
MOMENTS = np.array([1.0, 2.0, 3.0])
BODY = stability.RigidBody(*MOMENTS, physical=False)
W = 2.0


@pytest.fixture(scope="module")
def intermediate():
    x0 = np.array([[1e-10, 2.0 * W, 1e-10]])
    return run_tangents(FREE_BODY, x0, MOMENTS, h=0.005, every=100, windows=28, vectors=3)


def test_the_tangents_rate_in_the_linear_phase_is_sqrt_minus_omega_squared(intermediate):
    sigma = growth_rate(BODY, 2, W)
    linear = intermediate.sel(time=slice(7.0, 14.0))
    assert linear.time.size == 15
    assert np.max(np.abs(linear.window_rate.values / sigma - 1.0)) < 1e-6
    assert np.max(np.abs(linear.growth_rate.values / sigma - 1.0)) < 1e-6


def test_the_free_bodys_spectrum_is_sigma_zero_minus_sigma_and_sums_to_zero(intermediate):
    """Euler's flow keeps volume (div f = 0): the three exponents add up to 0 (RK4 keeps it to
    its error, ~1e-10 here), and near the saddle they are (sigma, 0, -sigma) but for the
    alignment transient, O(1/T)."""
    sigma = growth_rate(BODY, 2, W)
    exponents = intermediate.exponents.values[0]
    assert abs(exponents.sum()) < 1e-9
    assert np.allclose(exponents, [sigma, 0.0, -sigma], rtol=0, atol=0.1 * sigma)
    assert intermediate.stm_log_singular_value.values[0] >= exponents[0] * 14.0 - 1e-9


def test_the_largest_singular_value_is_that_of_the_state_transition_matrix_itself():
    """Over a run short enough to keep Phi unrenormalised (no overflow): log sigma_max of the
    matrix carried in one piece equals the renormalised product's to 1e-12."""
    x0 = np.array([[0.3, 3.0, 0.2]])
    ds = run_tangents(FREE_BODY, x0, MOMENTS, h=0.01, every=50, windows=8, vectors=3)
    scene = tangent_scene(FREE_BODY, 3)
    row = scene.method("rk4").params(MOMENTS, 0.01)
    whole = propagate_groups(scene, "rk4", np.hstack([x0, np.eye(3).reshape(1, 9)]), row[None],
                             np.array([1]), np.array([0.01]), np.array([400])).x_final
    phi = whole[0, 3:].reshape(3, 3).T
    expected = np.log(np.linalg.svd(phi, compute_uv=False)[0])
    assert abs(ds.stm_log_singular_value.values[0] - expected) < 1e-12 * max(1.0, expected)


@pytest.mark.parametrize("axis", [1, 3])
def test_about_the_smallest_and_largest_axes_the_ftle_tends_to_zero(axis):
    omega = oscillation_frequency(BODY, axis, W)
    period = 2.0 * np.pi / omega
    x0 = np.zeros((2, 3))
    x0[:, axis - 1] = MOMENTS[axis - 1] * W
    across = [a for a in range(3) if a != axis - 1]
    x0[0, across] = 1e-3
    x0[1, across] = [1e-2, -1e-2]
    ds = run_tangents(FREE_BODY, x0, MOMENTS, h=period / 512, every=512, windows=100)
    t = ds.time.values
    growth = ds.ftle_running.values * t
    assert np.all(growth <= np.log(2.0 * (1.0 + t / period)))
    assert np.all(np.abs(ds.ftle.values) <= np.log(2.0 * 101.0) / t[-1])
    assert np.all(np.abs(ds.ftle.values) < 0.01 * growth_rate(BODY, 2, W))


def test_the_damped_bodys_late_rate_is_the_real_part_of_its_leading_eigenvalue():
    values = np.array([1.0, 2.0, 3.0, 0.2, 0.1])
    lam = sphere_eigenvalues(values, 0, W)[0]
    assert lam.real > 0  # the minor axis is unstable with a damper
    period = 2.0 * np.pi / abs(lam.imag)
    x0 = sphere_steady_spin(values, 0, W)[None]
    across = np.array([[0.0], [1.0], [0.0], [0.0], [0.0], [0.0]])
    ds = run_tangents(SPHERE, x0, values, h=period / 512, every=64, windows=72,
                      tangents=across)
    last = ds.window_rate.values[0, -8:].mean()  # the last period, 8 windows of P / 8
    assert abs(last / lam.real - 1.0) < 1e-6


def test_the_ftle_is_bitwise_the_same_in_one_piece_and_chunked_into_a_store(tmp_path):
    rng = np.random.default_rng(5)
    x0 = np.column_stack([1e-2 * rng.standard_normal(5), np.full(5, 4.0),
                          1e-2 * rng.standard_normal(5)])
    sets = [MOMENTS, np.array([1.0, 1.5, 2.2])]
    kwargs = dict(h=0.01, every=20, windows=10, vectors=3, sizes=[3, 2])
    whole = run_tangents(FREE_BODY, x0, sets, **kwargs)
    stored = run_tangents(FREE_BODY, x0, sets, **kwargs, options=RunOptions(
        store=tmp_path / "store", chunk_members=2, progress=False))
    assert set(whole.data_vars) == set(stored.data_vars)
    for name in whole.data_vars:
        assert np.array_equal(whole[name].values, stored[name].values, equal_nan=True), name
    again = run_tangents(FREE_BODY, x0, sets, **kwargs, options=RunOptions(
        store=tmp_path / "store", resume=True, chunk_members=2, progress=False))
    xr.testing.assert_identical(stored.drop_attrs(), again.drop_attrs())


def test_the_ftle_is_bitwise_the_same_on_one_thread_and_on_dask_workers(tmp_path):
    """The same members on one Numba thread, and in chunks of 2 on a local dask cluster of two
    processes: every number of the Dataset is the one made here with every thread."""
    distributed = pytest.importorskip("distributed")
    rng = np.random.default_rng(6)
    x0 = np.column_stack([1e-2 * rng.standard_normal(6), np.full(6, 4.0),
                          1e-2 * rng.standard_normal(6)])
    kwargs = dict(h=0.01, every=20, windows=6, vectors=3)
    whole = run_tangents(FREE_BODY, x0, MOMENTS, **kwargs)
    one = run_tangents(FREE_BODY, x0, MOMENTS, **kwargs,
                       options=RunOptions(threads=1, progress=False))
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        there = run_tangents(FREE_BODY, x0, MOMENTS, **kwargs, options=RunOptions(
            store=tmp_path / "store", chunk_members=2, scheduler=client, progress=False))
    for ds in (one, there):
        for name in whole.data_vars:
            assert np.array_equal(whole[name].values, ds[name].values, equal_nan=True), name


def test_the_dataset_is_as_declared_and_follows_cf(tmp_path, intermediate):
    path = stability.save(intermediate, tmp_path / "tangents.nc")
    assert_declared(path, "tangents")
    assert_cf_compliant(path)


@pytest.mark.parametrize("change, message", [
    (dict(vectors=0), "vectors must be a whole number from 1 to its 3"),
    (dict(every=0), "every"),
    (dict(every=-5), "every"),
    (dict(windows=0), "windows"),
    (dict(h=-0.1), "h"),
    (dict(tangents=np.zeros((3, 1))), "linearly independent"),
])
def test_bad_input_is_one_line_before_any_work(change, message):
    kwargs = {**dict(h=0.01, every=10, windows=2), **change}
    with pytest.raises(ValueError, match=message) as info:
        run_tangents(FREE_BODY, np.array([[0.0, 2.0, 0.0]]), MOMENTS, **kwargs)
    assert "\n" not in str(info.value)


def test_a_scene_without_a_linearisation_is_refused_in_one_line():
    with pytest.raises(ValueError, match="declares no linearisation"):
        run_tangents(SCENES["whip_damper"], np.zeros((1, 7)), [1.0] * 7, h=0.01, every=10,
                     windows=2)
