"""The tumbler study: how well a tumbling asteroid's spin state is known from its light curve.

A published non-principal-axis rotator (its moment ratios I1/I3, I2/I3, its periods P_psi and
P_phi and their one-sigma errors, and its mode are keys of the study file; the default is
(99942) Apophis, Pravec et al., Icarus 233, 48 (2014)) is drawn ``members`` times from normal
errors; each member's state of that mode (:func:`stability.asteroid.model.spin_states`)
gives E/E0 and |L| / I3, and its synthetic light curve (a uniform ellipsoid of its moments,
:func:`stability.asteroid.lightcurve.lightcurve`) its strongest frequency, set beside the
theory's. Outputs: the Dataset, one figure (:func:`stability.asteroid.figures.tumbler_figure`)
and the study's configuration.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ...study.config import ConfigError, Key, Schema, Section
from ...study.kind import StudyKind, StudyRun, StudySummary
from ...study.outputs import output_files, write_outputs
from ...study.sections import output_section
from ..figures import tumbler_figure
from ..lightcurve import LAWS
from ..measure import draw_members, measure_tumblers
from ..model import MODES, spin_states

NAME = "tumbler"
FIGURE = "tumbler"

SCHEMA = Schema(
    top=(Key("title", "str", "Spin state of the tumbling asteroid (99942) Apophis",
             "one line describing the run (the Dataset's title)"),),
    sections=(
        Section("tumbler", "the published spin state and its one-sigma errors", (
            Key("name", "str", "(99942) Apophis", "the tumbler's name"),
            Key("mode", "str", "SAM", "short-axis (SAM) or long-axis (LAM) mode",
                choices=MODES),
            Key("moment_ratios", "floats", [0.61, 0.965], "I1/I3 and I2/I3", length=2,
                minimum=0.0, exclusive_minimum=True, maximum=1.0),
            Key("moment_ratio_errors", "floats", [0.03, 0.004], "their one-sigma errors",
                length=2, minimum=0.0),
            Key("period_psi", "float", 263.0, "rotation period P_psi", unit="h", minimum=0.0,
                exclusive_minimum=True),
            Key("period_psi_error", "float", 2.0, "its one-sigma error", unit="h",
                minimum=0.0),
            Key("period_phi", "float", 27.38, "mean precession period P_phi", unit="h",
                minimum=0.0, exclusive_minimum=True),
            Key("period_phi_error", "float", 0.023, "its one-sigma error", unit="h",
                minimum=0.0),
        )),
        Section("ensemble", "the members drawn from the errors", (
            Key("members", "int", 200, "members (member 0 the nominal state)", minimum=1),
            Key("seed", "int", 0, "seed of the draws", minimum=0),
        )),
        Section("lightcurve", "the synthetic light curves", (
            Key("sun", "floats", [1.0, 0.0, 0.3], "direction to the Sun, frame of L (Z along L)",
                length=3),
            Key("observer", "floats", [1.0, 0.2, 0.3], "direction to the observer, frame of L",
                length=3),
            Key("law", "str", "lommel-seeliger", "scattering law", choices=LAWS),
            Key("periods", "float", 20.0, "length in the longer of P_psi, P_phi", minimum=2.0),
            Key("samples", "int", 2048, "brightness samples", minimum=64),
            Key("rings", "int", 12, "rings of latitude of the ellipsoid mesh", minimum=3),
        )),
        output_section(NAME, (FIGURE,)),
    ),
)

#: ``--quick``: fewer members.
QUICK = {"ensemble": {"members": 16}}


def check(config: dict, source: str) -> dict:
    """A nominal state that the mode fits; directions that are not zero."""
    t = config["tumbler"]
    try:
        states = spin_states((*t["moment_ratios"], 1.0), t["period_psi"], t["period_phi"],
                             t["mode"])
    except ValueError as exc:
        raise ConfigError(str(exc), source, "tumbler", "moment_ratios") from None
    if not states:
        raise ConfigError(f"no {t['mode']} state has these periods at these moment ratios; "
                          "check which period is which, or the mode", source, "tumbler", "mode")
    for key in ("sun", "observer"):
        if not any(config["lightcurve"][key]):
            raise ConfigError("must be a non-zero direction", source, "lightcurve", key)
    return config


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    return output_files(config, (FIGURE,))


def run(config: dict, out_dir: Path, options: StudyRun) -> StudySummary:
    """Draw the members, solve and light each, save the Dataset, draw the figure."""
    t_start = time.perf_counter()
    t, ens, lc = config["tumbler"], config["ensemble"], config["lightcurve"]
    draws = draw_members(t["moment_ratios"], t["moment_ratio_errors"],
                         (t["period_psi"], t["period_phi"]),
                         (t["period_psi_error"], t["period_phi_error"]), ens["members"],
                         ens["seed"])
    ds = measure_tumblers(draws, t["mode"], lc["sun"], lc["observer"], periods=lc["periods"],
                          samples=lc["samples"], rings=lc["rings"], law=lc["law"])
    ds, files = write_outputs(ds, config, out_dir, NAME,
                              {FIGURE: lambda ds: tumbler_figure(ds, t["name"])},
                              overwrite=options.overwrite, history=options.history,
                              threads=options.run.threads,
                              attrs={"tumbler": t["name"]})
    return summarize(ds, out_dir, files, time.perf_counter() - t_start)


def summarize(ds, out_dir, files, wall) -> StudySummary:
    """Nominal and spread of E/E0; the light-curve frequency against theory."""
    ok = ds.fitted.values == 1
    e = ds.energy_ratio.values[ok]
    fm, fp = ds.frequency_measured.values[ok], ds.frequency_predicted.values[ok]
    worst = float(np.max(np.abs(fm / fp - 1.0))) if ok.any() else float("nan")
    values = {"energy_ratio_nominal": float(ds.energy_ratio.values[0]),
              "energy_ratio_mean": float(e.mean()), "energy_ratio_std": float(e.std()),
              "frequency_nominal": float(ds.frequency_predicted.values[0]),
              "frequency_std": float(fp.std()), "max_frequency_error": worst,
              "fitted": int(ok.sum()), "members": int(ds.sizes["member"]), "wall_time": wall}
    rows = [("E/E0 of the nominal state", f"{values['energy_ratio_nominal']:.4f}", ""),
            ("E/E0 over the members (mean, std)",
             f"{values['energy_ratio_mean']:.4f}, {values['energy_ratio_std']:.4f}", ""),
            ("main light-curve frequency, nominal (std)",
             f"{values['frequency_nominal']:.4f} ({values['frequency_std']:.4f})", "d-1"),
            ("max |measured / predicted - 1| of that frequency", f"{worst:.1e}", ""),
            ("members fitted by the mode", f"{values['fitted']} of {values['members']}", ""),
            ("wall time", f"{wall:.1f}", "s")]
    return StudySummary(NAME, Path(out_dir), files, rows, values)


STUDY = StudyKind(
    name=NAME,
    title="a tumbling asteroid's E/E0 and light-curve frequencies over its uncertain state",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    members_key=("ensemble", "members"),
)
