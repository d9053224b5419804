"""Any scene dispersed in its named parameters, the user's own included: each member its own
group, whose parameter set is the member's draw, run by :func:`stability.run_scene`.

A scene that names the numbers of its parameter sets (``Scene.parameters``: every scene of
:func:`stability.define_scene`, and the registered ones that name theirs, such as
``sphere_damper``'s I1, I2, I3, J, c) can have any of them dispersed
(:func:`~stability.uncertainty.dispersions.dispersions` over :func:`nominal`); member k runs
with the set ``(draws[name][k] for name in scene.parameters)``, which its Dataset's
``parameters`` reports back as it ran.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..ensemble.scene_run import run_scene
from .dispersions import Dispersions


def nominal(scene, values) -> dict:
    """The nominal values of ``scene``'s named parameters, from a parameter set (a mapping by
    name, or the numbers in order): what a dispersion of them takes as ``nominal``."""
    names = tuple(scene.parameters)
    if not names:
        raise ValueError(f"scene {scene.name!r} does not name its parameters; name them "
                         "(define_scene(parameters=...)) to disperse them")
    if isinstance(values, Mapping):
        missing = [n for n in names if n not in values]
        if missing or len(values) != len(names):
            raise ValueError(f"the parameter set of scene {scene.name!r} must give exactly "
                             f"{', '.join(names)}; got {', '.join(map(str, values))}")
        return {n: float(values[n]) for n in names}
    values = np.asarray(values, dtype=float).ravel()
    if values.size != len(names):
        raise ValueError(f"the parameter set of scene {scene.name!r} has {len(names)} numbers "
                         f"({', '.join(names)}), got {values.size}")
    return dict(zip(names, values.tolist()))


def parameter_sets(scene, draws: Mapping) -> np.ndarray:
    """Each member's parameter set (N, P), in the scene's order, from the draws
    (:meth:`~stability.uncertainty.dispersions.Dispersions.draw`)."""
    return np.column_stack([np.asarray(draws[name], dtype=float) for name in scene.parameters])


def run_dispersed(scene, method: str, x0, disp: Dispersions, unit, *, h, n_steps,
                  options=None, **kwargs):
    """Run one member per row of the unit design ``unit``, each with its own draw of the
    scene's parameters.

    Parameters
    ----------
    scene : Scene
        A scene that names its parameters.
    method : str
        A method of the scene.
    x0 : array_like, shape (n,) or (N, n)
        The start of every member, or of each.
    disp : Dispersions
        Over :func:`nominal` of the scene (the names it may disperse).
    unit : array_like, shape (N, columns)
        The design (:mod:`stability.uncertainty.designs`, a Sobol' or Morris design's
        ``unit``), one row per member.
    h : float or array_like, shape (N,)
        Step in s, of every member or of each.
    n_steps : int or array_like of int, shape (N,)
    options : RunOptions, optional
        How and where the members run (in chunks, resumed, on dask: the same result).
    **kwargs
        What else :func:`stability.run_scene` takes (``save_every``, ``axes``, ``levels``).

    Returns
    -------
    draws : dict
        Every parameter's values (N,), as drawn.
    ds : xarray.Dataset
        The run, member k in group k.
    """
    draws = disp.draw(unit)
    sets = parameter_sets(scene, draws)
    n = sets.shape[0]
    x0 = np.asarray(x0, dtype=float)
    if x0.ndim == 1:
        x0 = np.tile(x0, (n, 1))
    if x0.shape != (n, scene.width):
        raise ValueError(f"x0 must have shape ({scene.width},) or ({n}, {scene.width}), one "
                         f"start of every member or of each; got {x0.shape}")
    ds = run_scene(scene, method, x0, list(sets), h=h, n_steps=n_steps,
                   sizes=np.ones(n, dtype=int), options=options, **kwargs)
    return draws, ds
