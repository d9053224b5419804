"""Morris screening of per-member outputs: elementary effects along random one-at-a-time
trajectories, by SALib (Morris, Technometrics 33, 161 (1991); mu* of Campolongo, Cariboni &
Saltelli, Environ. Model. Softw. 22, 1509 (2007)).

r trajectories of d + 1 points on a grid of p levels of the unit cube
(``SALib.sample.morris.sample``) give r elementary effects per parameter; mu* (the mean of
their absolute values, with a bootstrap confidence interval) ranks the parameters at a cost of
r (d + 1) evaluations, for many parameters where Sobol' indices cost too much, and sigma flags
effects that are nonlinear or interact. Both are divided by the output's standard deviation
over the design, so that outputs of any units share one Dataset.

SALib's levels j / (p - 1) include 0 and 1, where an unbounded distribution (a normal) is
infinite: the members are drawn at the middles of p equal cells instead,
u = (j + 1/2) / p, and the effects, which SALib divides by its own step, are multiplied by
p / (p - 1), the ratio of its step to the one taken, so that an effect is still the change of
the output over the whole unit range (c (upper - lower) for Y = c x).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import xarray as xr
from SALib.analyze import morris as morris_analyze
from SALib.sample import morris as morris_sample

from ..util.checks import positive_int
from .dispersions import Dispersions
from .schema import MORRIS_SCREENING, OUTPUT, PARAMETER
from .sobol import problem


@dataclass(frozen=True)
class MorrisDesign:
    """Trajectories of the unit cube for :func:`morris_indices`: ``unit`` (r (d + 1), columns),
    row k design point k, at the middles of the cells (what the members are drawn from);
    ``grid`` the same points on SALib's levels j / (p - 1) (what its analysis reads);
    ``levels`` the grid's p."""

    dispersions: Dispersions
    unit: np.ndarray
    grid: np.ndarray
    trajectories: int
    levels: int
    seed: int


def morris_design(dispersions: Dispersions, trajectories: int, levels: int = 4,
                  seed: int = 0) -> MorrisDesign:
    """r = ``trajectories`` Morris trajectories on a grid of ``levels`` (even, >= 2)."""
    trajectories = positive_int("trajectories", trajectories)
    levels = positive_int("levels", levels)
    if levels < 2 or levels % 2:
        raise ValueError(f"levels must be even and >= 2, got {levels}")
    seed = positive_int("seed", seed, allow_zero=True)
    grid = morris_sample.sample(problem(dispersions), trajectories, num_levels=levels, seed=seed)
    unit = (grid * (levels - 1) + 0.5) / levels
    return MorrisDesign(dispersions, unit, grid, trajectories, levels, seed)


def morris_indices(design: MorrisDesign, outputs: Mapping, *, resamples: int = 100,
                   conf_level: float = 0.95, seed: int = 0) -> xr.Dataset:
    """mu*, its confidence interval and sigma of each output (``name -> (values, units,
    long_name)``, one value per design point) over each parameter, over sd(Y).

    Returns
    -------
    xarray.Dataset
        As :data:`stability.uncertainty.schema.MORRIS_SCREENING` declares it.
    """
    sal = problem(design.dispersions)
    rows = {"mu_star": [], "mu_star_conf": [], "sigma": []}
    units, long_names = [], []
    for name, (values, unit, long_name) in outputs.items():
        y = np.asarray(values, dtype=float)
        if y.shape != (design.unit.shape[0],) or not np.all(np.isfinite(y)):
            raise ValueError(f"output {name!r} must be finite, one value per design point "
                             f"({design.unit.shape[0]}), got shape {y.shape}")
        sd = float(np.std(y))
        got = morris_analyze.analyze(sal, design.grid, y, num_resamples=resamples,
                                     conf_level=conf_level, num_levels=design.levels, seed=seed)
        p = design.levels
        scale = p / (p - 1) / sd if sd > 0.0 else np.nan
        for key in rows:
            rows[key].append(np.asarray(got[key], dtype=float) * scale)
        units.append(unit)
        long_names.append(long_name)
    entries = MORRIS_SCREENING.entries({
        **{k: np.array(v) for k, v in rows.items()}, OUTPUT: list(outputs),
        PARAMETER: list(design.dispersions.names), "output_units": units,
        "output_long_name": long_names})
    ds = xr.Dataset(entries).set_coords(["output_units", "output_long_name"])
    ds.attrs.update({"analysis": "Morris screening (SALib; Campolongo et al. 2007 mu*)",
                     "trajectories": design.trajectories, "levels": design.levels,
                     "evaluations": int(design.unit.shape[0]), "design_seed": design.seed,
                     "bootstrap_resamples": resamples, "conf_level": conf_level})
    return ds
