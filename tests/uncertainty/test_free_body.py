"""The dispersed free body: indices against quadrature, draws bitwise what the kernels ran with
(in one piece, in chunks, resumed), dispersed tensors physical, and the study end to end."""

import numpy as np
import pytest
import tomli_w

import stability
from stability import RunOptions
from stability.free_body.dispersion import measure as M
from stability.free_body.dispersion.study import STUDY
from stability.free_body.exact import flip_interval
from stability.study import run_study
from stability.uncertainty.designs import unit_design
from stability.uncertainty.dispersions import dispersions
from stability.uncertainty.inertia import physical
from stability.uncertainty.sobol import sobol_design, sobol_indices

from ..helpers import assert_cf_compliant, assert_declared

BODY = (1.0, 2.0, 2.5)


def growth_rate(I1, I2, I3, W):
    """lambda = W sqrt((I2 - I1)(I3 - I2) / (I1 I3)), written again here."""
    return W * np.sqrt((I2 - I1) * (I3 - I2) / (I1 * I3))


def quadrature_indices(ranges, f, n=12):
    """S_i and S_Ti of f over independent uniforms on ``ranges`` by a tensor Gauss-Legendre
    grid: V_i = Var(E[Y | x_i]), E[Var(Y | x_~i)], each a weighted sum over the grid."""
    x, w = np.polynomial.legendre.leggauss(n)
    w = w / 2.0
    nodes = [lo + (hi - lo) * (x + 1.0) / 2.0 for lo, hi in ranges]
    d = len(ranges)
    y = f(*np.meshgrid(*nodes, indexing="ij"))
    W = np.ones(())
    for k in range(d):
        W = np.multiply.outer(W, w)
    mean = np.sum(W * y)
    var = np.sum(W * (y - mean) ** 2)
    first, total = [], []
    for i in range(d):
        others = tuple(k for k in range(d) if k != i)
        cond = np.tensordot(y, _weights(w, d, others), axes=(others, range(d - 1)))
        first.append(np.sum(w * (cond - mean) ** 2) / var)
        cond_i = np.tensordot(w, y, axes=(0, i))  # E[Y | x_~i], over the other axes
        cond_sq = np.tensordot(w, y * y, axes=(0, i))
        total.append(np.sum(_weights(w, d, others) * (cond_sq - cond_i**2)) / var)
    return np.array(first), np.array(total)


def _weights(w, d, axes):
    out = np.ones(())
    for _ in axes:
        out = np.multiply.outer(out, w)
    return out


def test_the_growth_rates_indices_agree_with_quadrature_within_their_intervals():
    nominal = M.nominal(BODY, 10.0, 1e-3)
    disp = dispersions({"moments": {"distribution": "uniform", "relative": 0.05},
                        "rate": {"distribution": "uniform", "relative": 0.1}}, nominal)
    design = sobol_design(disp, 2**13, 4)
    draws = M.members(disp, design.unit)
    rate = M.closed_form(draws)["growth_rate"]
    assert np.allclose(rate, growth_rate(*draws["moments"].T, draws["rate"]), rtol=1e-13)
    ds = sobol_indices(design, {"growth_rate": (rate, "s-1", "growth rate")}, seed=4)
    ranges = [(v * 0.95, v * 1.05) for v in BODY] + [(9.0, 11.0)]
    first, total = quadrature_indices(ranges, growth_rate)
    assert abs(first.sum() - 1.0) < 0.1 and np.all(total >= first - 1e-12)
    for name, quad in (("first_order", first), ("total", total)):
        est, conf = ds[name].values[0], ds[f"{name}_conf"].values[0]
        print(name, "quadrature", quad.round(4), "SALib", est.round(4), "+-", conf.round(4))
        assert np.all(np.abs(est - quad) <= conf), (name, est - quad, conf)
        assert np.all(conf < 0.05)


def test_the_closed_form_flip_interval_is_the_exact_modules():
    nominal = M.nominal(BODY, 10.0, 1e-3, 0.3)
    disp = dispersions({"moments": {"distribution": "uniform", "relative": 0.05}}, nominal)
    draws = M.members(disp, unit_design("random", 20, 3, 5))
    got = M.closed_form(draws)["flip_interval"]
    want = [flip_interval(stability.RigidBody(*I), w) for I, w in zip(draws["moments"],
                                                                      draws["w0"])]
    assert np.array_equal(got, want)


