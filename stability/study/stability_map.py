"""The stability map: measured against analytic Omega^2 for every shape of body and every axis.

Shapes: the physically allowed moments ``I1 <= I2 <= I3`` with ``I1 + I2 >= I3``, normalised so
that ``I3 = 1``, fill a triangle in the (I1, I2) plane with corners at the thin rod (0, 1, 1),
the flat disk (1/2, 1/2, 1) and the sphere (1, 1, 1); its edges are the prolate symmetric
bodies ``I2 = I3``, the oblate ones ``I1 = I2`` and the flat bodies ``I1 + I2 = I3``. A grid of
``divisions`` n (rows ``I2 = 1 - k / 2n``, steps ``1 / n`` in I1, computed from integers so that
equal moments are exactly equal) holds ``(n + 1)(n + 2) / 2 - 1`` shapes (the rod corner, with
``I1 = 0``, is no body); n = 32 gives 560. The edges are kept, not excluded.

For every shape and each of its three axes, an ensemble of ``members`` starts at steady spin
``W`` about the axis plus a perturbation ``epsilon W`` in a random perpendicular direction
(:func:`stability.ensemble.perturbed_starts`, the same directions for every ensemble) and runs
summaries-only (:func:`stability.run_ensemble` with ``summaries_only=True``: flips, crossings,
largest perpendicular amplitude and passage times through amplitude levels, tracked at every
step inside the member loop), so memory stays a few numbers per member. The run lasts
``horizon / |Omega|`` (up to ``t_max``; ``t_neutral`` where Omega^2 = 0): enough for two flips
of an unstable axis (the first comes after about ln(1/epsilon) / lambda, then one every
2 ln(1/epsilon) / lambda) and for ten periods of a stable one; it depends on |Omega^2| only,
never on its sign.

Each ensemble is classified and measured by :mod:`stability.estimators` (regime; growth rate
on the linear phase or frequency from zero crossings; Omega^2 = -rate^2 or +frequency^2; flips
against the exact 2K/nu and the asymptote (2/lambda) ln(4/k')). Each method runs at its ``h``
and, for the finite-order ones, again at ``h / 2`` on every ``bias_stride``-th shape: the
difference gives the method's own O(h^p) bias in Omega^2 by Richardson extrapolation,
``(X(h) - X(h/2)) / (1 - 2^-p)``, which is reported beside the measured error, not hidden.

Also: a flip-interval sweep (a few shapes, perturbation along the smallest axis, epsilon from
1e-1 down) against the exact curve and the ln(1/epsilon) law, and time series on the equal-moment
edges and the sphere showing the algebraic (linear in t) departure with the distinct-axis
component constant and no flip (ERRATA 3).

Outputs: the Dataset (dims integrator, shape, axis, where an integrator is a registry method
at its step h and is not called "method" so that ``ds.sel(integrator="rk4")`` works; the sweep
on flip_shape, epsilon; the edge time series on edge_case, edge_time), the resolved
configuration and four figures (:mod:`stability.figures.stability_map`).
"""

from __future__ import annotations

import math
import resource
import sys
import time
from pathlib import Path

import numpy as np

from ..threads import numba_threads
from .config import ConfigError, Key, Schema, Section, StudyKind, StudySummary

NAME = "stability_map"

#: Figure file stems: the map, measured against analytic, flip intervals, the edges.
FIGURES = ("fig1_map", "fig2_measured_vs_analytic", "fig3_flip_interval", "fig4_edges")

# Edge flags of a shape (bit mask, CF flag_masks).
EDGE_EQUAL_12 = 1  #: I1 = I2: oblate symmetric body (the sphere has both equalities)
EDGE_EQUAL_23 = 2  #: I2 = I3: prolate symmetric body
EDGE_FLAT = 4  #: I1 + I2 = I3: flat body (all mass in a plane)
EDGE_MEANINGS = "equal_I1_I2 equal_I2_I3 flat"

#: The time-series demonstrations on the edges: name, moments (I3 = 1), spin axis.
EDGE_CASES = (
    ("oblate_equal_I1_I2", (0.75, 0.75, 1.0), 1),
    ("prolate_equal_I2_I3", (0.5, 1.0, 1.0), 3),
    ("sphere", (1.0, 1.0, 1.0), 1),
)


def _method_names() -> tuple:
    from ..integrators import METHODS

    return tuple(METHODS)


