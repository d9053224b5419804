"""The register of every Dataset the package writes: each variable's dims, units and long name.

One declaration per Dataset kind (:class:`DatasetSchema`, in :data:`SCHEMAS`): here the free body's
ensemble (:func:`stability.run_ensemble`) and a run of any scene (:func:`stability.run_scene`,
``"scene_run"``: a :class:`SceneSchema`, a template whose variables are named from the scene,
:meth:`SceneSchema.of` one scene's declaration); in each family's ``schema.py`` the Dataset of each
of its study kinds (``stability run``, keyed by the kind's name), which :mod:`stability.registry`
adds (:func:`register`). The helpers (:func:`variable`, :func:`coordinate`, :func:`declare` ...)
and the unit spellings (:data:`ONE`, :data:`RAD_PER_S` ...) are what the declarations are written
with. Each names every variable and coordinate it may hold (:class:`Variable`): its dims, units
(UDUNITS spelling), long name, type, whether it is a coordinate, when it may be absent, and its
further CF attributes (standard names, flags, comments). The code that builds a Dataset takes the
dims and the attributes from here (:meth:`DatasetSchema.entries`), the documentation's Dataset
reference is generated from here, and the tests hold every study's written file to its declaration
(:meth:`DatasetSchema.problems`).

A declaration::

    BAT["angular_velocity"]  # stability.struck.schema.BAT
    # Variable(dims=('hold', 'pivot', 'strike'), units='rad s-1',
    #          long_name='angular velocity just after the contact', kind='f', ...)
    xr.Dataset(BAT.entries({"angular_velocity": w, ...}))  # dims and attributes from here

This module imports only :mod:`stability.util.conventions` (and NumPy for the flag arrays), so that
every module may import it.
"""

from __future__ import annotations

import functools
import re
import string
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from types import MappingProxyType

import numpy as np

from ..util import conventions as cv

#: Type letters of :attr:`Variable.kind`: what the file may store.
KINDS = {"f": "float", "i": "integer", "U": "text"}

#: Attributes stored as int8 arrays (CF flags).
_FLAG_ARRAYS = ("flag_values", "flag_masks")


@dataclass(frozen=True)
class Variable:
    """One variable or coordinate of a Dataset kind.

    Parameters
    ----------
    dims : tuple of str
        Its dimensions, in order.
    units : str
        UDUNITS units (``"1"``: dimensionless, counts, flags and labels).
    long_name : str
        What it is, in words. May hold ``{fields}`` filled in when the Dataset is built (a
        step, an axis): :meth:`attrs` takes them, :meth:`DatasetSchema.problems` accepts any
        value there.
    kind : {"f", "i", "U"}
        Float, integer (any width; flags are int8) or text.
    coordinate : bool
        A coordinate (an index, or an auxiliary coordinate such as a step per integrator)
        rather than a data variable.
    optional : str
        When the variable may be absent, in words; empty when every Dataset of the kind holds
        it.
    extra : tuple of (str, object)
        Further attributes: ``standard_name``, ``axis``, CF flags (``flag_values`` and
        ``flag_masks`` as tuples, written as int8 arrays), ``comment``.
    """

    dims: tuple[str, ...]
    units: str
    long_name: str
    kind: str = "f"
    coordinate: bool = False
    optional: str = ""
    extra: tuple = ()

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"kind must be one of {', '.join(KINDS)}, got {self.kind!r}")
        if not isinstance(self.units, str):
            raise ValueError(f"units must be a str, got {self.units!r}")

    def attrs(self, **fields) -> dict:
        """The variable's attributes: ``long_name`` (its ``{fields}`` filled in), ``units``,
        then the further ones."""
        out = {"long_name": self.long_name.format(**fields) if fields else self.long_name,
               "units": self.units}
        for key, value in self.extra:
            out[key] = np.array(value, dtype=np.int8) if key in _FLAG_ARRAYS else value
        return out

    def on(self, dims, **changes) -> Variable:
        """The same declaration over ``dims`` (a shared one placed in a Dataset kind)."""
        return replace(self, dims=tuple(dims), **changes)

    def long_name_pattern(self) -> re.Pattern:
        """A regular expression matching the long names :meth:`attrs` may give."""
        parts = []
        for text, name, _, _ in string.Formatter().parse(self.long_name):
            parts.append(re.escape(text))
            if name is not None:
                parts.append(".+?")
        return re.compile("".join(parts) + r"\Z")


