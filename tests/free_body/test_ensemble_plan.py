"""The free-body run's plan (stability.free_body.ensemble_plan): the memory it counts, and a time
series too large for it refused where summaries only are not."""

import pytest

import stability
from stability.free_body.spin_ensembles import run_ensemble
from stability.free_body.ensemble_plan import ensemble_memory
from stability.output.dataset import summary_bytes

BODY = stability.RigidBody(1.0, 2.0, 3.0, name="I=(1,2,3)")


def test_ensemble_memory_counts_members_samples_and_summaries():
    assert ensemble_memory(1000, 500, n_levels=13) == 1000 * 501 * 24 + 1000 * summary_bytes(13)
    assert ensemble_memory(10**6, 0, n_levels=13) == 10**6 * summary_bytes(13)
    assert summary_bytes(13) == 8 * (3 + 1 + 10 + 13) + 9


def test_big_time_series_is_refused_but_summaries_only_is_not():
    big = dict(h=0.01, t_end=100.0)  # 10**6 members x 10001 samples: 240 GB
    with pytest.raises(ValueError, match=r"summaries only \(Keep\(save_every=0\)\)"):
        run_ensemble(BODY, 2, 1.0, 1e-3, 10**6, **big)
    with pytest.raises(ValueError, match="max_memory"):
        run_ensemble(BODY, 2, 1.0, 1e-3, 1000, h=0.01, t_end=1.0,
                     options=stability.RunOptions(max_memory=1e5))