SCHEMA = Schema(
    top=(Key("title", "str",
             "Stability map: Monte Carlo Omega^2 against linear theory over all body shapes",
             "one line describing the run (the Dataset's title)"),),
    sections=(
        Section("grid", "the shapes: a triangular grid over I1 <= I2 <= I3 = 1, I1 + I2 >= 1", (
            Key("divisions", "int", 32,
                "subdivisions n of the triangle: (n + 1)(n + 2) / 2 - 1 shapes", minimum=1),
        )),
        Section("spin", "the steady spin of every ensemble", (
            Key("rate", "float", 1.0, "spin rate W", unit="rad s-1", minimum=0.0,
                exclusive_minimum=True),
        )),
        Section("ensemble", "the perturbed members of each (shape, axis)", (
            Key("members", "int", 64, "members per ensemble", minimum=2),
            Key("epsilon", "float", 1e-7,
                "perturbation relative to the spin, random perpendicular direction",
                minimum=0.0, exclusive_minimum=True, maximum=1e-3),
            Key("seed", "int", 1, "seed of the random directions (numpy SeedSequence entropy)",
                minimum=0),
        )),
        Section("integration", "methods, steps and run lengths", (
            Key("methods", "strs", ["rk4", "lp2", "exact"], "integrators to run",
                choices=_method_names),
            Key("h", "floats", [0.1, 0.05, 0.1], "step of each method, in the same order",
                unit="s", minimum=0.0, exclusive_minimum=True),
            Key("bias_check", "bool", True,
                "run each finite-order method again at h / 2 to measure its O(h^p) bias"),
            Key("bias_stride", "int", 8, "bias check on every n-th shape (1: all)", minimum=1),
            Key("horizon", "float", 70.0, "run length in units of 1 / |Omega|",
                minimum=0.0, exclusive_minimum=True),
            Key("t_max", "float", 2500.0, "longest run", unit="s",
                minimum=0.0, exclusive_minimum=True),
            Key("t_neutral", "float", 800.0, "run length where Omega^2 = 0 (equal moments)",
                unit="s", minimum=0.0, exclusive_minimum=True),
            Key("threads", "int", 1,
                "Numba threads per ensemble (small ensembles run fastest on one; "
                "stability run --threads overrides)", minimum=1),
        )),
        Section("analysis", "estimator window and the accuracy bar", (
            Key("window_low", "float", 300.0,
                "growth-rate window starts at this many times the initial amplitude",
                minimum=1.0, exclusive_minimum=True),
            Key("window_high", "float", 1e-2,
                "... and ends at this fraction of min(spin, saturation amplitude)",
                minimum=0.0, exclusive_minimum=True, maximum=0.5),
            Key("levels_per_decade", "int", 8, "passage-time amplitude levels per decade",
                minimum=2),
            Key("tolerance", "float", 1e-3,
                "accuracy bar: |measured - analytic| / |analytic| Omega^2",
                minimum=0.0, exclusive_minimum=True),
            Key("min_omega_squared", "float", 1e-3,
                "the bar applies where |Omega^2| / W^2 exceeds this", minimum=0.0),
        )),
        Section("flips", "flip interval against epsilon (figure 3)", (
            Key("shapes", "floats", [0.34375, 0.65625, 0.25, 0.75, 0.625, 0.875],
                "pairs I1, I2 (I3 = 1) with I1 < I2 < 1 and I1 + I2 >= 1"),
            Key("epsilons", "floats",
                [1e-1, 3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 1e-7, 1e-8,
                 1e-9],
                "perturbations along the smallest axis, relative to the spin",
                minimum=0.0, exclusive_minimum=True, maximum=0.5),
        )),
        Section("edges", "time series on the equal-moment edges and the sphere (figure 4)", (
            Key("epsilon", "float", 1e-3, "perturbation relative to the spin",
                minimum=0.0, exclusive_minimum=True, maximum=0.1),
            Key("t_end", "float", 400.0, "length of the time series", unit="s",
                minimum=0.0, exclusive_minimum=True),
        )),
        Section("output", "where the results go", (
            Key("dir", "str", "results/stability_map",
                "output folder (relative to the current directory)"),
            Key("dataset", "str", "stability_map.nc", "file name of the Dataset (netCDF)"),
            Key("figures", "bool", True, "draw the four figures"),
            Key("formats", "strs", ["png", "pdf"], "figure formats",
                choices=("png", "pdf", "svg")),
        )),
    ),
)

#: ``--quick``: a coarse grid and small ensembles, for tests and a first look (seconds).
QUICK = {
    "grid": {"divisions": 4},
    "ensemble": {"members": 32},
    "integration": {"bias_stride": 2},
    "flips": {"epsilons": [1e-2, 1e-3, 1e-4, 1e-5, 1e-6]},
    "edges": {"t_end": 100.0},
}


#: Relative bias of the growth rate, lambda_h / lambda - 1, at step h for I = (1, 2, 3) and spin
#: W = 1 (literature notes 4.1, table of discretization biases): RK4 -(h lambda)^4 / 120; the
#: two-part Lie-Poisson split (lp2: I_ref = I2, axis 1 outer) -1.4e-4 at h = 0.1, O(h^2). The
#: relative error of Omega^2 = -lambda^2 is minus twice this. Arguments: h W and lambda / W.
LITERATURE_RATE_BIAS = {
    "rk4": lambda hw, lam: -((hw * lam) ** 4) / 120.0,
    "lp2": lambda hw, lam: -1.4e-4 * (hw / 0.1) ** 2,
}


def check(config: dict, source: str) -> dict:
    """Checks across keys: one step per method, valid flip shapes, a non-empty window."""
    integ, flips = config["integration"], config["flips"]
    if len(integ["h"]) != len(integ["methods"]):
        raise ConfigError(
            f"must give one step per method ({len(integ['methods'])}), got {len(integ['h'])}",
            source, "integration", "h",
        )
    if len(set(integ["methods"])) != len(integ["methods"]):
        raise ConfigError("must not name a method twice", source, "integration", "methods")
    pairs = flips["shapes"]
    if len(pairs) % 2:
        raise ConfigError("must hold pairs I1, I2 (an even count of numbers)", source,
                          "flips", "shapes")
    for I1, I2 in zip(pairs[::2], pairs[1::2]):
        if not (0.0 < I1 < I2 < 1.0 and I1 + I2 >= 1.0):
            raise ConfigError(
                f"pair ({I1:g}, {I2:g}) must satisfy 0 < I1 < I2 < 1 and I1 + I2 >= 1 (three "
                "distinct moments of a real body with I3 = 1)", source, "flips", "shapes",
            )
    eps, low = config["ensemble"]["epsilon"], config["analysis"]["window_low"]
    if low * eps >= config["analysis"]["window_high"]:
        raise ConfigError(
            f"must be > window_low * [ensemble] epsilon = {low * eps:g}: the growth-rate window "
            f"is empty, got {config['analysis']['window_high']}", source, "analysis",
            "window_high",
        )
    return config


