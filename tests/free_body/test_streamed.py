"""The free body's streamed run (stability.free_body.streamed): a study's configuration and command,
handed to the streamed run, are what the Dataset records."""

import numpy as np

import stability
from stability import Keep, RunOptions
from stability.free_body.spin_ensembles import plan_arguments

BODY = stability.RigidBody(1.0, 2.0, 3.0, name="I=(1,2,3)")


def test_caller_config_is_stored(tmp_path):
    """A study's configuration and command, as the tennis-racket study hands them to the
    streamed run, are what the Dataset records."""
    import tomllib

    from stability.free_body.streamed import run_streamed

    study = {"study": {"kind": "tennis_racket", "members": 3, "epsilon": np.float64(1e-3)},
             "output": {"folder": "out", "figures": ["flips", "polhode"]}}
    kwargs = dict(body=BODY, axis=3, spin=1.0, epsilon=1e-3, members=3, h=0.01, t_end=1.0,
                  config=study, command="stability run x.toml",
                  **plan_arguments(Keep(), RunOptions()))
    ds = run_streamed(kwargs, RunOptions(store=tmp_path / "s", progress=False))
    assert tomllib.loads(ds.attrs["config_toml"]) == {
        "study": {"kind": "tennis_racket", "members": 3, "epsilon": 1e-3},
        "output": {"folder": "out", "figures": ["flips", "polhode"]},
    }
    first, streamed = ds.attrs["history"].splitlines()  # the command, then the run's record
    assert first.endswith(": stability run x.toml") and ": streamed to " in streamed
