"""The distributions a dispersion draws from: uniform, log-uniform, normal and truncated normal.

Each is a :class:`Distribution` that maps points ``u`` of the unit interval to values by its
inverse cumulative distribution function (``x = F^-1(u)``), so that random, Sobol' and Latin
hypercube designs of the unit cube (:mod:`.designs`) become draws of any distribution, and a
truncation to an interval ``[a, b]`` (the triangle inequality of the moments) is the same map
on ``F(a) + u (F(b) - F(a))`` (inverse transform sampling; Devroye, *Non-Uniform Random Variate
Generation*, 1986, section II.2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import ndtr, ndtri

#: The distributions by name, with the keys each takes in a study file or a spec mapping.
KINDS = {
    "uniform": "lower and upper, or relative (a half-width relative to the nominal value)",
    "log-uniform": "lower and upper (> 0), or decades (centred on the nominal value)",
    "normal": "sigma, or relative (sigma relative to the nominal value); mean (the nominal)",
    "truncated-normal": "as normal, with lower and/or upper",
}
_KEYS = {"distribution", "lower", "upper", "relative", "decades", "sigma", "mean"}

#: Unit points are kept this far inside (0, 1): a scrambled Sobol' point may be exactly 0.
_EDGE = 2.0**-53


@dataclass(frozen=True)
class Distribution:
    """One distribution of one parameter, as its inverse CDF on the unit interval.

    Attributes
    ----------
    kind : str
        A key of :data:`KINDS`.
    loc, scale : float
        The mean and standard deviation of a (truncated) normal; for the others unused (0, 1).
    lower, upper : float
        The support: finite for a uniform or log-uniform, +-inf for a normal, the truncation of
        a truncated normal.
    """

    kind: str
    loc: float = 0.0
    scale: float = 1.0
    lower: float = -math.inf
    upper: float = math.inf

    def cdf(self, x):
        """F(x), the probability of a value <= ``x``."""
        x = np.asarray(x, dtype=float)
        if self.kind == "uniform":
            return np.clip((x - self.lower) / (self.upper - self.lower), 0.0, 1.0)
        if self.kind == "log-uniform":
            lo, hi = math.log(self.lower), math.log(self.upper)
            with np.errstate(divide="ignore", invalid="ignore"):
                return np.clip((np.log(np.maximum(x, 0.0)) - lo) / (hi - lo), 0.0, 1.0)
        a, b = self._normal_bounds()
        return np.clip((ndtr((x - self.loc) / self.scale) - a) / (b - a), 0.0, 1.0)

    def ppf(self, u, lower=None, upper=None) -> np.ndarray:
        """The values at unit points ``u``: F^-1(u), or with ``lower``/``upper`` (arrays
        broadcast against ``u``) the distribution truncated further to [lower, upper]:
        F^-1(F(lower) + u (F(upper) - F(lower)))."""
        u = np.clip(np.asarray(u, dtype=float), _EDGE, 1.0 - _EDGE)
        if lower is not None or upper is not None:
            a = self.cdf(self.lower if lower is None else lower)
            b = self.cdf(self.upper if upper is None else upper)
            u = a + u * (b - a)
        if self.kind == "uniform":
            x = self.lower + u * (self.upper - self.lower)
        elif self.kind == "log-uniform":
            lo, hi = math.log(self.lower), math.log(self.upper)
            x = np.exp(lo + u * (hi - lo))
        else:
            a, b = self._normal_bounds()
            x = self.loc + self.scale * ndtri(a + u * (b - a))
        x = np.clip(x, self.lower, self.upper)
        if lower is not None:
            x = np.maximum(x, lower)
        if upper is not None:
            x = np.minimum(x, upper)
        return x

    def _normal_bounds(self) -> tuple[float, float]:
        """F of the standard normal at the truncation points (0 and 1 for a normal)."""
        return (float(ndtr((self.lower - self.loc) / self.scale)),
                float(ndtr((self.upper - self.loc) / self.scale)))

    def describe(self) -> str:
        """The distribution in words, for attributes and tables."""
        if self.kind in ("uniform", "log-uniform"):
            return f"{self.kind} on [{self.lower:.6g}, {self.upper:.6g}]"
        text = f"{self.kind} (mean {self.loc:.6g}, sigma {self.scale:.6g})"
        if self.kind == "truncated-normal":
            text += f" on [{self.lower:.6g}, {self.upper:.6g}]"
        return text


def distribution(name: str, spec, nominal: float) -> Distribution:
    """The distribution a spec mapping describes, checked; one-line ValueError otherwise.

    Parameters
    ----------
    name : str
        The parameter, for the messages.
    spec : Mapping
        ``{"distribution": kind, ...}`` with the keys of :data:`KINDS`, e.g.
        ``{"distribution": "uniform", "relative": 0.05}`` (the nominal value +-5 %) or
        ``{"distribution": "log-uniform", "lower": 1e-4, "upper": 1e-2}``.
    nominal : float
        The parameter's undispersed value (the centre of a relative spread, the mean of a
        normal by default).

    Returns
    -------
    Distribution
    """
    where = f"dispersion of {name!r}"
    if not isinstance(spec, dict):
        raise ValueError(f"{where} must be a table such as {{distribution = \"uniform\", "
                         f"relative = 0.05}}, got {spec!r:.80}")
    unknown = sorted(set(spec) - _KEYS)
    if unknown:
        raise ValueError(f"{where}: unknown key {unknown[0]!r}; allowed: {', '.join(sorted(_KEYS))}")
    kind = spec.get("distribution")
    if kind not in KINDS:
        raise ValueError(f"{where}: distribution must be one of {', '.join(KINDS)}, got {kind!r}")
    numbers = {}
    for key in _KEYS - {"distribution"}:
        if key in spec:
            value = spec[key]
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ValueError(f"{where}: {key} must be a finite number, got {value!r:.80}")
            numbers[key] = float(value)
    for key in ("relative", "sigma", "decades"):
        if numbers.get(key, 1.0) <= 0.0:
            raise ValueError(f"{where}: {key} (a spread) must be > 0, got {numbers[key]:g}")
    allowed = {"uniform": {"lower", "upper", "relative"},
               "log-uniform": {"lower", "upper", "decades"},
               "normal": {"sigma", "relative", "mean"},
               "truncated-normal": {"sigma", "relative", "mean", "lower", "upper"}}[kind]
    extra = sorted(set(numbers) - allowed)
    if extra:
        raise ValueError(f"{where}: a {kind} takes {KINDS[kind]}, not {extra[0]}")
    if kind == "uniform":
        return _bounded(where, kind, numbers, nominal, lambda r: (nominal - r * abs(nominal),
                                                                  nominal + r * abs(nominal)))
    if kind == "log-uniform":
        out = _bounded(where, kind, numbers, nominal, None)
        if out.lower <= 0.0:
            raise ValueError(f"{where}: a log-uniform needs lower > 0, got {out.lower:g}")
        return out
    if ("sigma" in numbers) == ("relative" in numbers):
        raise ValueError(f"{where}: a {kind} takes one of sigma or relative")
    mean = numbers.get("mean", nominal)
    sigma = numbers.get("sigma", numbers.get("relative", 0.0) * abs(mean))
    if not sigma > 0.0:
        raise ValueError(f"{where}: sigma must be > 0, got {sigma:g} (a relative spread of a "
                         "mean of 0)")
    if kind == "normal":
        return Distribution(kind, mean, sigma)
    lower, upper = numbers.get("lower", -math.inf), numbers.get("upper", math.inf)
    if "lower" not in numbers and "upper" not in numbers:
        raise ValueError(f"{where}: a truncated-normal needs lower and/or upper")
    if not lower < upper:
        raise ValueError(f"{where}: lower must be < upper, got {lower:g} >= {upper:g}")
    d = Distribution(kind, mean, sigma, lower, upper)
    a, b = d._normal_bounds()
    if not b - a > 1e-12:
        raise ValueError(f"{where}: [{lower:g}, {upper:g}] holds no probability of a normal "
                         f"of mean {mean:g} and sigma {sigma:g}")
    return d


def _bounded(where, kind, numbers, nominal, relative) -> Distribution:
    """A uniform or log-uniform from lower and upper, or from its relative spread."""
    spread = "relative" if kind == "uniform" else "decades"
    if spread in numbers:
        if "lower" in numbers or "upper" in numbers:
            raise ValueError(f"{where}: give {spread} or lower and upper, not both")
        if kind == "log-uniform":
            if not nominal > 0.0:
                raise ValueError(f"{where}: decades about a nominal value of {nominal:g}; "
                                 "a log-uniform needs values > 0")
            half = 10.0 ** (numbers["decades"] / 2.0)
            lower, upper = nominal / half, nominal * half
        else:
            if nominal == 0.0:
                raise ValueError(f"{where}: a relative spread of a nominal value of 0; give "
                                 "lower and upper")
            lower, upper = relative(numbers["relative"])
    elif "lower" in numbers and "upper" in numbers:
        lower, upper = numbers["lower"], numbers["upper"]
    else:
        raise ValueError(f"{where}: a {kind} takes {KINDS[kind]}")
    if not lower < upper:
        raise ValueError(f"{where}: lower must be < upper, got {lower:g} >= {upper:g}")
    return Distribution(kind, lower=lower, upper=upper)
