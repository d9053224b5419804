"""Designs of the unit cube that dispersions map to values: random, Sobol' and Latin hypercube.

A design is an array ``(members, d)`` of points in [0, 1)^d, one row per member, one column per
unit dimension of the dispersions (:meth:`stability.uncertainty.dispersions.Dispersions.columns`).
Each member's row never depends on how the members are later cut into chunks, threads or
workers, because the whole design is made once before any of them runs:

- ``"random"``: row k is a pure function of (seed, k, d): it is row ``k % RNG_BLOCK`` of the
  block ``k // RNG_BLOCK``, drawn by ``numpy.random.Generator(PCG64(SeedSequence(seed,
  spawn_key=(block,))))``; a design of N members is the first N rows of any larger one.
- ``"sobol"``: point k of one scrambled Sobol' sequence (``scipy.stats.qmc.Sobol``, Owen
  scrambling; Sobol' 1967, Owen 1998) of the whole design, seeded by ``seed``.
- ``"lhs"``: row k of one Latin hypercube of the whole design (``scipy.stats.qmc.LatinHypercube``;
  McKay, Beckman & Conover 1979), seeded by ``seed``.
"""

from __future__ import annotations

import numpy as np
from scipy.stats import qmc

from ..util.checks import positive_int

#: The designs by name.
DESIGNS = ("random", "sobol", "lhs")
#: Members per random block. Fixed, so that the draws never depend on how a run is chunked;
#: changing it changes every random design.
RNG_BLOCK = 4096


def unit_design(design: str, members: int, dims: int, seed: int) -> np.ndarray:
    """Points of the unit cube, one row per member.

    Parameters
    ----------
    design : {"random", "sobol", "lhs"}
        See the module docstring for how row k depends on (seed, k).
    members, dims : int
        Rows (>= 1) and columns (>= 1).
    seed : int
        >= 0.

    Returns
    -------
    ndarray, shape (members, dims)
    """
    if design not in DESIGNS:
        raise ValueError(f"design must be one of {', '.join(DESIGNS)}, got {design!r}")
    members, dims = positive_int("members", members), positive_int("dims", dims)
    seed = positive_int("seed", seed, allow_zero=True)
    if design == "sobol":
        return qmc.Sobol(dims, scramble=True, seed=seed).random(members)
    if design == "lhs":
        return qmc.LatinHypercube(dims, seed=seed).random(members)
    blocks = [np.random.Generator(np.random.PCG64(np.random.SeedSequence(seed, spawn_key=(b,))))
              .random((RNG_BLOCK, dims)) for b in range(-(-members // RNG_BLOCK))]
    return np.concatenate(blocks)[:members]
