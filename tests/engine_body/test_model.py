"""The engines' state (stability.engine_body.model): its conversions from and to the body-frame
(m, q) invert each other to round-off, and the space angular velocity has the body's length."""

import numpy as np

from stability.engine_body.model import body_state, world_state

I = np.array([1.0, 2.0, 3.0])  # canonical already


def test_state_conversions_invert_each_other():
    rng = np.random.default_rng(3)
    m, q = rng.standard_normal((5, 3)), rng.standard_normal((5, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    x = world_state(I, m, q)
    back_m, back_q = body_state(x, I)
    np.testing.assert_allclose(back_m, m, rtol=0, atol=1e-14)
    assert np.array_equal(back_q, q)
    # |omega_w| = |w|: a rotation
    np.testing.assert_allclose(np.linalg.norm(x[:, :3], axis=1),
                               np.linalg.norm(m / I, axis=1), rtol=1e-14)