@dataclass(frozen=True)
class DatasetSchema:
    """The declaration of one Dataset kind: every variable and coordinate it may hold.

    Parameters
    ----------
    name : str
        The register key: a study kind, or ``"ensemble"``.
    title : str
        What the Dataset holds, in one line.
    written_by : tuple of str
        The functions (dotted from ``stability``) that build it.
    file : str
        The file a study writes it to (empty where no study writes it alone).
    variables : Mapping of str to Variable
        In the order the Dataset holds them.
    """

    name: str
    title: str
    written_by: tuple
    file: str
    variables: Mapping = field(repr=False)

    def __post_init__(self):
        if isinstance(self.written_by, str):
            object.__setattr__(self, "written_by", (self.written_by,))
        object.__setattr__(self, "variables", MappingProxyType(dict(self.variables)))

    def __getitem__(self, name: str) -> Variable:
        try:
            return self.variables[name]
        except KeyError:
            raise KeyError(f"the {self.name} Dataset declares no variable {name!r}") from None

    def __contains__(self, name) -> bool:
        return name in self.variables

    def __iter__(self):
        return iter(self.variables)

    def attrs(self, name: str, **fields) -> dict:
        """Attributes of the variable ``name`` (:meth:`Variable.attrs`)."""
        return self[name].attrs(**fields)

    def entry(self, name: str, value, **fields) -> tuple:
        """``(dims, value, attrs)`` of the variable ``name``, as xarray takes it."""
        var = self[name]
        return var.dims, value, var.attrs(**fields)

    def entries(self, values: Mapping, fields: Mapping | None = None) -> dict:
        """``{name: (dims, value, attrs)}`` for the values given, as ``xarray.Dataset`` takes
        them; ``fields[name]`` fills in that variable's long name."""
        fields = fields or {}
        return {name: self.entry(name, value, **fields.get(name, {}))
                for name, value in values.items()}

    def extend(self, name: str, title: str, written_by, file: str,
               variables: Mapping, **changes) -> DatasetSchema:
        """A Dataset kind holding this one's variables (``changes``: name to a changed
        declaration) and then ``variables``."""
        own = {n: changes.get(n, v) for n, v in self.variables.items()}
        return DatasetSchema(name, title, written_by, file, {**own, **variables})

    def problems(self, ds) -> list[str]:
        """How the Dataset ``ds`` (as :func:`stability.load` reads it) departs from this
        declaration, one line each; empty if it does not.

        Every declared variable that is not optional is there, and every one there has its
        declared dims, units, long name, type, role (coordinate or data variable) and further
        attributes; nothing undeclared is there.
        """
        out = []
        coords = set(ds.coords)
        for name, var in self.variables.items():
            if name not in ds.variables:
                if not var.optional:
                    out.append(f"{name}: missing")
                continue
            have = ds.variables[name]
            if tuple(have.dims) != var.dims:
                out.append(f"{name}: dims {tuple(have.dims)}, declared {var.dims}")
            if have.attrs.get("units") != var.units:
                out.append(f"{name}: units {have.attrs.get('units')!r}, declared {var.units!r}")
            long_name = have.attrs.get("long_name")
            if not isinstance(long_name, str) or not var.long_name_pattern().match(long_name):
                out.append(f"{name}: long_name {long_name!r}, declared {var.long_name!r}")
            kind = {"u": "i", "S": "U", "O": "U"}.get(have.dtype.kind, have.dtype.kind)
            if kind != var.kind:
                out.append(f"{name}: {KINDS.get(kind, have.dtype)}, declared {KINDS[var.kind]}")
            if (name in coords) != var.coordinate:
                role = "a coordinate" if name in coords else "a data variable"
                out.append(f"{name}: {role}, declared "
                           f"{'a coordinate' if var.coordinate else 'a data variable'}")
            for key, value in var.attrs().items():
                if key in ("long_name", "units"):
                    continue
                got = have.attrs.get(key)
                if got is None or not np.array_equal(np.asarray(got), np.asarray(value)):
                    out.append(f"{name}: {key} {got!r}, declared {value!r}")
        out += [f"{name}: not declared" for name in ds.variables if name not in self.variables]
        return out


# --- declarations -----------------------------------------------------------------------------

ONE = cv.UNITS_DIMENSIONLESS
SECOND = cv.UNITS_TIME
RADIAN = cv.UNITS_ANGLE
RAD_PER_S = cv.UNITS_ANGULAR_VELOCITY
RAD_PER_S2 = "rad s-2"
PER_SECOND = cv.UNITS_RATE
PER_SECOND2 = cv.UNITS_RATE_SQUARED
KG_M2 = cv.UNITS_MOMENT_OF_INERTIA
METRE = "m"
METRE_PER_S = "m s-1"
NEWTON_SECOND = "N s"
ARCSEC = "arcsec"
ARCSEC_PER_YEAR = "arcsec yr-1"
DEGREE = "degree"
YEAR = "yr"
DAY = "d"
MEMBER, TIME, AXIS, QUATERNION = cv.MEMBER, cv.TIME, cv.AXIS, cv.QUATERNION
#: Dimension of the perpendicular-amplitude levels of ``passage_time``.
LEVEL = "level"