def outputs(config: dict) -> list[str]:
    """Files a run writes into the output folder."""
    out = config["output"]
    names = [out["dataset"], "config.toml"]
    if out["figures"]:
        names += [f"{stem}.{fmt}" for stem in FIGURES for fmt in out["formats"]]
    return names


# ------------------------------------------------------------------------------------ shapes


def shape_grid(divisions: int):
    """The triangle of allowed shapes, normalised to I3 = 1.

    Row k = 0 .. n holds ``I2 = (2n - k) / 2n`` and ``I1 = (k + 2j) / 2n`` for j = 0 .. n - k,
    so ``I1 + I2 >= 1`` (j = 0 is the flat edge) and ``I1 <= I2`` (j = n - k is the edge
    I1 = I2, where the two moments are the same float). The rod corner (k = j = 0, I1 = 0) is
    left out.

    Parameters
    ----------
    divisions : int
        n >= 1.

    Returns
    -------
    moments : ndarray, shape (S, 3)
        (I1, I2, I3) of each shape, S = (n + 1)(n + 2) / 2 - 1.
    edges : ndarray of int8, shape (S,)
        Bit mask of ``EDGE_EQUAL_12``, ``EDGE_EQUAL_23``, ``EDGE_FLAT``.
    """
    n = int(divisions)
    moments, edges = [], []
    for k in range(n + 1):
        for j in range(n - k + 1):
            if k == 0 and j == 0:
                continue
            moments.append(((k + 2 * j) / (2 * n), (2 * n - k) / (2 * n), 1.0))
            edges.append(
                (EDGE_EQUAL_12 if j == n - k else 0)
                | (EDGE_EQUAL_23 if k == 0 else 0)
                | (EDGE_FLAT if j == 0 else 0)
            )
    return np.array(moments), np.array(edges, dtype=np.int8)


def amplitude_levels(spin: float, epsilon: float, per_decade: int) -> np.ndarray:
    """Ascending perpendicular-amplitude levels (rad/s) from 1.5 epsilon W up to W."""
    first = math.floor(per_decade * math.log10(1.5 * epsilon))
    return spin * 10.0 ** (np.arange(first, 1) / per_decade)


def horizons(omega2: np.ndarray, horizon: float, t_max: float, t_neutral: float) -> np.ndarray:
    """Run length per (shape, axis) in s: ``horizon / |Omega|`` up to ``t_max``; ``t_neutral``
    where Omega^2 = 0. It depends on |Omega^2| only, never on its sign."""
    rate = np.sqrt(np.abs(omega2))
    with np.errstate(divide="ignore"):
        return np.where(rate > 0, np.minimum(t_max, horizon / rate), t_neutral)


# ----------------------------------------------------------------------------------- the run


def run(config: dict, out_dir: Path, *, overwrite=False, threads=None, progress=None,
        history=None) -> StudySummary:
    """Run the map described by the resolved ``config``; write its files into ``out_dir``."""
    import stability

    from .config import to_toml

    t_start = time.perf_counter()
    threads = config["integration"]["threads"] if threads is None else threads
    with numba_threads(threads):
        ds, work = compute(config, progress=progress)
    ds.attrs["history"] = history or f"stability run ({NAME})"
    ds.attrs["config_toml"] = to_toml(config)
    compute_time = time.perf_counter() - t_start

    out = config["output"]
    files = [out_dir / out["dataset"]]
    stability.save(ds, files[0], overwrite=overwrite)
    (out_dir / "config.toml").write_text(to_toml(config), encoding="utf-8")
    files.append(out_dir / "config.toml")
    if out["figures"]:
        from ..figures import stability_map as figures
        from ..figures.style import save

        for stem, make in zip(FIGURES, (figures.map_figure, figures.scatter_figure,
                                        figures.flip_interval_figure, figures.edges_figure)):
            files += save(make(ds), out_dir, stem, out["formats"])
    wall = time.perf_counter() - t_start
    return summarize(ds, config, out_dir, files, wall, compute_time, work)


