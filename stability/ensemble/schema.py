"""The register of every Dataset the package writes: each variable's dims, units and long name.

One declaration per Dataset kind (:class:`DatasetSchema`, in :data:`SCHEMAS`): the free body's
ensemble (:func:`stability.run_ensemble`), the Dataset of every study kind (``stability run``,
keyed by the kind's name) and that of a run of any scene (:func:`stability.run_scene`,
``"scene_run"``: a :class:`SceneSchema`, a template whose variables are named from the scene,
:meth:`SceneSchema.of` one scene's declaration). Each names every variable and coordinate it may
hold (:class:`Variable`): its dims, units (UDUNITS spelling), long name, type, whether it is a
coordinate, when it may be absent, and its further CF attributes (standard names, flags, comments).
The code that builds a Dataset takes the dims and the attributes from here
(:meth:`DatasetSchema.entries`), the documentation's Dataset reference is generated from here, and
the tests hold every study's written file to its declaration (:meth:`DatasetSchema.problems`).

A declaration::

    BAT["angular_velocity"]
    # Variable(dims=('hold', 'pivot', 'strike'), units='rad s-1',
    #          long_name='angular velocity just after the contact', kind='f', ...)
    xr.Dataset(BAT.entries({"angular_velocity": w, ...}))  # dims and attributes from here

This module imports only :mod:`stability.util.conventions` (and NumPy for the flag arrays), so that
every module may import it.
"""

from __future__ import annotations

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

_ONE = cv.UNITS_DIMENSIONLESS
_S = cv.UNITS_TIME
_RAD = cv.UNITS_ANGLE
_RAD_S = cv.UNITS_ANGULAR_VELOCITY
_RAD_S2 = "rad s-2"
_RATE = cv.UNITS_RATE
_S2 = cv.UNITS_RATE_SQUARED
_KGM2 = cv.UNITS_MOMENT_OF_INERTIA
_M = "m"
_M_S = "m s-1"
_NS = "N s"
_ARCSEC = "arcsec"
_ARCSEC_YR = "arcsec yr-1"
_DEGREE = "degree"
_YEAR = "yr"
_DAY = "d"
MEMBER, TIME, AXIS, QUATERNION = cv.MEMBER, cv.TIME, cv.AXIS, cv.QUATERNION
#: Dimension of the perpendicular-amplitude levels of ``passage_time``.
LEVEL = "level"


def _dims(dims) -> tuple:
    return (dims,) if isinstance(dims, str) else tuple(dims)


def _var(dims, units, long_name, *, kind="f", optional="", **extra) -> Variable:
    """A data variable; ``extra``: further attributes, in order."""
    return Variable(_dims(dims), units, long_name, kind, False, optional, tuple(extra.items()))


def _coord(dims, units, long_name, *, kind="f", optional="", **extra) -> Variable:
    """A coordinate (an index when its one dim is its name)."""
    return Variable(_dims(dims), units, long_name, kind, True, optional, tuple(extra.items()))


def _member(long_name="ensemble member", dim=MEMBER) -> Variable:
    """An ensemble-member coordinate (:func:`stability.util.conventions.member_attrs`)."""
    return _coord(dim, _ONE, long_name, kind="i", **cv.STANDARD_COORDINATES[MEMBER])


def _time_axis(long_name="time since the start", dim=TIME, optional="") -> Variable:
    """A CF time axis (:func:`stability.util.conventions.time_attrs`)."""
    return _coord(dim, cv.UNITS_TIME_COORDINATE, long_name, optional=optional,
                  **cv.STANDARD_COORDINATES[TIME])


def _status(dims, long_name="member status", **extra) -> Variable:
    """Per-member status codes, int8 CF flags (:data:`stability.util.conventions.STATUS_MEANINGS`)."""
    return _var(dims, _ONE, long_name, kind="i", flag_values=cv.STATUS_FLAG_VALUES,
                flag_meanings=cv.STATUS_MEANINGS, **extra)


def _schema(name, title, written_by, variables, file=None) -> DatasetSchema:
    return DatasetSchema(name, title, written_by, f"{name}.nc" if file is None else file,
                         variables)


# The free body's ensemble (stability.output.dataset.ensemble_dataset)
# --------------------------------

_SUMMARY_ONLY = "runs that save the time series (not summaries_only)"
_ATTITUDE = "the scene free_body_attitude (the attitude carried)"
_COUNT = "a count stored as float64 so that masked members can be NaN"

ENSEMBLE = _schema("ensemble", "an ensemble of free rigid bodies, per member",
                   "stability.run_ensemble", file="", variables={
    MEMBER: _member(),
    AXIS: _coord(AXIS, _ONE, "principal axis of the body", kind="i"),
    LEVEL: _coord(LEVEL, _RAD_S, "perpendicular angular-velocity amplitude level"),
    TIME: _time_axis(optional=_SUMMARY_ONLY),
    "w": _var((MEMBER, TIME, AXIS), _RAD_S, "body-frame angular velocity",
              optional=_SUMMARY_ONLY),
    "w0": _var((MEMBER, AXIS), _RAD_S, "initial body-frame angular velocity"),
    "status": _status(MEMBER, comment=(
        "ok: the member's numbers can be trusted; non_finite: its state overflowed; "
        "diverged: its energy or |L| left divergence_tolerance; not_converged: an "
        "implicit step's solver failed; step_too_large: h max|w| exceeds the method's "
        "max_step_angle (its numbers may look sane but are not trustworthy); numbers of "
        "members whose status is not ok are NaN (masked)")),
    "fail_time": _var(MEMBER, _S, "time at which the member's failure was detected", comment=(
        "NaN for members whose status is ok; the end of the run for diverged members; "
        "0 for step_too_large (known from the start)")),
    "flip_count": _var(MEMBER, _ONE,
                       "number of sign changes of the spin-axis component of w (flips)",
                       comment=_COUNT),
    "first_flip_time": _var(MEMBER, _S,
                            "time of the first flip (sign change of the spin-axis component)",
                            comment="NaN where no flip happened"),
    "last_flip_time": _var(MEMBER, _S,
                           "time of the last flip (sign change of the spin-axis component)"),
    "mean_flip_interval": _var(MEMBER, _S, "mean time between flips, (last - first) / "
                               "(count - 1)", comment="NaN where fewer than two flips happened"),
    "perp_crossing_count": _var(MEMBER, _ONE, "number of sign changes of w_b, b the lower of "
                                "the two axes other than the spin axis", comment=_COUNT),
    "first_perp_crossing": _var(MEMBER, _S, "time of the first sign change of w_b"),
    "last_perp_crossing": _var(MEMBER, _S, "time of the last sign change of w_b"),
    "max_perp_amplitude": _var(MEMBER, _RAD_S,
                               "maximum perpendicular amplitude sqrt(w_b^2 + w_c^2)"),
    "passage_time": _var((MEMBER, LEVEL), _S,
                         "first time the perpendicular amplitude reaches the level",
                         comment="NaN where the level was never reached; 0 where the start "
                                 "is above it"),
    "energy_error": _var(MEMBER, _ONE, "relative kinetic-energy error at the end, (E - E0) / "
                         "E0"),
    "angular_momentum_error": _var(MEMBER, _ONE, "relative |L| error at the end, (|L| - |L0|) "
                                   "/ |L0|"),
    QUATERNION: _coord(QUATERNION, _ONE, "quaternion component (0: scalar part cos(angle/2))",
                       kind="i", optional=_ATTITUDE),
    "q": _var((MEMBER, TIME, QUATERNION), _ONE, "attitude quaternion, body to space (scalar "
              "first)", optional=_ATTITUDE,
              comment="R(q) maps body components to space components; q' = q (0, w) / 2; "
                      "normalised on output (the carried norm error is q_norm_error)"),
    "q_norm_error": _var((MEMBER, TIME), _ONE, "norm error |q| - 1 of the carried attitude "
                         "quaternion", optional=_ATTITUDE,
                         comment="q is carried without renormalisation and normalised on "
                                 "output"),
    "attitude_error": _var((MEMBER, TIME), _RAD, "angle of the rotation from the exact "
                           "attitude to the computed one", optional=_ATTITUDE,
                           comment="exact attitude: Euler angles about L from the elliptic "
                                   "solution and an exact quadrature of the precession rate "
                                   "(stability.free_body.exact_attitude)"),
})

