"""The declarations of the dissipation family's Datasets: the Explorer-1 study and the dual-spin
map, registered from the family's ``DATASETS`` (:mod:`stability.registry`)."""

from ..util import conventions as cv
from ..ensemble.schema import (
    DEGREE, ONE, PER_SECOND, RAD_PER_S, SECOND, coordinate, declare, status_variable, variable,
)

__all__ = ["EXPLORER", "DUAL_SPIN"]


EXPLORER = declare(
    "explorer",
    "an Explorer-1-like body with an energy sink spun about its minor axis: "
    "nutation growth against the linear eigenvalue, the flat spin it ends in, the energy lost",
    "stability.dissipation.measure.measure_explorer",
    {
        'damping': coordinate('damping', '1', "damping c over the energy sink's optimum c*"),
        'angle': coordinate('angle', 'degree', 'initial nutation angle'),
        'whip_angle': coordinate(
            'whip_angle', 'degree', "initial nutation angle of the whip antennas' members"
        ),
        'growth_rate_measured': variable(
            ('damping', 'angle'),
            's-1',
            'growth rate of the nutation angle fitted in the linear regime',
        ),
        'growth_rate_linear': variable(
            ('damping', 'angle'), 's-1', 'growth rate of the nutation by the linear eigenvalue'
        ),
        'growth_rate_error': variable(
            ('damping', 'angle'), '1', 'measured / linear growth rate - 1'
        ),
        'decay_rate_measured': variable(
            ('damping', 'angle'), 's-1', 'rate of |cos theta| about the major axis, fitted'
        ),
        'decay_rate_linear': variable(
            ('damping', 'angle'),
            's-1',
            'rate of the departure from the major axis by the linear eigenvalue',
        ),
        'decay_rate_error': variable(('damping', 'angle'), '1', 'measured / linear decay rate - 1'),
        'flat_time': variable(
            ('damping', 'angle'),
            's',
            'time to the flat spin (nutation angle passing the flat-spin angle)',
        ),
        'flat_time_linear': variable(
            ('damping', 'angle'),
            's',
            'time to the flat spin at the linear growth rate, tan(theta) = tan(theta0) exp(rate t)',
        ),
        'angular_momentum_drift': variable(
            ('damping', 'angle'), '1', 'largest relative change of |H| over the kept states'
        ),
        'energy_rise': variable(
            ('damping', 'angle'),
            '1',
            'largest rise of the energy between kept states, relative to the start',
        ),
        'end_angle': variable(('damping', 'angle'), 'degree', 'nutation angle at the end'),
        'energy_lost': variable(('damping', 'angle'), 'J', 'energy lost, start to end'),
        'energy_lost_formula': variable(('damping', 'angle'), 'J', '|H|^2 / 2 (1/A_min - 1/A_max)'),
        'energy_lost_error': variable(('damping', 'angle'), '1', 'energy lost / formula - 1'),
        'end_energy_error': variable(
            ('damping', 'angle'), '1', 'end energy / (|H|^2 / (2 A_max)) - 1'
        ),
        'flat_energy_ratio': variable(
            ('damping', 'angle'), '1', "energy of the flat spin |H|^2 / (2 A_max) over the start's"
        ),
        'status': status_variable(('damping', 'angle')),
        'theta': variable(
            ('damping', 'angle', 'sample'), 'degree', 'nutation angle between the long axis and H'
        ),
        'energy_ratio': variable(('damping', 'angle', 'sample'), '1', 'energy over its start'),
        'sample_time': variable(('damping', 'sample'), 's', 'time of the kept states'),
        'c': variable('damping', 'N m s', 'viscous coefficient of the spherical damper'),
        'step': variable('damping', 's', 'integration step h'),
        't_end': variable('damping', 's', 'run time'),
        'growth_rate_energy_sink': variable(
            ('damping', 'angle'), 's-1', 'growth rate of the nutation by the energy-sink estimate'
        ),
        'major_axis_end': variable(
            ('damping', 'angle'),
            '1',
            'ends spinning about the major axis (1) or not (0)',
            kind='i',
            flag_values=(0, 1),
            flag_meanings='other_axis major_axis',
        ),
        'whip_growth_rate_measured': variable(
            'whip_angle',
            's-1',
            'whip antennas: growth rate of the nutation angle fitted in the linear regime',
        ),
        'whip_growth_rate_linear': variable(
            'whip_angle',
            's-1',
            'whip antennas: growth rate of the nutation by the linear eigenvalue',
        ),
        'whip_growth_rate_error': variable(
            'whip_angle', '1', 'whip antennas: measured / linear growth rate - 1'
        ),
        'whip_flat_time': variable(
            'whip_angle',
            's',
            'whip antennas: time to the flat spin (nutation angle passing the flat-spin angle)',
        ),
        'whip_flat_time_linear': variable(
            'whip_angle',
            's',
            'whip antennas: time to the flat spin at the linear growth rate, tan(theta) = '
            'tan(theta0) exp(rate t)',
        ),
        'whip_angular_momentum_drift': variable(
            'whip_angle', '1', 'whip antennas: largest relative change of |H| over the kept states'
        ),
        'whip_energy_rise': variable(
            'whip_angle',
            '1',
            'whip antennas: largest rise of the energy between kept states, relative to the start',
        ),
        'whip_end_angle': variable(
            'whip_angle', 'degree', 'whip antennas: nutation angle at the end'
        ),
        'whip_energy_lost': variable('whip_angle', 'J', 'whip antennas: energy lost, start to end'),
        'whip_energy_lost_formula': variable(
            'whip_angle', 'J', 'whip antennas: |H|^2 / 2 (1/A_min - 1/A_max)'
        ),
        'whip_energy_lost_error': variable(
            'whip_angle', '1', 'whip antennas: energy lost / formula - 1'
        ),
        'whip_end_energy_error': variable(
            'whip_angle', '1', 'whip antennas: end energy / (|H|^2 / (2 A_max)) - 1'
        ),
        'whip_status': status_variable('whip_angle', 'whip antennas: member status'),
        'whip_major_axis_end': variable(
            'whip_angle',
            '1',
            'whip antennas: ends spinning about the major axis (1) or not (0)',
            kind='i',
            flag_values=(0, 1),
            flag_meanings='other_axis major_axis',
        ),
        'whip_theta': variable(
            ('whip_angle', 'whip_sample'),
            'degree',
            'whip antennas: nutation angle between the long axis and H',
        ),
        'whip_sample_time': variable('whip_sample', 's', 'whip antennas: time of the kept states'),
        'whip_energy_ratio': variable(
            ('whip_angle', 'whip_sample'), '1', 'whip antennas: energy over its start'
        ),
    },
)

