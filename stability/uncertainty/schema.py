"""The Datasets of the sensitivity analyses: Sobol' indices and Morris screening, each over
(output, parameter), declared as every Dataset of the package is
(:mod:`stability.ensemble.schema`) and added to the register by :mod:`stability.registry`."""

from __future__ import annotations

from dataclasses import replace

from ..ensemble.schema import ONE, coordinate, declare, variable

OUTPUT, PARAMETER = "output", "parameter"
_DIMS = (OUTPUT, PARAMETER)

#: The labels of both analyses.
_AXES = {
    OUTPUT: coordinate(OUTPUT, ONE, "per-member output analysed", kind="U"),
    PARAMETER: coordinate(PARAMETER, ONE, "dispersed parameter", kind="U"),
    "output_units": coordinate(OUTPUT, ONE, "units of the output", kind="U"),
    "output_long_name": coordinate(OUTPUT, ONE, "what the output is", kind="U"),
}

SOBOL_INDICES = declare("sobol_indices", "first-order and total Sobol' indices of per-member "
                        "outputs over the dispersed parameters",
                        "stability.uncertainty.sobol.sobol_indices", {
    **_AXES,
    "first_order": variable(_DIMS, ONE, "first-order Sobol' index S_i = Var(E[Y | X_i]) / Var(Y)"),
    "first_order_conf": variable(_DIMS, ONE, "half-width of the bootstrap confidence interval "
                                 "of the first-order index"),
    "total": variable(_DIMS, ONE, "total Sobol' index S_Ti = E[Var(Y | X_~i)] / Var(Y)"),
    "total_conf": variable(_DIMS, ONE, "half-width of the bootstrap confidence interval of the "
                           "total index"),
}, file="")

MORRIS_SCREENING = declare("morris_screening", "Morris elementary effects of per-member outputs "
                           "over the dispersed parameters",
                           "stability.uncertainty.morris.morris_indices", {
    **_AXES,
    "mu_star": variable(_DIMS, ONE, "mean absolute elementary effect mu*, over the standard "
                        "deviation of the output"),
    "mu_star_conf": variable(_DIMS, ONE, "half-width of the bootstrap confidence interval of mu*, "
                             "over the standard deviation of the output"),
    "sigma": variable(_DIMS, ONE, "standard deviation of the elementary effects, over the "
                      "standard deviation of the output"),
}, file="")

#: A dispersed study's analysis: the Sobol' indices or the Morris screening, whichever its
#: ``[sensitivity] method`` chose (:mod:`stability.study.sensitivity`); what a dispersed
#: study's Dataset extends.
SENSITIVITY = declare("sensitivity", "Sobol' indices or Morris screening of per-member "
                      "outputs over the dispersed parameters",
                      "stability.study.sensitivity.analyse", {
    **_AXES,
    **{name: replace(var, optional="Sobol' analyses ([sensitivity] method = 'sobol')")
       for name, var in SOBOL_INDICES.variables.items() if name not in _AXES},
    **{name: replace(var, optional="Morris screenings ([sensitivity] method = 'morris')")
       for name, var in MORRIS_SCREENING.variables.items() if name not in _AXES},
}, file="")