# One trajectory (stability.integrate)
# ----------------------------------------------------------------

TRAJECTORY = _schema("trajectory", "one free rigid body's motion, sample by sample",
                     "stability.integrate", file="", variables={
    TIME: _time_axis("time"),
    AXIS: ENSEMBLE[AXIS],
    "w": ENSEMBLE["w"].on((TIME, AXIS), optional=""),
    QUATERNION: ENSEMBLE[QUATERNION],
    "q": ENSEMBLE["q"].on((TIME, QUATERNION), optional=_ATTITUDE, extra=(
        ("comment", "R(q) maps body components to space components; q' = q (0, w) / 2"),)),
    "q_norm_error": ENSEMBLE["q_norm_error"].on((TIME,)),
})

# The tennis racket: the ensemble, its exact answers and amplitude quantiles -------------------

_QUANTILE = "{quantile} over ok members of the amplitude perpendicular to axis {axis}"
TENNIS_RACKET = ENSEMBLE.extend(
    "tennis_racket", "the tennis-racket ensemble with its exact flip intervals and the "
    "quantiles of its perpendicular amplitude", "stability.free_body.tennis_racket.analysis.analyse_ensemble",
    "tennis_racket.nc", {
        "exact_flip_interval": _var(MEMBER, _S,
                                    "exact flip interval 2K(k)/nu of the member's start"),
        "flip_interval_asymptote": _var(MEMBER, _S, "small-perturbation asymptote (2/lambda) "
                                        "ln(4/k') of the flip interval"),
        "complementary_modulus": _var(MEMBER, _ONE,
                                      "complementary modulus k' of the member's Jacobi "
                                      "functions"),
        "perp_amplitude_p10": _var(TIME, _RAD_S, _QUANTILE),
        "perp_amplitude_median": _var(TIME, _RAD_S, _QUANTILE),
        "perp_amplitude_p90": _var(TIME, _RAD_S, _QUANTILE),
    },
    **{name: replace(ENSEMBLE[name], optional="") for name in (TIME, "w")})

# Ensemble estimates (stability.analysis), shared by the stability map -------------------------

#: Long names and units of the ensemble estimates of :mod:`stability.analysis`, scalars there
#: (``dims`` empty); a Dataset kind places them on its dims (:meth:`Variable.on`).
ESTIMATES = MappingProxyType({
    "regime": _var((), _ONE, "regime of the ensemble's motion", kind="i",
                   flag_values=cv.REGIME_FLAG_VALUES, flag_meanings=cv.REGIME_MEANINGS),
    "omega_squared_measured": _var((), _S2, "measured Omega^2 (-rate^2 for growth, "
                                   "+frequency^2 for oscillation)"),
    "omega_squared_measured_stderr": _var((), _S2, "standard error of the measured Omega^2"),
    "omega_squared": _var((), _S2, "analytic Omega^2 of linear theory"),
    "relative_error": _var((), _ONE, "(measured - analytic) / |analytic| Omega^2"),
    "sign_agrees": _var((), _ONE, "regime sign equals the sign of the analytic Omega^2",
                        kind="i"),
    "growth_rate": _var((), _RATE, "exponential growth rate"),
    "growth_rate_stderr": _var((), _RATE, "standard error of the growth rate"),
    "oscillation_frequency": _var((), _RAD_S, "oscillation angular frequency"),
    "oscillation_frequency_stderr": _var((), _RAD_S,
                                         "standard error of the oscillation frequency"),
    "drift_rate": _var((), _RAD_S2, "slope of the perpendicular amplitude (algebraic drift)"),
    "n_fitted": _var((), _ONE, "members that gave a rate or a frequency"),
    "first_flip_time_mean": _var((), _S, "mean time of the first flip"),
    "first_flip_time_stderr": _var((), _S, "standard error of the first-flip time"),
    "flip_interval_mean": _var((), _S, "mean flip interval"),
    "flip_interval_stderr": _var((), _S, "standard error of the flip interval"),
    "flip_interval_exact_mean": _var((), _S, "mean exact flip interval 2K/nu"),
    "flip_interval_asymptote_mean": _var((), _S,
                                         "mean asymptotic flip interval (2/lambda) ln(4/k')"),
    "flip_interval_relative_error": _var((), _ONE,
                                         "mean (measured - exact) / exact flip interval"),
    "flip_interval_relative_error_stderr": _var((), _ONE, "standard error of the flip-interval "
                                                "relative error"),
    "n_flips_mean": _var((), _ONE, "mean number of flips per member"),
    "n_with_interval": _var((), _ONE, "members with two or more flips"),
})

# The stability map (stability.free_body.stability_map.measure.map_dataset)
# ---------------------------------------

_MSA = ("integrator", "shape", AXIS)
_EDGE_CASE, _EDGE_TIME, _FLIP_SHAPE = "edge_case", "edge_time", "flip_shape"
_NORMALISED = "principal moment I{i}, normalised so that I3 = 1"


def _moment(dim, i) -> Variable:
    return _coord(dim, _KGM2, _NORMALISED.format(i=i))


