"""A step and a horizon chosen from the physics of a spin, for runs that do not give them.

``run_ensemble(body, axis=2, spin=10.0)`` and ``integrate(body, w0)`` need no step and no
horizon: the step keeps the angle turned per step, ``h max|w|``, at :data:`DEFAULT_STEP_ANGLE`
(``max|w|`` over the motion, :func:`stability.free_body.starts.max_angular_speed`), and the
horizon covers :data:`DEFAULT_FLIPS` flip intervals ``2K/nu`` of the exact motion
(:func:`stability.free_body.exact.flip_intervals`): flips about the intermediate axis, half
periods of the small oscillation ``pi / Omega`` about a stable one (Landau & Lifshitz,
Mechanics, section 37). A motion that never flips (a sphere, a steady spin)
gets :data:`FALLBACK_TURNS` turns of the spin instead. Both rules are written into the Dataset
(``h_rule``, ``t_end_rule``).
"""

from __future__ import annotations

import math

import numpy as np

from ..util.checks import positive_float, positive_int
from .exact import flip_intervals
from .starts import max_angular_speed

#: Default angle turned per step, h max|w| (rad): 314 steps a turn, well inside every method's
#: ``max_step_angle`` (1 rad and more) and accurate to about 1e-6 in Omega^2 for lp2.
DEFAULT_STEP_ANGLE = 0.02
#: Flip intervals 2K/nu the default horizon covers (two periods of w).
DEFAULT_FLIPS = 4
#: Turns of the spin the horizon covers when the motion has no finite flip interval.
FALLBACK_TURNS = 20
#: Perturbation and ensemble size of ``run_ensemble`` when neither they nor ``starts`` are given.
DEFAULT_EPSILON = 1e-3
DEFAULT_MEMBERS = 100


def nominal_start(axis: int, spin: float, epsilon: float) -> np.ndarray:
    """``W e_axis + epsilon W (e_b + e_c) / sqrt(2)``: a start the default step and horizon are
    chosen for, its perturbation shared by the two other axes (1-based ``axis``)."""
    w0 = np.zeros(3)
    w0[axis - 1] = spin
    for other in {1, 2, 3} - {axis}:
        w0[other - 1] = epsilon * spin / math.sqrt(2.0)
    return w0


def default_step(max_speed: float, t_end: float | None = None,
                 save_every: int = 1) -> tuple[float, str]:
    """The step for a motion whose |w| reaches ``max_speed`` (rad/s), and the rule, in words.

    With a horizon ``t_end`` (s) given, the step is shortened to the largest ``t_end / N`` no
    longer than that, ``N`` a multiple of ``save_every``, so that the horizon is a whole number
    of saved steps.
    """
    if not max_speed > 0.0:
        raise ValueError("w = 0 at every start: a body at rest has no time scale to choose the "
                         "step from; give h and t_end")
    h = DEFAULT_STEP_ANGLE / max_speed
    rule = f"h = {DEFAULT_STEP_ANGLE:g} rad / max|w| ({max_speed:.6g} rad/s)"
    if t_end is not None:
        steps = save_every * max(1, math.ceil(t_end / (h * save_every) - 1e-9))
        h = t_end / steps
        rule += f", shortened to t_end / {steps}"
    return h, rule + ", chosen by default"


def default_horizon(body, starts, h: float, save_every: int = 1) -> tuple[float, str]:
    """A horizon of :data:`DEFAULT_FLIPS` flip intervals (the median over ``starts`` (N, 3),
    rad/s), a whole number of ``save_every`` steps of ``h``; and the rule, in words."""
    starts = np.atleast_2d(np.asarray(starts, dtype=float))
    intervals = flip_intervals(body, starts)[0]
    interval = float(np.median(intervals)) if intervals.size else math.inf
    if math.isfinite(interval) and interval > 0.0:
        wanted = DEFAULT_FLIPS * interval
        rule = (f"{DEFAULT_FLIPS} flip intervals 2K/nu of the exact motion, "
                f"{DEFAULT_FLIPS} x {interval:.6g} s = {wanted:.6g} s")
    else:
        speed = float(np.median(np.linalg.norm(starts, axis=1)))
        wanted = FALLBACK_TURNS * 2.0 * math.pi / speed
        rule = (f"{FALLBACK_TURNS} turns of the spin (the motion has no finite flip "
                f"interval), {wanted:.6g} s")
    unit = h * save_every
    t_end = max(1, math.ceil(wanted / unit - 1e-9)) * unit
    return t_end, (f"t_end = {rule}, rounded up to whole saved steps: {t_end:.6g} s, chosen "
                   "by default")


def default_timescales(body, starts, h=None, t_end=None, save_every=1) -> tuple:
    """``(h, t_end, rules)`` for the motions from ``starts`` (N, 3), rad/s: each of ``h`` and
    ``t_end`` that is None chosen by :func:`default_step` (over the largest ``|w|`` of any
    start) and :func:`default_horizon`, and the rules chosen, by attribute name (``h_rule``,
    ``t_end_rule``). A default step is fitted to a ``t_end`` given where it and ``save_every``
    are valid; where they are not, they are returned as given, for the caller to name."""
    rules = {}
    if h is None:
        try:
            horizon = (positive_float("t_end", t_end, "s"), positive_int("save_every", save_every))
        except (TypeError, ValueError):
            horizon = ()  # none given, or one the caller's checks name
        speed = float(np.max(max_angular_speed(body.moments, starts)))
        h, rules["h_rule"] = default_step(speed, *horizon)
    if t_end is None:
        t_end, rules["t_end_rule"] = default_horizon(
            body, starts, positive_float("h", h, "s"), positive_int("save_every", save_every))
    return h, t_end, rules
