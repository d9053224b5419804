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
kwargs = dict(axis=2, spin=10.0, epsilon=1e-4, members=400, h=2e-3, t_end=4.0,
              keep=stability.Keep(save_every=50),
              method="rk4", seed=1)
here = stability.RunOptions(chunk_members=100, progress=False)

# %%
# A script that starts a local cluster runs its work under ``if __name__ == "__main__":``: the
# cluster's worker processes import the script to find what the tasks refer to, and without
# the guard each would run it again (a script without it is refused in one line, naming the
# line to guard). First the ensemble on this process's cores:

if __name__ == "__main__":
    local = stability.run_ensemble(body, **kwargs, options=here)

# %%
# The same ensemble, its four chunks run as tasks of a local dask.distributed cluster and
# written to a store: bitwise the run in this process.

if __name__ == "__main__":
    store = Path(tempfile.mkdtemp()) / "store"
    on_dask = stability.run_ensemble(body, **kwargs, options=stability.RunOptions(
        store=store, scheduler="dask", chunk_members=100, progress=False))
    print(f"{len(list(store.glob('*.nc')))} chunk files")
    print("bitwise equal:", bool(np.array_equal(local.w.values, on_dask.w.values)))
