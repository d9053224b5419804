"""Dispersed inertia tensors (stability.uncertainty.inertia): symmetric, positive definite and
physical."""

import numpy as np

from stability.uncertainty.inertia import physical

from ..free_body.dispersion.test_measure import racket_draws


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
