"""The plain speed-baseline loop of ``stability bench`` (stability.engine.baseline)."""

import numpy as np

from stability.engine import BLOCK, propagate_groups
from stability.registry import SCENES

from ..helpers import starts

MOMENTS = np.array([1.0, 2.0, 3.0])  # canonical already


def test_the_speed_baseline_loop_is_rk4_on_every_member():
    """``stability bench``'s plain loop (:mod:`stability.engine.baseline`) does the engine's
    RK4 on every member, the last partial block included: it differs from the engine's
    compensated loop by rounding only (1e-12 of |m| after 200 steps), so the bench's ratio of
    the two rates compares the same arithmetic."""
    from stability.engine.baseline import plain_rk4
    from stability.integrators.spec import body_params

    scene = SCENES["free_body"]
    m0 = starts(scene, BLOCK + 37)  # one whole block and a partial one
    h, steps = 0.01, 200
    m = m0.copy()
    plain_rk4(m, body_params(MOMENTS), h, steps)
    spec = scene.method("rk4")
    engine = propagate_groups(scene, spec, m0, spec.params(MOMENTS, h)[None], [len(m0)], h,
                              steps, progress=False)
    scale = np.abs(m0).max()
    assert np.abs(m - engine.x_final).max() < 1e-12 * scale
    assert np.abs(m - m0).max() > 1e-3 * scale  # the members changed
