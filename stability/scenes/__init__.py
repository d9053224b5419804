"""The scene registry: what the one member loop can integrate.

``SCENES`` maps a short lowercase name to a :class:`~stability.scenes.spec.Scene`;
``scene(name)`` looks one up and names the known ones when it is missing. To add a scene, write
one module beside these (copy ``free_body.py``; the checklist is in ``spec.py``), or the
``scene.py`` of a family package (``stability/dissipation/``), and add it to ``_ALL`` below. A scene in a module of the user's own comes from ``define_scene`` (``user.py``)
and is not registered: it is passed as it is.
"""

from ..dissipation.scene import SPHERE_DAMPER, WHIP_DAMPER
from .engine_body import ENGINE_BODY
from .free_body import FREE_BODY
from .free_body_attitude import FREE_BODY_ATTITUDE
from .heavy_top import HEAVY_TOP
from .lunisolar_earth import LUNISOLAR_EARTH
from .precessing_axis import PRECESSING_AXIS
from .rolling_body import ROLLING_BODY
from .struck_body import STRUCK_BODY
from .spec import Scene

_ALL = (FREE_BODY, FREE_BODY_ATTITUDE, HEAVY_TOP, LUNISOLAR_EARTH, PRECESSING_AXIS,
        ROLLING_BODY, STRUCK_BODY, ENGINE_BODY, SPHERE_DAMPER, WHIP_DAMPER)

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


# After scene(): the kernels' cache it reaches imports the engine, which looks scenes up with it.
from .user import define_scene  # noqa: E402

__all__ = ["SCENES", "Scene", "define_scene", "scene"]
