"""The relaxing tumbler's equations (stability.asteroid.methods): the right-hand side keeps |m|
and lowers the energy at -alpha |m x w|^2 at every state (bad parameters:
tests/test_bad_input.py)."""

import numpy as np

from stability.asteroid.methods import P_ALPHA, relaxation_params, relaxation_rhs


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

