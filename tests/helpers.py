"""Reference solutions shared by the tests."""

import time

import numpy as np
from scipy.integrate import solve_ivp

import stability

def euler_rhs(moments):
    """Right-hand side of the torque-free Euler equations for scipy, in w."""
    I1, I2, I3 = moments

    def rhs(t, w):
        return [
            (I2 - I3) / I1 * w[1] * w[2],
            (I3 - I1) / I2 * w[2] * w[0],
            (I1 - I2) / I3 * w[0] * w[1],
        ]

    return rhs


def dop853_omega(moments, w0, t_end, rtol=1e-13, atol=1e-15):
    """w(t_end) from scipy's DOP853 at tight tolerance (an independent reference)."""
    sol = solve_ivp(euler_rhs(moments), (0.0, t_end), np.asarray(w0, float), method="DOP853",
                    rtol=rtol, atol=atol)
    return sol.y[:, -1]


def reference_omega(body, w0, t_end):
    """The best available reference for w(t_end): the exact solution, else DOP853."""
    if hasattr(stability, "exact_omega"):
        return stability.exact_omega(body, w0, np.array([t_end]))[0]
    return dop853_omega(body.moments, w0, t_end)


def wait_until(predicate, proc, timeout=180.0, show_stderr=False):
    """Poll ``predicate()`` until it holds while the subprocess ``proc`` runs.

    AssertionError if ``proc`` ends first (with its stderr when ``show_stderr``, for a
    process whose stderr nobody else reads) or after ``timeout`` s (``proc`` is killed).
    """
    t0 = time.monotonic()
    while not predicate():
        if proc.poll() is not None:
            detail = f": {proc.stderr.read()}" if show_stderr else ""
            raise AssertionError(f"the process ended (exit {proc.returncode}) before the "
                                 f"state awaited{detail}")
        if time.monotonic() - t0 > timeout:
            proc.kill()
            raise AssertionError("timed out waiting for the state awaited")
        time.sleep(0.02)
