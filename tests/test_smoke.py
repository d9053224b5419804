import numpy as np

import stability


def test_integrate_returns_labelled_dataset():
    body = stability.RigidBody(1.0, 2.0, 3.0)
    ds = stability.integrate(body, [0.3, 1.0, 0.9], t_end=1.0, h=0.1, method="rk4")
    assert ds.w.dims == ("time", "axis")
    assert ds.w.attrs["units"] == "rad s-1"
    assert ds.time.size == 11
    np.testing.assert_allclose(ds.w.values[0], [0.3, 1.0, 0.9])
