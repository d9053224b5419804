"""What the asteroid studies measure from computed motion: a state's two periods read off its
exact attitude, and the main frequencies of its synthetic light curve.

The periods are measured, not taken from the closed forms of :mod:`.model`: P_psi is the
time between the first and the last of N upward zero crossings of the body's m2 = (R^T L)_2
(each crossing refined by brentq on the attitude itself), over N - 1 periods; P_phi is 2 pi
over the mean rate of the reference axis's azimuth about L between those two crossings, at
which the body's internal motion is at the same phase, so the periodic part of phi cancels.
"""

from __future__ import annotations

import math

import numpy as np

from ..util import conventions as cv
from .lightcurve import (
    ellipsoid_axes, ellipsoid_mesh, lightcurve, main_frequencies, spectral_peaks,
    spectrum,
)
from .schema import TUMBLER
from .model import SpinState, spin_states

#: The reference axis (canonical, 0-based) of each mode: the short axis in SAM, the long in LAM.
REFERENCE_AXIS = {"SAM": 2, "LAM": 0}


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
        return float(np.einsum("nji,j->ni", state.attitude(time), L)[0, 1])

    R = state.attitude(t)
    y = np.einsum("nji,j->ni", R, L)[:, 1]
    up = np.flatnonzero((y[:-1] < 0.0) & (y[1:] >= 0.0))
    first, last = (brentq(m2, t[j], t[j + 1], xtol=1e-300, rtol=4 * np.finfo(float).eps)
                   for j in (up[0], up[-1]))
    cycles = len(up) - 1
    times = np.concatenate([[first], t[(t > first) & (t < last)], [last]])
    axis = state.attitude(times)[:, :, REFERENCE_AXIS[state.mode]]  # reference axis, space
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


def draw_members(ratios, ratio_errors, periods, period_errors, members: int, seed: int
                 ) -> np.ndarray:
    """Normal draws of (I1/I3, I2/I3, P_psi, P_phi), shape (members, 4), member 0 the nominal."""
    rng = np.random.default_rng(seed)
    mean = np.array([*ratios, *periods], float)
    sigma = np.array([*ratio_errors, *period_errors], float)
    draws = mean + sigma * rng.standard_normal((members, 4))
    draws[0] = mean
    return draws


def measure_tumblers(draws, mode: str, sun, observer, *, periods: float = 20.0,
                     samples: int = 2048, rings: int = 12, law: str = "lommel-seeliger"):
    """Each member's spin state of ``mode`` and light curve; the study's Dataset.

    Parameters
    ----------
    draws : ndarray, shape (N, 4)
        (I1/I3, I2/I3, P_psi, P_phi) per member (:func:`draw_members`), periods in hours.
    mode : str
        ``"SAM"`` or ``"LAM"``: the mode the paper gives (the lowest-energy state of that mode
        when several fit).
    sun, observer : array_like, shape (3,)
        Directions in the frame of L (Z along L).
    periods, samples, rings, law
        Light-curve length in the longer period, samples, rings of the member's uniform
        ellipsoid mesh (:func:`~stability.asteroid.lightcurve.ellipsoid_mesh`), scattering law.

    Returns
    -------
    xarray.Dataset
        As declared in :data:`stability.asteroid.schema.TUMBLER`.
    """
    import xarray as xr

    n = len(draws)
    out = {name: np.full(n, np.nan) for name in
           ("energy_ratio", "momentum_per_i3", "frequency_predicted", "frequency_measured")}
    fitted = np.zeros(n, np.int32)
    for j, (r13, r23, p_psi, p_phi) in enumerate(draws):
        try:
            states = spin_states((r13, r23, 1.0), p_psi, p_phi, mode)
        except ValueError:  # a draw outside the physical moments or periods
            continue
        if not states:
            continue
        s = states[0]
        fitted[j] = 1
        shape = ellipsoid_mesh(*ellipsoid_axes(s.moments), n=rings)
        peaks, _ = lightcurve_peaks(s, sun, observer, periods=periods, samples=samples,
                                    count=1, shape=shape, law=law)
        out["energy_ratio"][j] = s.energy_ratio
        out["momentum_per_i3"][j] = s.momentum
        out["frequency_predicted"][j] = 24.0 * main_frequencies(s)[0]
        out["frequency_measured"][j] = 24.0 * peaks[0]
    data = {"moment_ratio_13": draws[:, 0], "moment_ratio_23": draws[:, 1],
            "period_psi": draws[:, 2], "period_phi": draws[:, 3], **out, "fitted": fitted}
    ds = xr.Dataset({k: (cv.MEMBER, np.asarray(v)) for k, v in data.items()},
                    coords={cv.MEMBER: np.arange(n)})
    for name, var in TUMBLER.variables.items():
        ds[name].attrs.update(var.attrs())
    ds.attrs["mode"] = mode
    return ds


__all__ = ["REFERENCE_AXIS", "draw_members", "lightcurve_peaks", "measure_tumblers",
           "measured_periods"]