STABILITY_MAP = _schema(
    "stability_map", "Omega^2 measured against linear theory over the triangle of shapes, "
    "per integrator, shape and spin axis; the flip-interval sweep and the edge cases",
    "stability.free_body.stability_map.measure.map_dataset", {
        "omega_squared": _var(("shape", AXIS), _S2,
                              "analytic Omega^2 = (Ia - Ib)(Ia - Ic) W^2 / (Ib Ic)"),
        "omega_squared_normalised": _var(("shape", AXIS), _ONE, "analytic Omega^2 / W^2"),
        "t_end": _var(("shape", AXIS), _S, "run length of the ensemble"),
        "edge": _var("shape", _ONE, "triangle edges the shape lies on", kind="i",
                     flag_masks=cv.EDGE_FLAG_MASKS, flag_meanings=cv.EDGE_MEANINGS),
        "regime": ESTIMATES["regime"].on(_MSA),
        "sign_agrees": ESTIMATES["sign_agrees"].on(_MSA, extra=(
            ("flag_values", (0, 1)), ("flag_meanings", "no yes"))),
        "status": _status(_MSA, "worst member status of the ensemble"),
        "members_failed": _var(_MSA, _ONE, "members whose status is not ok (left out of the "
                               "estimates)", kind="i"),
        "energy_error_max": _var(_MSA, _ONE, "largest relative kinetic-energy error at the end "
                                 "over members"),
        "first_flip_time_relative_error": _var(_MSA, _ONE, "mean relative difference of the "
                                               "first-flip time from the exact flow's, member "
                                               "by member"),
        "omega_squared_measured_half_step": _var(_MSA, _S2, "measured Omega^2 at step h / 2 "
                                                 "(bias check)"),
        "regime_half_step": ESTIMATES["regime"].on(
            _MSA, long_name="regime at step h / 2 (bias check)"),
        "step_bias": _var(_MSA, _ONE, "Richardson estimate of the method's relative O(h^p) "
                          "bias in Omega^2 at step h, (X(h) - X(h/2)) / (1 - 2^-p) / "
                          "|Omega^2|"),
        **{name: ESTIMATES[name].on(_MSA) for name in (
            "omega_squared_measured", "omega_squared_measured_stderr", "relative_error",
            "growth_rate", "growth_rate_stderr", "oscillation_frequency",
            "oscillation_frequency_stderr", "drift_rate", "n_fitted", "n_flips_mean",
            "first_flip_time_mean", "first_flip_time_stderr", "flip_interval_mean",
            "flip_interval_stderr", "flip_interval_exact_mean", "flip_interval_asymptote_mean",
            "flip_interval_relative_error", "flip_interval_relative_error_stderr")},
        "sweep_flip_interval": _var(("integrator", _FLIP_SHAPE, "epsilon"), _S,
                                    "measured flip interval, perturbation epsilon along axis 1"),
        "sweep_flip_interval_exact": _var((_FLIP_SHAPE, "epsilon"), _S,
                                          "exact flip interval 2K/nu"),
        "sweep_flip_interval_asymptote": _var((_FLIP_SHAPE, "epsilon"), _S,
                                              "asymptotic flip interval (2/lambda) ln(4/k')"),
        "sweep_growth_rate": _var(_FLIP_SHAPE, _RATE, "analytic growth rate lambda about axis 2"),
        "edge_w": _var((_EDGE_CASE, _EDGE_TIME, AXIS), _RAD_S,
                       "body-frame angular velocity on an edge case"),
        "edge_slope_predicted": _var(_EDGE_CASE, _RAD_S2, "initial rate of change of the "
                                     "drifting component (Euler's equations)"),
        "edge_slope_measured": _var(_EDGE_CASE, _RAD_S2,
                                    "least-squares slope of the drifting component"),
        "edge_distinct_change": _var(_EDGE_CASE, _RAD_S, "largest change of the component "
                                     "along the distinct axis"),
        "edge_flips": _var(_EDGE_CASE, _ONE, "sign changes of the spin component", kind="i"),
        "edge_regime": ESTIMATES["regime"].on((_EDGE_CASE,)),
        "edge_linear_residual": _var(_EDGE_CASE, _ONE, "rms relative misfit of a straight line "
                                     "to the amplitude"),
        "edge_exponential_residual": _var(_EDGE_CASE, _ONE,
                                          "rms misfit of an exponential to the amplitude"),
        "integrator": _coord("integrator", _ONE, "integrator", kind="U"),
        "h": _coord("integrator", _S, "step"),
        "method_order": _coord("integrator", _ONE, "order of the method (inf: exact flow)"),
        "shape": _coord("shape", _ONE, "shape index", kind="i"),
        "I1": _moment("shape", 1),
        "I2": _moment("shape", 2),
        "I3": _moment("shape", 3),
        AXIS: _coord(AXIS, _ONE, "principal axis of the spin", kind="i"),
        LEVEL: _coord(LEVEL, _RAD_S, "perpendicular amplitude level of the passage times"),
        _FLIP_SHAPE: _coord(_FLIP_SHAPE, _ONE, "flip sweep shape index", kind="i"),
        "flip_I1": _moment(_FLIP_SHAPE, 1),
        "flip_I2": _moment(_FLIP_SHAPE, 2),
        "epsilon": _coord("epsilon", _ONE, "perturbation relative to the spin"),
        _EDGE_CASE: _coord(_EDGE_CASE, _ONE, "edge case", kind="U"),
        "edge_I1": _moment(_EDGE_CASE, 1),
        "edge_I2": _moment(_EDGE_CASE, 2),
        "edge_I3": _moment(_EDGE_CASE, 3),
        "edge_axis": _coord(_EDGE_CASE, _ONE, "spin axis of the edge case", kind="i"),
        _EDGE_TIME: _coord(_EDGE_TIME, _S, "time since the start"),
    })

# The engine's artefacts (stability.engine_body.measure) ---------------------------------------

_RULE_STEP = ("rule", "step")
_SEARCHED = ("searched at h / 2^(k/2) from the largest step; NaN: not reached down to the "
             "search's smallest step")
ENGINE_ARTEFACTS = _schema(
    "engine_artefacts", "what each update rule or method does to the tennis racket's flips, "
    "growth and invariants, per step", "stability.engine_body.measure.measure_artefacts", {
        "fraction_flipping": _var(_RULE_STEP, _ONE, "fraction of members that flip at least "
                                  "once"),
        "flip_interval": _var(_RULE_STEP, _S, "median flip interval"),
        "flip_interval_error": _var(_RULE_STEP, _ONE, "mean relative error of the flip "
                                    "interval against the exact 2K/nu"),
        "growth_rate": _var(_RULE_STEP, _RATE, "growth rate of the perpendicular amplitude"),
        "growth_rate_error": _var(_RULE_STEP, _ONE, "relative error of the growth rate against "
                                  "sqrt(-Omega^2)"),
        "energy_drift": _var(_RULE_STEP, _ONE, "median relative energy error at the end"),
        "momentum_drift": _var(_RULE_STEP, _ONE, "median relative |L| error at the end"),
        "l_direction_drift": _var(_RULE_STEP, _RAD, "median angle turned by the spatial "
                                  "angular momentum at the end"),
        "cost_per_step": _var(_RULE_STEP, _S, "measured wall time per member-step (tracking "
                              "included)"),
        "members_ok": _var(_RULE_STEP, _ONE, "members whose run stayed finite"),
        "evaluations_per_second": _var(_RULE_STEP, _RATE, "right-hand-side evaluations (or "
                                       "sub-flows) per simulated second"),
        "step_needed": _var("rule", _S, "largest step with the flip interval within "
                            "{tolerance:g} of the exact", comment=_SEARCHED),
        "step_needed_energy": _var("rule", _S, "largest step with the energy at the end within "
                                   "{tolerance:g} of the start", comment=_SEARCHED),
        "spin_component": _var(("rule", TIME), _RAD_S, "member's spin-axis angular velocity w2 "
                               "at h = {h:g} s"),
        "spin_component_exact": _var(TIME, _RAD_S, "the same member's exact w2"),
        "family": _var("rule", _ONE, "family of the rule", kind="U"),
        "rule": _coord("rule", _ONE, "update rule or method", kind="U"),
        "step": _coord("step", _S, "time step"),
        TIME: _time_axis("time"),
    })

# The work-precision study (stability.free_body.work_precision.measure)
# -------------------------------------------

_WMS = ("workload", "method", "sweep")
_WMSM = _WMS + ("metric",)
WORK_PRECISION = _schema(
    "work_precision", "speed against error of every integrator, per workload, method and "
    "step; the long-horizon drift of the invariants",
    "stability.free_body.work_precision.measure.work_precision_dataset", {
        "w_error": _var(_WMSM, _ONE, "relative error of w at the end, |w - w_exact| / "
                        "|w_exact|"),
        "energy_error": _var(_WMSM, _ONE, "relative kinetic-energy error at the end, |E / E0 - "
                             "1|"),
        "momentum_error": _var(_WMSM, _ONE, "relative angular-momentum error at the end, | |L| "
                               "/ |L0| - 1 |"),
        "attitude_error": _var(_WMSM, _RAD, "attitude error at the end: angle of the rotation "
                               "from the reference attitude (DOP853) to the method's, over the "
                               "first [attitude] members"),
        "wall_time": _var(_WMS, _S, "kernel wall time for the whole ensemble (compilation "
                          "excluded)"),
        "member_step_time": _var(_WMS, _S, "wall time per member and step"),
        "steps": _var(_WMS, _ONE, "steps per member"),
        "evaluations": _var(_WMS, _ONE, "right-hand-side evaluations or exact sub-flows per "
                            "member"),
        "iterations": _var(_WMS, _ONE, "nonlinear-solver iterations per step, mean over "
                           "members"),
        "failed": _var(_WMS, _ONE, "members flagged non-finite, diverged or not converged"),
        "floor": _var(("workload", "metric"), _ONE, "conditioning floor: relative change of "
                      "the exact w(T) when D2 of the start moves by one rounding"),
        "drift_energy": _var(("method", "long_time"), _ONE, "RMS over members of the relative "
                             "energy error E / E0 - 1"),
        "drift_momentum": _var(("method", "long_time"), _ONE, "RMS over members of the "
                               "relative |L| error"),
        "drift_slope": _var("method", _ONE, "log-log slope of the energy error's running "
                            "maximum over the last two decades of the long run (0 bounded, 1/2 "
                            "round-off random walk, 1 drift)"),
        "workload": _coord("workload", _ONE, "workload", kind="U"),
        "method": _coord("method", _ONE, "integrator (registry name; dop853: scipy)", kind="U"),
        "sweep": _coord("sweep", _ONE, "index in the step-size or tolerance sweep", kind="i"),
        "metric": _coord("metric", _ONE, "statistic over members", kind="U"),
        "long_time": _coord("long_time", _S, "time in the long-horizon run"),
        "h": _coord(_WMS, _S, "step size"),
        "rtol": _coord(_WMS, _ONE, "scipy relative tolerance"),
        "order": _coord("method", _ONE, "declared order (dop853: 8, adaptive)"),
        "attitude_reference_error": _var(("workload", "metric"), _ONE, "relative w error of the "
                                         "attitude reference (DOP853, rtol = atol = 1e-13) "
                                         "against the exact solution"),
    })

