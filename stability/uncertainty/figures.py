"""Figures of the sensitivity analyses, drawn from their Datasets alone: the Sobol' indices as
bars with their confidence intervals (:func:`indices_figure`), Morris' mu* against sigma
(:func:`screening_figure`)."""

from __future__ import annotations

import numpy as np

from ..plotting.style import label, new_figure, place_legend, styled


@styled
def indices_figure(ds, fig=None):
    """One panel per output: S_i and S_Ti of each parameter, bars with their confidence
    intervals (``ds`` as :data:`stability.uncertainty.schema.SOBOL_INDICES`), drawn into
    ``fig`` where given (a pyplot figure, for the gallery)."""
    outputs = list(ds.output.values)
    size = (3.2 + 2.6 * len(outputs), 3.8)
    if fig is None:
        fig = new_figure(*size)
    else:
        fig.set_size_inches(*size)
        fig.set_layout_engine("constrained")
    axes = np.atleast_1d(fig.subplots(1, len(outputs), sharey=True))
    x = np.arange(ds.parameter.size)
    for ax, name in zip(axes, outputs):
        row = ds.sel(output=name)
        ax.bar(x - 0.2, row.first_order, 0.4, yerr=row.first_order_conf, capsize=3,
               label="first order S_i")
        ax.bar(x + 0.2, row.total, 0.4, yerr=row.total_conf, capsize=3, label="total S_Ti")
        many = ds.parameter.size > 5  # slanted, so that long names do not run together
        ax.set_xticks(x, [str(p) for p in ds.parameter.values], rotation=30 if many else 0,
                      ha="right" if many else "center")
        ax.set_xlabel(label("dispersed parameter", "1"))
        ax.set_title(str(row.output_long_name.values), fontsize=9)
        ax.axhline(0.0, color="0.3", lw=0.6)
    axes[0].set_ylabel(label("Sobol' index", "1"))
    place_legend(axes[0])
    return fig


@styled
def screening_figure(ds):
    """Morris mu* against sigma (both over sd(Y)) of each parameter, one marker per output
    (``ds`` as :data:`stability.uncertainty.schema.MORRIS_SCREENING`)."""
    fig = new_figure(5.5, 4.2)
    ax = fig.subplots()
    for name in ds.output.values:
        row = ds.sel(output=name)
        ax.errorbar(row.mu_star, row.sigma, xerr=row.mu_star_conf, fmt="o", capsize=3,
                    label=str(name))
        for p, mx, sy in zip(ds.parameter.values, row.mu_star.values, row.sigma.values):
            ax.annotate(str(p), (mx, sy), textcoords="offset points", xytext=(4, 4), fontsize=8)
    ax.set_xlabel(label("mu* / sd(output)", "1"))
    ax.set_ylabel(label("sigma / sd(output)", "1"))
    place_legend(ax)
    return fig
