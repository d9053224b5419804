"""What is uncertain, and how: :class:`Dispersions`, named parameters each with a distribution.

A dispersion maps a design of the unit cube (:mod:`.designs`, one row per member) to each
member's values: every dispersed parameter takes one column through its distribution's inverse
CDF (:mod:`.distributions`); the misalignment of the principal axes (``"axes"``) takes three:
the angle of a rotation from its distribution, and its axis uniform on the sphere
(z = 2 u - 1, longitude 2 pi u'). A parameter left out keeps its nominal value.

The principal moments ``I1, I2, I3`` are kept physical: each > 0 and each at most the sum of
the other two (the triangle inequality, which every body with mass obeys). Dispersions whose
supports could break it are refused before any work, unless ``truncate`` is set: the moment of
the largest nominal value, Ic, is then drawn from its distribution truncated to
[|Ia - Ib|, Ia + Ib] given the member's other two (the same unit column, so a design stays a
design and the Sobol' indices are those of the independent unit inputs).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from .distributions import distribution

#: The principal moments, as a dispersion names them.
MOMENTS = ("I1", "I2", "I3")
#: A dispersion of all three moments alike (each relative to its own nominal value).
ALL_MOMENTS = "moments"
#: The misalignment of the principal axes: a rotation by a random angle (rad).
AXES = "axes"


@dataclass(frozen=True)
class Dispersions:
    """Named parameters with their distributions, and the nominal values of the rest.

    Build it with :func:`dispersions`, which checks it.

    Attributes
    ----------
    distributions : Mapping of str to Distribution
        The dispersed parameters, in order (the Sobol' parameters).
    nominal : Mapping of str to float
        Every parameter's undispersed value.
    truncated : str or None
        The moment truncated to the triangle inequality, or None.
    """

    distributions: Mapping = field(repr=False)
    nominal: Mapping = field(repr=False)
    truncated: str | None = None

    @property
    def names(self) -> tuple[str, ...]:
        """The dispersed parameters, in order."""
        return tuple(self.distributions)

    def columns(self) -> tuple[str, ...]:
        """The parameter each column of a unit design serves (``"axes"`` three times)."""
        return tuple(name for name in self.names for _ in range(3 if name == AXES else 1))

    def draw(self, unit) -> dict:
        """Each member's values from the rows of a unit design.

        Parameters
        ----------
        unit : array_like, shape (N, len(columns()))
            Points of the unit cube (:func:`stability.uncertainty.designs.unit_design`).

        Returns
        -------
        dict
            Every parameter of :attr:`nominal` -> ndarray (N,), the nominal value where it is
            not dispersed; with ``"axes"`` dispersed also ``"axes_angle"`` (N,) in rad and
            ``"axes_axis"`` (N, 3), the rotation's unit axis.
        """
        unit = np.asarray(unit, dtype=float)
        columns = self.columns()
        if unit.ndim != 2 or unit.shape[1] != len(columns):
            raise ValueError(f"unit must have shape (members, {len(columns)}), one column per "
                             f"{', '.join(columns)}; got {unit.shape}")
        n = unit.shape[0]
        at = {name: columns.index(name) for name in self.names}
        out = {name: np.full(n, float(value)) for name, value in self.nominal.items()}
        for name, dist in self.distributions.items():
            if name != AXES and name != self.truncated:
                out[name] = dist.ppf(unit[:, at[name]])
        if self.truncated is not None:
            a, b = (out[m] for m in MOMENTS if m != self.truncated)
            out[self.truncated] = self.distributions[self.truncated].ppf(
                unit[:, at[self.truncated]], lower=np.abs(a - b), upper=a + b)
        if AXES in self.distributions:
            k = at[AXES]
            out[AXES] = out["axes_angle"] = self.distributions[AXES].ppf(unit[:, k])
            z = 2.0 * unit[:, k + 1] - 1.0
            phi = 2.0 * math.pi * unit[:, k + 2]
            r = np.sqrt(np.maximum(1.0 - z * z, 0.0))
            out["axes_axis"] = np.column_stack([r * np.cos(phi), r * np.sin(phi), z])
        return out


def dispersions(spec: Mapping, nominal: Mapping, *, truncate: bool = False) -> Dispersions:
    """Checked dispersions: one-line ValueError, before any work, for a bad one.

    Parameters
    ----------
    spec : Mapping
        Parameter name -> a distribution's spec (:func:`stability.uncertainty.distributions.
        distribution`), e.g. ``{"moments": {"distribution": "uniform", "relative": 0.05},
        "spin": {"distribution": "normal", "relative": 0.1}}``. ``"moments"`` disperses
        I1, I2 and I3 alike; ``"axes"`` the principal axes by a small angle (rad, nominal 0)
        where the moments are parameters.
    nominal : Mapping of str to float
        The value of every parameter that may be dispersed (a scene's named parameters, a
        body's moments, a spin ...): the names a spec may use.
    truncate : bool, default False
        Keep the moments physical by truncating the largest to the triangle inequality,
        where their dispersions could break it (else that is refused).

    Returns
    -------
    Dispersions
    """
    if not isinstance(spec, Mapping) or not isinstance(nominal, Mapping):
        raise ValueError("dispersions and the nominal values must be mappings by parameter name")
    nominal = dict(nominal)
    for name, value in nominal.items():
        if isinstance(value, bool) or not isinstance(value, (int, float, np.floating)) \
                or not math.isfinite(value):
            raise ValueError(f"nominal value of {name!r} must be a finite number, got {value!r}")
    has_moments = set(MOMENTS) <= set(nominal)
    if has_moments:
        nominal.setdefault(AXES, 0.0)
    known = list(nominal) + ([ALL_MOMENTS] if has_moments else [])
    spec = dict(spec)
    if ALL_MOMENTS in spec and has_moments:
        every = spec.pop(ALL_MOMENTS)
        twice = [m for m in MOMENTS if m in spec]
        if twice:
            raise ValueError(f"dispersion of {twice[0]!r} given twice: alone and in {ALL_MOMENTS!r}")
        spec = {**{m: every for m in MOMENTS}, **spec}
    for name in spec:
        if name not in known:
            raise ValueError(f"unknown parameter {name!r} to disperse; known: {', '.join(known)}")
    if not spec:
        raise ValueError(f"no parameter dispersed; give one of {', '.join(known)}")
    dists = {name: distribution(name, s, float(nominal[name])) for name, s in spec.items()}
    truncated = _physical_moments(dists, nominal, truncate) if has_moments else None
    if AXES in dists and not -math.pi <= dists[AXES].lower < dists[AXES].upper <= math.pi:
        raise ValueError(f"dispersion of {AXES!r}: the angle must stay within [-pi, pi] rad; "
                         "use a uniform or a truncated-normal within it")
    return Dispersions(MappingProxyType(dists), MappingProxyType(nominal), truncated)


def _physical_moments(dists, nominal, truncate) -> str | None:
    """Refuse moments that could be <= 0 or break the triangle inequality (unless truncated:
    then the moment truncated); return that moment or None."""
    bounds = {}
    for m in MOMENTS:
        d = dists.get(m)
        lo, hi = (d.lower, d.upper) if d is not None else (nominal[m], nominal[m])
        if not lo > 0.0:
            raise ValueError(f"dispersion of {m!r} ({d.describe()}) can give a moment <= 0 "
                             "kg m2; use a distribution bounded above 0 (a truncated-normal "
                             "with lower > 0, a uniform or a log-uniform)")
        bounds[m] = (lo, hi)
    broken = [m for m in MOMENTS
              if bounds[m][1] > sum(bounds[o][0] for o in MOMENTS if o != m)]
    if not broken:
        return None
    m = broken[0]
    a, b = (o for o in MOMENTS if o != m)
    if not truncate:
        raise ValueError(
            f"the dispersions of the moments can break the triangle inequality ({m} up to "
            f"{bounds[m][1]:.6g} > {a} + {b} down to {bounds[a][0] + bounds[b][0]:.6g} kg m2): "
            "narrow them, or truncate the largest moment to it (truncate = true)")
    c = max(MOMENTS, key=lambda k: nominal[k])
    if c not in dists:
        raise ValueError(f"truncation to the triangle inequality needs the largest moment {c} "
                         "dispersed; disperse it too, or narrow the others")
    a, b = (o for o in MOMENTS if o != c)
    (la, ha), (lb, hb), (lc, hc) = bounds[a], bounds[b], bounds[c]
    if not (lc < la + lb and hc > max(ha - lb, hb - la)):
        raise ValueError(f"truncating {c} to [|{a} - {b}|, {a} + {b}] can leave nothing of its "
                         f"dispersion ({dists[c].describe()}); widen it or narrow {a} and {b}")
    return c  # the lower bound |Ia - Ib| keeps the other two inequalities
