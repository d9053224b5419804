"""A scene of the user's own, for the GPU tests (``tests/gpu_simulated.py``): a rigid body with
a viscous spherical damper (``examples/plot_09_damped_body.py`` derives it). Not a test module."""

import numpy as np

import stability


def rhs(w1, w2, w3, s1, s2, s3, p):
    """I w' = (I w) x w + c (w_s - w), J w_s' = J w_s x w - c (w_s - w)"""
    I1, I2, I3, J, c = p[0], p[1], p[2], p[3], p[4]
    t1, t2, t3 = c * (s1 - w1), c * (s2 - w2), c * (s3 - w3)
    return (((I2 - I3) * w2 * w3 + t1) / I1, ((I3 - I1) * w3 * w1 + t2) / I2,
            ((I1 - I2) * w1 * w2 + t3) / I3,
            s2 * w3 - s3 * w2 - t1 / J, s3 * w1 - s1 * w3 - t2 / J, s1 * w2 - s2 * w1 - t3 / J)


def example(n, seed=0):
    """Bodies spun near their minor axis, the sphere with them; two dampers."""
    rng = np.random.default_rng(seed)
    w = np.column_stack([np.full(n, 2.0), 1e-2 * rng.standard_normal(n),
                         1e-2 * rng.standard_normal(n)])
    return np.concatenate([w, w], axis=1), [np.array([1.0, 2.0, 3.0, 0.1, 0.05]),
                                           np.array([1.0, 1.5, 2.2, 0.2, 0.5])]


DAMPED_BODY = stability.define_scene(
    "gpu_damped_body", ["w1", "w2", "w3", "ws1", "ws2", "ws3"], ["rad s-1"] * 6, rhs,
    ["I1", "I2", "I3", "J", "c"], example=example,
)
