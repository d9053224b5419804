"""The sections every dispersed study shares: ``[dispersions]``, what is uncertain, and
``[sensitivity]``, the design and its analysis; their checks, the design drawn, the analysis of
a study's per-member outputs, its figure and its summary tables.

A study kind that disperses declares the parameters it may disperse (name -> unit) with
:func:`dispersions_section` and takes :func:`sensitivity_section` as it is; its ``run`` draws
the design (:func:`draw_design`), evaluates every design point, and hands the outputs to
:func:`analyse`. ``[sensitivity] method`` chooses the analysis:

- ``"sobol"``: first-order and total Sobol' indices (:func:`stability.uncertainty.sobol.
  sobol_indices`) from a Saltelli design of ``base`` points, N (d + 2) members;
- ``"morris"``: Morris screening (:func:`stability.uncertainty.morris.morris_indices`) from
  ``trajectories`` one-at-a-time trajectories on a grid of ``levels``, r (d + 1) members: the
  ranking of many parameters at a fraction of the cost.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..uncertainty.dispersions import Dispersions, dispersions
from ..uncertainty.figures import indices_figure, screening_figure
from ..uncertainty.morris import morris_design, morris_indices
from ..uncertainty.sobol import sobol_design, sobol_indices
from .config import UNSET, ConfigError, Key, Section
from .kind import SummaryTable

#: The analyses ``[sensitivity] method`` may name.
ANALYSES = ("sobol", "morris")


def dispersions_section(units: Mapping, *, truncate: bool = False) -> Section:
    """``[dispersions]``: a table ``{distribution = ..., ...}`` for each parameter of
    ``units`` (name -> UDUNITS unit) that may be dispersed, and with ``truncate`` the key
    that keeps the moments physical by truncation."""
    keys = [Key(name, "table", UNSET, f"dispersion of {name} (in {unit})")
            for name, unit in units.items()]
    if truncate:
        keys.append(Key("truncate", "bool", False, "truncate the largest moment to the "
                        "triangle inequality where the moments' dispersions could break it"))
    return Section("dispersions", "what is uncertain: a table {distribution = ..., ...} each",
                   tuple(keys))


def sensitivity_section(base: int = 4096) -> Section:
    """``[sensitivity]``: the analysis, its design and its confidence intervals."""
    return Section("sensitivity", "the design and its analysis: Sobol' indices or Morris "
                   "screening", (
        Key("method", "str", "sobol", "sobol: first-order and total indices, N (d + 2) "
            "members; morris: screening, r (d + 1) members", choices=ANALYSES),
        Key("base", "int", base, "Sobol': base points N (a power of 2)", minimum=2),
        Key("trajectories", "int", 64, "Morris: trajectories r", minimum=2),
        Key("levels", "int", 4, "Morris: levels p of the grid (even)", minimum=2),
        Key("seed", "int", 1, "seed of the design (and of the bootstrap)", minimum=0),
        Key("resamples", "int", 100, "bootstrap resamples of the confidence intervals",
            minimum=10),
        Key("conf_level", "float", 0.95, "level of the confidence intervals", minimum=0.5,
            maximum=0.999),
    ))


def checked_dispersions(config: dict, source: str, nominal: Mapping) -> Dispersions:
    """The dispersions of ``config``'s ``[dispersions]`` over the ``nominal`` values; a bad
    one is a one-line ConfigError naming its key, before any work."""
    table = config["dispersions"]
    spec = {k: v for k, v in table.items() if k != "truncate" and v is not None}
    try:
        return dispersions(spec, nominal, truncate=bool(table.get("truncate", False)))
    except ValueError as exc:
        key = next((k for k in spec if repr(k) in str(exc)), "")
        raise ConfigError(str(exc), source, "dispersions", key) from None


def design_members(config: dict, source: str, disp: Dispersions) -> int:
    """The members of the design ``[sensitivity]`` asks for: N (d + 2) for Sobol' (N a power
    of 2, refused otherwise), r (d + 1) for Morris (p even, refused otherwise)."""
    sens = config["sensitivity"]
    d = len(disp.names)
    if sens["method"] == "sobol":
        base = sens["base"]
        if base & (base - 1):
            raise ConfigError(f"must be a power of 2 (the Sobol' sequence's balance), got "
                              f"{base}", source, "sensitivity", "base")
        return base * (d + 2)
    if sens["levels"] % 2:
        raise ConfigError(f"must be even (Morris' grid), got {sens['levels']}", source,
                          "sensitivity", "levels")
    return sens["trajectories"] * (d + 1)


def draw_design(config: dict, disp: Dispersions):
    """The design of ``[sensitivity]``: a :class:`~stability.uncertainty.sobol.SobolDesign`
    or a :class:`~stability.uncertainty.morris.MorrisDesign`, its ``unit`` one row per
    member."""
    sens = config["sensitivity"]
    if sens["method"] == "sobol":
        return sobol_design(disp, sens["base"], sens["seed"])
    return morris_design(disp, sens["trajectories"], sens["levels"], sens["seed"])


def analyse(config: dict, design, outputs: Mapping):
    """The indices (Sobol') or the screening (Morris) of ``outputs`` (name -> (values, units,
    long_name), one value per design point), as ``[sensitivity]`` asks: a Dataset over
    (output, parameter)."""
    sens = config["sensitivity"]
    kw = {"resamples": sens["resamples"], "conf_level": sens["conf_level"],
          "seed": sens["seed"]}
    if sens["method"] == "sobol":
        return sobol_indices(design, outputs, **kw)
    return morris_indices(design, outputs, **kw)


def analysis_figure(ds):
    """The analysis' figure: the indices as bars (Sobol'), mu* against sigma (Morris)."""
    return indices_figure(ds) if "total" in ds else screening_figure(ds)


def ranking(ds, output: str) -> np.ndarray:
    """What ranks the parameters for ``output``: the total index (Sobol'), mu* (Morris)."""
    row = ds.sel(output=output)
    return (row.total if "total" in ds else row.mu_star).values


def dominant(ds, output: str) -> str:
    """The parameter that dominates ``output``: the largest total index, or mu*."""
    return str(ds.parameter.values[int(np.argmax(ranking(ds, output)))])


def summary_values(ds) -> dict:
    """Each output's index of each parameter, for the summary's values: (S_i, S_Ti), or
    (mu*, sigma) for Morris."""
    first, second = ("first_order", "total") if "total" in ds else ("mu_star", "sigma")
    return {str(o): {str(p): (float(ds[first].sel(output=o, parameter=p)),
                              float(ds[second].sel(output=o, parameter=p)))
                     for p in ds.parameter.values} for o in ds.output.values}


def index_tables(ds) -> list[SummaryTable]:
    """One summary table per output: the indices with their interval half-widths, or mu*,
    its interval and sigma."""
    if "total" in ds:
        name, columns = "Sobol' indices", ("first_order", "first_order_conf", "total",
                                           "total_conf")
        heads = ("S_i", "+-", "S_Ti", "+-")
    else:
        name, columns = "Morris screening (over sd)", ("mu_star", "mu_star_conf", "sigma")
        heads = ("mu*", "+-", "sigma")
    level = float(ds.attrs["conf_level"])
    return [SummaryTable(f"{name} of the {str(o).replace('_', ' ')} ({level:g} intervals)",
                         [("parameter", ""), *((h, "") for h in heads)],
                         [(str(p), *(f"{float(ds[v].sel(output=o, parameter=p)):.3f}"
                                     for v in columns))
                          for p in ds.parameter.values])
            for o in ds.output.values]