# The twisting racket (stability.free_body.twisting_racket.measure.measure_twisting)
# ------------------------------------

TWISTING_RACKET = _schema(
    "twisting_racket", "Montgomery's angle and the twist of tossed bodies, per member, from "
    "the run and from the exact motion", "stability.free_body.twisting_racket.measure.measure_twisting", {
        "moments": _var((MEMBER, AXIS), _KGM2, "principal moments, ascending (canonical "
                        "frame)"),
        "w0": _var((MEMBER, AXIS), _RAD_S, "initial angular velocity, canonical frame"),
        "epsilon": _var(MEMBER, _ONE, "nudge across the middle axis relative to the spin"),
        "status": _status(MEMBER, "member status of the run"),
        "period": _var(MEMBER, _S, "period T of the body motion, 4 K / nu"),
        "montgomery_run": _var(MEMBER, _RAD, "Montgomery's angle from the run: R(T) R(0)^T "
                               "about L"),
        "montgomery_exact": _var(MEMBER, _RAD, "Montgomery's angle from the exact attitude, "
                                 "phi(T)"),
        "montgomery_formula": _var(MEMBER, _RAD, "Montgomery's angle from the formula, 2 E T / "
                                   "|L| - S (mod 2 pi)"),
        "dynamic_phase": _var(MEMBER, _RAD, "dynamic phase 2 E T / |L|"),
        "solid_angle": _var(MEMBER, "sr", "oriented solid angle S enclosed by m / |m| in the "
                            "body frame"),
        "montgomery_error": _var(MEMBER, _RAD, "|run - formula| of Montgomery's angle (mod 2 "
                                 "pi)"),
        "flip_time_run": _var(MEMBER, _S, "flip (m2 = 0) nearest T, from the run"),
        "flip_time_exact": _var(MEMBER, _S, "flip (m2 = 0) nearest T, exact"),
        "half_window_run": _var(MEMBER, _S, "half the window about the flip in which phi "
                                "advances 2 pi, run"),
        "half_window_exact": _var(MEMBER, _S, "half the window about the flip in which phi "
                                  "advances 2 pi, exact"),
        "twist_run": _var(MEMBER, _RAD, "twist: change of psi = atan2(m2, m3) over the window, "
                          "run"),
        "twist_exact": _var(MEMBER, _RAD, "twist: change of psi = atan2(m2, m3) over the "
                            "window, exact"),
        "twist_error": _var(MEMBER, _RAD, "|run - exact| of the twist"),
        "twist_defect": _var(MEMBER, _RAD, "defect of the twist from a half turn, pi - "
                             "|twist|"),
        "snapshot_time": _var("snapshot", _S, "instants across member 0's twist window"),
        "snapshot_q": _var(("snapshot", QUATERNION), _ONE, "member 0's exact attitude, body "
                           "(canonical) to space"),
        MEMBER: ENSEMBLE[MEMBER],
        AXIS: ENSEMBLE[AXIS],
        QUATERNION: replace(ENSEMBLE[QUATERNION], optional=""),
    })

# The Earth's free wobble (stability.earth.wobble.measure_free_wobble) -------------------------

_CONE_TIME = "cone_time"
EARTH_WOBBLE = _schema(
    "earth_wobble", "the free wobble of a rigid Earth: its period measured against Euler's, "
    "and one member's cones", "stability.earth.wobble.measure_free_wobble", {
        "wobble_period_measured": _var((), _DAY, "period of the rotation axis about the figure "
                                       "axis (body frame), mean over members"),
        "wobble_period_stderr": _var((), _DAY, "standard error of the measured period"),
        "member_wobble_period": _var(MEMBER, _DAY, "measured wobble period of each member"),
        "wobble_period_euler": _var((), _DAY, "Euler period 2 pi / (W sqrt((C - A)(C - B) / "
                                    "(A B)))"),
        "wobble_period_oblate": _var((), _DAY, "A / (C - A) turns, A the mean equatorial "
                                     "moment"),
        "relative_error": _var((), _ONE, "(measured - Euler) / Euler period"),
        "w_body": _var((_CONE_TIME, AXIS), _RAD_S, "angular velocity in the body frame (cone "
                       "member)"),
        "w_space": _var((_CONE_TIME, AXIS), _RAD_S, "angular velocity in space (cone member)"),
        "body_cone_angle": _var(_CONE_TIME, _ARCSEC, "angle of the rotation axis from the "
                                "figure axis"),
        "space_cone_angle": _var(_CONE_TIME, _ARCSEC, "angle of the rotation axis from the "
                                 "angular momentum"),
        "figure_axis_angle": _var(_CONE_TIME, _ARCSEC, "angle of the figure axis from the "
                                  "angular momentum"),
        MEMBER: _member(),
        _CONE_TIME: _coord(_CONE_TIME, _DAY, "time"),
        AXIS: _coord(AXIS, _ONE, "principal axis", kind="i"),
    })

# The precession of the equinoxes (stability.earth.equinoxes.measure_equinoxes) ----------------

_MTM = ("model", "torque", MEMBER)
_CYCLE = "a long run (cycle_years above 0; not in quick mode)"
EQUINOXES = _schema(
    "equinoxes", "the precession and nutation of the Earth's axis under the Sun and the "
    "Moon, full and orbit-averaged, per torque and member",
    "stability.earth.equinoxes.measure_equinoxes", {
        "precession_rate": _var(_MTM, _ARCSEC_YR, "precession of the equinox -dphi/dt, "
                                "fitted"),
        "nutation_longitude": _var(_MTM, _ARCSEC, "amplitude of the 18.6-year nutation in "
                                   "longitude"),
        "nutation_obliquity": _var(_MTM, _ARCSEC, "amplitude of the 18.6-year nutation in "
                                   "obliquity"),
        "obliquity_rate": _var(_MTM, _ARCSEC_YR, "secular rate of the obliquity, fitted"),
        "fit_residual": _var(_MTM, _ARCSEC, "rms residual of the longitude fit"),
        "precession_rate_formula": _var("torque", _ARCSEC_YR, "averaged formula (3/2) H "
                                        "cos(eps) / W G M / (a^3 (1 - e^2)^(3/2)) f"),
        "step_error": _var(MEMBER, _ARCSEC_YR, "estimated integration error of the precession "
                           "rate (Richardson, steps halved)"),
        "longitude": _var(("torque", "full_time"), _ARCSEC, "longitude of the equinox phi - phi(0), "
                          "member 0, full model"),
        "obliquity": _var(("torque", "full_time"), _ARCSEC, "obliquity, member 0, full model"),
        "longitude_averaged": _var(("torque", "averaged_time"), _ARCSEC, "longitude of the "
                                   "equinox phi - phi(0), member 0, averaged model"),
        "obliquity_averaged": _var(("torque", "averaged_time"), _ARCSEC, "obliquity, member 0, "
                                   "averaged model"),
        "cycle_longitude": _var("cycle_time", _DEGREE, "longitude of the equinox phi - "
                                "phi(0), long run", optional=_CYCLE),
        "cycle_obliquity": _var("cycle_time", _DEGREE, "obliquity, long run", optional=_CYCLE),
        "model": _coord("model", _ONE, "full (spin, orbits) or orbit-averaged model", kind="U"),
        "torque": _coord("torque", _ONE, "bodies whose torque acts", kind="U"),
        MEMBER: _member("member (0: J2000 phases)"),
        # Julian years, which CF's time units (s, d ... since a date) cannot hold exactly and
        # xarray cannot decode: plain coordinates, none named "time" (CF's time axis name).
        "full_time": _coord("full_time", _YEAR, "time since J2000, full model"),
        "averaged_time": _coord("averaged_time", _YEAR, "time since J2000, averaged model"),
        "cycle_time": _coord("cycle_time", _YEAR, "time since J2000, averaged model's long "
                             "run", optional=_CYCLE),
    })

