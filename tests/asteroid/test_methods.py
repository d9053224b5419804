"""The relaxing tumbler's equations (stability.asteroid.methods): the right-hand side keeps |m|
and lowers the energy at -alpha |m x w|^2 at every state; its Jacobian is its derivative and has
the linear theory's rates at the principal spins (bad parameters: tests/test_bad_input.py)."""

import numpy as np
import pytest

from stability.asteroid.methods import P_ALPHA, relaxation_jvp, relaxation_params, relaxation_rhs
from stability.asteroid.model import wobble_rate


def test_the_dissipation_keeps_the_angular_momentum_and_takes_the_energy():
    """On 200 random states of three bodies: m . m' = 0 to 1e-15 |m|^2 |w| and w . m' =
    -alpha |m x w|^2 to 1e-14 of it."""
    rng = np.random.default_rng(7)
    for parameters in ((1.0, 1.5, 2.2, 0.3), (0.2, 0.9, 1.0, 2.0), (1.0, 1.0, 3.0, 0.05)):
        p = relaxation_params(parameters)
        moments = np.array(parameters[:3])
        for m in rng.standard_normal((200, 3)):
            rate = np.array(relaxation_rhs(*m, p))
            w = m / moments
            scale = float(m @ m) * float(np.linalg.norm(w))
            assert abs(float(m @ rate)) <= 1e-15 * scale
            loss = p[P_ALPHA] * float(np.sum(np.cross(m, w) ** 2))
            assert abs(float(w @ rate) + loss) <= 1e-14 * (loss + scale * np.linalg.norm(w))



def test_the_jacobian_is_the_derivative_of_the_equations():
    """relaxation_jvp against a central difference of relaxation_rhs (step 1e-6, error
    ~1e-12) on 100 random states and directions, to 1e-8 of |J v|'s scale."""
    rng = np.random.default_rng(3)
    p = relaxation_params((0.2, 0.9, 1.0, 0.7))
    for m, v in zip(rng.standard_normal((100, 3)), rng.standard_normal((100, 3))):
        step = 1e-6
        difference = (np.array(relaxation_rhs(*(m + step * v), p))
                      - np.array(relaxation_rhs(*(m - step * v), p))) / (2 * step)
        product = np.array(relaxation_jvp(*m, *v, p))
        scale = np.linalg.norm(m) ** 2 * np.linalg.norm(v) * (1 + p[P_ALPHA] * np.linalg.norm(m))
        assert np.max(np.abs(product - difference)) <= 1e-8 * scale


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_the_jacobian_at_a_spin_has_the_linear_theorys_rate(axis):
    """At m = L e_j the largest real eigenvalue of the Jacobian's block across the axis is
    wobble_rate's, to 1e-13 (along the axis it is 0: spins of every |L| are fixed points)."""
    moments, alpha, length = (1.0, 1.5, 2.2), 0.3, 2.2
    p = relaxation_params((*moments, alpha))
    m = length * np.eye(3)[axis]
    jacobian = np.column_stack([relaxation_jvp(*m, *e, p) for e in np.eye(3)])
    across = [k for k in range(3) if k != axis]
    assert np.max(np.abs(jacobian[:, axis])) == 0.0
    rate = max(np.linalg.eigvals(jacobian[np.ix_(across, across)]).real)
    assert rate == pytest.approx(wobble_rate(moments, axis, length, alpha), abs=1e-13)
