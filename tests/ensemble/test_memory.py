"""Memory is checked before anything of the run's size is allocated, against the machine too.

A run refused for its memory is refused from the shapes of its arguments, before any array of
that size is made (a broadcast ``x0`` of 1e8 rows is never copied), for a batch of ensembles on
the batch's total, and against the memory this process may have (the machine's, or its
cgroup's limit, read from real cgroup files laid out in a folder), not only ``max_memory``:
each a one-line ValueError, never NumPy's MemoryError.
"""

import tracemalloc

import numpy as np
import pytest

import stability
from stability.ensemble import memory
from stability.heavy_top.model import HeavyTop, tilted_starts

BODY = stability.RigidBody(1.0, 2.0, 3.0, name="I=(1,2,3)")
TOP = HeavyTop.disk(mass=0.1, radius=0.03, length=0.04)


@pytest.fixture
def cgroup_of_1_mib(tmp_path, monkeypatch):
    """This process in a cgroup v2 whose memory.max is 1 MiB (its files in a folder)."""
    (tmp_path / "job").mkdir()
    (tmp_path / "job" / "memory.max").write_text(f"{2**20}\n")
    (tmp_path / "memory.max").write_text("max\n")
    proc = tmp_path / "cgroup"
    proc.write_text("0::/job\n")
    monkeypatch.setattr(memory, "CGROUP_ROOT", tmp_path)
    monkeypatch.setattr(memory, "PROC_CGROUP", proc)


def test_a_broadcast_x0_of_1e8_rows_is_refused_before_it_is_copied():
    row = tilted_starts(150.0, np.radians(60.0), 1, top=TOP)[0]
    x0 = np.broadcast_to(row, (10**8, row.size))  # 4.8 GB as a copy, none as a view
    tracemalloc.start()
    try:
        with pytest.raises(ValueError, match=r"a run of 100000000 members of scene 'heavy_top' "
                                             r"would take about .* GiB in memory"):
            stability.run_scene("heavy_top", "lp2", x0, TOP.parameters, h=1e-4, n_steps=10,
                                options=stability.RunOptions(progress=False))
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 50 * 2**20, f"{peak / 2**30:.2f} GiB allocated before the refusal"


def test_a_batch_is_checked_on_its_total_before_the_starts_of_its_last_calls_are_drawn():
    calls = [dict(body=BODY, axis=2, spin=1.0, epsilon=1e-3, members=1000, h=0.01, t_end=0.1,
                  keep=stability.Keep(save_every=0),
                  options=stability.RunOptions(max_memory=500_000)) for _ in range(3)]
    each = stability.ensemble_memory(1000, 0)
    assert each < 500_000 < 3 * each  # each call fits alone, the batch does not
    with pytest.raises(ValueError) as caught:
        stability.run_ensembles(calls, progress=False)
    message = str(caught.value)
    assert message.startswith("calls[2]: the summaries of 1000 members would take")
    assert "with the 439.5 KiB of the ensembles before it in the batch" in message
    assert "above max_memory = 488.3 KiB" in message and "\n" not in message


def test_a_cgroup_limit_below_the_machine_is_the_memory_there_is(cgroup_of_1_mib):
    assert memory.cgroup_limit() == 2**20
    assert memory.machine_memory() == 2**20
    line = memory.memory_problem(2 * 2**20, "a run of 2 MiB", "use fewer members")
    assert "this machine has 1.0 MiB for this process (its cgroup's limit)" in line


def test_a_cgroup_v1_limit_is_read_and_unlimited_is_none(tmp_path, monkeypatch):
    (tmp_path / "memory" / "batch").mkdir(parents=True)
    (tmp_path / "memory" / "memory.limit_in_bytes").write_text("9223372036854771712\n")
    (tmp_path / "memory" / "batch" / "memory.limit_in_bytes").write_text("3000000\n")
    proc = tmp_path / "cgroup"
    proc.write_text("5:cpu:/\n4:memory:/batch\n")
    monkeypatch.setattr(memory, "CGROUP_ROOT", tmp_path)
    monkeypatch.setattr(memory, "PROC_CGROUP", proc)
    assert memory.cgroup_limit() == 3_000_000
    proc.write_text("4:memory:/\n")
    assert memory.cgroup_limit() is None


def test_max_memory_above_the_machine_is_refused_naming_the_machine(cgroup_of_1_mib):
    for kind in ({"keep": stability.Keep(save_every=0)}, {}):
        with pytest.raises(ValueError) as caught:
            stability.run_ensemble(BODY, 2, 1.0, 1e-3, 10**4, h=0.01, t_end=0.1,
                                   options=stability.RunOptions(max_memory=10**15,
                                                                progress=False), **kind)
        message = str(caught.value)
        assert ("above the memory of this machine (it has 1.0 MiB for this process (its "
                "cgroup's limit); max_memory = 909.5 TiB is above it)") in message
        assert "raise max_memory" not in message and "\n" not in message
    x0 = np.broadcast_to(tilted_starts(150.0, np.radians(60.0), 1, top=TOP)[0], (10**4, 6))
    with pytest.raises(ValueError, match="this machine has 1.0 MiB for this process"):
        stability.run_scene("heavy_top", "lp2", x0, TOP.parameters, h=1e-4, n_steps=10,
                            options=stability.RunOptions(progress=False, max_memory=10**15))


def test_1e9_members_with_max_memory_1e15_is_one_line_not_a_memory_error():
    machine = memory.machine_memory()
    if machine is None or machine > 200 * 2**30:
        pytest.skip("the summaries of 1e9 members (209 GiB) would fit in this machine")
    with pytest.raises(ValueError, match=r"^the summaries of 1000000000 members would take "
                                         r"209.5 GiB .* above the memory of this machine"):
        stability.run_ensemble(BODY, 2, 1.0, 1e-3, 10**9, h=0.01, t_end=0.1,
                               keep=stability.Keep(save_every=0),
                               options=stability.RunOptions(max_memory=10**15, progress=False))
