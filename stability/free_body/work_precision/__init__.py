"""The speed-against-error study: which integrator to use, at which accuracy, in numbers.

- :mod:`.sweeps`: timed sweeps of one method over a ladder of steps, or of SciPy's DOP853;
- :mod:`.measure`: the work-precision Dataset, read as "which method is fastest";
- :mod:`.study`: the study kind ``work_precision``;
- :mod:`.figures`: its figures.
"""
