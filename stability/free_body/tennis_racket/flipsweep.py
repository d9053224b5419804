"""The flip interval against the perturbation: exact 2K/nu, the ln(1/epsilon) law, measured.

A body spins at W about its intermediate axis 2, nudged by ``epsilon W`` along axis 1
(:func:`flip_sweep_starts`, one start per epsilon). Its exact flip interval 2K/nu and the
small-perturbation asymptote (2/lambda) ln(4/k') (:func:`exact_flip_curve`, literature notes
1.5) are set beside the mean interval between the flips an integrator finds
(:func:`flip_sweep`).
"""

from __future__ import annotations

import math

import numpy as np

from ..model import growth_rate
from ...core.body import RigidBody
from ..spin_ensembles import completed, run_ensembles
from ..keep import Keep
from ..measure import exact_flip_intervals


def flip_sweep_starts(epsilons, spin: float) -> np.ndarray:
    """Starts ``(epsilon W, W, 0)``, one per epsilon; (E, 3) in rad/s.

    Parameters
    ----------
    epsilons : array_like, shape (E,)
        Perturbations along axis 1, relative to the spin.
    spin : float
        W, rad/s, about axis 2.

    Returns
    -------
    ndarray, shape (E, 3)
        Body-frame angular velocities, rad/s.
    """
    epsilons = np.asarray(epsilons, dtype=float)
    w0 = np.zeros((epsilons.size, 3))
    w0[:, 0] = epsilons * spin
    w0[:, 1] = spin
    return w0


def exact_flip_curve(moments, epsilons, spin: float):
    """Exact flip interval 2K/nu and its asymptote (2/lambda) ln(4/k') against epsilon.

    Parameters
    ----------
    moments : array_like, shape (3,)
        (I1, I2, I3) with I1 < I2 < I3: axis 2 is the intermediate one.
    epsilons : array_like, shape (E,)
        Perturbations along axis 1, relative to the spin.
    spin : float
        W, rad/s.

    Returns
    -------
    exact, asymptote : ndarray, shape (E,)
        In s (:func:`stability.free_body.measure.exact_flip_intervals`).
    """

    body = RigidBody(*moments, physical=False)
    return exact_flip_intervals(body, 2, flip_sweep_starts(epsilons, spin))


def flip_sweep(moments, epsilons, spin: float, methods, steps) -> dict:
    """Flip intervals against epsilon for a few shapes, measured by each method.

    Each shape's starts (:func:`flip_sweep_starts`) run as one summaries-only ensemble per
    method, long enough for three flips at the smallest epsilon (2.6 exact intervals).

    Parameters
    ----------
    moments : ndarray, shape (F, 3)
        The shapes.
    epsilons : array_like, shape (E,)
    spin : float
        W, rad/s.
    methods, steps : sequence of str and of float
        Registry names and their steps h, s.

    Returns
    -------
    dict
        ``moments`` (F, 3), ``epsilons`` (E,), ``measured`` (methods, F, E), ``exact`` and
        ``asymptote`` (F, E) in s, ``growth_rate`` (F,) in s-1 (NaN where fewer than two flips
        or a member failed).

    Raises
    ------
    KeyboardInterrupt
        When Ctrl-C stopped an ensemble.
    """

    moments = np.asarray(moments, dtype=float)
    epsilons = np.array(epsilons, dtype=float)
    w0 = flip_sweep_starts(epsilons, spin)
    measured = np.full((len(methods), moments.shape[0], epsilons.size), np.nan)
    exact = np.full((moments.shape[0], epsilons.size), np.nan)
    asymptote = np.full_like(exact, np.nan)
    rate = np.array([float(growth_rate(I, 2, spin)) for I in moments])
    calls = []
    for f, I in enumerate(moments):
        body = RigidBody(*I, name=f"flip shape {f}")
        exact[f], asymptote[f] = exact_flip_curve(I, epsilons, spin)
        t_end = 2.6 * float(np.nanmax(exact[f]))
        calls += [(i, f, dict(body=body, axis=2, starts=w0, h=h, t_end=h * math.ceil(t_end / h),
                              method=method, keep=Keep(save_every=0)))
                  for i, (method, h) in enumerate(zip(methods, steps))]
    # Every shape of a method in one parallel call, each ensemble bitwise what it gives alone.
    for (i, f, _), run in zip(calls, run_ensembles([c for _, _, c in calls], progress=False)):
        completed(run)
        measured[i, f] = run.mean_flip_interval.values  # NaN below two flips or not ok
    return {"moments": moments, "epsilons": epsilons, "measured": measured, "exact": exact,
            "asymptote": asymptote, "growth_rate": rate}
