"""The tumbler study's figure, drawn from its Dataset alone
(:func:`stability.asteroid.measure.measure_tumblers`): the spread of E/E0 over the ensemble,
and the strongest light-curve frequency measured against the theory's, member by member."""

from __future__ import annotations

import numpy as np

from ..plotting.style import EXACT_COLOR, label, new_figure, place_legend, styled


@styled
def tumbler_figure(ds, title: str = ""):
    """Histogram of E/E0; measured against predicted main light-curve frequency.

    Parameters
    ----------
    ds : xarray.Dataset
        The tumbler ensemble.
    title : str, optional
        The tumbler's name, above the figure.
    """
    fig = new_figure(9.0, 4.0)
    left, right = fig.subplots(1, 2)
    ok = ds.fitted.values == 1
    e = ds.energy_ratio.values[ok]
    left.hist(e, bins=max(5, int(np.sqrt(e.size))), color="0.55", edgecolor="white")
    left.axvline(float(ds.energy_ratio.values[0]), color=EXACT_COLOR, label="nominal state")
    left.set_xlabel(label("E / E0", "1"))
    left.set_ylabel(label("members", "1"))
    place_legend(left)
    fp, fm = ds.frequency_predicted.values[ok], ds.frequency_measured.values[ok]
    right.plot(fp, fm, "o", ms=3, alpha=0.7, label="synthetic light curves")
    span = np.array([fp.min(), fp.max()])
    right.plot(span, span, color=EXACT_COLOR, lw=1, label=f"theory ({ds.attrs.get('mode', '')})")
    right.set_xlabel(label("predicted main frequency", "d-1"))
    right.set_ylabel(label("measured main frequency", "d-1"))
    place_legend(right)
    if title:
        fig.suptitle(title)
    return fig


__all__ = ["tumbler_figure"]
