"""A registered scene dispersed in its named parameters: each member runs with its own draw,
which its Dataset reports bitwise, and its result is that of the member run alone with that
set; a scene that names none, or a set of the wrong size, is one line. (A scene of the user's
own: tests/test_user_scene.py.)"""

import numpy as np
import pytest

import stability
from stability import RunOptions
from stability.uncertainty.designs import unit_design
from stability.uncertainty.dispersions import dispersions
from stability.uncertainty.scenes import nominal, parameter_sets, run_dispersed

DAMPER = stability.registry.scene("sphere_damper")


def test_each_member_runs_with_its_own_draw_of_the_dampers_j_and_c():
    """J and c of the spherical damper dispersed over a Latin hypercube: the J and c each
    member reports are its draws, the others nominal; member k's end state is bitwise that of
    a run of member k alone with its own set."""
    values = {"I1": 1.0, "I2": 1.5, "I3": 2.2, "J": 0.2, "c": 0.1}
    disp = dispersions({"J": {"distribution": "uniform", "relative": 0.3},
                        "c": {"distribution": "log-uniform", "lower": 0.01, "upper": 1.0}},
                       nominal(DAMPER, values))
    unit = unit_design("lhs", 9, 2, 4)
    x0, _ = DAMPER.example(1, seed=2)
    draws, ds = run_dispersed(DAMPER, "rk4", x0[0], disp, unit, h=0.01, n_steps=300,
                              options=RunOptions(progress=False))
    assert np.array_equal(ds.J.values, draws["J"]) and np.array_equal(ds.c.values, draws["c"])
    assert np.all(ds.I2.values == 1.5) and np.unique(ds.c.values).size == 9
    sets = parameter_sets(DAMPER, draws)
    finals = np.column_stack([ds[f"{c}_final"].values for c in DAMPER.components])
    for k in (0, 4, 8):
        alone = stability.run_scene(DAMPER, "rk4", x0, sets[k], h=0.01, n_steps=300,
                                    options=RunOptions(progress=False))
        want = np.array([alone[f"{c}_final"].values[0] for c in DAMPER.components])
        assert np.array_equal(finals[k], want)
    assert np.ptp(finals[:, 3]) > 1e-3  # the draws made a difference


def test_a_scene_that_names_no_parameters_or_a_set_of_the_wrong_size_is_one_line():
    with pytest.raises(ValueError, match="does not name its parameters") as info:
        nominal(stability.registry.scene("free_body"), [1.0, 2.0, 3.0])
    assert "\n" not in str(info.value)
    with pytest.raises(ValueError, match=r"has 5 numbers \(I1, I2, I3, J, c\), got 2"):
        nominal(DAMPER, [1.0, 2.0])
    with pytest.raises(ValueError, match="must give exactly I1, I2, I3, J, c"):
        nominal(DAMPER, {"I1": 1.0})
    disp = dispersions({"c": {"distribution": "uniform", "relative": 0.1}},
                       nominal(DAMPER, [1.0, 1.5, 2.2, 0.2, 0.1]))
    with pytest.raises(ValueError, match=r"x0 must have shape \(6,\) or \(3, 6\)"):
        run_dispersed(DAMPER, "rk4", np.zeros(4), disp, unit_design("random", 3, 1, 0),
                      h=0.01, n_steps=10)
