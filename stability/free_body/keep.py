"""What a free-body ensemble keeps of its members: :class:`Keep`, one small frozen object.

Beside the per-member summaries, which every ensemble keeps (flips, crossings, the largest
perpendicular amplitude, the passage times through amplitude levels, the end errors of the
invariants, tracked at every step inside the member loop), an ensemble keeps the time series of
w every ``save_every`` steps (0: none, the summaries only), and with ``attitude`` each member's
attitude too (the scene ``free_body_attitude``). ``divergence_tolerance`` is the rule by which a
member's numbers are kept as trusted: past it in relative energy or |L|, the member is labelled
diverged and its numbers are NaN.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..util.checks import positive_float, positive_int

#: A member whose relative energy or |L| error at the end exceeds this is "diverged".
DEFAULT_DIVERGENCE_TOLERANCE = 1e-2


@dataclass(frozen=True)
class Keep:
    """What :func:`stability.run_ensemble` keeps; the fields are the constructor's parameters.

    Parameters
    ----------
    save_every : int, default 1
        Keep w every ``save_every`` steps (the Dataset's ``w``, over ``time``); 0 keeps the
        per-member summaries only (memory about ``ensemble_memory(members, 0)``, ~250 bytes a
        member: for ensembles of 1e6 members and more, and for many small ensembles). The
        summaries do not depend on it: they are tracked at every step, bitwise those of a
        time-series run.
    levels : array_like, shape (n_levels,), optional
        Ascending perpendicular-amplitude levels in rad/s for ``passage_time``; default
        ``DEFAULT_LEVELS`` times the spin (with ``starts``, times the median |w0|).
    attitude : bool, default False
        Keep each member's attitude too (the scene ``free_body_attitude``, a method of
        ``stability.free_body.attitude.attitude_methods()``, time series only, on the CPU; w is
        bitwise the same): every member starts at the identity, and the Dataset gains ``q``,
        ``q_norm_error`` and ``attitude_error``, the angle to the exact attitude.
    divergence_tolerance : float, default 1e-2
        A member whose relative energy or |L| error at the end exceeds this is "diverged".

    Examples
    --------
    >>> Keep(save_every=0).summaries_only
    True
    """

    save_every: int = 1
    levels: object = None
    attitude: bool = False
    divergence_tolerance: float = DEFAULT_DIVERGENCE_TOLERANCE

    def __post_init__(self):
        object.__setattr__(self, "save_every",
                           positive_int("save_every", self.save_every, allow_zero=True))
        if not isinstance(self.attitude, (bool, np.bool_)):
            raise ValueError(f"attitude must be True or False, got {self.attitude!r:.80}")
        if self.attitude and self.save_every == 0:
            raise ValueError("the attitude is kept with the time series: give save_every >= 1 "
                             "with attitude=True")
        object.__setattr__(self, "divergence_tolerance", positive_float(
            "divergence_tolerance", self.divergence_tolerance))

    @property
    def summaries_only(self) -> bool:
        """No time series: the per-member summaries only."""
        return self.save_every == 0

    @property
    def scene(self) -> str:
        """The scene integrated: ``"free_body_attitude"`` with the attitude, else
        ``"free_body"``."""
        return "free_body_attitude" if self.attitude else "free_body"

    def plan_arguments(self) -> dict:
        """These choices as :func:`stability.free_body.ensemble_plan.plan_ensemble` takes them."""
        return {"save_every": max(self.save_every, 1), "summaries_only": self.summaries_only,
                "levels": self.levels, "scene": self.scene,
                "divergence_tolerance": self.divergence_tolerance}


def kept(keep) -> Keep:
    """``keep`` as :class:`Keep` (None: the defaults); ValueError for anything else."""
    if keep is None:
        return Keep()
    if not isinstance(keep, Keep):
        raise ValueError(f"keep must be a stability.Keep, got {type(keep).__name__}; e.g. "
                         "Keep(save_every=10), or Keep(save_every=0) for the summaries only")
    return keep
