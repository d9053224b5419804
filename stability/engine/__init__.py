"""The engine: one cached, parallel member loop for every scene and method.

- :mod:`stability.engine.loop`: the loop, written once as a template and rendered per
  (scene, method);
- :mod:`stability.engine.cache`: where rendered loops are kept, and when they are compiled again;
- :mod:`stability.engine.driver`: the Python driver (groups of ensembles, chunks in time, Ctrl-C,
  progress);
- :mod:`stability.engine.baseline`: a plain RK4 loop, the speed baseline of ``stability bench``.
"""

from .loop import BLOCK, CHECK_EVERY
from .driver import Propagation, compiled_loop, propagate_groups, untrusted

__all__ = ["BLOCK", "CHECK_EVERY", "Propagation", "compiled_loop", "propagate_groups",
           "untrusted"]
