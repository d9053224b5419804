"""What the heavy-top studies share: the keys of a symmetric top, its methods, its checks."""

from __future__ import annotations

from ...study.config import ConfigError, Key
from ..methods import METHODS
from ..model import HeavyTop


def top_methods() -> tuple:
    """Names of the heavy top's methods (the ``method`` key's choices)."""

    return tuple(METHODS)


def top_keys(length: Key) -> tuple:
    """The ``[top]`` keys of a symmetric disk-like top: mass, central moments, ``length`` (one
    distance or a list, as the study needs) and gravity."""
    return (
        Key("mass", "float", 0.1, "mass M", unit="kg", minimum=0.0, exclusive_minimum=True),
        Key("central_moments", "floats", [2.25e-5, 2.25e-5, 4.5e-5],
            "principal moments about the centre of mass, axis 3 the symmetry axis "
            "(I1 = I2); default: a disk of radius 3 cm", unit="kg m2", minimum=0.0,
            exclusive_minimum=True, length=3),
        length,
        Key("gravity", "float", 9.80665, "g", unit="m s-2", minimum=0.0,
            exclusive_minimum=True),
    )


def symmetric_top(config: dict, length: float, source: str = "<config>", name: str = "top"):
    """The :class:`~stability.heavy_top.model.HeavyTop` of ``[top]`` at ``length``; a ConfigError
    for a top that is not symmetric or not physical."""

    t = config["top"]
    I1, I2, _ = t["central_moments"]
    if I1 != I2:
        raise ConfigError(f"must have I1 = I2 (a symmetric top), got {I1:g} and {I2:g}",
                          source, "top", "central_moments")
    try:
        return HeavyTop(t["mass"], length, tuple(t["central_moments"]), t["gravity"], name=name)
    except ValueError as exc:
        raise ConfigError(str(exc), source, "top", "central_moments") from None


def check_spins(config: dict, source: str) -> None:
    """A non-empty ``[spins]`` range."""
    s = config["spins"]
    if s["max"] <= s["min"]:
        raise ConfigError(f"must exceed [spins] min ({s['min']:g}), got {s['max']:g}", source,
                          "spins", "max")
