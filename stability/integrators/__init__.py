"""The integrator registry.

``METHODS`` maps a short lowercase name to the :class:`~stability.integrators.spec.MethodSpec`
of that method; ``method_spec(name)`` looks one up and names the known ones when it is missing.

To add a method: write its step kernel and spec in the module of its family, then add the spec
to ``_ALL`` below. Tests parametrized over ``METHODS`` (order, invariants) cover it from then on.
"""

from .composition import LP4, LP6, LP8
from .exact_flow import EXACT
from .lgvi import LGVI
from .lie_poisson import LP2
from .midpoint import MIDPOINT
from .moser_veselov import DMV, DMV4
from .munthe_kaas import RKMK4
from .rk4 import RK4
from .spec import MethodSpec, body_params
from ..util.checks import registered

_ALL = (RK4, LP2, LP4, LP6, LP8, EXACT, DMV, DMV4, LGVI, RKMK4, MIDPOINT)

METHODS: dict[str, MethodSpec] = {spec.name: spec for spec in _ALL}


def method_spec(name) -> MethodSpec:
    """Return the spec registered under ``name``; ``ValueError`` listing the known names if none.

    Parameters
    ----------
    name : str or MethodSpec
        A key of :data:`METHODS` (``"rk4"``, ``"lp2"``, ...); a spec is returned as it is.

    Returns
    -------
    MethodSpec
    """
    if isinstance(name, MethodSpec):
        return name
    return registered(METHODS, name, "method")


__all__ = ["METHODS", "MethodSpec", "body_params", "method_spec"]
