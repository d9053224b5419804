"""Tests of the GPU kernels (stability.engine.gpu), checked on numba-cuda's CUDA simulator against
the CPU; the free body's GPU twins in ``tests/free_body/test_propagate_gpu.py``, the benchmark in
``tests/cli/test_gpu_bench.py``.

The simulator (``NUMBA_ENABLE_CUDASIM=1``) runs every kernel as Python on the CPU, one thread
after another: it checks the kernels' logic (indexing, layout, tracking, chunks, groups, frame
conversions), not their speed or the device's arithmetic. It is switched on in a subprocess
(``tests/gpu_simulated.py``, which prints its results as JSON; the ``simulated`` fixture of
``tests/conftest.py`` runs it once in a run of the suite): numba reads the variable once,
when ``numba.cuda`` is first imported, and pytest-xdist runs several test modules in one worker
process, so setting it here would turn the simulator on for whichever module came next.

Why a real GPU agrees with the CPU to round-off and not bitwise: NVVM contracts a * b + c into
fused multiply-adds (one rounding instead of two) wherever it can, the device's libm (``log``
of the level passages, ``cosh``, ``asinh``, ``sqrt`` of the exact flow) is not glibc's, and
every contracted or reassociated expression rounds differently. Each is an ulp per operation;
over a run they add up like the method's own round-off, far below the 1e-12 asked here. Python
rounds every operation once, as the CPU loop does, so under the simulator the results are in
fact bitwise the CPU's (asserted to 1e-12 all the same, which is what a GPU must meet).
"""