def compute(config: dict, progress=None):
    """All the runs of the map; returns the Dataset and the work done (member-steps, s).

    Parameters
    ----------
    config : dict
        Resolved configuration of this study kind.
    progress : bool, optional
        Progress bar over the ensembles; by default shown on a terminal.

    Returns
    -------
    ds : xarray.Dataset
    work : dict
        ``member_steps`` and ``loop_time`` (s, in compiled code) summed over the map's runs.
    """
    import stability

    from .. import conventions as cv
    from .. import estimators as est
    from ..ensemble import perturbed_starts
    from ..integrators import method_spec

    spin = config["spin"]["rate"]
    ens, integ, ana = config["ensemble"], config["integration"], config["analysis"]
    members, eps, seed = ens["members"], ens["epsilon"], ens["seed"]
    moments, edges = shape_grid(config["grid"]["divisions"])
    n_shapes = moments.shape[0]
    bodies = [stability.RigidBody(*I, name=f"shape {s}") for s, I in enumerate(moments)]
    axes = np.array(cv.AXES)
    omega2 = np.array([[float(stability.omega_squared(b, a, spin)) for a in axes]
                       for b in bodies])
    t_end = horizons(omega2, integ["horizon"], integ["t_max"], integ["t_neutral"])
    levels = amplitude_levels(spin, eps, ana["levels_per_decade"])
    # The same random directions for every ensemble about an axis (run_ensemble draws them so).
    starts = {a: perturbed_starts(a, spin, eps, members, seed) for a in axes}

    specs = [method_spec(m) for m in integ["methods"]]
    # The exact flow first: its per-member flip times are the reference of the others.
    order = sorted(range(len(specs)), key=lambda i: not specs[i].is_exact)
    runs = []  # (method index, h, shape indices, is the half-step bias run)
    for i in order:
        runs.append((i, integ["h"][i], np.arange(n_shapes), False))
        if integ["bias_check"] and not specs[i].is_exact:
            runs.append((i, integ["h"][i] / 2, np.arange(0, n_shapes, integ["bias_stride"]), True))

    exact_flip = {}  # (s, a) -> (exact 2K/nu, asymptote) per member, unstable axes only
    for s in range(n_shapes):
        for a in axes:
            if omega2[s, a - 1] < 0:
                exact_flip[s, a] = est.exact_flip_intervals(bodies[s], a, starts[a])

    n_methods = len(specs)
    shape3 = (n_methods, n_shapes, 3)
    nan = np.full(shape3, np.nan)
    out = {name: nan.copy() for name in _MAP_FLOATS}
    out["regime"] = np.zeros(shape3, dtype=np.int8)
    out["sign_agrees"] = np.zeros(shape3, dtype=np.int8)
    out["members_failed"] = np.zeros(shape3, dtype=np.int32)
    out["status"] = np.zeros(shape3, dtype=np.int8)
    half = {"omega_squared_measured": nan.copy(), "regime": np.zeros(shape3, dtype=np.int8)}
    first_exact = {}
    total = sum(len(shapes) for _, _, shapes, _ in runs) * 3
    bar = _bar(total, progress)
    member_steps = 0
    loop_time = 0.0
    for i, h, shapes, is_half in runs:
        spec = specs[i]
        for s in shapes:
            for a in axes:
                n_steps = max(1, int(math.ceil(t_end[s, a - 1] / h - 1e-9)))
                run = stability.run_ensemble(
                    bodies[s], int(a), spin, eps, members, h=h, t_end=n_steps * h, seed=seed,
                    method=spec.name, summaries_only=True, levels=levels, progress=False,
                    command=f"stability run ({NAME})",
                )
                if run.attrs["interrupted"]:  # Ctrl-C stopped this ensemble: stop the map
                    bar.close()
                    raise KeyboardInterrupt
                member_steps += run.attrs["members"] * run.attrs["steps_done"]
                loop_time += run.attrs["wall_time"]
                mem = est.members(run)
                e = est.omega_squared_estimate(mem, omega2[s, a - 1], low_factor=ana["window_low"],
                                               high_fraction=ana["window_high"])
                if is_half:
                    half["omega_squared_measured"][i, s, a - 1] = e["omega_squared_measured"]
                    half["regime"][i, s, a - 1] = e["regime"]
                    bar.update(1)
                    continue
                exact, asymptote = exact_flip.get((s, a), (None, None))
                if exact is not None and not np.array_equal(run.w0.values, starts[a]):
                    exact, asymptote = est.exact_flip_intervals(bodies[s], a, run.w0.values)
                f = est.flip_estimate(mem, exact, asymptote)
                if spec.is_exact:
                    first_exact[s, a] = f["first_flip_time"]
                elif (s, a) in first_exact:
                    with np.errstate(invalid="ignore", divide="ignore"):
                        rel = (f["first_flip_time"] - first_exact[s, a]) / first_exact[s, a]
                    out["first_flip_time_relative_error"][i, s, a - 1] = _finite_mean(rel)
                for name in _MAP_FLOATS:
                    if name in e:
                        out[name][i, s, a - 1] = e[name]
                    elif name in f:
                        out[name][i, s, a - 1] = f[name]
                status = run.status.values
                out["regime"][i, s, a - 1] = e["regime"]
                out["sign_agrees"][i, s, a - 1] = e["sign_agrees"]
                out["members_failed"][i, s, a - 1] = int(np.sum(status != cv.STATUS_OK))
                out["status"][i, s, a - 1] = int(np.max(status))
                out["energy_error_max"][i, s, a - 1] = _nanmax_abs(run.energy_error.values)
                bar.update(1)
    bar.close()

    p = np.array([spec.order if not spec.is_exact else np.inf for spec in specs])
    with np.errstate(invalid="ignore", divide="ignore"):
        bias = (out["omega_squared_measured"] - half["omega_squared_measured"]) / (
            1.0 - 2.0 ** -p[:, None, None]) / np.abs(omega2)[None]
    sweep = flip_sweep(config, specs)
    edge = edge_series(config, specs[0], integ["h"][0])
    ds = _dataset(config, specs, moments, edges, omega2, t_end, levels, out, half, bias,
                  sweep, edge)
    return ds, {"member_steps": member_steps, "loop_time": loop_time}


#: Float estimates stored per (integrator, shape, axis).
_MAP_FLOATS = (
    "omega_squared_measured", "omega_squared_measured_stderr", "relative_error",
    "growth_rate", "growth_rate_stderr", "oscillation_frequency",
    "oscillation_frequency_stderr", "drift_rate", "n_fitted", "n_flips_mean",
    "first_flip_time_mean", "first_flip_time_stderr", "flip_interval_mean",
    "flip_interval_stderr", "flip_interval_exact_mean", "flip_interval_asymptote_mean",
    "flip_interval_relative_error", "flip_interval_relative_error_stderr",
    "first_flip_time_relative_error", "energy_error_max",
)


def _finite_mean(x):
    x = np.asarray(x, dtype=float)
    x = x[np.isfinite(x)]
    return float(x.mean()) if x.size else math.nan


def _nanmax_abs(x):
    x = np.abs(np.asarray(x, dtype=float))
    x = x[np.isfinite(x)]
    return float(x.max()) if x.size else math.nan


class _NoBar:
    def update(self, n):
        pass

    def close(self):
        pass


