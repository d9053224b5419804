"""The declarations of the free body's Datasets: one trajectory, the tennis racket's ensemble, the
stability map, the work-precision study and the twisting racket, registered from the family's
``DATASETS`` (:mod:`stability.registry`)."""

from dataclasses import replace

from ..util import conventions as cv
from ..ensemble.schema import (
    ATTITUDE_NOTE, AXIS, ENSEMBLE, ESTIMATES, KG_M2, LEVEL, MEMBER, ONE, PER_SECOND, PER_SECOND2,
    QUATERNION, RADIAN, RAD_PER_S, RAD_PER_S2, SECOND, TIME, Variable, coordinate, declare,
    member_coordinate, status_variable, time_coordinate, variable,
)

__all__ = ["TRAJECTORY", "TENNIS_RACKET", "STABILITY_MAP", "FTLE_MAP", "WORK_PRECISION",
           "TWISTING_RACKET", "FLIP_SENSITIVITY"]


# One trajectory (stability.integrate)
# ----------------------------------------------------------------

TRAJECTORY = declare(
    "trajectory",
    "one free rigid body's motion, sample by sample",
    "stability.integrate",
    file="",
    variables={
        TIME: time_coordinate("time"),
        AXIS: ENSEMBLE[AXIS],
        "w": ENSEMBLE["w"].on((TIME, AXIS), optional=""),
        QUATERNION: ENSEMBLE[QUATERNION],
        "q": ENSEMBLE["q"].on(
            (TIME, QUATERNION),
            optional=ATTITUDE_NOTE,
            extra=(
                ("comment", "R(q) maps body components to space components; q' = q (0, w) / 2"),
            ),
        ),
        "q_norm_error": ENSEMBLE["q_norm_error"].on((TIME,)),
    },
)

# The tennis racket: the ensemble, its exact answers and amplitude quantiles -------------------

_AMPLITUDE_BIN, SERIES_MEMBER = "amplitude_bin", cv.SERIES_MEMBER
_QUANTILE = "{quantile} over ok members of the amplitude perpendicular to axis {axis}"
TENNIS_RACKET = ENSEMBLE.extend(
    "tennis_racket",
    "the tennis-racket ensemble with its exact flip intervals and the "
    "quantiles of its perpendicular amplitude",
    "stability.free_body.tennis_racket.measure.finish_analysis",
    "tennis_racket.nc",
    {
        "exact_flip_interval": variable(
            MEMBER, SECOND, "exact flip interval 2K(k)/nu of the member's start"
        ),
        "flip_interval_asymptote": variable(
            MEMBER, SECOND, "small-perturbation asymptote (2/lambda) ln(4/k') of the flip interval"
        ),
        "complementary_modulus": variable(
            MEMBER, ONE, "complementary modulus k' of the member's Jacobi functions"
        ),
        "member_growth_rate": variable(
            MEMBER, PER_SECOND, "growth rate of the member's perpendicular amplitude fitted "
            "over its linear phase", comment=(
                "the slope of ln sqrt(w_b^2 + w_c^2) against time over the window "
                "[growth_window_low_factor x its start, growth_window_high_fraction x "
                "min(spin, saturation)); NaN where the member's departure is not exponential "
                "(stability.measured_growth_rate, member by member)")),
        "attitude_error_max": variable(
            MEMBER, RADIAN, "largest angle of the rotation from the exact attitude over the run",
            optional=ATTITUDE_NOTE),
        SERIES_MEMBER: member_coordinate("ensemble member whose time series is kept",
                                         dim=SERIES_MEMBER),
        _AMPLITUDE_BIN: coordinate(_AMPLITUDE_BIN, RAD_PER_S,
                                   "perpendicular amplitude at the geometric centre of the bin"),
        "amplitude_bin_bounds": variable(
            (_AMPLITUDE_BIN, "bound"), RAD_PER_S, "edges of the perpendicular-amplitude bins",
            comment="lower and upper edge; the bins are log-spaced, 0.002 decades wide"),
        "perp_amplitude_count": variable(
            (TIME, _AMPLITUDE_BIN), ONE, "ok members whose amplitude perpendicular to axis "
            "{axis} lies in the bin", kind="i", comment=(
                "log-spaced bins; the quantiles perp_amplitude_p10, _median and _p90 are "
                "taken from these counts, within one bin of the exact ones")),
        "perp_amplitude_p10": variable(TIME, RAD_PER_S, _QUANTILE),
        "perp_amplitude_median": variable(TIME, RAD_PER_S, _QUANTILE),
        "perp_amplitude_p90": variable(TIME, RAD_PER_S, _QUANTILE),
    },
    **{name: replace(ENSEMBLE[name], optional="") for name in (TIME,)},
    **{name: replace(ENSEMBLE[name].on((SERIES_MEMBER,) + ENSEMBLE[name].dims[1:]),
                     optional=ENSEMBLE[name].optional or "")
       for name in ("w", "q", "q_norm_error", "attitude_error")},
)