# The gyroscope (stability.heavy_top.measure.measure_gyroscopes) ----------------------------------

_TSR = ("tilt", "spin", "release")
_PATH = ("release", "path_time")
GYROSCOPE = _schema(
    "gyroscope", "the heavy symmetric top's precession and nutation measured against the "
    "exact motion and the fast-top formulas, per tilt, spin and release",
    "stability.heavy_top.measure.measure_gyroscopes", {
        "precession_rate_measured": _var(_TSR, _RAD_S, "mean precession rate of the figure "
                                         "axis, from the run (weighted mean of phi')"),
        "precession_rate_exact": _var(_TSR, _RAD_S, "exact mean precession rate over a "
                                      "nutation period"),
        "precession_rate_error": _var(_TSR, _ONE, "(measured - exact) / exact mean precession "
                                      "rate"),
        "precession_rate_gyroscopic": _var("spin", _RAD_S, "fast-top precession rate M g l / "
                                           "(C w3)"),
        "nutation_frequency_measured": _var(_TSR, _RAD_S, "nutation frequency 2 pi / T, from "
                                            "the run"),
        "nutation_frequency_exact": _var(_TSR, _RAD_S, "exact nutation frequency 2 pi / T"),
        "nutation_frequency_error": _var(_TSR, _ONE, "(measured - exact) / exact nutation "
                                         "frequency"),
        "nutation_frequency_gyroscopic": _var("spin", _RAD_S, "fast-top nutation frequency C "
                                              "w3 / A"),
        "nutation_amplitude_measured": _var(_TSR, _RAD, "nutation amplitude theta_max - "
                                            "theta_min, from the run"),
        "nutation_amplitude_exact": _var(_TSR, _RAD, "exact nutation amplitude (turning points "
                                         "of the cubic)"),
        "nutation_amplitude_error": _var(_TSR, _ONE, "(measured - exact) / exact nutation "
                                         "amplitude"),
        "nutation_amplitude_gyroscopic": _var(_TSR, _RAD, "fast-top nutation amplitude 2 |1 - "
                                              "release| A M g l sin(theta0) / (C w3)^2"),
        "status": _status(_TSR),
        "step": _var(("tilt", "spin"), _S, "integration step h"),
        "t_end": _var(("tilt", "spin"), _S, "run time"),
        "path_theta": _var(_PATH, _RAD, "tilt theta of the figure axis, from the run"),
        "path_phi": _var(_PATH, _RAD, "precession angle phi of the figure axis, from the run"),
        "path_theta_exact": _var(_PATH, _RAD, "exact tilt theta of the figure axis"),
        "path_phi_exact": _var(_PATH, _RAD, "exact precession angle phi of the figure axis"),
        "tilt": _coord("tilt", _DEGREE, "release tilt from the vertical"),
        "spin": _coord("spin", _RAD_S, "spin w3 about the symmetry axis"),
        "release": _coord("release", _ONE, "initial precession rate / (M g l / (C w3)) (0: "
                          "released at rest)"),
        "path_time": _coord("path_time", _S, "time of the kept paths"),
    })

# The sleeping top (stability.heavy_top.measure.measure_sleeping_tops) ----------------------------

_LS = ("length", "spin")
SLEEPING_TOP = _schema(
    "sleeping_top", "the growth rate of a sleeping top's tilt measured against linear theory, "
    "per length and spin", "stability.heavy_top.measure.measure_sleeping_tops", {
        "growth_rate_measured": _var(_LS, _RATE, "measured growth rate of the tilt (0: "
                                     "bounded)"),
        "growth_rate_stderr": _var(_LS, _RATE, "standard error of the measured growth rate"),
        "growth_rate_analytic": _var(_LS, _RATE, "sqrt(4 A M g l - C^2 w3^2) / (2 A), 0 above "
                                     "w_c"),
        "relative_error": _var(_LS, _ONE, "(measured - analytic) / analytic growth rate"),
        "rate_fraction": _var(_LS, _ONE, "analytic growth rate / its value at zero spin"),
        "tilt_amplification": _var(_LS, _ONE, "largest sin(tilt) / initial sin(tilt) over "
                                   "members"),
        "slow_frequency": _var(_LS, _RAD_S, "slow precession frequency of a stable tilt"),
        "fast_frequency": _var(_LS, _RAD_S, "fast (nutation) frequency of a stable tilt"),
        "step": _var(_LS, _S, "integration step h"),
        "t_end": _var(_LS, _S, "run time"),
        "n_fitted": _var(_LS, _ONE, "members with a fitted growth rate", kind="i"),
        "members_failed": _var(_LS, _ONE, "members whose status is not ok", kind="i"),
        "critical_spin": _var("length", _RAD_S, "critical spin 2 sqrt(A M g l) / C"),
        "mgl": _var("length", "N m", "M g l"),
        "pivot_moment_transverse": _var("length", _KGM2, "transverse moment about the pivot A"),
        "length": _coord("length", _M, "pivot to centre of mass"),
        "spin": _coord("spin", _RAD_S, "spin about the symmetry axis"),
    })

# The struck bat (stability.struck.model.measure_strikes) --------------------------------------

_HPS = ("hold", "pivot", "strike")
BAT = _schema(
    "bat", "the centre of percussion of a struck bat or racket, held at the hands or free, "
    "from the runs and by the formulas", "stability.struck.model.measure_strikes", {
        "angular_velocity": _var(_HPS, _RAD_S, "angular velocity just after the contact"),
        "cm_velocity_across": _var(_HPS, _M_S, "velocity of the centre of mass across the "
                                   "body, just after the contact"),
        "hand_velocity_across": _var(_HPS, _M_S, "velocity across the body of its point at the "
                                     "hands, just after the contact (0 when held)"),
        "reaction_impulse_across": _var(_HPS, _NS, "reaction impulse across the body at the "
                                        "hands over the contact (0 when free)"),
        "reaction_impulse_along": _var(_HPS, _NS, "reaction impulse along the body at the hands "
                                       "over the contact (centripetal; 0 when free)"),
        "reaction_impulse_formula": _var(("pivot", "strike"), _NS, "held, instantaneous "
                                         "impulse: J (M d s / I_P - 1)"),
        "hand_velocity_formula": _var(("pivot", "strike"), _M_S, "free, instantaneous impulse: "
                                      "J / M - d (s - d) J / I_cm"),
        "percussion_centre_measured": _var(("hold", "pivot"), _M, "centre of percussion from "
                                           "the runs (zero reaction held, hands at rest free), "
                                           "from the end held"),
        "percussion_centre_formula": _var("pivot", _M, "centre of percussion pivot + I_P / (M "
                                          "d), from the end held"),
        "sweet_zone_measured": _var(("pivot", "edge"), _M, "strike points where the reaction "
                                    "across is sting x J, from the runs (held)"),
        "sweet_zone_formula": _var(("pivot", "edge"), _M, "pivot + (1 -+ sting) I_P / (M d) "
                                   "(NaN: beyond the tip)"),
        "status": _status(_HPS),
        "outline": _var(("station", "xy"), _M, "outline of the body: stations (x from the end "
                        "held, half-width)"),
        "hold": _coord("hold", _ONE, "hands: a hinge at the pivot, or none", kind="U"),
        "pivot": _coord("pivot", _M, "hands (pivot), from the end held"),
        "strike": _coord("strike", _M, "strike point, from the end held"),
        "edge": _coord("edge", _ONE, "edge of the sweet zone", kind="U"),
    })

