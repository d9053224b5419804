"""A step and a horizon chosen from the physics of a spin, for runs that do not give them.

``run_ensemble(body, axis=2, spin=10.0)`` and ``integrate(body, w0)`` need no step and no
horizon: the step keeps the angle turned per step, ``h max|w|``, at :data:`DEFAULT_STEP_ANGLE`
(``max|w|`` over the motion, :func:`max_angular_speed`), and the
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


def max_angular_speed(moments, w0) -> np.ndarray:
    """The largest |w| the exact motion from each start reaches, in rad/s; shape (N,).

    The motion keeps the energy E and |L| = |m| (m = I w), so it stays on the set
    ``sum m_i^2 = |L|^2``, ``sum m_i^2 / I_i = 2E`` where ``|w|^2 = sum m_i^2 / I_i^2``; all three
    are linear in ``u_i = m_i^2 >= 0``, so the largest |w| on that set is reached where one
    ``u_i`` is 0 (a vertex of the segment), and is found from the three pairs in closed form.
    It is at least |w0| and at most |L| / min(I) (reached only by spins about the axis of the
    smallest moment); for a spin near a principal axis it is |w0| to first order.

    Parameters
    ----------
    moments : array_like, shape (3,)
        Principal moments in kg m^2.
    w0 : array_like, shape (N, 3)
        Starts in rad/s.
    """
    I = np.asarray(moments, dtype=float)
    w0 = np.atleast_2d(np.asarray(w0, dtype=float))
    # The motion is the same for moments scaled alike, and scales with w0: both are brought to
    # order 1 first, so that the squares below neither overflow (a spin of 1e160 rad/s) nor
    # underflow (moments of 1e-160 kg m^2) into inf or nan.
    I = I / I.max()
    with np.errstate(invalid="ignore", over="ignore"):
        scale = np.max(np.abs(w0), axis=1)
        w0 = w0 / np.where(scale > 0.0, scale, 1.0)[:, None]
    m = w0 * I
    L2 = np.sum(m * m, axis=1)
    E2 = np.sum(m * w0, axis=1)  # 2E
    b, best = 1.0 / I, np.sum(w0 * w0, axis=1)  # |w0|^2: the start is on the set
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for i, j in ((0, 1), (0, 2), (1, 2)):
            if b[i] == b[j]:
                continue  # equal moments: |w| is fixed along this edge
            ui = (E2 - L2 * b[j]) / (b[i] - b[j])
            uj = L2 - ui
            inside = (ui >= 0.0) & (uj >= 0.0)
            best = np.where(inside, np.maximum(best, ui * b[i] ** 2 + uj * b[j] ** 2), best)
    return np.sqrt(best) * scale



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
