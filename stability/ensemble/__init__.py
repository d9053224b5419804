"""Ensembles of any scene: grouped runs cut into chunks, streamed to a store, resumed and run on
dask; the memory a run may hold; the register of every Dataset the package writes; and
:func:`~stability.ensemble.scene_run.run_scene`, a run of any scene as a labelled Dataset.

- :mod:`.schema`: the register (each variable's dims, units, long name, declared once);
- :mod:`.memory`: the one memory check every run makes before any work;
- :mod:`.starts`: the start rule of an ensemble about a steady spin (perturbed at random,
  reproducible for any chunks);
- :mod:`.chunks`: grouped runs of any scene, in chunks, stored, resumable and distributed;
- :mod:`.scene_run`: ``run_scene``;
- :mod:`.adaptive_run`: ``run_adaptive``, adaptive runs of any scene (Dormand-Prince 5(4), events).
"""
