"""The tumbler study: a quick run of studies/tumbler.toml, its Dataset and figure."""

from pathlib import Path

import pytest

from stability.asteroid.figures import tumbler_figure
from stability.plotting.style import missing_units
from stability.study import ConfigError, load_study

from ...helpers import assert_cf_compliant, assert_declared, quick_study

ROOT = Path(__file__).resolve().parents[3]


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    return quick_study(tmp_path_factory, "tumbler", threads=1)


def test_study_gives_apophis_e_over_e0_and_the_theorys_frequency(quick):
    summary, out = quick
    v = summary.values
    assert round(v["energy_ratio_nominal"], 3) == 1.024  # Pravec et al. 2014: 1.024 +- 0.013
    assert v["energy_ratio_std"] < 0.013  # the one-sigma draws stay within the paper's 3 sigma
    assert v["max_frequency_error"] < 1e-4
    assert v["fitted"] == v["members"] == 16
    assert round(24.0 / (v["frequency_nominal"] / 2.0), 2) == 30.56  # P1 in hours


def test_study_dataset_follows_cf(quick):
    assert_cf_compliant(quick[1] / "tumbler.nc")


def test_study_dataset_is_as_the_register_declares(quick):
    assert_declared(quick[1] / "tumbler.nc", "tumbler")


def test_figure_labels_every_axis_with_units(quick):
    import xarray as xr

    with xr.open_dataset(quick[1] / "tumbler.nc") as ds:
        assert missing_units(tumbler_figure(ds, "Apophis")) == []


def test_a_mode_the_periods_do_not_fit_is_refused_naming_the_key(tmp_path):
    text = (ROOT / "studies" / "tumbler.toml").read_text().replace(
        'period_psi = 263.0', 'period_psi = 2.0')
    (tmp_path / "t.toml").write_text(text)
    with pytest.raises(ConfigError) as info:
        load_study(tmp_path / "t.toml")
    assert "[tumbler] mode" in str(info.value) or "mode" in str(info.value)
    assert "\n" not in str(info.value)