def _bar(total, progress):
    if progress is False or (progress is None and not sys.stderr.isatty()):
        return _NoBar()
    from tqdm.auto import tqdm

    return tqdm(total=total, unit="ensemble", desc=NAME, leave=False)


def flip_sweep(config: dict, specs) -> dict:
    """Flip intervals against epsilon for the ``[flips]`` shapes, every method.

    Each shape spins about its intermediate axis 2 with the perturbation ``epsilon W`` along
    axis 1 (one member per epsilon, all in one run of each method), long enough for three flips
    at the smallest epsilon.

    Returns
    -------
    dict
        ``moments`` (F, 3), ``epsilons`` (E,), ``measured`` (methods, F, E), ``exact`` and
        ``asymptote`` (F, E) in s, ``growth_rate`` (F,) in s-1.
    """
    import stability

    from .. import estimators as est

    spin = config["spin"]["rate"]
    pairs = config["flips"]["shapes"]
    moments = np.array([(I1, I2, 1.0) for I1, I2 in zip(pairs[::2], pairs[1::2])])
    epsilons = np.array(config["flips"]["epsilons"], dtype=float)
    w0 = np.zeros((epsilons.size, 3))
    w0[:, 0] = epsilons * spin
    w0[:, 1] = spin
    measured = np.full((len(specs), moments.shape[0], epsilons.size), np.nan)
    exact = np.full((moments.shape[0], epsilons.size), np.nan)
    asymptote = np.full_like(exact, np.nan)
    rate = np.array([float(stability.growth_rate(I, 2, spin)) for I in moments])
    for f, I in enumerate(moments):
        body = stability.RigidBody(*I, name=f"flip shape {f}")
        exact[f], asymptote[f] = est.exact_flip_intervals(body, 2, w0)
        t_end = 2.6 * float(np.nanmax(exact[f]))
        for i, spec in enumerate(specs):
            h = config["integration"]["h"][i]
            run = stability.run_ensemble(
                body, 2, starts=w0, h=h, t_end=h * math.ceil(t_end / h), method=spec.name,
                summaries_only=True, progress=False, command=f"stability run ({NAME})",
            )
            if run.attrs["interrupted"]:
                raise KeyboardInterrupt
            measured[i, f] = run.mean_flip_interval.values  # NaN below two flips or not ok
    return {"moments": moments, "epsilons": epsilons, "measured": measured, "exact": exact,
            "asymptote": asymptote, "growth_rate": rate}


def edge_series(config: dict, spec, h: float) -> dict:
    """Time series on the equal-moment edges and the sphere: drift, not growth (ERRATA 3).

    Each case spins about an axis whose moment equals another one, perturbed by
    ``epsilon W / sqrt(2)`` along both other axes. Linear theory: Omega^2 = 0; exactly, the
    distinct-axis component stays constant and the other perpendicular one moves off linearly
    in t at its initial rate of change (Euler's equations at the start), with no flip.

    Returns
    -------
    dict
        ``names`` (C,), ``moments`` (C, 3), ``axis`` (C,), ``time`` (T,), ``w`` (C, T, 3) in
        rad/s, ``slope_predicted`` and ``slope_measured`` (C,) in rad s-2 (of the drifting
        component), ``distinct_change`` (C,) in rad/s (largest change of the component along
        the distinct axis), ``flips`` (C,), ``regime``, ``linear_residual``,
        ``exponential_residual`` (C,).
    """
    import stability

    from .. import estimators as est

    spin, eps = config["spin"]["rate"], config["edges"]["epsilon"]
    t_end = h * math.ceil(config["edges"]["t_end"] / h - 1e-9)
    save_every = max(1, int(round(t_end / h / 400)))
    while round(t_end / h) % save_every:
        save_every -= 1
    names, moments, axis = [], [], []
    series, predicted, measured, distinct, flips = [], [], [], [], []
    regime, lin, expo = [], [], []
    for name, I, a in EDGE_CASES:
        body = stability.RigidBody(*I, physical=False)
        w0 = np.full(3, eps * spin / math.sqrt(2.0))
        w0[a - 1] = spin
        ds = stability.integrate(body, w0, t_end, h, method=spec.name, save_every=save_every)
        w = ds.w.values
        t = ds.time.values
        others = [b for b in (1, 2, 3) if b != a]
        equal = [b for b in others if I[b - 1] == I[a - 1]]
        c = ([b for b in others if b not in equal] or [others[0]])[0]  # the distinct axis
        e = [b for b in others if b != c][0]  # the drifting one
        rhs = _euler_rhs(np.asarray(I), w0)
        slope = np.polyfit(t, w[:, e - 1], 1)[0]
        reg = est.member_regimes(ds, axis=a, spin=spin)
        names.append(name)
        moments.append(I)
        axis.append(a)
        series.append(w)
        predicted.append(rhs[e - 1])
        measured.append(slope)
        distinct.append(float(np.max(np.abs(w[:, c - 1] - w0[c - 1]))))
        flips.append(int(est.zero_crossings(t, w[None, :, a - 1])[0][0]))
        regime.append(int(reg.regime.values[0]))
        lin.append(float(reg.linear_residual.values[0]))
        expo.append(float(reg.exponential_residual.values[0]))
    return {
        "names": names, "moments": np.array(moments), "axis": np.array(axis), "time": t,
        "w": np.array(series), "slope_predicted": np.array(predicted),
        "slope_measured": np.array(measured), "distinct_change": np.array(distinct),
        "flips": np.array(flips), "regime": np.array(regime, dtype=np.int8),
        "linear_residual": np.array(lin), "exponential_residual": np.array(expo),
        "method": spec.name, "h": h,
    }