def _dims(dims) -> tuple:
    return (dims,) if isinstance(dims, str) else tuple(dims)


def variable(dims, units, long_name, *, kind="f", optional="", **extra) -> Variable:
    """A data variable; ``extra``: further attributes, in order."""
    return Variable(_dims(dims), units, long_name, kind, False, optional, tuple(extra.items()))


def coordinate(dims, units, long_name, *, kind="f", optional="", **extra) -> Variable:
    """A coordinate (an index when its one dim is its name)."""
    return Variable(_dims(dims), units, long_name, kind, True, optional, tuple(extra.items()))


def member_coordinate(long_name="ensemble member", dim=MEMBER) -> Variable:
    """An ensemble-member coordinate (:func:`stability.util.conventions.member_attrs`)."""
    return coordinate(dim, ONE, long_name, kind="i", **cv.STANDARD_COORDINATES[MEMBER])


def time_coordinate(long_name="time since the start", dim=TIME, optional="") -> Variable:
    """A CF time axis (:func:`stability.util.conventions.time_attrs`)."""
    return coordinate(dim, cv.UNITS_TIME_COORDINATE, long_name, optional=optional,
                      **cv.STANDARD_COORDINATES[TIME])


def status_variable(dims, long_name="member status", **extra) -> Variable:
    """Per-member status codes, int8 CF flags
    (:data:`stability.util.conventions.STATUS_MEANINGS`)."""
    return variable(dims, ONE, long_name, kind="i", flag_values=cv.STATUS_FLAG_VALUES,
                    flag_meanings=cv.STATUS_MEANINGS, **extra)


def declare(name, title, written_by, variables, file=None) -> DatasetSchema:
    return DatasetSchema(name, title, written_by, f"{name}.nc" if file is None else file,
                         variables)


# The free body's ensemble (stability.output.dataset.ensemble_dataset)
# --------------------------------

SUMMARY_ONLY_NOTE = "runs that save the time series (save_every >= 1)"
ATTITUDE_NOTE = "the scene free_body_attitude (the attitude carried)"
COUNT_NOTE = "a count stored as float64 so that masked members can be NaN"

ENSEMBLE = declare("ensemble", "an ensemble of free rigid bodies, per member",
                   "stability.run_ensemble", file="", variables={
    MEMBER: member_coordinate(),
    AXIS: coordinate(AXIS, ONE, "principal axis of the body", kind="i"),
    LEVEL: coordinate(LEVEL, RAD_PER_S, "perpendicular angular-velocity amplitude level"),
    TIME: time_coordinate(optional=SUMMARY_ONLY_NOTE),
    "w": variable((MEMBER, TIME, AXIS), RAD_PER_S, "body-frame angular velocity",
                  optional=SUMMARY_ONLY_NOTE),
    "w0": variable((MEMBER, AXIS), RAD_PER_S, "initial body-frame angular velocity"),
    "status": status_variable(MEMBER, comment=(
        "ok: the member's numbers can be trusted; non_finite: its state overflowed; "
        "diverged: its energy or |L| left divergence_tolerance; not_converged: an "
        "implicit step's solver failed; step_too_large: h max|w| exceeds the method's "
        "max_step_angle (its numbers may look sane but are not trustworthy); numbers of "
        "members whose status is not ok are NaN (masked)")),
    "fail_time": variable(MEMBER, SECOND, "time at which the member's failure was detected",
                          comment=(
        "NaN for members whose status is ok; the end of the run for diverged members; "
        "0 for step_too_large (known from the start)")),
    "flip_count": variable(MEMBER, ONE,
                           "number of sign changes of the spin-axis component of w (flips)",
                           comment=COUNT_NOTE),
    "first_flip_time": variable(MEMBER, SECOND,
                                "time of the first flip (sign change of the spin-axis component)",
                                comment="NaN where no flip happened"),
    "last_flip_time": variable(MEMBER, SECOND,
                               "time of the last flip (sign change of the spin-axis component)"),
    "mean_flip_interval": variable(MEMBER, SECOND, "mean time between flips, (last - first) / "
                                   "(count - 1)",
                                   comment="NaN where fewer than two flips happened"),
    "perp_crossing_count": variable(MEMBER, ONE, "number of sign changes of w_b, b the lower of "
                                    "the two axes other than the spin axis", comment=COUNT_NOTE),
    "first_perp_crossing": variable(MEMBER, SECOND, "time of the first sign change of w_b"),
    "last_perp_crossing": variable(MEMBER, SECOND, "time of the last sign change of w_b"),
    "max_perp_amplitude": variable(MEMBER, RAD_PER_S,
                                   "maximum perpendicular amplitude sqrt(w_b^2 + w_c^2)"),
    "passage_time": variable((MEMBER, LEVEL), SECOND,
                             "first time the perpendicular amplitude reaches the level",
                             comment="NaN where the level was never reached; 0 where the start "
                                 "is above it"),
    "energy_error": variable(MEMBER, ONE, "relative kinetic-energy error at the end, (E - E0) / "
                             "E0"),
    "angular_momentum_error": variable(MEMBER, ONE, "relative |L| error at the end, (|L| - |L0|) "
                                       "/ |L0|"),
    QUATERNION: coordinate(QUATERNION, ONE, "quaternion component (0: scalar part cos(angle/2))",
                           kind="i", optional=ATTITUDE_NOTE),
    "q": variable((MEMBER, TIME, QUATERNION), ONE, "attitude quaternion, body to space (scalar "
                  "first)", optional=ATTITUDE_NOTE,
                  comment="R(q) maps body components to space components; q' = q (0, w) / 2; "
                      "normalised on output (the carried norm error is q_norm_error)"),
    "q_norm_error": variable((MEMBER, TIME), ONE, "norm error |q| - 1 of the carried attitude "
                             "quaternion", optional=ATTITUDE_NOTE,
                             comment="q is carried without renormalisation and normalised on "
                                 "output"),
    "attitude_error": variable((MEMBER, TIME), RADIAN, "angle of the rotation from the exact "
                               "attitude to the computed one", optional=ATTITUDE_NOTE,
                               comment="exact attitude: Euler angles about L from the elliptic "
                                   "solution and an exact quadrature of the precession rate "
                                   "(stability.free_body.exact_attitude)"),
})

