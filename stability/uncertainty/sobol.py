"""First-order and total Sobol' indices of per-member outputs, with bootstrap confidence
intervals, by SALib's estimators.

The design is Saltelli's (Saltelli et al., Comput. Phys. Commun. 181, 259 (2010)): N base
points of a scrambled Sobol' sequence in 2 d dimensions give the matrices A and B and the d
matrices AB_i (A with column i from B), N (d + 2) evaluations in all
(``SALib.sample.sobol.sample``, ``calc_second_order=False``). The indices are SALib's
estimators (``SALib.analyze.sobol.analyze``): S_i by Saltelli (2010) Table 2 (b),
S_Ti by Jansen's formula (ibid. (f)), their confidence intervals by bootstrap over the N base
points. A parameter that takes several unit columns (the axes' rotation) is one group.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import xarray as xr
from SALib.analyze import sobol as sobol_analyze
from SALib.sample import sobol as sobol_sample

from ..util.checks import positive_int
from .dispersions import Dispersions
from .schema import OUTPUT, PARAMETER, SOBOL_INDICES


def problem(dispersions: Dispersions) -> dict:
    """SALib's problem of the unit design of ``dispersions``: one variable per unit column on
    [0, 1], grouped by parameter where a parameter takes several."""
    columns = dispersions.columns()
    out = {"num_vars": len(columns), "names": [f"{c}_{k}" for k, c in enumerate(columns)],
           "bounds": [[0.0, 1.0]] * len(columns)}
    if len(set(columns)) < len(columns):
        out["groups"] = list(columns)
    return out


@dataclass(frozen=True)
class SobolDesign:
    """A Saltelli design of the unit cube for :func:`sobol_indices`.

    Attributes
    ----------
    dispersions : Dispersions
    unit : ndarray, shape (N (d + 2), columns)
        Row k is design point k of the whole design (SALib's order: A_j, AB_j^1..AB_j^d, B_j
        for each base point j); draw the members from it (:meth:`Dispersions.draw`).
    base : int
        N, the base points.
    seed : int
    """

    dispersions: Dispersions
    unit: np.ndarray
    base: int
    seed: int


def sobol_design(dispersions: Dispersions, base: int, seed: int = 0) -> SobolDesign:
    """The Saltelli design of ``base`` points (a power of 2 keeps the Sobol' sequence
    balanced) for the dispersed parameters; N (d + 2) members, d the parameters."""
    base = positive_int("base", base)
    if base & (base - 1):
        raise ValueError(f"base must be a power of 2 (the Sobol' sequence's balance), got {base}")
    seed = positive_int("seed", seed, allow_zero=True)
    unit = sobol_sample.sample(problem(dispersions), base, calc_second_order=False,
                               scramble=True, seed=seed)
    return SobolDesign(dispersions, unit, base, seed)


def sobol_indices(design: SobolDesign, outputs: Mapping, *, resamples: int = 100,
                  conf_level: float = 0.95, seed: int = 0) -> xr.Dataset:
    """S_i and S_Ti of each output over each dispersed parameter, with confidence intervals.

    Parameters
    ----------
    design : SobolDesign
        The design the outputs were computed on.
    outputs : Mapping
        Output name -> ``(values, units, long_name)``, values of shape (N (d + 2),), one per
        design point, finite.
    resamples : int, default 100
        Bootstrap resamples.
    conf_level : float, default 0.95
    seed : int, default 0
        Seed of the bootstrap.

    Returns
    -------
    xarray.Dataset
        As :data:`stability.uncertainty.schema.SOBOL_INDICES` declares it.
    """
    names = list(design.dispersions.names)
    rows = {key: [] for key in ("first_order", "first_order_conf", "total", "total_conf")}
    units, long_names = [], []
    sal = problem(design.dispersions)
    for name, (values, unit, long_name) in outputs.items():
        y = np.asarray(values, dtype=float)
        if y.shape != (design.unit.shape[0],):
            raise ValueError(f"output {name!r} must have one value per design point "
                             f"({design.unit.shape[0]}), got shape {y.shape}")
        if not np.all(np.isfinite(y)):
            raise ValueError(f"output {name!r} is not finite at {int((~np.isfinite(y)).sum())} "
                             "design points; Sobol' indices need every value")
        got = sobol_analyze.analyze(sal, y, calc_second_order=False, num_resamples=resamples,
                                    conf_level=conf_level, seed=seed)
        for key, sal_key in zip(rows, ("S1", "S1_conf", "ST", "ST_conf")):
            rows[key].append(np.asarray(got[sal_key], dtype=float))
        units.append(unit)
        long_names.append(long_name)
    entries = SOBOL_INDICES.entries({
        **{key: np.array(v) for key, v in rows.items()}, OUTPUT: list(outputs),
        PARAMETER: names, "output_units": units, "output_long_name": long_names})
    ds = xr.Dataset(entries).set_coords(["output_units", "output_long_name"])
    ds.attrs.update({"analysis": "Sobol' indices (SALib; Saltelli et al. 2010, Jansen)",
                     "base_samples": design.base, "evaluations": int(design.unit.shape[0]),
                     "design_seed": design.seed, "bootstrap_resamples": resamples,
                     "conf_level": conf_level})
    return ds
