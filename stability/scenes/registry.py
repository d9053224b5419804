"""The registered scenes: ``SCENES`` by name, and :func:`scene` to look one up.

A module of its own, below :mod:`stability.scenes.user`, which refuses a user's scene named as a
registered one: the package's ``__init__`` re-exports both.
"""

from ..dissipation.scene import GYROSTAT, SPHERE_DAMPER, WHIP_DAMPER
from ..earth.scene import LUNISOLAR_EARTH, PRECESSING_AXIS
from ..engine_body.scene import ENGINE_BODY
from ..heavy_top.scene import HEAVY_TOP
from ..rolling.scene import ROLLING_BODY
from ..struck.scene import STRUCK_BODY
from ..free_body.scene import FREE_BODY
from ..free_body.scene_attitude import FREE_BODY_ATTITUDE
from .spec import Scene

_ALL = (FREE_BODY, FREE_BODY_ATTITUDE, HEAVY_TOP, LUNISOLAR_EARTH, PRECESSING_AXIS,
        ROLLING_BODY, STRUCK_BODY, ENGINE_BODY, SPHERE_DAMPER, WHIP_DAMPER, GYROSTAT)

SCENES: dict[str, Scene] = {s.name: s for s in _ALL}


def scene(name) -> Scene:
    """The scene registered under ``name``; ValueError listing the known ones if none.

    Parameters
    ----------
    name : str or Scene
        A key of :data:`SCENES`; a Scene is returned as it is.

    Returns
    -------
    Scene
    """
    if isinstance(name, Scene):
        return name
    try:
        return SCENES[name]
    except (KeyError, TypeError):
        raise ValueError(
            f"unknown scene {name!r}; known scenes: {', '.join(SCENES)}"
        ) from None


__all__ = ["SCENES", "scene"]