# Ensemble estimates (stability.analysis), shared by the stability map -------------------------

#: Long names and units of the ensemble estimates of :mod:`stability.analysis`, scalars there
#: (``dims`` empty); a Dataset kind places them on its dims (:meth:`Variable.on`).
ESTIMATES = MappingProxyType({
    "regime": variable((), ONE, "regime of the ensemble's motion", kind="i",
                       flag_values=cv.REGIME_FLAG_VALUES, flag_meanings=cv.REGIME_MEANINGS),
    "omega_squared_measured": variable((), PER_SECOND2, "measured Omega^2 (-rate^2 for growth, "
                                       "+frequency^2 for oscillation)"),
    "omega_squared_measured_stderr": variable((), PER_SECOND2,
                                              "standard error of the measured Omega^2"),
    "omega_squared": variable((), PER_SECOND2, "analytic Omega^2 of linear theory"),
    "relative_error": variable((), ONE, "(measured - analytic) / |analytic| Omega^2"),
    "sign_agrees": variable((), ONE, "regime sign equals the sign of the analytic Omega^2",
                            kind="i"),
    "growth_rate": variable((), PER_SECOND, "exponential growth rate"),
    "growth_rate_stderr": variable((), PER_SECOND, "standard error of the growth rate"),
    "oscillation_frequency": variable((), RAD_PER_S, "oscillation angular frequency"),
    "oscillation_frequency_stderr": variable((), RAD_PER_S,
                                             "standard error of the oscillation frequency"),
    "drift_rate": variable((), RAD_PER_S2,
                           "slope of the perpendicular amplitude (algebraic drift)"),
    "n_fitted": variable((), ONE, "members that gave a rate or a frequency"),
    "first_flip_time_mean": variable((), SECOND, "mean time of the first flip"),
    "first_flip_time_stderr": variable((), SECOND, "standard error of the first-flip time"),
    "flip_interval_mean": variable((), SECOND, "mean flip interval"),
    "flip_interval_stderr": variable((), SECOND, "standard error of the flip interval"),
    "flip_interval_exact_mean": variable((), SECOND, "mean exact flip interval 2K/nu"),
    "flip_interval_asymptote_mean": variable((), SECOND,
                                             "mean asymptotic flip interval (2/lambda) ln(4/k')"),
    "flip_interval_relative_error": variable((), ONE,
                                             "mean (measured - exact) / exact flip interval"),
    "flip_interval_relative_error_stderr": variable((), ONE, "standard error of the flip-interval "
                                                    "relative error"),
    "n_flips_mean": variable((), ONE, "mean number of flips per member"),
    "n_with_interval": variable((), ONE, "members with two or more flips"),
})


# A run of any scene (stability.run_scene): its variables are named from the scene ------------

