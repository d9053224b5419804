"""Adaptive runs of any scene through the one pipeline: :func:`run_adaptive`.

Members of a scene with a vector field, in groups of one parameter set each, integrated to their
own end times with Dormand-Prince 5(4) steps under ``rtol`` and ``atol`` and their events located
(:mod:`stability.engine.adaptive`, :mod:`stability.engine.events`). The run is a
:class:`~stability.ensemble.plan.Plan` handed to :func:`~stability.ensemble.chunks.run_plan` with
the measurement :class:`AdaptiveMeasure`, which integrates each chunk's members itself: in this
process, or chunk by chunk into a store (resumed, on dask), with bitwise the same Dataset, as
:data:`stability.ensemble.schema.ADAPTIVE_RUN` declares it.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numpy as np
import xarray as xr

from ..engine.adaptive import (
    MAX_STEPS, adaptive_scene, checked_samples, checked_tolerances, integrate_adaptive,
)
from ..engine.events import checked_events
from ..engine.scene import Scene
from ..engine.user_scene import ParameterRow
from ..output.dataset import header_attrs
from ..util import conventions as cv
from ..util.checks import real_array
from ..version import __version__
from .chunks import run_plan
from .options import run_options
from .plan import Plan
from .schema import ADAPTIVE_RUN, UNITS_SEPARATOR

#: The method's name in a run's attributes.
METHOD = "dopri5"
REFERENCE = ("Dormand & Prince, J. Comput. Appl. Math. 6, 19 (1980); Hairer, Norsett & Wanner, "
             "Solving ODEs I, II.4 (step control) and II.6 (dense output)")


def run_adaptive(scene, x0, parameters, t_end, *, rtol, atol, events=(), samples=None,
                 sizes=None, max_steps=MAX_STEPS, options=None) -> xr.Dataset:
    """Run members of ``scene`` with adaptive Dormand-Prince 5(4) steps and user events.

    Parameters
    ----------
    scene : str or Scene
        A scene with a vector field (every scene of :func:`stability.define_scene`;
        ``free_body``, ``heavy_top``, ``sphere_damper``, ``gyrostat``, ``relaxing_tumbler``):
        a registered scene's name (looked up by :func:`stability.run_adaptive`) or the
        scene. This function itself takes the Scene alone.
    x0 : array_like, shape (N, n)
        Starts, group after group, in the kernels' frame and units.
    parameters : parameter set, or list of them
        Each group's set, as the scene's methods take it.
    t_end : float or array_like, shape (N,)
        Each member's end time in s (> 0).
    rtol, atol : float
        Tolerances of the error per step (``rtol > 0``, ``atol >= 0``).
    events : Event or sequence of Event, optional
        :class:`stability.engine.events.Event`.
    samples : array_like, shape (S,), optional
        Times (s, ascending) at which every member's state is kept (the Dataset's ``time``),
        from the continuous extension of the step that holds each: the run is the same with
        and without.
    sizes : array_like of int, shape (G,), optional
        Members per group; by default all in the one group.
    max_steps : int, default MAX_STEPS
        Steps per member (accepted and rejected) before it is flagged ``max_steps``.
    options : RunOptions, optional
        How and where it runs (``store``, ``resume``, ``chunk_members``, ``threads`` ...);
        never changes the result, but ``device="gpu"``: the members then run on a CUDA GPU
        (:func:`stability.engine.gpu.integrate_adaptive_gpu`), with results that agree with
        the CPU's to round-off.

    Returns
    -------
    xarray.Dataset
        As :data:`stability.ensemble.schema.ADAPTIVE_RUN` declares it for this scene.

    Raises
    ------
    ValueError, TypeError
        One line, before any work: tolerances, shapes, sample times, events (a ``g`` that does
        not compile or returns no number, an unknown direction or action, a count < 1).
    """
    scene = adaptive_scene(scene, "run_adaptive")
    rtol, atol, max_steps = checked_tolerances(rtol, atol, max_steps)
    samples = checked_samples(samples)
    x0 = real_array("x0", x0, "the scene's units")
    if x0.ndim != 2 or x0.shape[1] != scene.width or x0.shape[0] == 0:
        raise ValueError(f"x0 must have shape (members, {scene.width}) for scene "
                         f"{scene.name!r}, got shape {x0.shape}")
    sets = [parameters] if isinstance(parameters, (dict, np.ndarray)) and np.ndim(
        parameters) <= 1 else list(parameters)
    rows = np.array([scene.linearisation.params(s, 0.0) for s in sets], dtype=float)
    n = x0.shape[0]
    sizes = np.array([n] if sizes is None else sizes, dtype=np.int64).reshape(-1)
    if sizes.size != len(sets) or sizes.sum() != n or np.any(sizes < 0):
        raise ValueError(f"sizes must give the members of each of the {len(sets)} groups, "
                         f"adding up to the {n} rows of x0, got {sizes.tolist()}")
    t_end = np.array(np.broadcast_to(np.asarray(t_end, dtype=float), (n,)))
    if not np.all(np.isfinite(t_end) & (t_end > 0)):
        raise ValueError("t_end must be finite and > 0 (in s) for every member")
    events = checked_events(events, x0[0], rows[0])
    named = isinstance(scene.linearisation.params, ParameterRow)
    numbers = np.array([scene.linearisation.params.values(s) if named
                        else real_array("parameters", s).reshape(-1) for s in sets])
    options = run_options(options)
    plan = Plan(scene, next(iter(scene.methods)), x0, rows, sizes, np.zeros(len(sets)),
                np.zeros(len(sets), dtype=np.int64), label=f"{scene.name} ({METHOD})",
                device=options.device)
    measure = AdaptiveMeasure(scene, sizes, numbers, bool(named and scene.parameters), t_end,
                              rtol, atol, max_steps, events, samples)
    return run_plan(plan, options, measure=measure)


@dataclass(eq=False)
class AdaptiveMeasure:
    """The measurement of :func:`run_adaptive`: each chunk's members integrated (its own loop,
    ``integrates``) and labelled. The fields are the constructor's parameters."""

    scene: Scene
    sizes: np.ndarray
    numbers: np.ndarray
    named: bool
    t_end: np.ndarray
    rtol: float
    atol: float
    max_steps: int
    events: tuple
    samples: np.ndarray

    integrates = True

    def declaration(self):
        scene = self.scene
        return ADAPTIVE_RUN.of(scene.name, scene.components, scene.units,
                               scene.parameters if self.named else (),
                               scene.parameter_units if self.named else ())

    def identity(self, run: Plan) -> dict:
        """The run, its end times, sample times, tolerances and events (their functions' names
        and code)."""
        h = hashlib.sha256(self.t_end.tobytes())
        if self.samples.size:
            h.update(b"samples" + self.samples.tobytes())
        h.update(np.ascontiguousarray(self.numbers).tobytes())
        for e in self.events:
            h.update(f"{e.name} {e.direction} {e.action} {e.count}".encode())
            h.update(e.python.__code__.co_code)
        return {"grouped_run": run.identity(), "adaptive_run": {
            "rtol": self.rtol, "atol": self.atol, "max_steps": self.max_steps,
            "digest": h.hexdigest()}, "software": f"stability {__version__}"}

    def __call__(self, part: Plan, _, lo: int, hi: int, threads=None) -> xr.Dataset:
        scene = self.scene
        group_of = np.searchsorted(np.cumsum(self.sizes), np.arange(lo, hi), side="right")
        local = np.searchsorted(np.cumsum(part.sizes), np.arange(hi - lo), side="right")
        integrate = integrate_adaptive
        if part.device == "gpu":
            from ..engine.gpu import integrate_adaptive_gpu as integrate  # numba-cuda: optional

        run = integrate(scene, part.x0, part.params, local, self.t_end[lo:hi], rtol=self.rtol,
                        atol=self.atol, events=self.events, max_steps=self.max_steps,
                        samples=self.samples)
        data = {f"{c}_start": part.x0[:, k] for k, c in enumerate(scene.components)}
        data.update({f"{c}_final": run.x_final[:, k] for k, c in enumerate(scene.components)})
        data.update(member_group=group_of.astype(np.int64), t_end=self.t_end[lo:hi],
                    t_final=run.t_final, accepted_steps=run.accepted,
                    rejected_steps=run.rejected, error_estimate=run.error,
                    error_sum=run.error_sum, h_last=run.h_last,
                    status=run.status)
        coords = {cv.MEMBER: np.arange(lo, hi, dtype=np.int64),
                  "group": np.arange(self.sizes.size, dtype=np.int64)}
        if self.samples.size:
            coords[cv.TIME] = self.samples
            data.update({c: run.x_sample[:, :, k] for k, c in enumerate(scene.components)})
        if self.events:
            coords["event"] = np.array([e.name for e in self.events])
            data.update(stop_event=run.stop_event, event_count=run.event_count,
                        event_time=run.event_time)
        data["members"] = self.sizes
        if self.named:
            data.update({p: self.numbers[:, k] for k, p in enumerate(scene.parameters)})
        else:
            data["parameters"] = self.numbers
        declared = self.declaration()
        members = int(self.sizes.sum())
        command = (f"stability.run_adaptive({scene.name!r}, <{members} starts>, "
                   f"<{self.sizes.size} parameter sets>, rtol={self.rtol!r}, "
                   f"atol={self.atol!r}, events=<{len(self.events)}>, "
                   f"samples=<{self.samples.size}>)")
        attrs = header_attrs(f"{members}-member adaptive run of scene {scene.name} "
                             f"({scene.title})", command, REFERENCE)
        attrs.update({
            "scene": scene.name, "scene_components": " ".join(scene.components),
            "scene_units": UNITS_SEPARATOR.join(scene.units),
            **({"scene_parameters": " ".join(scene.parameters)} if self.named else {}),
            **({"scene_parameter_units": UNITS_SEPARATOR.join(scene.parameter_units)}
               if self.named and scene.parameter_units else {}),
            "method": METHOD, "rtol": self.rtol, "atol": self.atol, "max_steps": self.max_steps,
            "wall_time": run.wall_time, "compile_time": run.compile_time})
        return xr.Dataset(declared.entries(data), coords=declared.entries(coords), attrs=attrs)


__all__ = ["AdaptiveMeasure", "METHOD", "run_adaptive"]