# The stability map (stability.free_body.stability_map.measure.map_dataset)
# ---------------------------------------

_MSA = ("integrator", "shape", AXIS)
_EDGE_CASE, _EDGE_TIME, _FLIP_SHAPE = "edge_case", "edge_time", "flip_shape"
_NORMALISED = "principal moment I{i}, normalised so that I3 = 1"


def _moment(dim, i) -> Variable:
    return coordinate(dim, KG_M2, _NORMALISED.format(i=i))


STABILITY_MAP = declare(
    "stability_map",
    "Omega^2 measured against linear theory over the triangle of shapes, "
    "per integrator, shape and spin axis; the flip-interval sweep and the edge cases",
    "stability.free_body.stability_map.measure.map_dataset",
    {
        "omega_squared": variable(
            ("shape", AXIS), PER_SECOND2, "analytic Omega^2 = (Ia - Ib)(Ia - Ic) W^2 / (Ib Ic)"
        ),
        "omega_squared_normalised": variable(("shape", AXIS), ONE, "analytic Omega^2 / W^2"),
        "t_end": variable(("shape", AXIS), SECOND, "run length of the ensemble"),
        "edge": variable(
            "shape",
            ONE,
            "triangle edges the shape lies on",
            kind="i",
            flag_masks=cv.EDGE_FLAG_MASKS,
            flag_meanings=cv.EDGE_MEANINGS,
        ),
        "regime": ESTIMATES["regime"].on(_MSA),
        "sign_agrees": ESTIMATES["sign_agrees"].on(
            _MSA, extra=(("flag_values", (0, 1)), ("flag_meanings", "no yes"))
        ),
        "status": status_variable(_MSA, "worst member status of the ensemble"),
        "members_failed": variable(
            _MSA, ONE, "members whose status is not ok (left out of the estimates)", kind="i"
        ),
        "energy_error_max": variable(
            _MSA, ONE, "largest relative kinetic-energy error at the end over members"
        ),
        "first_flip_time_relative_error": variable(
            _MSA,
            ONE,
            "mean relative difference of the "
            "first-flip time from the exact flow's, member "
            "by member",
        ),
        "omega_squared_measured_half_step": variable(
            _MSA, PER_SECOND2, "measured Omega^2 at step h / 2 (bias check)"
        ),
        "regime_half_step": ESTIMATES["regime"].on(
            _MSA, long_name="regime at step h / 2 (bias check)"
        ),
        "step_bias": variable(
            _MSA,
            ONE,
            "Richardson estimate of the method's relative O(h^p) "
            "bias in Omega^2 at step h, (X(h) - X(h/2)) / (1 - 2^-p) / "
            "|Omega^2|",
        ),
        **{
            name: ESTIMATES[name].on(_MSA)
            for name in (
                "omega_squared_measured",
                "omega_squared_measured_stderr",
                "relative_error",
                "growth_rate",
                "growth_rate_stderr",
                "oscillation_frequency",
                "oscillation_frequency_stderr",
                "drift_rate",
                "n_fitted",
                "n_flips_mean",
                "first_flip_time_mean",
                "first_flip_time_stderr",
                "flip_interval_mean",
                "flip_interval_stderr",
                "flip_interval_exact_mean",
                "flip_interval_asymptote_mean",
                "flip_interval_relative_error",
                "flip_interval_relative_error_stderr",
            )
        },
        "sweep_flip_interval": variable(
            ("integrator", _FLIP_SHAPE, "epsilon"),
            SECOND,
            "measured flip interval, perturbation epsilon along axis 1",
        ),
        "sweep_flip_interval_exact": variable(
            (_FLIP_SHAPE, "epsilon"), SECOND, "exact flip interval 2K/nu"
        ),
        "sweep_flip_interval_asymptote": variable(
            (_FLIP_SHAPE, "epsilon"), SECOND, "asymptotic flip interval (2/lambda) ln(4/k')"
        ),
        "sweep_growth_rate": variable(
            _FLIP_SHAPE, PER_SECOND, "analytic growth rate lambda about axis 2"
        ),
        "edge_w": variable(
            (_EDGE_CASE, _EDGE_TIME, AXIS), RAD_PER_S, "body-frame angular velocity on an edge case"
        ),
        "edge_slope_predicted": variable(
            _EDGE_CASE,
            RAD_PER_S2,
            "initial rate of change of the drifting component (Euler's equations)",
        ),
        "edge_slope_measured": variable(
            _EDGE_CASE, RAD_PER_S2, "least-squares slope of the drifting component"
        ),
        "edge_distinct_change": variable(
            _EDGE_CASE, RAD_PER_S, "largest change of the component along the distinct axis"
        ),
        "edge_flips": variable(_EDGE_CASE, ONE, "sign changes of the spin component", kind="i"),
        "edge_regime": ESTIMATES["regime"].on((_EDGE_CASE,)),
        "edge_linear_residual": variable(
            _EDGE_CASE, ONE, "rms relative misfit of a straight line to the amplitude"
        ),
        "edge_exponential_residual": variable(
            _EDGE_CASE, ONE, "rms misfit of an exponential to the amplitude"
        ),
        "integrator": coordinate("integrator", ONE, "integrator", kind="U"),
        "h": coordinate("integrator", SECOND, "step"),
        "method_order": coordinate("integrator", ONE, "order of the method (inf: exact flow)"),
        "shape": coordinate("shape", ONE, "shape index", kind="i"),
        "I1": _moment("shape", 1),
        "I2": _moment("shape", 2),
        "I3": _moment("shape", 3),
        AXIS: coordinate(AXIS, ONE, "principal axis of the spin", kind="i"),
        LEVEL: coordinate(LEVEL, RAD_PER_S, "perpendicular amplitude level of the passage times"),
        _FLIP_SHAPE: coordinate(_FLIP_SHAPE, ONE, "flip sweep shape index", kind="i"),
        "flip_I1": _moment(_FLIP_SHAPE, 1),
        "flip_I2": _moment(_FLIP_SHAPE, 2),
        "epsilon": coordinate("epsilon", ONE, "perturbation relative to the spin"),
        _EDGE_CASE: coordinate(_EDGE_CASE, ONE, "edge case", kind="U"),
        "edge_I1": _moment(_EDGE_CASE, 1),
        "edge_I2": _moment(_EDGE_CASE, 2),
        "edge_I3": _moment(_EDGE_CASE, 3),
        "edge_axis": coordinate(_EDGE_CASE, ONE, "spin axis of the edge case", kind="i"),
        _EDGE_TIME: coordinate(_EDGE_TIME, SECOND, "time since the start"),
    },
)