#: Separator of the units (which hold spaces) in a scene Dataset's ``scene_units`` and
#: ``scene_parameter_units`` attributes; names are separated by spaces.
UNITS_SEPARATOR = ", "
#: Names in the scene template that stand for each state component, parameter or invariant.
COMPONENT, PARAMETER, INVARIANT = "<component>", "<parameter>", "<invariant>"
#: Units of what a template variable holds, where its scene says them.
_OWN = "(its own)"
_TRACKED_UNITS = "(the tracked quantity's)"
_STATE_UNITS = "(the state's)"


@dataclass(frozen=True)
class SceneSchema(DatasetSchema):
    """The Dataset kind of a run of any scene, whose variables are named from the scene.

    :attr:`variables` is the template: a name holding ``<component>``, ``<parameter>`` or
    ``<invariant>`` stands for one variable per state component, named parameter or
    invariant of the scene, with its units (``(its own)``: the component's or parameter's;
    ``(the tracked quantity's)``: those of what the scene's ``observe`` tracks; ``(the
    state's)``: those of every component where they share one, else ``"1"``). :meth:`of`
    makes the declaration of one scene's Dataset; :meth:`problems` checks a Dataset against
    the declaration of the scene its attributes name (``scene``, ``scene_components``,
    ``scene_units``, ``scene_parameters``, ``scene_parameter_units``, ``scene_invariants``,
    ``tracked_units``).

    Parameters
    ----------
    name, title, written_by, file, variables
        As :class:`DatasetSchema`.
    note : str, default ""
        How the template is read, for the documentation.
    """

    note: str = ""

    def of(self, scene: str, components, units, parameters=(), parameter_units=(),
           invariants=(), tracked_units: str = ONE) -> DatasetSchema:
        """The declaration of the Dataset of a run of one scene.

        Parameters
        ----------
        scene : str
            The scene's name.
        components, units : sequence of str
            The state's components and their units.
        parameters : sequence of str, optional
            The names of a parameter set's numbers, where the scene names them (one variable
            each); else the sets are one variable ``parameters`` (group, parameter).
        parameter_units : sequence of str, optional
            Their units, where the scene gives them (else ``"1"``).
        invariants : sequence of str, optional
            The scene's invariants (one drift variable each).
        tracked_units : str, default "1"
            Units of the tracked quantity's amplitude and levels.

        Returns
        -------
        DatasetSchema

        Raises
        ------
        ValueError
            If two variables would have one name (a component named as a parameter, say).
        """
        components, units = tuple(components), tuple(units)
        parameter_units = tuple(parameter_units) or (ONE,) * len(parameters)
        if len(units) != len(components) or len(parameter_units) != len(parameters):
            raise ValueError(f"scene {scene!r}: one unit per component and per parameter")
        out = {}

        def put(name, var):
            if name in out:
                raise ValueError(f"scene {scene!r}: {name!r} would name two variables of its "
                                 "Dataset (a component, a parameter, an invariant's drift or "
                                 "one of the run's own); rename it in the scene")
            out[name] = var

        for name, var in self.variables.items():
            if COMPONENT in name:
                for component, unit in zip(components, units):
                    put(name.replace(COMPONENT, component), replace(
                        var, units=unit, long_name=var.long_name.replace(COMPONENT, component)))
            elif PARAMETER in name:
                for parameter, unit in zip(parameters, parameter_units):
                    put(name.replace(PARAMETER, parameter), replace(
                        var, units=unit, long_name=var.long_name.replace(PARAMETER, parameter),
                        optional=""))
            elif INVARIANT in name:
                for invariant in invariants:
                    put(name.replace(INVARIANT, invariant), replace(
                        var, long_name=var.long_name.replace(INVARIANT, invariant),
                        optional=""))
            elif name == "parameters":
                if not parameters:
                    put(name, replace(var, optional=""))
            elif var.units == _STATE_UNITS:  # a norm over the components
                put(name, replace(var, units=units[0] if len(set(units)) == 1 else ONE))
            else:
                put(name, replace(var, units=tracked_units) if var.units == _TRACKED_UNITS
                    else var)
        return DatasetSchema(f"{self.name}:{scene}", f"{self.title}: scene {scene}",
                             self.written_by, self.file, out)

    def problems(self, ds) -> list[str]:
        """How ``ds`` departs from the declaration of the scene its attributes name (see the
        class), one line each; empty if it does not."""
        attrs = ds.attrs
        missing = [key for key in ("scene", "scene_components", "scene_units") if key not in attrs]
        if missing:
            return [f"attribute {key}: missing (it names the scene the Dataset is declared by)"
                    for key in missing]
        words = (lambda key: tuple(str(attrs.get(key, "")).split()))
        units = (lambda key: tuple(u for u in str(attrs.get(key, "")).split(UNITS_SEPARATOR)
                                   if u))
        try:
            declared = self.of(str(attrs["scene"]), words("scene_components"),
                               units("scene_units"), words("scene_parameters"),
                               units("scene_parameter_units"), words("scene_invariants"),
                               str(attrs.get("tracked_units", ONE)))
        except ValueError as exc:
            return [f"attributes: {exc}"]
        return declared.problems(ds)