# Rolling and slipping (stability.rolling.model.measure_incline and measure_launches) ----------

_CELL = ("shape", "angle", "mu_s")
_SAMR = _CELL + ("replica",)
ROLLING = _schema(
    "rolling", "balls, cylinders and hoops on inclines (roll or slip, per shape, angle, "
    "friction and replica) and launched along a floor (per member), from the runs and by the "
    "formulas", ("stability.rolling.model.measure_incline",
                 "stability.rolling.model.measure_launches"), {
        "slipped": _var(_SAMR, _ONE, "slipped (friction did work) in the run", kind="i"),
        "rolls_formula": _var(_SAMR, _ONE, "rolls: tan(theta) <= mu_s (1 + M R^2 / I), own mu_s "
                              "and k", kind="i"),
        "acceleration": _var(_SAMR, "m s-2", "acceleration along the incline, 2 x(T) / T^2 "
                             "from the run"),
        "acceleration_formula": _var(_SAMR, "m s-2", "g sin(theta) / (1 + k) rolling, g "
                                     "(sin(theta) - mu_k cos(theta)) slipping"),
        "spin_rate": _var(_SAMR, _RAD_S2, "angular acceleration w(T) / T from the run"),
        "spin_rate_formula": _var(_SAMR, _RAD_S2, "a / R rolling, mu_k M g R cos(theta) / I "
                                  "slipping"),
        "member_mu_s": _var(_SAMR, _ONE, "member's static friction coefficient"),
        "member_k": _var(_SAMR, _ONE, "member's I / (M R^2)"),
        "slip_fraction": _var(_CELL, _ONE, "fraction of the cell's members that slipped"),
        "rolls_nominal": _var(_CELL, _ONE, "rolls by the formula at the cell's nominal mu_s and "
                              "shape", kind="i"),
        "scatter_straddles": _var(_CELL, _ONE, "the cell's scatter spans the rolling boundary",
                                  kind="i"),
        "wrong_side": _var(_CELL, _ONE, "cell's majority regime against the formula, scatter "
                           "not spanning the boundary", kind="i"),
        "boundary_mu_s": _var(("shape", "angle"), _ONE, "mu_s on the boundary, tan(theta) / (1 "
                              "+ M R^2 / I)"),
        "incline_status": _status(_SAMR, "member status (inclines)"),
        "shape": _coord("shape", _ONE, "shape", kind="U"),
        "shape_factor": _coord("shape", _ONE, "nominal I / (M R^2)"),
        "angle": _coord("angle", _DEGREE, "incline angle theta"),
        "mu_s": _coord("mu_s", _ONE, "nominal static friction coefficient"),
        "replica": _member("member of the cell (own mu_s, mu_k and shape)", "replica"),
        "v0": _var(MEMBER, _M_S, "launch speed"),
        "w0": _var(MEMBER, _RAD_S, "launch spin (negative: backspin)"),
        "spin_ratio": _var(MEMBER, _ONE, "R w0 / v0 (1: launched rolling)"),
        "mu_k": _var(MEMBER, _ONE, "kinetic friction coefficient"),
        "t_roll": _var(MEMBER, _S, "time pure rolling starts, from the run"),
        "t_roll_formula": _var(MEMBER, _S, "|v0 - R w0| / (mu_k g (1 + M R^2 / I))"),
        "x_roll": _var(MEMBER, _M, "distance to pure rolling, from the run"),
        "x_roll_formula": _var(MEMBER, _M, "v0 t - sign(u0) mu_k g t^2 / 2 at t = t_roll"),
        "v_final": _var(MEMBER, _M_S, "speed at the end, from the run"),
        "v_final_formula": _var(MEMBER, _M_S, "(v0 + k R w0) / (1 + k)"),
        "heat": _var(MEMBER, cv.UNITS_ENERGY, "work done by kinetic friction, from the run"),
        "energy_lost": _var(MEMBER, cv.UNITS_ENERGY, "kinetic energy lost, from the run"),
        "energy_lost_formula": _var(MEMBER, cv.UNITS_ENERGY, "M (v0 - R w0)^2 k / (2 (1 + k))"),
        "switches": _var(MEMBER, _ONE, "switches of regime in the run", kind="i"),
        "launch_status": _status(MEMBER, "member status (launches)"),
        "path_v": _var(("path", TIME), _M_S, "speed of the centre v (kept members)"),
        "path_rw": _var(("path", TIME), _M_S, "R w, the speed rolling would need (kept "
                        "members)"),
        "path_member": _var("path", _ONE, "member of each kept path", kind="i"),
        MEMBER: _member("member"),
        TIME: _time_axis("time"),
    })