# The stability map from tangents (stability.free_body.stability_map.ftle_map)
# ----------------------------------------------------------------

_RATIO_GRID = ("I2", "I1")
_OUTSIDE = "NaN outside the triangle of real bodies"

FTLE_MAP = declare(
    "ftle_map",
    "finite-time Lyapunov exponents of spin about one axis over a grid of inertia ratios, "
    "beside the analytic growth rate",
    "stability.free_body.stability_map.ftle_map.ftle_map",
    {
        "I1": coordinate("I1", ONE, "principal moment ratio I1 / I3 (cell centre)"),
        "I2": coordinate("I2", ONE, "principal moment ratio I2 / I3 (cell centre)"),
        "ftle": variable(_RATIO_GRID, PER_SECOND, "finite-time Lyapunov exponent over the "
                         "horizon, log sigma_max(Phi(T)) / T, mean over the cell's members",
                         comment=_OUTSIDE),
        "ftle_spread": variable(_RATIO_GRID, PER_SECOND, "largest minus smallest member FTLE "
                                "of the cell", comment=_OUTSIDE),
        "growth_rate_analytic": variable(_RATIO_GRID, PER_SECOND, "analytic growth rate "
                                         "sqrt(max(-Omega^2, 0))", comment=_OUTSIDE),
        "omega_squared": variable(_RATIO_GRID, PER_SECOND2, "analytic Omega^2 = (Ia - Ib)"
                                  "(Ia - Ic) W^2 / (Ib Ic)", comment=_OUTSIDE),
        "eigenvector_aspect": variable(_RATIO_GRID, ONE, "aspect ratio rho >= 1 of the "
                                       "linearisation's eigenvectors across the axis",
                                       comment=_OUTSIDE),
        "physical": variable(_RATIO_GRID, ONE, "the cell centre is a real body "
                             "(I1 <= I2 <= I3 <= I1 + I2)", kind="i", flag_values=(0, 1),
                             flag_meanings="no yes"),
    },
)