def _euler_rhs(I, w):
    """dw/dt of the torque-free Euler equations (ERRATA 1): I1 w1' = (I2 - I3) w2 w3, cyclic."""
    I1, I2, I3 = I
    w1, w2, w3 = w
    return np.array([(I2 - I3) * w2 * w3 / I1, (I3 - I1) * w3 * w1 / I2,
                     (I1 - I2) * w1 * w2 / I3])


# ------------------------------------------------------------------------------- the Dataset


def _dataset(config, specs, moments, edges, omega2, t_end, levels, out, half, bias, sweep,
             edge):
    import xarray as xr

    from .. import conventions as cv
    from .. import estimators as est
    from ..dataset import software_attrs

    spin = config["spin"]["rate"]
    M, S, A = "integrator", "shape", cv.AXIS
    one, s2 = cv.UNITS_DIMENSIONLESS, cv.UNITS_RATE_SQUARED
    data = {
        "omega_squared": ((S, A), omega2, {
            "long_name": "analytic Omega^2 = (Ia - Ib)(Ia - Ic) W^2 / (Ib Ic)", "units": s2}),
        "omega_squared_normalised": ((S, A), omega2 / spin**2, {
            "long_name": "analytic Omega^2 / W^2", "units": one}),
        "t_end": ((S, A), t_end, {"long_name": "run length of the ensemble",
                                  "units": cv.UNITS_TIME}),
        "edge": ((S,), edges, {"long_name": "triangle edges the shape lies on",
                               "flag_masks": np.array([1, 2, 4], dtype=np.int8),
                               "flag_meanings": EDGE_MEANINGS, "units": one}),
        "regime": ((M, S, A), out["regime"], est.ESTIMATE_ATTRS["regime"]),
        "sign_agrees": ((M, S, A), out["sign_agrees"], {
            **est.ESTIMATE_ATTRS["sign_agrees"], "flag_values": np.array([0, 1], dtype=np.int8),
            "flag_meanings": "no yes"}),
        "status": ((M, S, A), out["status"], {
            "long_name": "worst member status of the ensemble",
            "flag_values": np.array(cv.STATUS_FLAG_VALUES, dtype=np.int8),
            "flag_meanings": cv.STATUS_MEANINGS, "units": one}),
        "members_failed": ((M, S, A), out["members_failed"], {
            "long_name": "members whose status is not ok (left out of the estimates)",
            "units": one}),
        "energy_error_max": ((M, S, A), out["energy_error_max"], {
            "long_name": "largest relative kinetic-energy error at the end over members",
            "units": one}),
        "first_flip_time_relative_error": ((M, S, A), out["first_flip_time_relative_error"], {
            "long_name": "mean relative difference of the first-flip time from the exact "
                         "flow's, member by member", "units": one}),
        "omega_squared_measured_half_step": ((M, S, A), half["omega_squared_measured"], {
            "long_name": "measured Omega^2 at step h / 2 (bias check)", "units": s2}),
        "regime_half_step": ((M, S, A), half["regime"],
                             {**est.ESTIMATE_ATTRS["regime"],
                              "long_name": "regime at step h / 2 (bias check)"}),
        "step_bias": ((M, S, A), bias, {
            "long_name": "Richardson estimate of the method's relative O(h^p) bias in Omega^2 "
                         "at step h, (X(h) - X(h/2)) / (1 - 2^-p) / |Omega^2|", "units": one}),
    }
    for name in _MAP_FLOATS:
        if name in data:
            continue
        attrs = est.ESTIMATE_ATTRS.get(name)
        data[name] = ((M, S, A), out[name], attrs)
    F, E = "flip_shape", "epsilon"
    data.update({
        "sweep_flip_interval": ((M, F, E), sweep["measured"], {
            "long_name": "measured flip interval, perturbation epsilon along axis 1",
            "units": cv.UNITS_TIME}),
        "sweep_flip_interval_exact": ((F, E), sweep["exact"], {
            "long_name": "exact flip interval 2K/nu", "units": cv.UNITS_TIME}),
        "sweep_flip_interval_asymptote": ((F, E), sweep["asymptote"], {
            "long_name": "asymptotic flip interval (2/lambda) ln(4/k')", "units": cv.UNITS_TIME}),
        "sweep_growth_rate": ((F,), sweep["growth_rate"], {
            "long_name": "analytic growth rate lambda about axis 2", "units": cv.UNITS_RATE}),
    })
    C, T = "edge_case", "edge_time"
    data.update({
        "edge_w": ((C, T, A), edge["w"], {
            "long_name": "body-frame angular velocity on an edge case",
            "units": cv.UNITS_ANGULAR_VELOCITY}),
        "edge_slope_predicted": ((C,), edge["slope_predicted"], {
            "long_name": "initial rate of change of the drifting component (Euler's equations)",
            "units": "rad s-2"}),
        "edge_slope_measured": ((C,), edge["slope_measured"], {
            "long_name": "least-squares slope of the drifting component", "units": "rad s-2"}),
        "edge_distinct_change": ((C,), edge["distinct_change"], {
            "long_name": "largest change of the component along the distinct axis",
            "units": cv.UNITS_ANGULAR_VELOCITY}),
        "edge_flips": ((C,), edge["flips"], {"long_name": "sign changes of the spin component",
                                             "units": one}),
        "edge_regime": ((C,), edge["regime"], est.ESTIMATE_ATTRS["regime"]),
        "edge_linear_residual": ((C,), edge["linear_residual"], {
            "long_name": "rms relative misfit of a straight line to the amplitude",
            "units": one}),
        "edge_exponential_residual": ((C,), edge["exponential_residual"], {
            "long_name": "rms misfit of an exponential to the amplitude", "units": one}),
    })
    coords = {
        M: (M, [spec.name for spec in specs], {"long_name": "integrator"}),
        "h": (M, np.array(config["integration"]["h"], dtype=float),
              {"long_name": "step", "units": cv.UNITS_TIME}),
        "method_order": (M, np.array([spec.order for spec in specs], dtype=float),
                         {"long_name": "order of the method (inf: exact flow)", "units": one}),
        S: (S, np.arange(moments.shape[0]), {"long_name": "shape index"}),
        "I1": (S, moments[:, 0], _moment_attrs(1)),
        "I2": (S, moments[:, 1], _moment_attrs(2)),
        "I3": (S, moments[:, 2], _moment_attrs(3)),
        A: (A, np.array(cv.AXES), {"long_name": "principal axis of the spin"}),
        "level": ("level", levels, {"long_name": "perpendicular amplitude level of the "
                                                 "passage times", "units":
                                    cv.UNITS_ANGULAR_VELOCITY}),
        F: (F, np.arange(sweep["moments"].shape[0]), {"long_name": "flip sweep shape index"}),
        "flip_I1": (F, sweep["moments"][:, 0], _moment_attrs(1)),
        "flip_I2": (F, sweep["moments"][:, 1], _moment_attrs(2)),
        E: (E, sweep["epsilons"], {"long_name": "perturbation relative to the spin",
                                   "units": one}),
        C: (C, edge["names"], {"long_name": "edge case"}),
        "edge_I1": (C, edge["moments"][:, 0], _moment_attrs(1)),
        "edge_I2": (C, edge["moments"][:, 1], _moment_attrs(2)),
        "edge_I3": (C, edge["moments"][:, 2], _moment_attrs(3)),
        "edge_axis": (C, edge["axis"], {"long_name": "spin axis of the edge case"}),
        T: (T, edge["time"], {"long_name": "time since the start", "units": cv.UNITS_TIME}),
    }
    ens, integ, ana = config["ensemble"], config["integration"], config["analysis"]
    attrs = {
        "Conventions": "CF-1.10",
        "title": config["title"],
        **software_attrs(),
        "references": "literature notes 1.4-1.5, 2.1-2.3; course-notes ERRATA 2-3",
        "spin": spin,
        "spin_units": cv.UNITS_ANGULAR_VELOCITY,
        "epsilon": ens["epsilon"],
        "members": ens["members"],
        "seed_entropy": str(ens["seed"]),
        "horizon": integ["horizon"],
        "t_max": integ["t_max"],
        "t_neutral": integ["t_neutral"],
        "bias_stride": integ["bias_stride"],
        "window": f"[{ana['window_low']:g} x initial amplitude, {ana['window_high']:g} x "
                  "min(spin, saturation amplitude))",
        "tolerance": ana["tolerance"],
        "min_omega_squared": ana["min_omega_squared"],
        "edge_method": edge["method"],
        "edge_h": edge["h"],
        "edge_epsilon": config["edges"]["epsilon"],
    }
    return xr.Dataset(data, coords=coords, attrs=attrs)


