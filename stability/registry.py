"""The families' scenes, in one table: ``SCENES`` by name, and :func:`scene` to look one up.

To add a family's scene: import it here and add it to ``_ALL``; the generic tests, the docs'
scene pages and ``stability methods`` pick it up from this table. A scene in a module of the
user's own comes from :func:`stability.define_scene` (:mod:`stability.engine.user_scene`, which
refuses a name registered here) and is passed as it is.
"""

from .dissipation.scene import GYROSTAT, SPHERE_DAMPER, WHIP_DAMPER
from .earth.scene import LUNISOLAR_EARTH, PRECESSING_AXIS
from .engine_body.scene import ENGINE_BODY
from .heavy_top.scene import HEAVY_TOP
from .rolling.scene import ROLLING_BODY
from .struck.scene import STRUCK_BODY
from .free_body.scene import FREE_BODY
from .free_body.scene_attitude import FREE_BODY_ATTITUDE
from .engine.scene import Scene

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