_DS_CELL = ("placement", "ratio", "speed")
_DS_MEMBER = ("placement", "ratio", "speed", "start")
_DS_VERDICT = dict(kind="i", flag_values=(0, 1, 2), flag_meanings="grows decays undetermined")

DUAL_SPIN = declare(
    "dual_spin",
    "a gyrostat (dual-spin body) with a damper on its platform, in its rotor or "
    "both, over the inertia ratio and the rotor's speed: the nutation measured against its "
    "eigenvalue and the energy-sink criterion",
    "stability.dissipation.measure_gyrostat.measure_dual_spin",
    {
        "placement": coordinate(
            "placement",
            ONE,
            "where the dampers are: on the platform, in the rotor, or one on each",
            kind="U",
        ),
        "ratio": coordinate(
            "ratio",
            ONE,
            "inertia ratio A3 / A_t (spin-axis moment over transverse moment, rotor included)",
        ),
        "speed": coordinate("speed", RAD_PER_S, "the rotor's spin relative to the platform"),
        "start": coordinate("start", DEGREE, "nominal initial nutation angle"),
        "rate_measured": variable(
            _DS_MEMBER, PER_SECOND, "growth rate of the nutation angle fitted in the linear regime"
        ),
        "rate_error": variable(_DS_MEMBER, ONE, "measured / linear growth rate - 1"),
        "trend_measured": variable(
            _DS_MEMBER,
            PER_SECOND,
            "slope of ln(nutation angle) over the linear regime, however short",
        ),
        "angular_momentum_drift": variable(
            _DS_MEMBER, ONE, "largest relative change of |H| over the kept states"
        ),
        "energy_rise": variable(
            _DS_MEMBER, ONE, "largest rise of the energy between kept states, relative to the start"
        ),
        "end_angle": variable(_DS_MEMBER, DEGREE, "nutation angle at the end"),
        "status": status_variable(_DS_MEMBER),
        "start_angle": variable(
            _DS_MEMBER,
            DEGREE,
            "initial nutation angle (the nominal one, "
            "lowered by the linear growth over the settling where it grows)",
        ),
        "rate_linear": variable(
            _DS_CELL, PER_SECOND, "growth rate of the nutation by the linear eigenvalue"
        ),
        "rate_energy_sink": variable(
            _DS_CELL, PER_SECOND, "growth rate of the nutation by the energy-sink estimate"
        ),
        "rate_first_order": variable(
            _DS_CELL,
            PER_SECOND,
            "growth rate at first order in the damping, -(cp lambda_p + cq lambda_r) / h",
        ),
        "rate_sink_error": variable(_DS_CELL, ONE, "energy-sink / linear growth rate - 1"),
        "verdict_linear": variable(
            _DS_CELL, ONE, "the nutation by the linear eigenvalue", **_DS_VERDICT
        ),
        "verdict_energy_sink": variable(
            _DS_CELL,
            ONE,
            "the nutation by the energy-sink criterion D_p / lambda_p + D_r / lambda_r > 0",
            **_DS_VERDICT,
        ),
        "verdict_measured": variable(
            _DS_CELL,
            ONE,
            "the nutation as measured (the sign of every member's trend)",
            **_DS_VERDICT,
        ),
        "c_platform": variable(
            _DS_CELL, "N m s", "viscous coefficient of the platform's damper (0: none)"
        ),
        "c_rotor": variable(
            _DS_CELL, "N m s", "viscous coefficient of the rotor's damper (0: none)"
        ),
        "settle_time": variable(
            _DS_CELL, SECOND, "time left to the dampers' faster modes before the fit"
        ),
        "step": variable(_DS_CELL, SECOND, "integration step h"),
        "t_end": variable(_DS_CELL, SECOND, "run time"),
        "axial_momentum": variable(
            ("ratio", "speed"),
            cv.UNITS_ANGULAR_MOMENTUM,
            "axial momentum of platform and rotor h = A3 w_p + Jr Omega",
        ),
        "nutation_frequency_platform": variable(
            ("ratio", "speed"),
            RAD_PER_S,
            "nutation frequency seen by the platform, lambda_p = h / A_t - w_p",
        ),
        "nutation_frequency_rotor": variable(
            ("ratio", "speed"),
            RAD_PER_S,
            "nutation frequency seen by the rotor, lambda_r = lambda_p - Omega",
        ),
    },
)