def _moment_attrs(i):
    from .. import conventions as cv

    return {"long_name": f"principal moment I{i}, normalised so that I3 = 1",
            "units": cv.UNITS_MOMENT_OF_INERTIA}


# ------------------------------------------------------------------------------- the summary


def summarize(ds, config, out_dir, files, wall, compute_time, work) -> StudySummary:
    """The accuracy bars, the edges, the flips, the cost: rows of the printed table."""
    from .. import estimators as est

    ana = config["analysis"]
    tol, floor = ana["tolerance"], ana["min_omega_squared"]
    spin = float(ds.attrs["spin"])
    norm = ds.omega_squared_normalised.values
    bar_set = np.abs(norm) > floor
    rows, values = [], {}
    n_shapes, members = ds.sizes["shape"], ds.attrs["members"]
    rows.append(("shapes x axes (ensembles per method)", f"{n_shapes} x 3 = {3 * n_shapes}", ""))
    rows.append(("members per ensemble, perturbation epsilon",
                 f"{members}, {ds.attrs['epsilon']:g}", ""))
    passed_all = True
    for k, method in enumerate(ds.integrator.values):
        h = float(ds.h.values[k])
        rel = ds.relative_error.values[k]
        sign = ds.sign_agrees.values[k].astype(bool)
        in_bar = rel[bar_set]
        worst = float(np.nanmax(np.abs(in_bar))) if np.isfinite(in_bar).any() else math.nan
        missing = int(np.sum(~np.isfinite(in_bar)))
        passed = int(np.sum(np.abs(in_bar) <= tol))
        ok = passed == in_bar.size and missing == 0 and bool(sign.all())
        passed_all &= ok
        where = np.unravel_index(np.nanargmax(np.where(bar_set, np.abs(rel), -1.0)), rel.shape)
        I = [float(ds[f"I{i}"].values[where[0]]) for i in (1, 2, 3)]
        tag = f"{method} (h = {h:g} s)"
        rows.append((f"{tag}: worst |rel. error| of Omega^2 where |Omega^2|/W^2 > {floor:g}",
                     f"{worst:.2e}", f"at I = ({I[0]:.4g}, {I[1]:.4g}, 1), axis {where[1] + 1}"))
        rows.append((f"{tag}: within the bar {tol:g}", f"{passed} / {in_bar.size}",
                     "PASS" if ok else "FAIL"))
        rows.append((f"{tag}: regime sign right", f"{int(sign.sum())} / {sign.size}", ""))
        med = float(np.nanmedian(np.abs(in_bar))) if np.isfinite(in_bar).any() else math.nan
        rows.append((f"{tag}: median |rel. error|", f"{med:.1e}", ""))
        bias = ds.step_bias.values[k][bar_set]
        if np.isfinite(bias).any():
            rows.append((f"{tag}: O(h^p) bias in Omega^2 (h vs h/2), median / max |.|",
                         f"{np.nanmedian(np.abs(bias)):.1e} / {np.nanmax(np.abs(bias)):.1e}",
                         f"{int(np.isfinite(bias).sum())} ensembles"))
        if method in LITERATURE_RATE_BIAS:
            # The grid shape nearest I = (1, 2, 3) / 3, spin about axis 2: literature notes 4.1.
            s = int(np.argmin((ds.I1.values - 1 / 3) ** 2 + (ds.I2.values - 2 / 3) ** 2))
            lam = math.sqrt(-float(ds.omega_squared.values[s, 1]))
            predicted = -2.0 * LITERATURE_RATE_BIAS[method](h * spin, lam / spin)
            rows.append((f"{tag}: rel. error at I = ({float(ds.I1[s]):.4g}, "
                         f"{float(ds.I2[s]):.4g}, 1), axis 2 / literature bias",
                         f"{rel[s, 1]:.1e} / {predicted:.1e}",
                         f"+- {float(ds.omega_squared_measured_stderr[k, s, 1]) / lam**2:.0e}"
                         " (stderr); literature notes 4.1"))
        flip_rel = ds.flip_interval_relative_error.values[k]
        if np.isfinite(flip_rel).any():
            rows.append((f"{tag}: flip interval vs exact 2K/nu, median / max |rel.|",
                         f"{np.nanmedian(np.abs(flip_rel)):.1e} / "
                         f"{np.nanmax(np.abs(flip_rel)):.1e}", "unstable axes"))
        first_rel = ds.first_flip_time_relative_error.values[k]
        if np.isfinite(first_rel).any():
            rows.append((f"{tag}: first flip vs the exact flow, max |rel.|",
                         f"{np.nanmax(np.abs(first_rel)):.1e}", "member by member"))
        values[f"{method}_worst_relative_error"] = worst
        values[f"{method}_passed"] = passed
        values[f"{method}_sign_right"] = int(sign.sum())
    values["bar_size"] = int(bar_set.sum())
    values["all_passed"] = bool(passed_all)

    # The edges, classified rather than fitted.
    edge = ds.edge.values
    zero = norm == 0.0
    reg = ds.regime.values
    for label, mask in (("I1 = I2 edge", (edge & EDGE_EQUAL_12) > 0),
                        ("I2 = I3 edge", (edge & EDGE_EQUAL_23) > 0)):
        not_sphere = edge != (EDGE_EQUAL_12 | EDGE_EQUAL_23)
        sel = (mask & not_sphere)[:, None] & zero
        alg = int(np.sum(reg[:, sel] == est.REGIME_ALGEBRAIC))
        flips = float(np.nanmax(ds.n_flips_mean.values[:, sel])) if sel.any() else 0.0
        rows.append((f"{label}, equal-moment axes (Omega^2 = 0): algebraic drift",
                     f"{alg} / {reg[:, sel].size}", f"flips per member at most {flips:g}"))
    sphere = edge == (EDGE_EQUAL_12 | EDGE_EQUAL_23)
    if sphere.any():
        neutral = int(np.sum(reg[:, sphere, :] == est.REGIME_NEUTRAL))
        rows.append(("sphere: no departure (neutral)", f"{neutral} / {reg[:, sphere, :].size}", ""))
    flat = (edge & EDGE_FLAT) > 0
    flat_rel = ds.relative_error.values[:, flat, :][:, bar_set[flat]]
    if np.isfinite(flat_rel).any():
        rows.append(("flat edge I1 + I2 = I3: worst |rel. error| (all methods)",
                     f"{np.nanmax(np.abs(flat_rel)):.2e}", ""))
    for c, name in enumerate(ds.edge_case.values):
        rows.append((f"edge series {name}: slope measured / predicted",
                     f"{float(ds.edge_slope_measured[c]):.4e} / "
                     f"{float(ds.edge_slope_predicted[c]):.4e}", "rad s-2"))
        rows.append((f"edge series {name}: distinct component change, flips",
                     f"{float(ds.edge_distinct_change[c]):.1e}, {int(ds.edge_flips[c])}",
                     "rad s-1"))

    sweep = ds.sweep_flip_interval.values
    exact = ds.sweep_flip_interval_exact.values
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.abs(sweep - exact[None]) / exact[None]
    for k, method in enumerate(ds.integrator.values):
        for lo in (1e-6,):
            sel = ds.epsilon.values >= lo
            if np.isfinite(rel[k][:, sel]).any():
                rows.append((f"flip sweep {method}: max |rel.| vs 2K/nu, epsilon >= {lo:g}",
                             f"{np.nanmax(rel[k][:, sel]):.1e}", ""))

    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # KiB on Linux
    rate = work["member_steps"] / work["loop_time"] if work["loop_time"] > 0 else math.nan
    rows.append(("wall time (all, with compile, figures and files)", f"{wall:.1f}", "s"))
    rows.append(("  of which the runs", f"{compute_time:.1f}", "s"))
    rows.append(("member-steps in the map, per second in compiled code",
                 f"{work['member_steps']:.3g}, {rate:.3g}", "s-1"))
    rows.append(("peak memory (resident set, getrusage)", f"{peak:.0f}", "MiB"))
    values.update({"wall_time": wall, "compute_time": compute_time, "peak_memory_mib": peak,
                   "member_steps": work["member_steps"]})
    return StudySummary(NAME, Path(out_dir), files, rows, values)


STUDY = StudyKind(
    name=NAME,
    title="stability map",
    schema=SCHEMA,
    run=run,
    outputs=outputs,
    check=check,
    quick=QUICK,
    members_key=("ensemble", "members"),
)