_SERIES = "runs that keep the time series (save_every > 0)"
_TRACKING = "runs that track (axes given)"
_PARAMETERS_NAMED = "scenes that name their parameters"
_GROUP = "group"
_TRACK = "track"
_COMPONENT_VALUE = ("the state as the scene's kernels hold it; members whose status is not ok "
                    "keep what the loop left")

_EVENTS = "runs with events"
_OCCURRENCE = "occurrence"

SCENE_RUN = SceneSchema(
    "scene_run", "a run of any scene's members in groups, per member and per group",
    "stability.run_scene", "", {
        MEMBER: member_coordinate(),
        _GROUP: coordinate(_GROUP, ONE, "group of members (one parameter set, step and step "
                           "count)", kind="i"),
        TIME: time_coordinate(optional=_SERIES),
        LEVEL: coordinate(LEVEL, _TRACKED_UNITS, "amplitude level across the spin axis of the "
                          "passage times", optional="runs that track at levels (axes and "
                          "levels given)", comment="the levels of every group, ascending"),
        "event": coordinate("event", ONE, "user event (the name of its function)", kind="U",
                            optional=_EVENTS),
        COMPONENT: variable((MEMBER, TIME), _OWN, f"{COMPONENT} (state component) at each saved "
                            "time", optional=_SERIES, comment=_COMPONENT_VALUE + "; NaN past the "
                            "end of a shorter group"),
        f"{COMPONENT}_start": variable(MEMBER, _OWN, f"{COMPONENT} (state component) at the "
                                       "start"),
        f"{COMPONENT}_final": variable(MEMBER, _OWN, f"{COMPONENT} (state component) at the end "
                                       "of the run", comment=_COMPONENT_VALUE),
        "member_group": variable(MEMBER, ONE, "group of the member", kind="i"),
        "status": status_variable(MEMBER, comment=(
            "ok: the member's numbers can be trusted; non_finite: its state overflowed; "
            "not_converged: an implicit step's solver failed; derived numbers (drifts, "
            "tracked events) of members whose status is not ok are NaN")),
        "fail_time": variable(MEMBER, SECOND, "time at which the member's failure was detected",
                              comment="NaN for members whose status is ok"),
        "iterations": variable(MEMBER, ONE, "nonlinear-solver iterations over the run (0 for "
                               "explicit methods)", kind="i"),
        f"{INVARIANT}_drift": variable(MEMBER, ONE, f"relative drift of the invariant {INVARIANT} "
                                       "over the run, (I(end) - I(0)) / |I(0)|",
                                       optional="scenes that declare invariants",
                                       comment="NaN where the invariant is 0 at the start"),
        "t_final": variable(MEMBER, SECOND, "time the member's run ended", optional=_EVENTS,
                            comment="the end of its group's steps, or a stop event's located "
                                    "time (the final state is the one there)"),
        "stop_event": variable(MEMBER, ONE, "event that stopped the member (-1: none)",
                               kind="i", optional=_EVENTS),
        "event_count": variable((MEMBER, "event"), ONE, "crossings of the event found",
                                kind="i", optional=_EVENTS),
        "event_time": variable((MEMBER, "event", _OCCURRENCE), SECOND, "time of each crossing "
                               "of the event, in order", optional=_EVENTS, comment=(
                                   "located on the method's own step from the state before "
                                   "it; NaN past the crossings found or kept")),
        "axis_crossings": variable(MEMBER, ONE, "sign changes of the tracked spin-axis quantity",
                                   kind="i", optional=_TRACKING),
        "first_axis_crossing": variable(MEMBER, SECOND, "time of the first sign change of the "
                                        "tracked spin-axis quantity", optional=_TRACKING,
                                        comment="NaN where none happened"),
        "last_axis_crossing": variable(MEMBER, SECOND, "time of the last sign change of the "
                                       "tracked spin-axis quantity", optional=_TRACKING),
        "perp_crossings": variable(MEMBER, ONE, "sign changes of the first tracked quantity "
                                   "across the spin axis", kind="i", optional=_TRACKING),
        "first_perp_crossing": variable(MEMBER, SECOND, "time of the first sign change of the "
                                        "first tracked quantity across the spin axis",
                                        optional=_TRACKING),
        "last_perp_crossing": variable(MEMBER, SECOND, "time of the last sign change of the first "
                                       "tracked quantity across the spin axis", optional=_TRACKING),
        "max_perp_amplitude": variable(MEMBER, _TRACKED_UNITS, "largest amplitude across the spin "
                                       "axis, sqrt(b^2 + c^2) of the tracked quantities",
                                       optional=_TRACKING),
        "passage_time": variable((MEMBER, LEVEL), SECOND, "first time the amplitude across the "
                                 "spin axis reaches the level", optional=_TRACKING,
                                 comment="NaN where the level was never reached or is one "
                                     "of another group's levels only; 0 where the start is "
                                     "above it"),
        "members": variable(_GROUP, ONE, "members of the group", kind="i"),
        "h": variable(_GROUP, SECOND, "integration step h"),
        "n_steps": variable(_GROUP, ONE, "steps of the run", kind="i"),
        PARAMETER: variable(_GROUP, _OWN, f"parameter {PARAMETER} of the group",
                            optional=_PARAMETERS_NAMED),
        "parameters": variable((_GROUP, "parameter"), ONE, "the group's parameter set, as the "
                               "scene's methods take it", optional="scenes that do not name their "
                               "parameters", comment="in the scene's own units"),
        "tracked_components": variable((_GROUP, _TRACK), ONE, "state components the tracking "
                                       "reads (spin axis, then the two across it), numbered from 0",
                                       kind="i", optional=_TRACKING),
    }, note=(
        "Its variables are named from the scene: a name holding `<component>` stands for one "
        "variable per state component (its units the component's), `<parameter>` one per "
        "named parameter, `<invariant>` one per invariant the scene declares; the amplitude "
        "and levels are in the units of what the scene tracks (`tracked_units`). The global "
        "attributes `scene_components`, `scene_units`, `scene_parameters`, "
        "`scene_parameter_units` and `scene_invariants` record what the scene declared, and "
        "`stability.ensemble.schema.SCENE_RUN.of(...)` gives one scene's declaration"))


