"""The free body's methods (stability.free_body.methods): the table, and the exact flow as a
one-step method: registered, its kernel's increments reproduce exact_omega, and it runs and
reverses through integrate."""

import math

import numpy as np
import pytest

import stability
from stability import RigidBody, exact_omega
from stability.free_body.exact import flow
from stability.free_body.methods import METHODS, exact_step
from stability.integrators.spec import body_params

EPS = np.finfo(float).eps
#: A body and start on the separatrix, as in tests/free_body/test_exact.py.
SEP_I = (3.0, 4.0, 6.0)


def test_exact_method_is_registered():
    spec = METHODS["exact"]
    assert spec.is_exact and spec.order == math.inf
    assert spec.preserves_casimir and spec.preserves_energy and spec.symmetric and spec.explicit
    assert spec.describe()["order"] == "exact"


def run_kernel(I, w0, h, n_steps):
    """Steps of the ``exact`` kernel in the canonical frame, summed as
    stability.free_body.propagate does."""
    p = body_params(I)
    m = I * np.asarray(w0, dtype=float)
    comp = np.zeros(3)
    out = np.empty((n_steps, 3))
    for n in range(n_steps):
        d1, d2, d3, iterations = exact_step(m[0], m[1], m[2], h, p, 0)
        assert iterations == 0
        y = np.array([d1, d2, d3]) - comp  # Kahan
        s = m + y
        comp = (s - m) - y
        m = s
        out[n] = m / I
    return out


@pytest.mark.parametrize(
    "I, w0, n_steps",
    [
        ((1.0, 1.7, 2.2), (0.4, 0.9, -0.3), 2000),  # "minor"
        ((1.0, 1.7, 2.2), (0.2, -0.5, 0.9), 2000),  # "major"
        ((2.0, 2.0, 3.0), (0.6, -0.5, 0.7), 2000),  # symmetric, I1 = I2
        ((1.0, 2.0, 2.0), (0.6, -0.5, 0.7), 2000),  # symmetric, I2 = I3
        (SEP_I, (2.0, 5.0, -1.0), 200),  # on the separatrix (short: the saddle amplifies)
    ],
)
def test_exact_kernel_increments_reproduce_exact_omega(I, w0, n_steps):
    """The increments summed over many steps of h = 0.01 stay within 1e-13 of one evaluation
    (measured: <= 4e-15 after 2000 steps; without cancellation-free increments it was 4e-13)."""
    I = np.array(I)
    h = 0.01
    got = run_kernel(I, w0, h, n_steps)
    ref = exact_omega(RigidBody(*I, physical=False), w0, h * np.arange(1, n_steps + 1))
    assert np.max(np.abs(got - ref)) <= 1e-13 * np.linalg.norm(w0)


def test_integrate_with_exact_method():
    body = RigidBody(2.2, 1.0, 1.7)  # unsorted
    w0 = np.array([-0.3, 0.4, 0.9])
    ds = stability.integrate(body, w0, t_end=100.0, h=0.05, method="exact", progress=False)
    ref = exact_omega(body, w0, ds.time.values)
    assert ds.attrs["method_order"] == "exact"
    assert np.max(np.abs(ds.w.values - ref)) <= 1e-13
    I = body.moments
    m = ds.w.values * I
    L = np.linalg.norm(m, axis=1)
    E = np.sum(m * ds.w.values, axis=1)
    assert np.max(np.abs(L / L[0] - 1.0)) <= 1e-14
    assert np.max(np.abs(E / E[0] - 1.0)) <= 1e-14
    # Long steps (several periods each) go through the same kernel.
    ds = stability.integrate(body, w0, t_end=100.0, h=10.0, method="exact", progress=False)
    assert np.max(np.abs(ds.w.values - exact_omega(body, w0, ds.time.values))) <= 1e-12


def test_exact_flow_is_reversible():
    I1, I2, I3 = 1.0, 1.7, 2.2
    w = (0.4, 0.9, -0.3)
    fwd = flow(I1, I2, I3, *w, 0.37)
    back = flow(I1, I2, I3, *fwd, -0.37)
    np.testing.assert_allclose(back, w, rtol=0, atol=2 * EPS)
