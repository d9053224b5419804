"""Synthetic light curves of a tumbling body: facets, a scattering law, the exact attitude.

The brightness of a convex body of facets (unit outward normals n_k, areas A_k) lit from the
unit direction s and seen from o (both from the body towards the Sun and the observer, far
away) is the sum over the facets that are lit and seen, mu0 = n . s > 0 and mu = n . o > 0,

    Lommel-Seeliger:  F = sum A_k mu0 mu / (mu0 + mu)      Lambert:  F = sum A_k mu0 mu

(Kaasalainen, Torppa & Muinonen, Icarus 153, 37 (2001); Muinonen & Lumme, A&A 584, A23 (2015)),
in units of the albedo times the flux; no shadowing, so exact for convex shapes only. s and o
are turned into the body frame by the state's exact attitude
(:meth:`stability.asteroid.model.SpinState.attitude`) in the frame of L: space Z along the
angular momentum.

A tumbler's light curve is periodic in neither period alone: its spectrum holds the
combinations j f_psi + k f_phi of the two fundamental frequencies (Kaasalainen 2001, A&A 376,
302, section 3), the strongest, for an elongated body, where the long axis turns about L:
2 (f_phi - f_psi) in SAM (the P1 of Apophis, Pravec et al. 2014), 2 f_phi and 2 (f_phi + f_psi)
in LAM (the 2.77 and 6.42 cycles/day of 'Oumuamua, Belton et al. 2018)
(:func:`main_frequencies`).
"""

from __future__ import annotations

import math

import numpy as np

from ..util.checks import positive_int, real_array
from .model import SpinState

#: The scattering laws by name.
LAWS = ("lommel-seeliger", "lambert")


def ellipsoid_mesh(a, b, c, n: int = 48) -> tuple[np.ndarray, np.ndarray]:
    """A closed triangle mesh of the ellipsoid x^2/a^2 + y^2/b^2 + z^2/c^2 = 1, facets outward.

    Parameters
    ----------
    a, b, c : float
        Semi-axes along x, y, z (a >= b >= c puts the long axis on canonical axis 1).
    n : int
        Rings of latitude (2n meridians); 4 n (n - 1) triangles.

    Returns
    -------
    vertices : ndarray, shape (V, 3)
    faces : ndarray of int, shape (F, 3)
        Counter-clockwise seen from outside.
    """
    n = positive_int("n", n)
    if n < 3:
        raise ValueError(f"n must be >= 3 rings of latitude, got {n}")
    theta = np.linspace(0.0, math.pi, n + 1)[1:-1]
    phi = np.linspace(0.0, 2.0 * math.pi, 2 * n, endpoint=False)
    th, ph = np.meshgrid(theta, phi, indexing="ij")
    ring = np.stack([a * np.sin(th) * np.cos(ph), b * np.sin(th) * np.sin(ph),
                     c * np.cos(th)], axis=-1).reshape(-1, 3)
    vertices = np.vstack([[0.0, 0.0, c], ring, [0.0, 0.0, -c]])
    m = 2 * n
    idx = 1 + np.arange((n - 1) * m).reshape(n - 1, m)
    nxt = np.roll(idx, -1, axis=1)
    faces = [np.stack([np.zeros(m, int), idx[0], nxt[0]], axis=1)]
    for i in range(n - 2):
        faces.append(np.stack([idx[i], idx[i + 1], nxt[i + 1]], axis=1))
        faces.append(np.stack([idx[i], nxt[i + 1], nxt[i]], axis=1))
    south = len(vertices) - 1
    faces.append(np.stack([np.full(m, south), nxt[-1], idx[-1]], axis=1))
    return vertices, np.vstack(faces)


def facets(vertices, faces) -> tuple[np.ndarray, np.ndarray]:
    """Unit outward normals (F, 3) and areas (F,) of a triangle mesh."""
    v = real_array("vertices", vertices)
    f = np.asarray(faces)
    if v.ndim != 2 or v.shape[1] != 3 or f.ndim != 2 or f.shape[1] != 3 or f.size == 0:
        raise ValueError(f"a mesh is vertices (V, 3) and faces (F, 3), got {v.shape} and "
                         f"{f.shape}")
    if not np.issubdtype(f.dtype, np.integer) or f.min() < 0 or f.max() >= len(v):
        raise ValueError(f"faces must index the {len(v)} vertices with integers")
    cross = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    norm = np.linalg.norm(cross, axis=1)
    keep = norm > 0.0
    return cross[keep] / norm[keep, None], 0.5 * norm[keep]