_SAMPLES = "runs with sample times"

ADAPTIVE_RUN = SceneSchema(
    "adaptive_run", "a run of any scene's members with adaptive Dormand-Prince 5(4) steps and "
    "user events, per member and per group", "stability.run_adaptive", "", {
        MEMBER: member_coordinate(),
        _GROUP: coordinate(_GROUP, ONE, "group of members (one parameter set)", kind="i"),
        "event": coordinate("event", ONE, "user event (the name of its function)", kind="U",
                            optional=_EVENTS),
        TIME: time_coordinate("time since the start of the samples asked for",
                              optional=_SAMPLES),
        COMPONENT: variable((MEMBER, TIME), _OWN, f"{COMPONENT} (state component) at each "
                            "sample time", optional=_SAMPLES, comment=(
                                "from the continuous extension of the step that holds the "
                                "time (order 4); NaN past t_final")),
        f"{COMPONENT}_start": variable(MEMBER, _OWN, f"{COMPONENT} (state component) at the "
                                       "start"),
        f"{COMPONENT}_final": variable(MEMBER, _OWN, f"{COMPONENT} (state component) at the end "
                                       "of the member's run", comment="at t_final"),
        "member_group": variable(MEMBER, ONE, "group of the member", kind="i"),
        "t_end": variable(MEMBER, SECOND, "end time asked for the member"),
        "t_final": variable(MEMBER, SECOND, "time the member's run ended", comment=(
            "t_end, a stop event's located time, or where a failure stopped it")),
        "accepted_steps": variable(MEMBER, ONE, "accepted steps", kind="i"),
        "rejected_steps": variable(MEMBER, ONE, "rejected steps (redone shorter)", kind="i"),
        "error_estimate": variable(MEMBER, ONE, "error estimate of the last accepted step, in "
                                   "units of the tolerance atol + rtol |x|", comment=(
                                       "the embedded order-4 solution's difference, RMS over "
                                       "the components; at most 1")),
        "error_sum": variable(MEMBER, _STATE_UNITS, "Euclidean norms of the accepted steps' "
                              "local error estimates, summed", comment=(
                                  "an estimate of the Euclidean norm of the global error at "
                                  "t_final; a bound where the flow does not stretch the steps' "
                                  "errors; components of different units are added as numbers "
                                  "in their own units")),
        "h_last": variable(MEMBER, SECOND, "last accepted step h"),
        "status": variable(MEMBER, ONE, "member status", kind="i",
                           flag_values=(cv.STATUS_OK, cv.STATUS_NONFINITE, cv.STATUS_MAX_STEPS,
                                        cv.STATUS_STEP_TOO_SMALL),
                           flag_meanings="ok non_finite max_steps step_too_small"),
        "stop_event": variable(MEMBER, ONE, "event that stopped the member (-1: none)",
                               kind="i", optional=_EVENTS),
        "event_count": variable((MEMBER, "event"), ONE, "crossings of the event found",
                                kind="i", optional=_EVENTS),
        "event_time": variable((MEMBER, "event", _OCCURRENCE), SECOND, "time of each crossing "
                               "of the event, in order", optional=_EVENTS,
                               comment="NaN past the crossings found or kept"),
        "members": variable(_GROUP, ONE, "members of the group", kind="i"),
        PARAMETER: variable(_GROUP, _OWN, f"parameter {PARAMETER} of the group",
                            optional=_PARAMETERS_NAMED),
        "parameters": variable((_GROUP, "parameter"), ONE, "the group's parameter set, as the "
                               "scene's methods take it", optional="scenes that do not name their "
                               "parameters", comment="in the scene's own units"),
    }, note="Named from the scene as the scene_run Dataset; rtol, atol and max_steps are "
            "global attributes")


