"""What physics engines' update rules do to the tennis-racket flip, measured against the exact motion.

An ensemble tossed about the middle axis is run with each engine rule (scene ``engine_body``,
:mod:`stability.engine_body.methods`) and, beside them, with the package's integrators
carrying the attitude (scene ``free_body_attitude``), at the time steps engines use. Per rule and
step (:func:`measure_rule`): the fraction of members that flip, the flip interval and the growth
rate against the exact ones (:func:`stability.analysis.estimates.flip_estimate`,
:func:`stability.analysis.estimates.omega_squared_estimate`), the drift of the energy, of |L| and of the
direction of the spatial angular momentum, and the measured cost per step;
:func:`step_for_accuracy` finds the step each rule needs for a flip interval within a tolerance
(:func:`steps_for_accuracy`: for several quantities in one search).
Everything in the canonical frame, spin about axis 2.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..free_body.model import growth_rate, omega_squared
from ..free_body.attitude import FREE_BODY_SCENES
from ..core.quaternions import IDENTITY, spatial_angular_momentum
from ..core.body import RigidBody
from ..analysis.estimates import flip_estimate, omega_squared_estimate
from ..analysis.members import tracked_members
from ..free_body.exact import exact_omega, flip_intervals
from ..output.dataset import storable_attrs
from ..ensemble.chunks import run_plan
from ..ensemble.options import RunOptions, run_options
from ..ensemble.plan import Plan
from ..engine.scene import Scene
from .scene import ENGINE_BODY
from .schema import ENGINE_ARTEFACTS
from ..util import conventions as cv
from .methods import ENGINE_RULES
from .model import body_state, world_state

#: Tracked axes in the canonical frame: spin about axis 2, across it axes 1 and 3.
_AXES = np.array([[1, 0, 2]])

#: Perpendicular-amplitude levels for the growth rate, relative to the spin.
LEVELS = np.geomspace(1e-3, 0.3, 12)

#: The growth rate's fit window: from 10 times the start's amplitude to 3 % of the spin (the
#: tennis-racket study's), so that nudges of 1e-4 of the spin leave a linear phase to fit.
GROWTH_WINDOW = (10.0, 0.03)


def integrator_rules() -> tuple[str, ...]:
    """The package's methods an engine rule is set beside: those that carry the attitude
    (scene ``free_body_attitude``) and the exact flow (``"exact"``, scene ``free_body``)."""
    return (*FREE_BODY_SCENES["free_body_attitude"].methods, "exact")


def rule_scene(rule: str) -> Scene:
    """The scene a rule runs on: ``engine_body`` for the engine rules, the attitude scene for
    the package's methods that carry it, ``free_body`` for the exact flow.

    Parameters
    ----------
    rule : str
        An engine rule (``ENGINE_RULES``), an attitude method, or ``"exact"``.

    Returns
    -------
    Scene
    """
    if rule in ENGINE_RULES:
        return ENGINE_BODY
    return FREE_BODY_SCENES["free_body" if rule == "exact" else "free_body_attitude"]


def run_rule(rule, moments, w0, h, t_end, *, save_every=0, options=None):
    """Run the members ``w0`` (N, 3, rad/s, canonical) of the body ``moments`` (canonical) with
    ``rule`` from the identity attitude, tracking flips; returns the Propagation, the final
    body angular momenta (N, 3) and attitudes (N, 4), and the saved body angular velocities
    (N, n_saved, 3).

    Parameters
    ----------
    rule : str
        An engine rule (``ENGINE_RULES``), an attitude method, or ``"exact"``.
    moments : ndarray, shape (3,)
        Canonical (ascending) principal moments, kg m^2.
    w0 : ndarray, shape (N, 3)
        Initial body angular velocities, canonical frame, rad/s.
    h : float
        Time step in s.
    t_end : float
        Horizon in s; the run takes ``round(t_end / h)`` steps.
    save_every : int, default 0
        Store the state every ``save_every`` steps; 0 stores only the final state (and no
        angular velocities are returned).
    options : RunOptions, optional
        How and where the members run (:class:`~stability.ensemble.options.RunOptions`): by
        default in one piece here; with a ``store``, chunk by chunk into it, resumable and on
        dask. The result is the same, bitwise.

    Returns
    -------
    prop : Propagation
        The run, with the flip tracking in ``extras``.
    m : ndarray, shape (N, 3)
        Final body angular momenta, canonical frame, kg m^2/s.
    q : ndarray, shape (N, 4) or None
        Final attitudes (body to space quaternions, scalar first); None for ``"exact"``.
    saved_w : ndarray, shape (N, n_saved, 3) or None
        Saved body angular velocities in rad/s; None when ``save_every`` is 0.

    Raises
    ------
    KeyboardInterrupt
        If Ctrl-C stopped the run.
    """
    scene = rule_scene(rule)
    spec = scene.method(rule)
    m0 = moments * w0
    q0 = np.tile(IDENTITY, (w0.shape[0], 1))
    x0 = {"engine_body": lambda: world_state(moments, m0, q0), "free_body": lambda: m0,
          "free_body_attitude": lambda: np.concatenate([m0, q0], axis=1)}[scene.name]()
    n_steps = int(round(t_end / h))
    spin = float(np.median(np.abs(w0[:, 1])))
    prop = run_plan(
        Plan(scene, spec.name, x0, spec.params(moments, h)[None, :], [w0.shape[0]],
             h, n_steps, save_every=save_every, axes=_AXES,
             levels=(LEVELS * spin)[None, :], label=f"{rule}, h = {h:.3g} s"),
        options)

    def body(x):
        if scene.name == "engine_body":
            m, q = body_state(x.reshape(-1, 7), moments)
            return m.reshape(x.shape[:-1] + (3,)), q.reshape(x.shape[:-1] + (4,))
        if scene.name == "free_body":  # the exact flow: the attitude is exact, not carried
            return x, None
        return x[..., :3], x[..., 3:]

    m, q = body(prop.x_final)
    saved_w = body(prop.saved)[0] / moments if save_every else None
    return prop, m, q, saved_w


def measure_rule(rule, moments, w0, h, t_end, options=None) -> dict:
    """The numbers of one rule at one step (see the module docstring); scalars.

    Parameters
    ----------
    rule : str
        An engine rule (``ENGINE_RULES``), an attitude method, or ``"exact"``.
    moments : ndarray, shape (3,)
        Canonical (ascending) principal moments, kg m^2.
    w0 : ndarray, shape (N, 3)
        Starts near axis 2, canonical frame, rad/s.
    h : float
        Time step in s.
    t_end : float
        Horizon in s.
    options : RunOptions, optional
        How and where the members run (:class:`~stability.ensemble.options.RunOptions`): by
        default in one piece here; with a ``store``, chunk by chunk into it, resumable and on
        dask. The result is the same, bitwise.

    Returns
    -------
    dict
        ``fraction_flipping``, ``flip_interval`` (s), ``flip_interval_error``,
        ``growth_rate`` (1/s), ``growth_rate_error``, ``energy_drift``, ``momentum_drift``,
        ``l_direction_drift`` (rad), ``cost_per_step`` (s per member-step) and ``members_ok``.
    """
    body = RigidBody(*moments, physical=False)
    spin = float(np.median(np.abs(w0[:, 1])))
    prop, m, q, _ = run_rule(rule, moments, w0, h, t_end, options=options)
    ok = prop.status == cv.STATUS_OK
    mem = tracked_members(prop.extras, w0, 2, spin, LEVELS * spin, prop.status)
    exact, asymptote, _ = flip_intervals(body, w0)  # spin about axis 2, the intermediate
    flips = flip_estimate(mem, exact, asymptote)
    growth = omega_squared_estimate(mem, omega_squared(body, 2, spin), low_factor=GROWTH_WINDOW[0],
                                    high_fraction=GROWTH_WINDOW[1])
    m0 = moments * w0
    energy0 = 0.5 * np.sum(m0 * w0, axis=1)
    energy = 0.5 * np.sum(m * m / moments, axis=1)
    if q is None:
        turned = np.zeros(w0.shape[0])
    else:  # angle between the spatial angular momentum R(q) m and its start m0
        space_l = spatial_angular_momentum(q, m)
        turned = np.arctan2(np.linalg.norm(np.cross(space_l, m0), axis=1),
                            np.sum(space_l * m0, axis=1))
    exact_rate = float(growth_rate(body, 2, spin))
    with np.errstate(invalid="ignore"):
        return {
            "fraction_flipping": float(np.mean(flips["flip_count"][ok] >= 1)) if ok.any() else 0.0,
            "flip_interval": float(np.nanmedian(flips["flip_interval"]))
            if np.isfinite(flips["flip_interval"]).any() else math.nan,
            "flip_interval_error": flips["flip_interval_relative_error"],
            "growth_rate": growth["growth_rate"],
            "growth_rate_error": (growth["growth_rate"] - exact_rate) / exact_rate,
            "energy_drift": float(np.median(((energy - energy0) / energy0)[ok])),
            "momentum_drift": float(np.median((np.linalg.norm(m, axis=1)
                                               / np.linalg.norm(m0, axis=1) - 1.0)[ok])),
            "l_direction_drift": float(np.median(turned[ok])),
            "cost_per_step": prop.wall_time / (w0.shape[0] * max(int(round(t_end / h)), 1)),
            "members_ok": int(ok.sum()),
        }


def step_for_accuracy(rule, moments, w0, t_end, h_max, tolerance=0.01, halvings=20,
                      quantity="flip_interval_error", progress=None) -> float:
    """The largest step ``h_max / 2^(k/2)``, k = 0, 1, ..., 2 halvings, at which ``quantity``
    of :func:`measure_rule` (a relative error) is within ``tolerance``; NaN if at none.

    Each trial step is rounded so that ``t_end`` is a whole number of steps.

    Parameters
    ----------
    rule : str
        An engine rule (``ENGINE_RULES``), an attitude method, or ``"exact"``.
    moments : ndarray, shape (3,)
        Canonical (ascending) principal moments, kg m^2.
    w0 : ndarray, shape (N, 3)
        Starts near axis 2, canonical frame, rad/s.
    t_end : float
        Horizon in s.
    h_max : float
        Largest step tried, s.
    tolerance : float, default 0.01
        Largest accepted ``abs(quantity)``.
    halvings : int, default 20
        The search goes down to ``h_max / 2^halvings``.
    quantity : str, default "flip_interval_error"
        Key of :func:`measure_rule`'s result to test.
    progress : bool or None, optional
        The engine's progress bars; ``False`` shows none.

    Returns
    -------
    float
        The step in s, or NaN.
    """
    return steps_for_accuracy(rule, moments, w0, t_end, h_max, tolerance, halvings,
                              (quantity,), progress)[quantity]


def steps_for_accuracy(rule, moments, w0, t_end, h_max, tolerance=0.01, halvings=20,
                       quantities=("flip_interval_error", "energy_drift"),
                       progress=None) -> dict:
    """:func:`step_for_accuracy` for several quantities in one search: each trial step is run
    once for all of them, and the search stops when every quantity has its step.

    Parameters
    ----------
    rule, moments, w0, t_end, h_max, tolerance, halvings, progress
        As in :func:`step_for_accuracy`.
    quantities : sequence of str, default ("flip_interval_error", "energy_drift")
        Keys of :func:`measure_rule`'s result to test.

    Returns
    -------
    dict
        Each quantity's step in s, or NaN.
    """
    found = dict.fromkeys(quantities, math.nan)
    for k in range(2 * halvings + 1):
        steps = int(round(t_end * 2.0 ** (0.5 * k) / h_max))
        result = measure_rule(rule, moments, w0, t_end / steps, t_end,
                              RunOptions(progress=progress))
        for quantity in quantities:
            if math.isnan(found[quantity]) and abs(result[quantity]) <= tolerance:
                found[quantity] = t_end / steps
        if not any(math.isnan(h) for h in found.values()):
            break
    return found


def measure_artefacts(rules, moments, w0, steps, t_end, *, tolerance=0.01, search_members=64,
                      halvings=12, trace_member=0, options=None) -> xr.Dataset:
    """Every rule at every step, the step each needs, and one member's spin-axis trace.

    Parameters
    ----------
    rules : sequence of str
        Engine rules (``ENGINE_RULES``) and attitude methods.
    moments : array_like, shape (3,)
        Canonical (ascending) moments, kg m^2.
    w0 : array_like, shape (N, 3)
        Starts near axis 2, rad/s, canonical frame.
    steps : sequence of float
        Time steps in s (engines: 1/60, 1/120, 1/240).
    t_end : float
        Horizon in s, a whole number of every step.
    tolerance : float, default 0.01
        Relative flip-interval error (and energy error) for ``step_for_accuracy``.
    search_members : int, default 64
        Members used to search that step.
    halvings : int, default 12
        The search goes down to ``steps[0] / 2^halvings``.
    trace_member : int, default 0
        Index of the member whose spin-axis angular velocity w2 is stored, run at
        ``steps[0]``, beside its exact w2.
    options : RunOptions, optional
        How and where the members run (:class:`~stability.ensemble.options.RunOptions`): by
        default in one piece here; with a ``store``, chunk by chunk into it, resumable and on
        dask. The result is the same, bitwise.

    Returns
    -------
    xarray.Dataset
    """
    moments = np.asarray(moments, dtype=float)
    w0 = np.atleast_2d(np.asarray(w0, dtype=float))
    options = run_options(options)
    table = {name: np.full((len(rules), len(steps)), np.nan) for name in _TABLE}
    for i, rule in enumerate(rules):
        for j, h in enumerate(steps):
            for name, value in measure_rule(rule, moments, w0, h, t_end,
                                            options.within(f"{rule}-{j}")).items():
                table[name][i, j] = value
    searches = [steps_for_accuracy(rule, moments, w0[:search_members], t_end, steps[0],
                                   tolerance, halvings, progress=options.progress)
                for rule in rules]
    needed = np.array([[found[quantity] for found in searches]
                       for quantity in ("flip_interval_error", "energy_drift")])
    trace_h = steps[0]
    traces = []
    for rule in rules:
        saved = run_rule(rule, moments, w0[trace_member:trace_member + 1], trace_h, t_end,
                         save_every=1, options=options.within(f"{rule}-trace"))[3]
        traces.append(np.concatenate([w0[trace_member:trace_member + 1, 1], saved[0, :, 1]]))
    exact = flip_intervals(RigidBody(*moments, physical=False), w0)[0]
    spin = float(np.median(np.abs(w0[:, 1])))
    exact_trace = _exact_trace(moments, w0[trace_member], trace_h, t_end)
    return _dataset(rules, steps, table, needed, traces, exact_trace, trace_h, moments, exact,
                    spin, tolerance, t_end, w0.shape[0])


def _exact_trace(moments, w0, h, t_end):

    t = np.arange(int(round(t_end / h)) + 1) * h
    return exact_omega(RigidBody(*moments, physical=False), w0, t)[:, 1]


#: What is measured per (rule, step), in the order of the Dataset.
_TABLE = ("fraction_flipping", "flip_interval", "flip_interval_error", "growth_rate",
          "growth_rate_error", "energy_drift", "momentum_drift", "l_direction_drift",
          "cost_per_step", "members_ok")


def _dataset(rules, steps, table, needed, traces, exact_trace, trace_h, moments, exact, spin,
             tolerance, t_end, members):

    specs = {r: rule_scene(r).method(r) for r in rules}
    data = dict(table)
    evaluations = np.array([specs[r].evaluations for r in rules], dtype=float)
    data["evaluations_per_second"] = evaluations[:, None] / np.asarray(steps)[None, :]
    data["step_needed"] = needed[0]
    data["step_needed_energy"] = needed[1]
    data["spin_component"] = np.array(traces)
    data["spin_component_exact"] = exact_trace
    data["family"] = np.array(
        ["engine rule" if r in ENGINE_RULES else specs[r].family for r in rules], dtype=object)
    fields = {"step_needed": {"tolerance": tolerance},
              "step_needed_energy": {"tolerance": tolerance},
              "spin_component": {"h": trace_h}}
    coords = {
        "rule": np.array(rules, dtype=object),
        "step": np.asarray(steps, dtype=float),
        "time": np.arange(exact_trace.size) * trace_h,
    }
    attrs = {"moments": moments, "spin": spin, "members": members, "t_end": t_end,
             "flip_interval_exact": float(np.median(exact)),
             "growth_rate_exact": float(growth_rate(RigidBody(*moments, physical=False), 2,
                                                    spin)),
             "tolerance": tolerance}
    return xr.Dataset(ENGINE_ARTEFACTS.entries(data, fields),
                      coords=ENGINE_ARTEFACTS.entries(coords), attrs=storable_attrs(attrs))