RACKET = stability.RigidBody.preset("tennis_racket")
SPEC = {"moments": {"distribution": "uniform", "relative": 0.02},
        "axes": {"distribution": "uniform", "lower": 0.0, "upper": 0.01},
        "rate": {"distribution": "normal", "relative": 0.1},
        "epsilon": {"distribution": "log-uniform", "lower": 1e-4, "upper": 1e-2}}


def racket_draws(n=12, design="random"):
    disp = dispersions(SPEC, M.nominal(RACKET.moments, 10.0, 1e-3), truncate=True)
    return disp, M.members(disp, unit_design(design, n, len(disp.columns()), 7))


def test_a_members_draw_is_a_function_of_the_seed_and_its_number_alone():
    disp, few = racket_draws(10)
    _, many = racket_draws(5000)
    for key in ("moments", "w0", "tensor", "rate", "epsilon"):
        assert np.array_equal(few[key], many[key][:10]), key
    one = disp.draw(unit_design("random", 5000, len(disp.columns()), 7)[4321:4322])
    assert one["I3"][0] == many["I3"][4321]


def test_every_dispersed_tensor_is_symmetric_positive_definite_and_physical():
    disp, draws = racket_draws(4096, "sobol")
    J, I, A = draws["tensor"], draws["moments"], draws["axes"]
    assert np.array_equal(J, np.transpose(J, (0, 2, 1)))
    assert np.all(np.linalg.eigvalsh(J) > 0.0)
    assert np.all(physical(I)) and np.all(physical(np.column_stack(
        [draws["I1"], draws["I2"], draws["I3"]])))
    assert np.allclose(np.einsum("nij,njk->nik", np.transpose(A, (0, 2, 1)), A), np.eye(3),
                       atol=1e-14)
    assert np.allclose(np.linalg.det(A), 1.0)
    assert np.allclose(J @ A, A * I[:, None, :], rtol=0, atol=1e-15)
    tilt = np.degrees(np.arccos(np.clip(np.diagonal(A, axis1=1, axis2=2), -1, 1)))
    assert tilt.max() <= np.degrees(0.01) * 1.0001 and tilt.max() > 0.1  # the draws reach it
    assert disp.truncated == "I3"


def test_the_stored_draws_are_bitwise_what_the_kernels_ran_with(tmp_path):
    """The moments each run's group reports back, and each member's start, equal the draws:
    in one piece, in chunks of 5, and resumed after a chunk is lost."""
    _, draws = racket_draws(12)
    want_I, want_m = draws["moments"], draws["w0"] * draws["moments"]
    whole = M.integrated(draws, 12, steps_per_flip=64, flips=2)
    store = tmp_path / "store"
    chunked = M.integrated(draws, 12, steps_per_flip=64, flips=2,
                           options=RunOptions(store=store, chunk_members=5, progress=False))
    chunks = sorted(p for p in store.rglob("*.nc"))
    assert len(chunks) >= 3
    chunks[1].unlink()
    resumed = M.integrated(draws, 12, steps_per_flip=64, flips=2, options=RunOptions(
        store=store, chunk_members=5, resume=True, progress=False))
    for ds in (whole, chunked, resumed):
        assert np.array_equal(ds.parameters.values, want_I)
        got_m = np.column_stack([ds[f"m{k}_start"].values for k in (1, 2, 3)])
        assert np.array_equal(got_m, want_m)
        assert np.array_equal(ds.flip_interval_run.values, whole.flip_interval_run.values)
    exact = M.closed_form(draws)["flip_interval"]
    assert np.nanmax(np.abs(whole.flip_interval_run.values / exact - 1.0)) < 1e-4


def test_the_stored_draws_are_what_the_kernels_ran_with_on_dask_workers(tmp_path):
    """The same members in chunks of 5 on a local dask cluster of two processes: the moments
    and starts each chunk reports back are the draws, and every output is the one-piece
    run's, bitwise."""
    distributed = pytest.importorskip("distributed")
    _, draws = racket_draws(12)
    kwargs = dict(steps_per_flip=64, flips=2)
    whole = M.integrated(draws, 12, **kwargs)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        there = M.integrated(draws, 12, **kwargs, options=RunOptions(
            store=tmp_path / "store", chunk_members=5, scheduler=client, progress=False))
    assert len(list((tmp_path / "store").rglob("*.nc"))) >= 3
    assert np.array_equal(there.parameters.values, draws["moments"])
    got_m = np.column_stack([there[f"m{k}_start"].values for k in (1, 2, 3)])
    assert np.array_equal(got_m, draws["w0"] * draws["moments"])
    for name in ("flip_interval_run", "axis_crossings", "status"):
        assert np.array_equal(there[name].values, whole[name].values, equal_nan=True), name


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
