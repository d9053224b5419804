"""Figure of the engine artefacts (:mod:`stability.engine_body.measure`): what each update rule
does to the flip.

:func:`artefacts_figure`: the flip interval's error, the energy drift and the growth rate's error
against the time step for every rule, and one member's spin-axis angular velocity at the
largest step beside the exact one.
"""

from __future__ import annotations

import numpy as np

from ..plotting.style import EXACT_COLOR, label, new_figure, styled

#: Zero drawn on a log axis at this value (an invariant kept exactly).
_FLOOR = 1e-17


@styled
def artefacts_figure(ds):
    """Errors against the step per rule (engine rules solid, the package's methods dashed)."""
    fig = new_figure(11.0, 8.0)
    (flip_ax, energy_ax), (growth_ax, trace_ax) = fig.subplots(2, 2)
    steps = ds.step.values
    colors = [f"C{k % 10}" for k in range(ds.rule.size)]
    # Rules can give the same numbers (rescaling the energy or the momentum): each has its own
    # hollow marker and the earlier ones are drawn wider, so a curve on another still shows.
    markers = "osD^vP*Xhd"
    widths = [max(2.4 - 0.3 * k, 0.8) for k in range(ds.rule.size)]
    for k, rule in enumerate(ds.rule.values):
        engine = str(ds.family.values[k]) == "engine rule"
        style = dict(color=colors[k], ls="-" if engine else "--", lw=widths[k],
                     marker=markers[k % len(markers)], mfc="none", ms=3 + 0.6 * (ds.rule.size - k),
                     label=str(rule))
        flip_ax.loglog(steps, np.maximum(np.abs(ds.flip_interval_error.values[k]), _FLOOR),
                       **style)
        energy_ax.loglog(steps, np.maximum(np.abs(ds.energy_drift.values[k]), _FLOOR), **style)
        growth_ax.loglog(steps, np.maximum(np.abs(ds.growth_rate_error.values[k]), _FLOOR),
                         **style)
        if engine:
            trace_ax.plot(ds.time, ds.spin_component.values[k], color=colors[k], lw=widths[k],
                          label=str(rule))
    trace_ax.plot(ds.time, ds.spin_component_exact, color=EXACT_COLOR, lw=2.0, ls=":",
                  label="exact")
    tolerance = ds.attrs["tolerance"]
    flip_ax.axhline(tolerance, color="black", lw=0.8, ls=":")
    for ax, what in ((flip_ax, "|flip interval error|, relative"),
                     (energy_ax, "|energy drift| at the end, relative"),
                     (growth_ax, "|growth rate error|, relative")):
        ax.set_xlabel(label("time step h", "s"))
        ax.set_ylabel(label(what, "1"))
        ax.invert_xaxis()
    flip_ax.set_title(f"flip interval vs exact 2K/nu ({ds.attrs['flip_interval_exact']:.3f} s); "
                      f"dotted: {100 * tolerance:g} %", fontsize=9)
    energy_ax.set_title(f"energy drift after the run (round-off is ~1e-16; an exact 0 is drawn "
                        f"at {_FLOOR:g})", fontsize=9)
    growth_ax.set_title(f"growth rate vs sqrt(-Omega^2) = {ds.attrs['growth_rate_exact']:.3f} "
                        "1/s", fontsize=9)
    trace_ax.set_xlabel(label("time", "s"))
    trace_ax.set_ylabel(label("spin-axis angular velocity w2", "rad s-1"))
    trace_ax.set_title(f"one member, engine rules at h = {float(steps[0]):.4g} s", fontsize=9)
    # One legend for the four panels (the rules keep their colour in each), below them: inside
    # an axes it covered the flat lines of the energy panel and the traces.
    handles, labels = energy_ax.get_legend_handles_labels()
    exact = trace_ax.get_lines()[-1]
    fig.legend(handles + [exact], labels + ["exact solution"], loc="outside lower center",
               ncols=5, fontsize=8)
    fig.suptitle(f"{ds.attrs['members']} tossed rackets, spin {ds.attrs['spin']:g} rad/s about "
                 "the middle axis: engine update rules (solid) and the package's methods "
                 "(dashed)", fontsize=10)
    return fig
