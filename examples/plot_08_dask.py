"""
A run on dask.distributed
=========================

The same ensemble streamed chunk by chunk to a folder and run on a local dask.distributed
cluster (``scheduler="dask"``; a scheduler address runs it on an existing cluster). The result
is bitwise that of the run on the local cores.
"""

import tempfile
from pathlib import Path

import numpy as np

import stability

body = stability.RigidBody.preset("tennis_racket")
kwargs = dict(axis=2, spin=10.0, epsilon=1e-4, members=400, h=2e-3, t_end=4.0, save_every=50,
              method="rk4", seed=1, chunk_members=100, progress=False)
local = stability.run_ensemble(body, **kwargs)

# %%
# The same ensemble, its four chunks run as tasks of a local dask.distributed cluster and
# written to a store: bitwise the run in this process.

store = Path(tempfile.mkdtemp()) / "store"
on_dask = stability.run_ensemble(body, store=store, scheduler="dask", **kwargs)
print(f"{len(list(store.glob('*.nc')))} chunk files")
print("bitwise equal:", bool(np.array_equal(local.w.values, on_dask.w.values)))
