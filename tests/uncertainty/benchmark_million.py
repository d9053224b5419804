"""One million closed-form evaluations of the free body's flip interval with their Sobol'
indices: PYTHONPATH=. python tests/uncertainty/benchmark_million.py (prints the times; no assertion)."""

import time

import numpy as np

import stability
from stability.free_body.dispersion import measure as M
from stability.uncertainty.dispersions import dispersions
from stability.uncertainty.sobol import sobol_design, sobol_indices

body = stability.RigidBody.preset("tennis_racket")
disp = dispersions({"moments": {"distribution": "uniform", "relative": 0.02},
                    "rate": {"distribution": "uniform", "relative": 0.1},
                    "epsilon": {"distribution": "log-uniform", "lower": 1e-4, "upper": 1e-2}},
                   M.nominal(body.moments, 10.0, 1e-3), truncate=True)
M.flip_intervals(np.array([[1.0, 2.0, 3.0]]), np.array([[0.01, 1.0, 0.0]]))  # compiled
t0 = time.perf_counter()
design = sobol_design(disp, 2**17, 1)  # 2^17 x (5 + 2) = 917504 members
t1 = time.perf_counter()
draws = M.members(disp, design.unit)
t2 = time.perf_counter()
flip = M.flip_intervals(draws["moments"], draws["w0"])
t3 = time.perf_counter()
ds = sobol_indices(design, {"flip_interval": (flip, "s", "flip interval")})
t4 = time.perf_counter()
n = flip.size
print(f"{n} members: design {t1 - t0:.2f} s, draws {t2 - t1:.2f} s, flip intervals "
      f"{t3 - t2:.2f} s ({(t3 - t2) / n * 1e9:.0f} ns each), indices {t4 - t3:.2f} s; "
      f"total {t4 - t0:.2f} s")
print(ds.first_order.round(3).values, ds.total.round(3).values, list(ds.parameter.values))