#: The FTLE map's names in the stability map study's Dataset (``[ftle] run = true``).
FTLE_IN_MAP = {"I1": "ftle_I1", "I2": "ftle_I2", "ftle": "ftle", "ftle_spread": "ftle_spread",
               "growth_rate_analytic": "ftle_growth_rate_analytic",
               "omega_squared": "ftle_omega_squared",
               "eigenvector_aspect": "ftle_eigenvector_aspect", "physical": "ftle_physical"}
_FTLE_NOTE = "maps with the FTLE ([ftle] run = true)"
STABILITY_MAP = STABILITY_MAP.extend(
    STABILITY_MAP.name, STABILITY_MAP.title, STABILITY_MAP.written_by, STABILITY_MAP.file,
    {FTLE_IN_MAP[name]: replace(var, dims=tuple(FTLE_IN_MAP.get(d, d) for d in var.dims),
                                optional=_FTLE_NOTE)
     for name, var in FTLE_MAP.variables.items()})

# The work-precision study (stability.free_body.work_precision.measure)
# -------------------------------------------

_WMS = ("workload", "method", "sweep")
_WMSM = _WMS + ("metric",)
WORK_PRECISION = declare(
    "work_precision",
    "speed against error of every integrator, per workload, method and "
    "step; the long-horizon drift of the invariants",
    "stability.free_body.work_precision.measure.work_precision_dataset",
    {
        "w_error": variable(
            _WMSM, ONE, "relative error of w at the end, |w - w_exact| / |w_exact|"
        ),
        "energy_error": variable(
            _WMSM, ONE, "relative kinetic-energy error at the end, |E / E0 - 1|"
        ),
        "momentum_error": variable(
            _WMSM, ONE, "relative angular-momentum error at the end, | |L| / |L0| - 1 |"
        ),
        "attitude_error": variable(
            _WMSM,
            RADIAN,
            "attitude error at the end: angle of the rotation "
            "from the reference attitude (DOP853) to the method's, over the "
            "first [attitude] members",
        ),
        "wall_time": variable(
            _WMS, SECOND, "kernel wall time for the whole ensemble (compilation excluded)"
        ),
        "member_step_time": variable(_WMS, SECOND, "wall time per member and step"),
        "steps": variable(_WMS, ONE, "steps per member"),
        "evaluations": variable(
            _WMS, ONE, "right-hand-side evaluations or exact sub-flows per member"
        ),
        "iterations": variable(
            _WMS, ONE, "nonlinear-solver iterations per step, mean over members"
        ),
        "failed": variable(_WMS, ONE, "members flagged non-finite, diverged or not converged"),
        "floor": variable(
            ("workload", "metric"),
            ONE,
            "conditioning floor: relative change of "
            "the exact w(T) when D2 of the start moves by one rounding",
        ),
        "drift_energy": variable(
            ("method", "long_time"), ONE, "RMS over members of the relative energy error E / E0 - 1"
        ),
        "drift_momentum": variable(
            ("method", "long_time"), ONE, "RMS over members of the relative |L| error"
        ),
        "drift_slope": variable(
            "method",
            ONE,
            "log-log slope of the energy error's running "
            "maximum over the last two decades of the long run (0 bounded, 1/2 "
            "round-off random walk, 1 drift)",
        ),
        "workload": coordinate("workload", ONE, "workload", kind="U"),
        "method": coordinate("method", ONE, "integrator (registry name; dop853: scipy)", kind="U"),
        "sweep": coordinate("sweep", ONE, "index in the step-size or tolerance sweep", kind="i"),
        "metric": coordinate("metric", ONE, "statistic over members", kind="U"),
        "long_time": coordinate("long_time", SECOND, "time in the long-horizon run"),
        "h": coordinate(_WMS, SECOND, "step size"),
        "rtol": coordinate(_WMS, ONE, "scipy relative tolerance"),
        "order": coordinate("method", ONE, "declared order (dopri5: 5, dop853: 8; both adaptive)"),
        "attitude_reference_error": variable(
            ("workload", "metric"),
            ONE,
            "relative w error of the "
            "attitude reference (DOP853, rtol = atol = 1e-13) "
            "against the exact solution",
        ),
    },
)

