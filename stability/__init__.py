"""stability: Monte Carlo studies of rigid-body rotation.

Notation, used everywhere in the package:

- Principal moments of inertia ``I1, I2, I3`` (kg m^2) about body axes 1, 2, 3. Kernels work in
  a canonical frame where ``I1 <= I2 <= I3`` (axis 2 intermediate); the public API takes the
  axes in the order the user gives them.
- ``w`` = (w1, w2, w3): body-frame angular velocity (rad/s); ``m = I w``: body angular momentum
  (kg m^2/s); ``L = |m|``; kinetic energy ``E = (I1 w1^2 + I2 w2^2 + I3 w3^2) / 2`` (J).
- ``R``: attitude, the body-to-space rotation; ``h``: step size (s).
- Euler's equations, torque-free: ``I1 w1' = (I2 - I3) w2 w3`` and cyclic, i.e. ``m' = m x w``.
- Steady spin ``W`` about axis 3, linearised: ``w1'' = -Omega^2 w1`` with
  ``Omega^2 = (I3 - I1)(I3 - I2) W^2 / (I1 I2)``: > 0 (oscillation) for the largest or smallest
  axis, < 0 (growth at rate ``sqrt(-Omega^2)``) for the intermediate one.
"""

import importlib

from .util import numba_env  # noqa: F401  (first: readies Numba's environment, see there)
from .version import __version__
from .free_body.model import axis_stability, growth_rate, omega_squared, oscillation_frequency
from .core.body import Part, RigidBody
from .free_body.exact import exact_omega, flip_interval, full_period
from .free_body.integrate import integrate
from .free_body.methods import METHODS, method_spec
from .integrators.spec import MethodSpec
from .free_body import accessor  # noqa: F401  (registers the ds.stability accessor)
from .analysis.estimates import measured_frequency, measured_growth_rate
from .analysis.regimes import member_regimes
from .free_body.measure import flip_statistics, measured_omega_squared


__all__ = ["METHODS", "MethodSpec", "Part", "RigidBody", "__version__", "axis_stability",
           "exact_omega", "flip_interval", "full_period",
           "growth_rate", "integrate", "method_spec", "omega_squared", "oscillation_frequency"]

from .free_body.spin_ensembles import run_ensemble, run_ensembles  # noqa: E402
from .free_body.ensemble_plan import ensemble_memory  # noqa: E402
from .output.io import load, save  # noqa: E402
from .engine.user_scene import define_scene  # noqa: E402
from .api import run_adaptive, run_scene, run_tangents  # noqa: E402
from .engine.events import Event  # noqa: E402
from .ensemble.options import RunOptions  # noqa: E402
from .free_body.keep import Keep  # noqa: E402

__all__ += ["Event", "Keep", "RunOptions", "animate_flip", "animate_top", "define_scene", "ensemble_memory",
            "load", "run_adaptive", "run_ensemble", "run_ensembles", "run_scene", "run_tangents",
            "save"]
__all__ += ["flip_statistics", "measured_frequency", "measured_growth_rate", "measured_omega_squared", "member_regimes"]  # noqa: E501

#: Names whose modules load matplotlib, imported when first used: ``import stability`` stays
#: free of matplotlib (start-up time, and no font cache where the home folder is read-only).
ON_FIRST_USE = {"animate_flip": "stability.free_body.animation",
                "animate_top": "stability.heavy_top.animation"}


def __getattr__(name):
    """A name of :data:`ON_FIRST_USE`, imported from its module on first use."""
    if name not in ON_FIRST_USE:
        raise AttributeError(f"module 'stability' has no attribute {name!r}")
    value = getattr(importlib.import_module(ON_FIRST_USE[name]), name)
    globals()[name] = value
    return value
