"""What a run leaves on disk: netCDF files written atomically and read back
(:mod:`~stability.output.io`), the chunk store of a streamed run
(:mod:`~stability.output.store`), streaming any chunk job to it here or on dask.distributed
(:mod:`~stability.output.stream`), publishing into an output folder that is a boundary
(:mod:`~stability.output.publish`, :mod:`~stability.output.lock`), and the provenance every
Dataset carries (:mod:`~stability.output.dataset`); a file opened with plain xarray made what
:func:`stability.load` reads (:mod:`~stability.output.plain`).
"""