EXPLORER = _schema(
    "explorer", "an Explorer-1-like body with an energy sink spun about its minor axis: "
    "nutation growth against the linear eigenvalue, the flat spin it ends in, the energy lost",
    "stability.dissipation.explorer.measure_explorer", {
        'damping': _coord(
            'damping', '1',
            "damping c over the energy sink's optimum c*"),
        'angle': _coord(
            'angle', 'degree',
            'initial nutation angle'),
        'whip_angle': _coord(
            'whip_angle', 'degree',
            "initial nutation angle of the whip antennas' members"),
        'growth_rate_measured': _var(
            ('damping', 'angle'), 's-1',
            'growth rate of the nutation angle fitted in the linear regime'),
        'growth_rate_linear': _var(
            ('damping', 'angle'), 's-1',
            'growth rate of the nutation by the linear eigenvalue'),
        'growth_rate_error': _var(
            ('damping', 'angle'), '1',
            'measured / linear growth rate - 1'),
        'decay_rate_measured': _var(
            ('damping', 'angle'), 's-1',
            'rate of |cos theta| about the major axis, fitted'),
        'decay_rate_linear': _var(
            ('damping', 'angle'), 's-1',
            'rate of the departure from the major axis by the linear eigenvalue'),
        'decay_rate_error': _var(
            ('damping', 'angle'), '1',
            'measured / linear decay rate - 1'),
        'flat_time': _var(
            ('damping', 'angle'), 's',
            'time to the flat spin (nutation angle passing the flat-spin angle)'),
        'flat_time_linear': _var(
            ('damping', 'angle'), 's',
            'time to the flat spin at the linear growth rate, tan(theta) = tan(theta0) exp(rate'
            ' t)'),
        'angular_momentum_drift': _var(
            ('damping', 'angle'), '1',
            'largest relative change of |H| over the kept states'),
        'energy_rise': _var(
            ('damping', 'angle'), '1',
            'largest rise of the energy between kept states, relative to the start'),
        'end_angle': _var(
            ('damping', 'angle'), 'degree',
            'nutation angle at the end'),
        'energy_lost': _var(
            ('damping', 'angle'), 'J',
            'energy lost, start to end'),
        'energy_lost_formula': _var(
            ('damping', 'angle'), 'J',
            '|H|^2 / 2 (1/A_min - 1/A_max)'),
        'energy_lost_error': _var(
            ('damping', 'angle'), '1',
            'energy lost / formula - 1'),
        'end_energy_error': _var(
            ('damping', 'angle'), '1',
            'end energy / (|H|^2 / (2 A_max)) - 1'),
        'flat_energy_ratio': _var(
            ('damping', 'angle'), '1',
            "energy of the flat spin |H|^2 / (2 A_max) over the start's"),
        'status': _status(('damping', 'angle')),
        'theta': _var(
            ('damping', 'angle', 'sample'), 'degree',
            'nutation angle between the long axis and H'),
        'energy_ratio': _var(
            ('damping', 'angle', 'sample'), '1',
            'energy over its start'),
        'sample_time': _var(
            ('damping', 'sample'), 's',
            'time of the kept states'),
        'c': _var(
            'damping', 'N m s',
            'viscous coefficient of the spherical damper'),
        'step': _var(
            'damping', 's',
            'integration step h'),
        't_end': _var(
            'damping', 's',
            'run time'),
        'growth_rate_energy_sink': _var(
            ('damping', 'angle'), 's-1',
            'growth rate of the nutation by the energy-sink estimate'),
        'major_axis_end': _var(
            ('damping', 'angle'), '1',
            'ends spinning about the major axis (1) or not (0)', kind='i',
            flag_values=(0, 1),
            flag_meanings='other_axis major_axis'),
        'whip_growth_rate_measured': _var(
            'whip_angle', 's-1',
            'whip antennas: growth rate of the nutation angle fitted in the linear regime'),
        'whip_growth_rate_linear': _var(
            'whip_angle', 's-1',
            'whip antennas: growth rate of the nutation by the linear eigenvalue'),
        'whip_growth_rate_error': _var(
            'whip_angle', '1',
            'whip antennas: measured / linear growth rate - 1'),
        'whip_flat_time': _var(
            'whip_angle', 's',
            'whip antennas: time to the flat spin (nutation angle passing the flat-spin angle)'),
        'whip_flat_time_linear': _var(
            'whip_angle', 's',
            'whip antennas: time to the flat spin at the linear growth rate, tan(theta) = '
            'tan(theta0) exp(rate t)'),
        'whip_angular_momentum_drift': _var(
            'whip_angle', '1',
            'whip antennas: largest relative change of |H| over the kept states'),
        'whip_energy_rise': _var(
            'whip_angle', '1',
            'whip antennas: largest rise of the energy between kept states, relative to the '
            'start'),
        'whip_end_angle': _var(
            'whip_angle', 'degree',
            'whip antennas: nutation angle at the end'),
        'whip_energy_lost': _var(
            'whip_angle', 'J',
            'whip antennas: energy lost, start to end'),
        'whip_energy_lost_formula': _var(
            'whip_angle', 'J',
            'whip antennas: |H|^2 / 2 (1/A_min - 1/A_max)'),
        'whip_energy_lost_error': _var(
            'whip_angle', '1',
            'whip antennas: energy lost / formula - 1'),
        'whip_end_energy_error': _var(
            'whip_angle', '1',
            'whip antennas: end energy / (|H|^2 / (2 A_max)) - 1'),
        'whip_status': _status('whip_angle',
                          'whip antennas: member status'),
        'whip_major_axis_end': _var(
            'whip_angle', '1',
            'whip antennas: ends spinning about the major axis (1) or not (0)', kind='i',
            flag_values=(0, 1),
            flag_meanings='other_axis major_axis'),
        'whip_theta': _var(
            ('whip_angle', 'whip_sample'), 'degree',
            'whip antennas: nutation angle between the long axis and H'),
        'whip_sample_time': _var(
            'whip_sample', 's',
            'whip antennas: time of the kept states'),
        'whip_energy_ratio': _var(
            ('whip_angle', 'whip_sample'), '1',
            'whip antennas: energy over its start'),
    })


_DS_CELL = ("placement", "ratio", "speed")
_DS_MEMBER = ("placement", "ratio", "speed", "start")
_DS_VERDICT = dict(kind="i", flag_values=(0, 1, 2), flag_meanings="grows decays undetermined")