_DECLARED: dict[str, DatasetSchema] = {s.name: s for s in (ENSEMBLE, SCENE_RUN, ADAPTIVE_RUN)}

#: Every Dataset kind, by name (read-only, live): the free body's ensemble and a run of any
#: scene, declared here, then each family's (its ``schema.py``), which the registry adds
#: (:func:`register`) when it loads the families.
SCHEMAS: Mapping[str, DatasetSchema] = MappingProxyType(_DECLARED)


def register(*schemas: DatasetSchema) -> None:
    """Add Dataset declarations to :data:`SCHEMAS` (a family's, from :mod:`stability.registry`).

    Parameters
    ----------
    *schemas : DatasetSchema
        Each under its name, which no other declaration may have.

    Raises
    ------
    ValueError
        If a name is taken by another declaration.
    """
    for s in schemas:
        if _DECLARED.get(s.name, s) is not s:
            raise ValueError(f"Dataset kind {s.name!r} is declared twice")
        _DECLARED[s.name] = s


def _time_dims(s: DatasetSchema) -> set:
    """The dims of ``s`` whose coordinate is a CF time axis."""
    return {
        name
        for name, var in s.variables.items()
        if var.coordinate and var.dims == (name,) and ("standard_name", "time") in var.extra
    }


@functools.cache
def _file_orders(kinds: int) -> dict:
    """``{(name, frozenset(dims)): (held dims, file dims)}`` for each declared variable that a
    file holds in another order than the Dataset: CF 2.4 wants the time dimension right of
    every other, where the package keeps each member's samples of one instant together
    (``w`` (member, time, axis) is written (member, axis, time)). ``kinds``: the size of
    :data:`SCHEMAS`, so that the orders are made again once the register has grown."""
    orders = {}
    for s in SCHEMAS.values():
        time = _time_dims(s)
        for name, var in s.variables.items():
            file = tuple(d for d in var.dims if d not in time) + tuple(
                d for d in var.dims if d in time
            )
            if file != var.dims:
                orders[(name, frozenset(var.dims))] = (var.dims, file)
    return orders


def file_order(ds):
    """``ds`` with each declared variable in the order a file holds it (:func:`held_order`
    undoes it); a view, no copy. Variables the register does not declare keep their order.

    Parameters
    ----------
    ds : xarray.Dataset
    """
    return _reorder(ds, to_file=True)


def held_order(ds):
    """``ds`` read from a file, with each declared variable back in the order the package
    holds it (the inverse of :func:`file_order`); lazy arrays stay lazy.

    Parameters
    ----------
    ds : xarray.Dataset
    """
    return _reorder(ds, to_file=False)


def _reorder(ds, to_file: bool):
    file_orders = _file_orders(len(SCHEMAS))
    changes = {}
    for name, var in ds.variables.items():
        orders = file_orders.get((name, frozenset(var.dims)))
        if orders is not None:
            held, file = orders
            want, have = (file, held) if to_file else (held, file)
            if tuple(var.dims) == have:
                changes[name] = want
    if not changes:
        return ds
    out = ds.copy(deep=False)
    for name, dims in changes.items():
        out[name] = out[name].transpose(*dims)
    return out


def schema(name: str) -> DatasetSchema:
    """The declaration of the Dataset kind ``name`` (:data:`SCHEMAS`).

    Parameters
    ----------
    name : str
        ``"ensemble"`` or a study kind.

    Raises
    ------
    KeyError
        Listing the known kinds.
    """
    try:
        return SCHEMAS[name]
    except KeyError:
        raise KeyError(f"no Dataset kind {name!r}; known: {', '.join(SCHEMAS)}") from None


__all__ = [
    "ADAPTIVE_RUN",
    "DatasetSchema",
    "ESTIMATES",
    "KINDS",
    "LEVEL",
    "SCENE_RUN",
    "SCHEMAS",
    "SceneSchema",
    "Variable",
    "file_order",
    "held_order",
    "register",
    "schema",
]