# The twisting racket (stability.free_body.twisting_racket.measure.measure_twisting)
# ------------------------------------

TWISTING_RACKET = declare(
    "twisting_racket",
    "Montgomery's angle and the twist of tossed bodies, per member, from "
    "the run and from the exact motion",
    "stability.free_body.twisting_racket.measure.measure_twisting",
    {
        "moments": variable(
            (MEMBER, AXIS), KG_M2, "principal moments, ascending (canonical frame)"
        ),
        "w0": variable((MEMBER, AXIS), RAD_PER_S, "initial angular velocity, canonical frame"),
        "epsilon": variable(MEMBER, ONE, "nudge across the middle axis relative to the spin"),
        "status": status_variable(MEMBER, "member status of the run"),
        "period": variable(MEMBER, SECOND, "period T of the body motion, 4 K / nu"),
        "montgomery_run": variable(
            MEMBER, RADIAN, "Montgomery's angle from the run: R(T) R(0)^T about L"
        ),
        "montgomery_exact": variable(
            MEMBER, RADIAN, "Montgomery's angle from the exact attitude, phi(T)"
        ),
        "montgomery_formula": variable(
            MEMBER, RADIAN, "Montgomery's angle from the formula, 2 E T / |L| - S (mod 2 pi)"
        ),
        "dynamic_phase": variable(MEMBER, RADIAN, "dynamic phase 2 E T / |L|"),
        "solid_angle": variable(
            MEMBER, "sr", "oriented solid angle S enclosed by m / |m| in the body frame"
        ),
        "montgomery_error": variable(
            MEMBER, RADIAN, "|run - formula| of Montgomery's angle (mod 2 pi)"
        ),
        "flip_time_run": variable(MEMBER, SECOND, "flip (m2 = 0) nearest T, from the run"),
        "flip_time_exact": variable(MEMBER, SECOND, "flip (m2 = 0) nearest T, exact"),
        "half_window_run": variable(
            MEMBER, SECOND, "half the window about the flip in which phi advances 2 pi, run"
        ),
        "half_window_exact": variable(
            MEMBER, SECOND, "half the window about the flip in which phi advances 2 pi, exact"
        ),
        "twist_run": variable(
            MEMBER, RADIAN, "twist: change of psi = atan2(m2, m3) over the window, run"
        ),
        "twist_exact": variable(
            MEMBER, RADIAN, "twist: change of psi = atan2(m2, m3) over the window, exact"
        ),
        "twist_error": variable(MEMBER, RADIAN, "|run - exact| of the twist"),
        "twist_defect": variable(
            MEMBER, RADIAN, "defect of the twist from a half turn, pi - |twist|"
        ),
        "snapshot_time": variable("snapshot", SECOND, "instants across member 0's twist window"),
        "snapshot_q": variable(
            ("snapshot", QUATERNION), ONE, "member 0's exact attitude, body (canonical) to space"
        ),
        MEMBER: ENSEMBLE[MEMBER],
        AXIS: ENSEMBLE[AXIS],
        QUATERNION: replace(ENSEMBLE[QUATERNION], optional=""),
    },
)


# The first flip's sensitivities (stability.free_body.flip_sensitivity.flip_sensitivities)
# --------------------------------

FLIP_SENSITIVITY = declare(
    "flip_sensitivity",
    "first flip times of free bodies spun near their middle axis, and their derivatives with "
    "respect to the moments and the start, by the tangent of the computed RK4 map",
    "stability.free_body.flip_sensitivity.flip_sensitivities",
    {
        MEMBER: member_coordinate(),
        AXIS: coordinate(AXIS, ONE, "principal axis of the body", kind="i"),
        "moments": variable((MEMBER, AXIS), KG_M2, "principal moments, ascending"),
        "w0": variable((MEMBER, AXIS), RAD_PER_S, "initial angular velocity"),
        "step": variable(MEMBER, SECOND, "RK4 step h"),
        "flip_time": variable(MEMBER, SECOND, "time of the first sign change of the middle "
                              "component (the root of its cubic Hermite interpolant over the "
                              "step)"),
        "dflip_dmoments": variable((MEMBER, AXIS), "s kg-1 m-2", "derivative of the first flip "
                                   "time with respect to each moment at a fixed w0"),
        "dflip_dw0": variable((MEMBER, AXIS), "s2", "derivative of the first flip time with "
                              "respect to each component of w0"),
    },
    file="",
)
