"""The dispersed free body's Sobol indices of the growth rate against quadrature (its draws,
tensors and study: tests/free_body/dispersion/, tests/uncertainty/test_inertia.py)."""

import numpy as np

from stability.free_body.dispersion import measure as M
from stability.uncertainty.dispersions import dispersions
from stability.uncertainty.sobol import sobol_design, sobol_indices

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

