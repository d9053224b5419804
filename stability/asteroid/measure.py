"""What the asteroid studies measure from computed motion: a state's two periods read off its
exact attitude, and the main frequencies of its synthetic light curve.

The periods are measured, not taken from the closed forms of :mod:`.spin_state`: P_psi is the
time between the first and the last of N upward zero crossings of the body's m2 = (R^T L)_2
(each crossing refined by brentq on the attitude itself), over N - 1 periods; P_phi is 2 pi
over the mean rate of the reference axis's azimuth about L between those two crossings, at
which the body's internal motion is at the same phase, so the periodic part of phi cancels.
"""

from __future__ import annotations

import math

import numpy as np

from ..core.quaternions import quaternion_to_matrix
from ..free_body.exact_attitude import exact_attitude
from .lightcurve import l_frame_start, lightcurve, spectral_peaks, spectrum
from .spin_state import SpinState

#: The reference axis (canonical, 0-based) of each mode: the short axis in SAM, the long in LAM.
REFERENCE_AXIS = {"SAM": 2, "LAM": 0}


def _attitude(state: SpinState, t) -> np.ndarray:
    q0 = l_frame_start(state.w0, state.moments)
    return quaternion_to_matrix(exact_attitude(state.body, state.w0, np.atleast_1d(t), q0))


def measured_periods(state: SpinState, periods: int = 50, samples: int = 64
                     ) -> tuple[float, float]:
    """(P_psi, P_phi) read off the exact attitude over ``periods`` rotation periods.

    Parameters
    ----------
    state : SpinState
    periods : int
        Rotation periods spanned by the run.
    samples : int
        Attitude samples per rotation period (to find the crossings and unwrap the azimuth).

    Returns
    -------
    period_psi, period_phi : float
        In the state's time unit.
    """
    from scipy.optimize import brentq

    span = periods * state.period_psi
    t = np.linspace(0.0, span, periods * samples + 1)
    L = np.array([0.0, 0.0, 1.0])

    def m2(time):
        return float(np.einsum("nji,j->ni", _attitude(state, time), L)[0, 1])

    R = _attitude(state, t)
    y = np.einsum("nji,j->ni", R, L)[:, 1]
    up = np.flatnonzero((y[:-1] < 0.0) & (y[1:] >= 0.0))
    first, last = (brentq(m2, t[j], t[j + 1], xtol=1e-300, rtol=4 * np.finfo(float).eps)
                   for j in (up[0], up[-1]))
    cycles = len(up) - 1
    times = np.concatenate([[first], t[(t > first) & (t < last)], [last]])
    axis = _attitude(state, times)[:, :, REFERENCE_AXIS[state.mode]]  # reference axis, space
    azimuth = np.unwrap(np.arctan2(axis[:, 1], axis[:, 0]))
    rate = (azimuth[-1] - azimuth[0]) / (last - first)
    return (last - first) / cycles, 2.0 * math.pi / abs(rate)


def lightcurve_peaks(state: SpinState, sun, observer, *, periods: float = 40.0,
                     samples: int = 4096, count: int = 2, shape=None,
                     law: str = "lommel-seeliger") -> tuple[np.ndarray, float]:
    """The ``count`` strongest frequencies of a synthetic light curve of ``state``.

    The run spans ``periods`` times the longer of P_psi and P_phi in ``samples`` even steps.

    Returns
    -------
    peaks : ndarray, shape (count,)
        Cycles per time unit, strongest first.
    resolution : float
        1 / (run length), the spectrum's frequency resolution.
    """
    span = periods * max(state.period_psi, state.period_phi)
    t = np.linspace(0.0, span, samples)
    flux = lightcurve(state, t, sun, observer, shape=shape, law=law)
    f, a = spectrum(t, flux)
    return spectral_peaks(f, a, count), 1.0 / span


__all__ = ["REFERENCE_AXIS", "lightcurve_peaks", "measured_periods"]