DUAL_SPIN = _schema(
    "dual_spin", "a gyrostat (dual-spin body) with a damper on its platform, in its rotor or "
    "both, over the inertia ratio and the rotor's speed: the nutation measured against its "
    "eigenvalue and the energy-sink criterion",
    "stability.dissipation.dual_spin.measure_dual_spin", {
        "placement": _coord("placement", _ONE, "where the dampers are: on the platform, in the "
                            "rotor, or one on each", kind="U"),
        "ratio": _coord("ratio", _ONE, "inertia ratio A3 / A_t (spin-axis moment over "
                        "transverse moment, rotor included)"),
        "speed": _coord("speed", _RAD_S, "the rotor's spin relative to the platform"),
        "start": _coord("start", _DEGREE, "nominal initial nutation angle"),
        "rate_measured": _var(_DS_MEMBER, _RATE, "growth rate of the nutation angle fitted in "
                              "the linear regime"),
        "rate_error": _var(_DS_MEMBER, _ONE, "measured / linear growth rate - 1"),
        "trend_measured": _var(_DS_MEMBER, _RATE, "slope of ln(nutation angle) over the linear "
                               "regime, however short"),
        "angular_momentum_drift": _var(_DS_MEMBER, _ONE, "largest relative change of |H| over "
                                       "the kept states"),
        "energy_rise": _var(_DS_MEMBER, _ONE, "largest rise of the energy between kept states, "
                            "relative to the start"),
        "end_angle": _var(_DS_MEMBER, _DEGREE, "nutation angle at the end"),
        "status": _status(_DS_MEMBER),
        "start_angle": _var(_DS_MEMBER, _DEGREE, "initial nutation angle (the nominal one, "
                            "lowered by the linear growth over the settling where it grows)"),
        "rate_linear": _var(_DS_CELL, _RATE, "growth rate of the nutation by the linear "
                            "eigenvalue"),
        "rate_energy_sink": _var(_DS_CELL, _RATE, "growth rate of the nutation by the "
                                 "energy-sink estimate"),
        "rate_first_order": _var(_DS_CELL, _RATE, "growth rate at first order in the damping, "
                                 "-(cp lambda_p + cq lambda_r) / h"),
        "rate_sink_error": _var(_DS_CELL, _ONE, "energy-sink / linear growth rate - 1"),
        "verdict_linear": _var(_DS_CELL, _ONE, "the nutation by the linear eigenvalue",
                               **_DS_VERDICT),
        "verdict_energy_sink": _var(_DS_CELL, _ONE, "the nutation by the energy-sink "
                                    "criterion D_p / lambda_p + D_r / lambda_r > 0",
                                    **_DS_VERDICT),
        "verdict_measured": _var(_DS_CELL, _ONE, "the nutation as measured (the sign of every "
                                 "member's trend)", **_DS_VERDICT),
        "c_platform": _var(_DS_CELL, "N m s", "viscous coefficient of the platform's damper "
                           "(0: none)"),
        "c_rotor": _var(_DS_CELL, "N m s", "viscous coefficient of the rotor's damper "
                        "(0: none)"),
        "settle_time": _var(_DS_CELL, _S, "time left to the dampers' faster modes before the "
                            "fit"),
        "step": _var(_DS_CELL, _S, "integration step h"),
        "t_end": _var(_DS_CELL, _S, "run time"),
        "axial_momentum": _var(("ratio", "speed"), cv.UNITS_ANGULAR_MOMENTUM,
                               "axial momentum of platform and rotor h = A3 w_p + Jr Omega"),
        "nutation_frequency_platform": _var(("ratio", "speed"), _RAD_S,
                                            "nutation frequency seen by the platform, "
                                            "lambda_p = h / A_t - w_p"),
        "nutation_frequency_rotor": _var(("ratio", "speed"), _RAD_S,
                                         "nutation frequency seen by the rotor, "
                                         "lambda_r = lambda_p - Omega"),
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


@dataclass(frozen=True)
class SceneSchema(DatasetSchema):
    """The Dataset kind of a run of any scene, whose variables are named from the scene.

    :attr:`variables` is the template: a name holding ``<component>``, ``<parameter>`` or
    ``<invariant>`` stands for one variable per state component, named parameter or
    invariant of the scene, with its units (``(its own)``: the component's or parameter's;
    ``(the tracked quantity's)``: those of what the scene's ``observe`` tracks). :meth:`of`
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
           invariants=(), tracked_units: str = _ONE) -> DatasetSchema:
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
        parameter_units = tuple(parameter_units) or (_ONE,) * len(parameters)
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
                               str(attrs.get("tracked_units", _ONE)))
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

SCENE_RUN = SceneSchema(
    "scene_run", "a run of any scene's members in groups, per member and per group",
    "stability.run_scene", "", {
        MEMBER: _member(),
        _GROUP: _coord(_GROUP, _ONE, "group of members (one parameter set, step and step "
                       "count)", kind="i"),
        TIME: _time_axis(optional=_SERIES),
        LEVEL: _coord(LEVEL, _ONE, "number of the tracked amplitude level", kind="i",
                      optional=_TRACKING),
        COMPONENT: _var((MEMBER, TIME), _OWN, f"{COMPONENT} (state component) at each saved "
                        "time", optional=_SERIES, comment=_COMPONENT_VALUE + "; NaN past the "
                        "end of a shorter group"),
        f"{COMPONENT}_start": _var(MEMBER, _OWN, f"{COMPONENT} (state component) at the "
                                   "start"),
        f"{COMPONENT}_final": _var(MEMBER, _OWN, f"{COMPONENT} (state component) at the end "
                                   "of the run", comment=_COMPONENT_VALUE),
        "member_group": _var(MEMBER, _ONE, "group of the member", kind="i"),
        "status": _status(MEMBER, comment=(
            "ok: the member's numbers can be trusted; non_finite: its state overflowed; "
            "not_converged: an implicit step's solver failed; derived numbers (drifts, "
            "tracked events) of members whose status is not ok are NaN")),
        "fail_time": _var(MEMBER, _S, "time at which the member's failure was detected",
                          comment="NaN for members whose status is ok"),
        "iterations": _var(MEMBER, _ONE, "nonlinear-solver iterations over the run (0 for "
                           "explicit methods)", kind="i"),
        f"{INVARIANT}_drift": _var(MEMBER, _ONE, f"relative drift of the invariant {INVARIANT} "
                                   "over the run, (I(end) - I(0)) / |I(0)|",
                                   optional="scenes that declare invariants",
                                   comment="NaN where the invariant is 0 at the start"),
        "axis_crossings": _var(MEMBER, _ONE, "sign changes of the tracked spin-axis quantity",
                               kind="i", optional=_TRACKING),
        "first_axis_crossing": _var(MEMBER, _S, "time of the first sign change of the tracked "
                                    "spin-axis quantity", optional=_TRACKING,
                                    comment="NaN where none happened"),
        "last_axis_crossing": _var(MEMBER, _S, "time of the last sign change of the tracked "
                                   "spin-axis quantity", optional=_TRACKING),
        "perp_crossings": _var(MEMBER, _ONE, "sign changes of the first tracked quantity "
                               "across the spin axis", kind="i", optional=_TRACKING),
        "first_perp_crossing": _var(MEMBER, _S, "time of the first sign change of the first "
                                    "tracked quantity across the spin axis",
                                    optional=_TRACKING),
        "last_perp_crossing": _var(MEMBER, _S, "time of the last sign change of the first "
                                   "tracked quantity across the spin axis", optional=_TRACKING),
        "max_perp_amplitude": _var(MEMBER, _TRACKED_UNITS, "largest amplitude across the spin "
                                   "axis, sqrt(b^2 + c^2) of the tracked quantities",
                                   optional=_TRACKING),
        "passage_time": _var((MEMBER, LEVEL), _S, "first time the amplitude across the spin "
                             "axis reaches the level", optional=_TRACKING,
                             comment="NaN where the level was never reached; 0 where the "
                                     "start is above it"),
        "members": _var(_GROUP, _ONE, "members of the group", kind="i"),
        "h": _var(_GROUP, _S, "integration step h"),
        "n_steps": _var(_GROUP, _ONE, "steps of the run", kind="i"),
        PARAMETER: _var(_GROUP, _OWN, f"parameter {PARAMETER} of the group",
                        optional=_PARAMETERS_NAMED),
        "parameters": _var((_GROUP, "parameter"), _ONE, "the group's parameter set, as the "
                           "scene's methods take it", optional="scenes that do not name their "
                           "parameters", comment="in the scene's own units"),
        "tracked_components": _var((_GROUP, _TRACK), _ONE, "state components the tracking "
                                   "reads (spin axis, then the two across it), numbered from 0",
                                   kind="i", optional=_TRACKING),
        "levels": _var((_GROUP, LEVEL), _TRACKED_UNITS, "amplitude levels of the passage times",
                       optional=_TRACKING),
    }, note=(
        "Its variables are named from the scene: a name holding `<component>` stands for one "
        "variable per state component (its units the component's), `<parameter>` one per "
        "named parameter, `<invariant>` one per invariant the scene declares; the amplitude "
        "and levels are in the units of what the scene tracks (`tracked_units`). The global "
        "attributes `scene_components`, `scene_units`, `scene_parameters`, "
        "`scene_parameter_units` and `scene_invariants` record what the scene declared, and "
        "`stability.ensemble.schema.SCENE_RUN.of(...)` gives one scene's declaration"))


#: Every Dataset kind, by name: the free body's ensemble, each study kind's Dataset and a run of
#: any scene's.
SCHEMAS: Mapping[str, DatasetSchema] = MappingProxyType({s.name: s for s in (
    ENSEMBLE, TRAJECTORY, TENNIS_RACKET, TWISTING_RACKET, ENGINE_ARTEFACTS, STABILITY_MAP,
    WORK_PRECISION, EARTH_WOBBLE, EQUINOXES, GYROSCOPE, SLEEPING_TOP, BAT, ROLLING, EXPLORER,
    DUAL_SPIN, SCENE_RUN,
)})


def _time_dims(s: DatasetSchema) -> set:
    """The dims of ``s`` whose coordinate is a CF time axis."""
    return {name for name, var in s.variables.items()
            if var.coordinate and var.dims == (name,) and ("standard_name", "time") in var.extra}


def _file_orders() -> dict:
    """``{(name, frozenset(dims)): (held dims, file dims)}`` for each declared variable that a
    file holds in another order than the Dataset: CF 2.4 wants the time dimension right of
    every other, where the package keeps each member's samples of one instant together
    (``w`` (member, time, axis) is written (member, axis, time))."""
    orders = {}
    for s in SCHEMAS.values():
        time = _time_dims(s)
        for name, var in s.variables.items():
            file = tuple(d for d in var.dims if d not in time) + tuple(
                d for d in var.dims if d in time)
            if file != var.dims:
                orders[(name, frozenset(var.dims))] = (var.dims, file)
    return orders


_FILE_ORDERS = _file_orders()


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
    changes = {}
    for name, var in ds.variables.items():
        orders = _FILE_ORDERS.get((name, frozenset(var.dims)))
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


__all__ = ["DatasetSchema", "ESTIMATES", "KINDS", "LEVEL", "SCENE_RUN", "SCHEMAS", "SceneSchema",
           "Variable", "file_order", "held_order", "schema"]