def brightness(normals, areas, sun, observer, law: str = "lommel-seeliger") -> np.ndarray:
    """Disk-integrated brightness for Sun and observer directions in the body frame.

    Parameters
    ----------
    normals : ndarray, shape (F, 3)
        Unit outward facet normals; ``areas`` (F,) their areas.
    sun, observer : ndarray, shape (n, 3)
        Unit directions towards the Sun and the observer, body frame, one row per time.
    law : str
        ``"lommel-seeliger"`` or ``"lambert"`` (module docstring).

    Returns
    -------
    ndarray, shape (n,)
        Brightness in units of (albedo x flux) x area.
    """
    if law not in LAWS:
        raise ValueError(f"law must be one of {', '.join(map(repr, LAWS))}, got {law!r}")
    out = np.empty(len(sun))
    step = max(1, 2**22 // max(1, len(areas)))
    for lo in range(0, len(sun), step):
        mu0 = np.clip(sun[lo:lo + step] @ normals.T, 0.0, None)
        mu = np.clip(observer[lo:lo + step] @ normals.T, 0.0, None)
        if law == "lambert":
            term = mu0 * mu
        else:
            total = mu0 + mu
            term = np.divide(mu0 * mu, total, out=np.zeros_like(total), where=total > 0.0)
        out[lo:lo + step] = term @ areas
    return out


def _direction(name, value) -> np.ndarray:
    d = real_array(name, value)
    if d.shape != (3,) or not np.all(np.isfinite(d)) or not np.any(d):
        raise ValueError(f"{name} must be a non-zero direction of shape (3,), got {d.tolist()}")
    return d / np.linalg.norm(d)


def lightcurve(state: SpinState, t, sun, observer, shape=None,
               law: str = "lommel-seeliger") -> np.ndarray:
    """Brightness of a tumbling body over time, from the exact attitude of ``state``.

    Parameters
    ----------
    state : SpinState
        The tumbler (:func:`stability.asteroid.model.spin_states`); the attitude starts
        with L along space Z.
    t : array_like, shape (n,)
        Times, in the state's time unit.
    sun, observer : array_like, shape (3,)
        Directions towards the Sun and the observer in the frame of L (Z along L), fixed.
    shape : (vertices, faces), optional
        The body's facets in its canonical principal frame (axis 1 the long one); default the
        uniform ellipsoid of the state's moments (:func:`ellipsoid_axes`).
    law : str
        The scattering law (:data:`LAWS`).

    Returns
    -------
    ndarray, shape (n,)
    """
    if not isinstance(state, SpinState):
        raise ValueError(f"state must be a SpinState, got {type(state).__name__}")
    t = np.atleast_1d(real_array("t", t))
    s, o = _direction("sun", sun), _direction("observer", observer)
    if shape is None:
        shape = ellipsoid_mesh(*ellipsoid_axes(state.moments))
    normals, areas = facets(*shape)
    R = state.attitude(t)  # body to space; rows of R^T are the body axes in space
    return brightness(normals, areas, np.einsum("nji,j->ni", R, s),
                      np.einsum("nji,j->ni", R, o), law)


def ellipsoid_axes(moments) -> np.ndarray:
    """Semi-axes (a, b, c), a >= b >= c, of the uniform ellipsoid with these moment ratios.

    From I1 : I2 : I3 = (b^2 + c^2) : (a^2 + c^2) : (a^2 + b^2), so a^2 ∝ I2 + I3 - I1 (and
    cyclic); scaled to a = 1. Needs the triangle inequality.
    """
    I1, I2, I3 = np.asarray(moments, float)
    sq = np.array([I2 + I3 - I1, I1 + I3 - I2, I1 + I2 - I3])
    if np.any(sq <= 0.0):
        raise ValueError(f"moments {[I1, I2, I3]} are those of no ellipsoid (I1 + I2 > I3 "
                         "needed)")
    return np.sqrt(sq / sq[0])


def main_frequencies(state: SpinState) -> np.ndarray:
    """The light curve's strongest frequencies by theory (module docstring), cycles per time
    unit: SAM 2 (f_phi - f_psi); LAM 2 f_phi, 2 (f_phi + f_psi)."""
    f_phi, f_psi = state.frequencies
    if state.mode == "SAM":
        return np.array([2.0 * abs(f_phi - f_psi)])
    return np.array([2.0 * f_phi, 2.0 * (f_phi + f_psi)])


def spectrum(t, flux, oversample: int = 8) -> tuple[np.ndarray, np.ndarray]:
    """Amplitude spectrum of an evenly sampled light curve (Hann window, zero padded).

    Returns
    -------
    frequency : ndarray
        Cycles per time unit of ``t``.
    amplitude : ndarray
        |FFT| of the windowed, mean-removed flux, normalised to its largest value.
    """
    t = np.asarray(t, float)
    y = np.asarray(flux, float)
    y = (y - y.mean()) * np.hanning(y.size)
    n = oversample * y.size
    a = np.abs(np.fft.rfft(y, n))
    return np.fft.rfftfreq(n, t[1] - t[0]), a / a.max()


def spectral_peaks(frequency, amplitude, count: int = 3) -> np.ndarray:
    """The ``count`` highest local maxima of a spectrum, by decreasing height, each refined by
    a parabola through its three highest samples (cycles per time unit)."""
    a = np.asarray(amplitude)
    interior = np.flatnonzero((a[1:-1] > a[:-2]) & (a[1:-1] >= a[2:])) + 1
    top = interior[np.argsort(a[interior])[::-1][:count]]
    df = frequency[1] - frequency[0]
    left, mid, right = a[top - 1], a[top], a[top + 1]
    shift = 0.5 * (left - right) / (left - 2.0 * mid + right)
    return frequency[top] + shift * df


__all__ = ["LAWS", "brightness", "ellipsoid_axes", "ellipsoid_mesh", "facets", "lightcurve",
           "main_frequencies", "spectral_peaks", "spectrum"]
