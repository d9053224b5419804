"""The scene registry: what the one member loop can integrate.

``SCENES`` maps a short lowercase name to a :class:`~stability.scenes.spec.Scene`;
``scene(name)`` looks one up and names the known ones when it is missing. To add a scene, write
one module beside these (copy ``free_body.py``; the checklist is in ``spec.py``), or the
``scene.py`` of a family package (``stability/dissipation/``), and add it to ``_ALL`` in
``registry.py``. A scene in a module of the user's own comes from ``define_scene``
(``user.py``) and is not registered: it is passed as it is.
"""

from .registry import SCENES, scene
from .spec import Scene

# After the registry: the kernels' cache that define_scene reaches imports the engine, which looks
# scenes up with scene().
from .user import define_scene

__all__ = ["SCENES", "Scene", "define_scene", "scene"]
