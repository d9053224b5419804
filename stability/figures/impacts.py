"""The old path of the struck bat's and rolling's figures, for one release.

Its figures moved to their families: :func:`stability.struck.figures.bat_figure`,
:func:`stability.rolling.figures.rolling_map_figure` and
:func:`~stability.rolling.figures.rolling_launch_figure`. Their names still import from here,
each with a ``FutureWarning`` (:func:`stability.moved.old_names`): a module that moved to one
place would go in :data:`stability.moved.MOVED`, but these went to two.
"""

from ..moved import old_names

__getattr__ = old_names(__name__)
