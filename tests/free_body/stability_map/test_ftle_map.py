"""The stability map from tangents against linear theory, on a 12 x 12 grid of inertia ratios.

72 of the 144 cell centres are real bodies; W = 1 rad s-1, 2 members per cell started 1e-8 W off
the axis. The FTLE is log sigma_max(Phi(T)) / T of the computed RK4 map's state-transition
matrix; at the steady spin Phi is the exponential of the linearisation, whose 2 x 2 block across
the axis has eigenvectors of aspect ratio rho (``eigenvector_aspect``), so:

- intermediate axis, T = 10 s: ``sigma <= FTLE <= sigma + log((1 + rho) / 2) / T``, sigma =
  sqrt(-Omega^2) (cosh(sigma T) + rho sinh(sigma T) bounds sigma_max, the unstable eigenvector
  grows by exactly e^(sigma T)); the linear phase holds (epsilon e^(sigma_max T) = 3e-5: the
  amplitude's correction to a rate ~1e-9), RK4's error on a rate is (h sigma)^4 / 120 < 1e-10,
  so each side holds to 1e-6 s-1 (measured: the FTLE is 4e-6 s-1 or more above sigma, 4e-4 s-1
  or more below the upper side). Where the alignment term is under 0.1 sigma (25 cells) the
  FTLE is sigma within 10 % (measured 7 %); the median over the grid is 10 % above sigma.
- largest and smallest axes, T = 100 s: ``0 <= FTLE <= log(rho) / T`` (Phi = S R(t) S^-1 with
  cond(S) = rho, det Phi = 1), to 1e-6 s-1 for the amplitude's shear; at most 0.035 s-1 over
  the grid, against 0.8 s-1 for the intermediate axis's fastest.
"""

import numpy as np
import pytest

import stability
from stability.free_body.stability_map.figures import ftle_map_figure
from stability.free_body.stability_map.ftle_map import ftle_map, ratio_grid
from stability.plotting.style import label

from ...helpers import assert_cf_compliant, assert_declared, assert_readable


@pytest.fixture(scope="module")
def intermediate():
    return ftle_map(12, axis=2, horizon=10.0)


def inside(ds, name):
    return ds[name].values[ds.physical.values == 1]


def test_the_grid_holds_the_triangle_and_every_cell_is_a_body(intermediate):
    ds = intermediate
    assert ds.sizes == {"I1": 12, "I2": 12}
    assert int(ds.physical.sum()) == 72
    assert np.all(np.isfinite(inside(ds, "ftle")))
    assert np.all(np.isnan(ds.ftle.values[ds.physical.values == 0]))


def test_about_the_intermediate_axis_the_ftle_is_the_analytic_rate_to_its_alignment(
        intermediate):
    ds, T = intermediate, 10.0
    sigma, ftle = inside(ds, "growth_rate_analytic"), inside(ds, "ftle")
    alignment = np.log((1.0 + inside(ds, "eigenvector_aspect")) / 2.0) / T
    assert np.all(sigma > 0)
    assert 1e-8 * np.exp(sigma.max() * T) < 1e-4  # the linear phase
    assert np.all(ftle >= sigma - 1e-6)
    assert np.all(ftle <= sigma + alignment + 1e-6)
    aligned = alignment < 0.1 * sigma
    assert aligned.sum() >= 20
    assert np.all(np.abs(ftle[aligned] / sigma[aligned] - 1.0) < 0.1)
    assert np.max(inside(ds, "ftle_spread")) < 1e-6  # the members' directions do not matter


@pytest.mark.parametrize("axis", [1, 3])
def test_about_a_stable_axis_the_ftle_is_below_the_linear_bound(axis):
    T = 100.0
    ds = ftle_map(12, axis=axis, horizon=T, windows=20)
    ftle = inside(ds, "ftle")
    bound = np.log(inside(ds, "eigenvector_aspect")) / T
    assert np.all(inside(ds, "growth_rate_analytic") == 0.0)
    assert np.all(ftle >= -1e-9)
    assert np.all(ftle <= bound + 1e-6)
    assert ftle.max() < 0.05


def test_the_dataset_is_declared_cf_and_drawn_with_units(tmp_path, intermediate):
    path = stability.save(intermediate, tmp_path / "ftle_map.nc")
    assert_declared(path, "ftle_map")
    assert_cf_compliant(path)
    fig = ftle_map_figure(intermediate)
    assert_readable(fig)
    assert fig.axes[-1].get_ylabel() == label("FTLE", "s-1")  # the colour bar, in s-1


@pytest.mark.parametrize("change, message", [
    (dict(divisions=1), "divisions"),
    (dict(divisions=2.5), "divisions"),
    (dict(horizon=0.0), "horizon"),
    (dict(horizon=-1.0), "horizon"),
    (dict(axis=4), "axis must be 1, 2 or 3"),
    (dict(ratios=([0.2, 1.2], [0.6, 0.9])), "no body"),
    (dict(ratios=([0.0, 0.5], [0.6, 0.9])), "no body"),
    (dict(ratios=([0.5], [0.6, 0.9])), "at least 2"),
    (dict(ratios=([0.1, 0.2], [0.6, 0.7])), "no real body"),
    (dict(epsilon=-1e-3), "epsilon"),
    (dict(members=0), "members"),
])
def test_bad_input_is_one_line_before_any_work(change, message):
    with pytest.raises(ValueError, match=message) as info:
        ftle_map(**change)
    assert "\n" not in str(info.value)


def test_the_grids_cell_centres_miss_the_triangles_edges():
    i1, i2 = ratio_grid(12)
    x, y = np.meshgrid(i1, i2)
    assert np.all(x != y) and np.all(x + y != 1.0)
