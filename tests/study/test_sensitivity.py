"""The sections every dispersed study shares: the member count of each analysis' design, its
refusals in one line, and the analysis, its ranking and its tables, Sobol' or Morris, on a
function whose indices are known."""

import numpy as np
import pytest

from stability.study import load_study
from stability.study.config import ConfigError
from stability.study.sensitivity import (
    analyse, design_members, dominant, draw_design, index_tables, summary_values
)
from stability.uncertainty.dispersions import dispersions

#: Y = 4 a + b over independent uniforms on [0, 1]: S_a = 16/17, S_b = 1/17, no interaction.
DISP = dispersions({"a": {"distribution": "uniform", "lower": 0.0, "upper": 1.0},
                    "b": {"distribution": "uniform", "lower": 0.0, "upper": 1.0}},
                   {"a": 0.5, "b": 0.5})


def config(**sensitivity):
    return {"sensitivity": {"method": "sobol", "base": 1024, "trajectories": 32, "levels": 4,
                            "seed": 3, "resamples": 50, "conf_level": 0.95, **sensitivity}}


@pytest.mark.parametrize("method, members", [("sobol", 1024 * 4), ("morris", 32 * 3)])
def test_the_design_has_the_members_its_analysis_needs_and_ranks_what_matters(method,
                                                                               members):
    cfg = config(method=method)
    assert design_members(cfg, "x.toml", DISP) == members
    design = draw_design(cfg, DISP)
    assert design.unit.shape == (members, 2)
    x = DISP.draw(design.unit)
    ds = analyse(cfg, design, {"y": (4.0 * x["a"] + x["b"], "1", "a linear function")})
    assert dominant(ds, "y") == "a"
    if method == "sobol":
        assert ds.total.sel(parameter="a").item() == pytest.approx(16 / 17, abs=0.02)
        assert ds.first_order.sel(parameter="b").item() == pytest.approx(1 / 17, abs=0.02)
    else:  # an elementary effect of Y = c x over the whole unit range is c
        assert ds.mu_star.values[0] * np.std(4.0 * x["a"] + x["b"]) == pytest.approx(
            [4.0, 1.0], rel=1e-9)
    (table,) = index_tables(ds)
    assert [row[0] for row in table.rows] == ["a", "b"]
    assert set(summary_values(ds)["y"]) == {"a", "b"}


@pytest.mark.parametrize("sensitivity, message", [
    ({"base": 1000}, r"\[sensitivity\] base must be a power of 2.*got 1000"),
    ({"method": "morris", "levels": 3}, r"\[sensitivity\] levels must be even.*got 3"),
])
def test_a_design_it_cannot_draw_is_one_line(sensitivity, message):
    with pytest.raises(ConfigError, match=message) as info:
        design_members(config(**sensitivity), "x.toml", DISP)
    assert "\n" not in str(info.value)


def test_dispersions_in_a_study_that_draws_none_name_the_studies_that_do(tmp_path):
    path = tmp_path / "bat.toml"
    path.write_text('study = "bat"\n[dispersions]\nmass = {distribution = "uniform", '
                    'relative = 0.1}\n', encoding="utf-8")
    with pytest.raises(ConfigError, match=r"study 'bat' draws no dispersions; the studies "
                       r"that take \[dispersions\] .* are dispersion, explorer_dispersion; "
                       r"or disperse any scene's named parameters") as info:
        load_study(path)
    assert "\n" not in str(info.value) and str(info.value).startswith(str(path))
