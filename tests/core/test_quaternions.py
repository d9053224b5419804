"""Quaternion helpers (stability.core.quaternions): products, matrices and back, and the canonical
frame's rotation."""

import numpy as np
import pytest

from stability.core.quaternions import (
    attitude_error,
    canonical_quaternion,
    matrix_to_quaternion,
    quaternion_multiply,
    quaternion_to_matrix,
)


def test_quaternion_helpers_round_trip():
    rng = np.random.default_rng(3)
    q = rng.standard_normal((20, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    q *= np.sign(q[:, :1])
    R = quaternion_to_matrix(q)
    np.testing.assert_allclose(R @ np.swapaxes(R, -1, -2), np.broadcast_to(np.eye(3), R.shape),
                               atol=1e-15)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-14)
    back = np.array([matrix_to_quaternion(r) for r in R])
    np.testing.assert_allclose(back, q, atol=1e-15)
    np.testing.assert_allclose(quaternion_to_matrix(quaternion_multiply(q[0], q[1])), R[0] @ R[1],
                               atol=1e-15)
    assert attitude_error(q[0], -q[0]) == 0.0


@pytest.mark.parametrize("moments", [(1, 2, 3), (3, 1, 2), (2, 1, 3), (3, 2, 1)])
def test_canonical_quaternion_is_the_frame_rotation(moments):
    """R(c) is the signed permutation taking body components to the canonical (sorted) frame."""
    from stability.core.body import canonical_frame, to_canonical

    perm, signs = canonical_frame(np.array(moments, float))
    x = np.array([0.3, -1.2, 2.5])
    R = quaternion_to_matrix(canonical_quaternion(np.array(moments, float)))
    np.testing.assert_allclose(R @ x, to_canonical(x, perm, signs), atol=1e-15)
