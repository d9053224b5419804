"""A run of any scene as a Dataset labelled from what the scene declares: :func:`run_scene`.

Any scene, registered (``"heavy_top"``) or of the user's own (:func:`stability.define_scene`),
runs its members in groups (each with its own parameter set, step and step count) through the
one pipeline above the member loop (:func:`stability.ensemble.chunks.run_plan`): in
this process, or chunk by chunk into a store, resumable after a crash and runnable on
dask.distributed, bitwise the same however it was cut or wherever it ran. What the run would
hold is checked before any work, and the result is an xarray Dataset declared in the register
(:data:`stability.ensemble.schema.SCENE_RUN`, a template its scene fills in): one variable per state
component, named and in the units the scene gives (its start, its end and, with
``save_every``, its time series), each group's parameters, step and step count, each member's
status (CF flags), failure time, the relative drift of each invariant the scene declares and,
where tracking is asked, the tracked events. A scene's own measurement then reads that Dataset.
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping
from dataclasses import dataclass, replace

import numpy as np
import xarray as xr

from ..engine.events import checked_events
from ..engine.loop import N_TRACK
from .memory import memory_problem
from ..output.dataset import header_attrs, method_attrs, storable_attrs
from .chunks import default_chunk_members, run_plan, summed_attrs
from .options import run_options
from .plan import Plan
from ..engine.scene import Scene, checked_scene
from ..engine.user_scene import ParameterRow, tracked_components
from .schema import LEVEL, SCENE_RUN, UNITS_SEPARATOR
from ..util import conventions as cv
from ..util.checks import checked_progress, positive_int, real_array
from ..version import __version__

#: Working copies of the time series a run holds at its peak: the loop's samples, the series
#: with its start, and what is written or read back of it.
PEAK_COPIES = 3

#: The tracked events of the member loop (:func:`stability.engine.driver.tracking_results`) that
#: the Dataset keeps, float ones masked (NaN) for members whose status is not ok.
TRACKED = ("axis_crossings", "first_axis_crossing", "last_axis_crossing", "perp_crossings",
           "first_perp_crossing", "last_perp_crossing", "max_perp_amplitude", "passage_time")


def run_scene(scene, method, x0, parameters, *, h, n_steps, sizes=None, save_every=0,
              axes=None, levels=None, tracked_units=None, options=None,
              label=None, events=()) -> xr.Dataset:
    """Run members of ``scene`` with ``method`` in groups and return their labelled Dataset.

    Parameters
    ----------
    scene : str or Scene
        A registered scene's name (``stability.registry.SCENES``, looked up by
        :func:`stability.run_scene`), or a scene: a family's or one of the user's own
        (:func:`stability.define_scene`). This function itself takes the Scene alone.
    method : str
        A method of the scene.
    x0 : array_like, shape (N, n)
        Initial states, the members of group 0 first, then group 1 ...; one column per
        component of the scene, in its kernels' frame and units.
    parameters : parameter set, or sequence of them
        Each group's parameter set, as the scene's methods take it (``spec.params(set, h)``):
        for a scene that names its parameters a mapping by name or the numbers in order; one
        set alone (a mapping or a 1-D array) is one group.
    h : float or array_like, shape (G,)
        Step in s, of every group or of each.
    n_steps : int or array_like of int, shape (G,)
        Steps, of every group or of each.
    sizes : array_like of int, shape (G,), optional
        Members of each group (adding up to N); by default all N in the one group there is.
    save_every : int, default 0
        Keep the state every ``save_every`` steps, with the start (the variables named as the
        components, over ``time``); 0 keeps the final state only. A time series needs one step
        for every group.
    axes : array_like of int, shape (3,) or (G, 3), optional
        Turns tracking on: the components (numbered from 0) the scene's ``observe`` reads as
        the spin axis and the two across it; the Dataset gains the tracked events.
    levels : array_like, shape (L,) or (G, L), optional
        Ascending amplitude levels (with ``axes``) for the passage times, the Dataset's
        ``level`` coordinate (levels given per group: all of them, a member's passage times
        NaN at those of the other groups).
    tracked_units : str, optional
        Units of what the scene tracks (the amplitude and the levels); by default those the
        scene declares (``Scene.tracked_units``: every registered scene, and a scene of the
        user's given ``tracked_units=``), else those of the components read, for a scene that
        tracks its components (a scene of the user's without an ``observe`` of its own).
    options : RunOptions, optional
        How and where it runs (:class:`~stability.ensemble.options.RunOptions`). With a
        ``store`` the members run chunk by chunk into that folder
        (:class:`~stability.output.store.ChunkStore`) and the Dataset is over its files: memory
        is one chunk's, and a stopped run is finished with ``resume``; the time series are dask
        arrays, read as they are used (``.load()`` reads one into memory), the rest comes back
        loaded (:func:`~stability.ensemble.chunks.small_loaded`). ``scheduler`` (with a store)
        runs the chunks on dask.distributed (a scene of the user's own must be importable
        there); ``chunk_members`` (default
        :func:`~stability.ensemble.chunks.default_chunk_members`) never changes the result;
        ``max_memory`` refuses a run that would hold more than that many bytes (or more than
        the machine has).
    label : str, optional
        The progress bar's label.
    events : Event or sequence of Event, optional
        User events (:class:`stability.Event`): each ``g(x, t, p)``'s sign changes located on
        the method's own step (the exact flow for an exact method) to round-off in ``t``,
        kept as ``event_count`` and ``event_time``; a stop event ends its member at the
        located state (``t_final``, the final state there). Time ``t`` starts at 0. On the CPU
        and the GPU (``options.device``).

    Returns
    -------
    xarray.Dataset
        As :data:`stability.ensemble.schema.SCENE_RUN` declares it for this scene.

    Raises
    ------
    ValueError
        One line, before any work: an argument that does not fit the scene (the width of
        ``x0``, an unknown method, a negative count, a parameter set its methods refuse...), or
        a run that would not fit in memory.

    Examples
    --------
    >>> from stability.heavy_top.model import HeavyTop, tilted_starts
    >>> top = HeavyTop.disk(mass=0.1, radius=0.03, length=0.04)
    >>> x0 = tilted_starts(150.0, np.radians(60.0), 4, top=top)  # 4 tops at 150 rad/s, 60 deg
    >>> ds = stability.run_scene("heavy_top", "lp2", x0, top.parameters, h=1e-4,
    ...                          n_steps=1000, save_every=10,
    ...                          options=stability.RunOptions(progress=False))
    >>> ds.g3.shape  # the cosine of the tilt of axis 3, per member over time
    (4, 101)
    """
    scene = checked_scene(scene, "stability.ensemble.scene_run.run_scene")
    spec = scene.method(method)
    width = scene.width
    options = run_options(options)
    store, chunk_members = options.store, options.chunk_members
    checked_progress(options.progress)
    # Only the shape of x0 until the memory check (a broadcast array of 1e9 rows copies to GiB)
    x0 = real_array("x0", x0, "the scene's units", copy=False)
    if x0.ndim != 2 or x0.shape[1] != width:
        raise ValueError(f"x0 must have shape (members, {width}) for scene {scene.name!r}, one "
                         f"column per component ({', '.join(scene.components)}), got shape "
                         f"{x0.shape}")
    if x0.shape[0] == 0:
        raise ValueError(f"x0 has no rows: give at least one member, a row of {width} numbers")
    sets = _in_order(scene, spec, _parameter_sets(parameters))
    groups = len(sets)
    n = x0.shape[0]
    sizes = _sizes(sizes, groups, n)
    hs = _per_group("h", h, groups, "s")
    if not np.all(np.isfinite(hs) & (hs > 0.0)):
        raise ValueError(f"h must be finite and > 0 (in s), got {_shown(h)}")
    steps = _steps(n_steps, groups)
    save_every = positive_int("save_every", save_every, allow_zero=True)
    if save_every > int(steps.max()):
        raise ValueError(f"save_every = {save_every} is more than the {int(steps.max())} steps "
                         "of the longest group, so the series would hold the start alone; "
                         "choose save_every <= n_steps (or 0: the final states only)")
    if label is not None and not isinstance(label, str):
        raise ValueError(f"label must be a string (the progress bar's), got {label!r:.80}")
    if save_every and np.unique(hs).size > 1:
        raise ValueError(f"a time series (save_every = {save_every}) needs one step for every "
                         f"group, got h = {_shown(hs)}; run the groups apart or keep the final "
                         "states only (save_every=0)")
    numbers = _numbers(scene, spec, sets)
    rows = _rows(scene, spec, sets, hs)
    events = checked_events(events, np.asarray(x0[0], dtype=float), rows[0])
    axes, levels, tracked_units = _tracking(scene, axes, levels, tracked_units, groups)
    if chunk_members is not None:
        chunk_members = positive_int("chunk_members", chunk_members)
    named = bool(scene.parameters) and numbers.shape[1] == len(scene.parameters)
    measure = SceneMeasure(
        scene=scene, method=spec.name, sets=sets, numbers=numbers,
        named=named, sizes=sizes, h=hs, n_steps=steps, save_every=save_every, axes=axes,
        levels=levels, tracked_units=tracked_units or "",
        events=tuple(event.name for event in events))
    measure.declaration()  # two variables of one name: refused before any work
    n_saved = int(steps.max()) // save_every if save_every else 0
    if store is not None and chunk_members is None:
        chunk_members = default_chunk_members(n, float(np.sum(sizes * steps)))
    held = n if store is None else min(chunk_members, n)
    nbytes = n * width * 8 + held * member_bytes(
        width, n_saved, len(scene.invariants), 0 if axes is None else levels.shape[1] + 1)
    problem = memory_problem(
        nbytes, f"a run of {n} members of scene {scene.name!r}" + (
            f" keeping {n_saved + 1} states of {width} numbers each" if n_saved else ""),
        "use fewer members" + (", a larger save_every (or 0: the final states only)"
                               if n_saved else "")
        + ("" if store is not None else ", or give RunOptions(store=...) (a chunk of members "
                                         "at a time in memory)"), options.max_memory)
    if problem is not None:
        raise ValueError(problem)
    x0 = np.array(x0, dtype=float)
    if not np.all(np.isfinite(x0)):
        row = int(np.flatnonzero(~np.all(np.isfinite(x0), axis=1))[0])
        raise ValueError(f"x0 must be finite; its row {row} is not")
    plan = Plan(scene, spec.name, x0, rows, sizes, hs, steps, save_every=save_every, axes=axes,
                levels=levels, label=label or f"{scene.name} ({spec.name})",
                device=options.device, chunk_steps=options.chunk_steps, events=events)
    return run_plan(plan, replace(options, chunk_members=chunk_members), measure=measure)


def member_bytes(width: int, n_saved: int, n_invariants: int = 0, tracked: int = 0) -> int:
    """Bytes one member of :func:`run_scene` holds at its peak: its states (start, end and,
    with ``n_saved`` samples, :data:`PEAK_COPIES` copies of its series), status and failure,
    invariant drifts and, with ``tracked`` levels + 1 (0: no tracking), the loop's tracking
    and the tracked events."""
    series = (n_saved + 1) * width * 8 * PEAK_COPIES if n_saved else 0
    scalars = 8 * (4 + 2 * width + n_invariants) + 1  # member, group, fail time, iterations
    tracking = 8 * (N_TRACK + len(TRACKED) + 2 * tracked) if tracked else 0
    return series + scalars + tracking


@dataclass(eq=False)
class SceneMeasure:
    """The measurement of :func:`run_scene`: a chunk's propagation as its part of the Dataset.

    Picklable (a dask worker measures its chunk): it holds the whole run's groups, so that
    every chunk carries the per-group variables of all of them and the chunks' Datasets join
    along ``member``. The fields are the constructor's parameters and the instance's
    attributes.

    Parameters
    ----------
    scene : Scene
        The scene run.
    method : str
    sets : list
        Each group's parameter set as given (what the scene's invariants take).
    numbers : ndarray, shape (G, p)
        The sets' numbers.
    named : bool
        The numbers are the scene's named parameters (one variable each).
    sizes, h, n_steps : ndarray, shape (G,)
    save_every : int
    axes : ndarray of int, shape (G, 3), or None
    levels : ndarray, shape (G, L), or None
    tracked_units : str
        Units of the tracked amplitude ("" without tracking).
    events : tuple of str, default ()
        The names of the run's events.
    """

    scene: Scene
    method: str
    sets: list
    numbers: np.ndarray
    named: bool
    sizes: np.ndarray
    h: np.ndarray
    n_steps: np.ndarray
    save_every: int
    axes: np.ndarray | None
    levels: np.ndarray | None
    tracked_units: str
    events: tuple = ()

    @property
    def n_saved(self) -> int:
        return int(self.n_steps.max()) // self.save_every if self.save_every else 0

    def declaration(self):
        """The register's declaration of this run's Dataset (:meth:`SceneSchema.of`)."""
        scene = self.scene
        return SCENE_RUN.of(
            scene.name, scene.components, scene.units,
            scene.parameters if self.named else (),
            scene.parameter_units if self.named else (), tuple(scene.invariants),
            self.tracked_units or cv.UNITS_DIMENSIONLESS)

    def identity(self, run: Plan) -> dict:
        """What makes the stored run what it is: the grouped run and what the measurement
        reads besides (the parameter sets' numbers, the units of what is tracked)."""
        digest = hashlib.sha256(np.ascontiguousarray(self.numbers).tobytes()).hexdigest()
        return {"grouped_run": run.identity(),
                "scene_run": {"parameters": digest, "tracked_units": self.tracked_units},
                "software": f"stability {__version__}"}

    def __call__(self, part: Plan, run, lo: int, hi: int, threads=None) -> xr.Dataset:
        """The Dataset of members ``lo ... hi - 1`` from their propagation ``run``."""
        scene = self.scene
        spec = scene.method(self.method)
        declared = self.declaration()
        n = hi - lo
        group = np.searchsorted(np.cumsum(self.sizes), np.arange(lo, hi), side="right")
        ok = run.status == cv.STATUS_OK
        x0, x1 = part.x0, run.x_final
        coords = {cv.MEMBER: np.arange(lo, hi, dtype=np.int64),
                  "group": np.arange(self.sizes.size, dtype=np.int64)}
        data = {}
        if self.n_saved:
            series = np.full((n, self.n_saved + 1, scene.width), np.nan)
            series[:, 0] = x0
            series[:, 1:1 + run.saved.shape[1]] = run.saved
            coords[cv.TIME] = np.arange(self.n_saved + 1) * (self.save_every * self.h[0])
            if self.events:  # a stopped member's series ends where it stopped
                series[coords[cv.TIME][None, :] > run.extras["t_final"][:, None]] = np.nan
            data.update({c: series[:, :, k] for k, c in enumerate(scene.components)})
        data.update({f"{c}_start": x0[:, k] for k, c in enumerate(scene.components)})
        data.update({f"{c}_final": x1[:, k] for k, c in enumerate(scene.components)})
        data["member_group"] = group.astype(np.int64)
        data["status"] = np.asarray(run.status, dtype=np.int8)
        data["fail_time"] = np.where(ok, np.nan, run.fail_step * self.h[group])
        data["iterations"] = np.asarray(run.iterations, dtype=np.int64)
        for name, invariant in scene.invariants.items():
            data[f"{name}_drift"] = self._drift(invariant, x0, x1, group, ok)
        if self.events:
            coords["event"] = np.array(self.events)
            data.update({name: run.extras[name] for name in
                         ("t_final", "stop_event", "event_count", "event_time")})
        if self.axes is not None:
            tracked = self._tracked(run.extras, ok)
            if "passage_time" in tracked:
                coords[LEVEL], tracked["passage_time"] = self._at_levels(
                    tracked["passage_time"], group)
            data.update(tracked)
        data["members"] = self.sizes
        data["h"] = self.h
        data["n_steps"] = self.n_steps
        if self.named:
            data.update({p: self.numbers[:, k] for k, p in enumerate(scene.parameters)})
        else:
            data["parameters"] = self.numbers
        if self.axes is not None:
            data["tracked_components"] = self.axes
        return xr.Dataset(declared.entries(data), coords=declared.entries(coords),
                          attrs=storable_attrs(self._attrs(scene, spec, part, run)))

    def whole_attrs(self, chunks, todo, elapsed, chunk_attrs=None) -> dict:
        """The whole stored run's attributes (:func:`summed_attrs`, from ``chunk_attrs`` where
        the chunks' attributes were read), its rate that of the chunks ``todo`` this call ran
        in ``elapsed`` seconds."""
        attrs = summed_attrs(chunks, elapsed, chunk_attrs)
        steps = np.repeat(self.n_steps, self.sizes)
        ran = sum(float(steps[slice(*chunks.bounds(k))].sum()) for k in todo)
        attrs["member_steps_per_second"] = ran / elapsed if elapsed > 0 else 0.0
        attrs["chunks"] = chunks.n_chunks
        attrs["chunk_members"] = chunks.chunk_members
        return attrs

    def _drift(self, invariant, x0, x1, group, ok) -> np.ndarray:
        drift = np.full(x0.shape[0], np.nan)
        for g in np.unique(group):
            rows = group == g
            start = np.asarray(invariant(x0[rows], self.sets[g]), dtype=float)
            end = np.asarray(invariant(x1[rows], self.sets[g]), dtype=float)
            with np.errstate(divide="ignore", invalid="ignore"):
                drift[rows] = np.where(start != 0.0, (end - start) / np.abs(start), np.nan)
        drift[~ok] = np.nan
        return drift

    def _at_levels(self, passage, group):
        """The levels of every group, ascending, and each member's passage times at them (NaN
        at the levels of other groups than its own)."""
        levels = np.unique(self.levels)
        if levels.size == self.levels.shape[1]:  # one list for every group
            return levels, passage
        out = np.full((passage.shape[0], levels.size), np.nan)
        columns = np.searchsorted(levels, self.levels[group])
        out[np.arange(passage.shape[0])[:, None], columns] = passage
        return levels, out

    def _tracked(self, extras, ok) -> dict:
        out = {}
        for name in TRACKED:
            value = np.array(extras[name])
            if name == "passage_time" and value.shape[1] == 0:
                continue  # no levels: no dimension of length 0 in the file
            if value.dtype.kind == "f":
                value[~ok] = np.nan
            out[name] = value
        return out

    def _attrs(self, scene, spec, part, run) -> dict:
        members = int(self.sizes.sum())
        title = (f"{members}-member run of scene {scene.name} ({scene.title}), {spec.name}, "
                 f"{self.sizes.size} group{'s' * (self.sizes.size != 1)}")
        member_steps = float(np.sum(part.sizes * np.asarray(run.steps_done)))
        attrs = header_attrs(title, _command(scene, spec, members, self), spec.reference)
        attrs.update({
            "scene": scene.name,
            "scene_title": scene.title,
            "scene_equations": scene.equations,
            "scene_components": " ".join(scene.components),
            "scene_units": UNITS_SEPARATOR.join(scene.units),
            **({"scene_parameters": " ".join(scene.parameters)} if self.named else {}),
            **({"scene_parameter_units": UNITS_SEPARATOR.join(scene.parameter_units)}
               if self.named and scene.parameter_units else {}),
            **({"scene_invariants": " ".join(scene.invariants)} if scene.invariants else {}),
            **({"scene_source": scene.source} if scene.source else {}),
            **({"tracked_units": self.tracked_units} if self.axes is not None else {}),
            **method_attrs(spec),
            "members": members,
            "groups": int(self.sizes.size),
            "save_every": self.save_every,
            "wall_time": run.wall_time,
            "compile_time": run.compile_time,
            "member_steps_per_second": member_steps / run.wall_time if run.wall_time > 0
            else 0.0,
        })
        return attrs


# --- the arguments, each refused in one line ---------------------------------------------------


def _shown(value) -> str:
    x = np.asarray(value)
    if x.size <= 6:
        return str(x.tolist())
    return " ".join(np.array2string(x, threshold=6, separator=", ").split())


def _parameter_sets(parameters) -> list:
    if isinstance(parameters, Mapping) or (isinstance(parameters, np.ndarray)
                                           and parameters.ndim <= 1):
        return [parameters]
    if isinstance(parameters, (str, bytes)) or not hasattr(parameters, "__len__"):
        raise ValueError(f"parameters must be a parameter set or a list of them (one per "
                         f"group), got {parameters!r:.80}")
    sets = list(parameters)
    if not sets:
        raise ValueError("parameters must hold at least one parameter set (one per group)")
    return sets


def _in_order(scene, spec, sets) -> list:
    """The sets of a registered scene that names its parameters as its numbers in that order
    (a mapping by name taken as a user scene takes it); the others as given."""
    if isinstance(spec.params, ParameterRow):
        return sets  # a scene of the user's: its methods take mappings themselves
    if not scene.parameters:
        if any(isinstance(values, Mapping) for values in sets):
            raise ValueError(f"scene {scene.name!r} does not name its parameters: give each "
                             "set as the numbers its methods take, not a mapping")
        return sets
    row = ParameterRow(scene.name, scene.parameters)
    out = []
    for g, values in enumerate(sets):
        try:
            out.append(row.values(values) if isinstance(values, Mapping) else values)
        except ValueError as exc:
            raise ValueError(f"parameter set {g}: {_one_line(exc)}") from None
    return out


def _sizes(sizes, groups, n) -> np.ndarray:
    if sizes is None:
        if groups != 1:
            raise ValueError(f"give sizes=, the members of each of the {groups} groups "
                             f"(parameter sets), adding up to the {n} rows of x0 (a list of "
                             "numbers is one set per number: pass one set as an array, or as "
                             "[set])")
        return np.array([n], dtype=np.int64)
    x = np.asarray(sizes)
    if x.dtype.kind not in "iu" and not (x.dtype.kind == "f" and np.all(np.mod(x, 1) == 0)):
        raise ValueError(f"sizes must be whole numbers of members, got {_shown(sizes)}")
    x = x.astype(np.int64).reshape(-1)
    if np.any(x < 0):
        raise ValueError(f"sizes must be whole numbers of members >= 0, got {_shown(sizes)}")
    if x.size != groups:
        raise ValueError(f"sizes must give the members of each of the {groups} groups "
                         f"(parameter sets), got {x.size} numbers")
    if int(x.sum()) != n:
        raise ValueError(f"sizes add up to {int(x.sum())} members but x0 has {n} rows")
    return x


def _per_group(name, value, groups, unit) -> np.ndarray:
    x = real_array(name, value, unit)
    if x.ndim > 1 or x.size not in (1, groups):
        raise ValueError(f"{name} must be one number or one per group ({groups}), got shape "
                         f"{x.shape}")
    return np.array(np.broadcast_to(x.reshape(-1), (groups,)), dtype=float)


def _steps(n_steps, groups) -> np.ndarray:
    x = np.asarray(n_steps)
    if x.ndim > 1 or x.size not in (1, groups):
        raise ValueError(f"n_steps must be one count or one per group ({groups}), got shape "
                         f"{x.shape}")
    counts = [positive_int("n_steps", v.item() if hasattr(v, "item") else v)
              for v in x.reshape(-1)]
    return np.array(np.broadcast_to(np.array(counts, dtype=np.int64), (groups,)))


def _numbers(scene, spec, sets) -> np.ndarray:
    """The numbers of each parameter set, one row per group."""
    rows = []
    for g, values in enumerate(sets):
        try:
            if isinstance(spec.params, ParameterRow):
                row = spec.params.values(values)
            else:
                row = real_array(f"parameters[{g}]", values).reshape(-1)
        except ValueError as exc:
            raise ValueError(_one_line(exc)) from None
        rows.append(row)
    if len({row.size for row in rows}) > 1:
        raise ValueError(f"the parameter sets of scene {scene.name!r} must hold as many numbers "
                         f"each, got {[row.size for row in rows]}")
    return np.array(rows, dtype=float)


def _rows(scene, spec, sets, hs) -> np.ndarray:
    """Each group's kernel parameter row, ``spec.params(set, h)``."""
    rows = []
    for g, (values, h) in enumerate(zip(sets, hs)):
        try:
            row = np.asarray(spec.params(values, float(h)), dtype=float).reshape(-1)
        except Exception as exc:  # the scene's own function: its complaint, in one line
            raise ValueError(f"parameter set {g} of scene {scene.name!r} ({spec.name}): "
                             f"{_one_line(exc)}") from None
        rows.append(row)
    if len({row.size for row in rows}) > 1:
        raise ValueError(f"the parameter rows of scene {scene.name!r} differ in length: "
                         f"{[row.size for row in rows]}")
    return np.array(rows)


def _tracking(scene, axes, levels, tracked_units, groups):
    """Validated tracking axes (G, 3), levels (G, L) and the tracked units; Nones without."""
    if axes is None:
        if levels is not None or tracked_units is not None:
            raise ValueError("levels and tracked_units go with axes=, which turns tracking on")
        return None, None, None
    a = np.asarray(axes)
    if a.dtype.kind not in "iu" or a.shape not in ((3,), (groups, 3)):
        raise ValueError(f"axes must be 3 component numbers (spin axis, two across it), or 3 "
                         f"per group ({groups}), got {_shown(axes)}")
    a = np.array(np.broadcast_to(a, (groups, 3)), dtype=np.int64)
    if np.any(a < 0) or np.any(a >= scene.width):
        raise ValueError(f"axes must number components of scene {scene.name!r} from 0 to "
                         f"{scene.width - 1}, got {_shown(axes)}")
    lv = np.zeros((groups, 0)) if levels is None else real_array("levels", levels)
    if lv.ndim not in (1, 2) or (lv.ndim == 2 and lv.shape[0] != groups):
        raise ValueError(f"levels must be one list of levels or one per group ({groups}), got "
                         f"shape {lv.shape}")
    lv = np.array(np.broadcast_to(lv, (groups, lv.shape[-1])))
    if not np.all(np.isfinite(lv)) or np.any(lv <= 0.0) or np.any(np.diff(lv, axis=1) <= 0.0):
        raise ValueError(f"levels must be finite, > 0 and strictly ascending, got "
                         f"{_shown(levels)}")
    if tracked_units is None and scene.tracked_units:
        tracked_units = scene.tracked_units
    if tracked_units is None:
        if scene.tracked is not tracked_components:
            raise ValueError(f"say in tracked_units= the units of what scene {scene.name!r} "
                             "tracks (its observe), or declare them in the scene "
                             "(define_scene(..., tracked_units=))")
        last = scene.width - 1
        read = {scene.units[min(int(i), last)] for i in a[:, 1:].ravel()}
        if len(read) != 1:
            raise ValueError(f"the components read across the spin axis have units "
                             f"{', '.join(sorted(read))}; say in tracked_units= those of the "
                             "amplitude")
        tracked_units = read.pop()
    if not isinstance(tracked_units, str) or not tracked_units.strip():
        raise ValueError(f"tracked_units must be a UDUNITS string such as 'rad s-1', got "
                         f"{tracked_units!r}")
    return a, lv, tracked_units


def _one_line(exc) -> str:
    text = " ".join(str(exc).split())
    return text or type(exc).__name__


def _command(scene, spec, members, measure) -> str:
    """The call that made the Dataset, for its first ``history`` line."""
    return (f"stability.run_scene({scene.name!r}, {spec.name!r}, <{members} starts>, "
            f"<{measure.sizes.size} parameter sets>, h={_shown(measure.h)}, "
            f"n_steps={_shown(measure.n_steps)}, save_every={measure.save_every}"
            + (", axes=<given>" if measure.axes is not None else "") + ")")
