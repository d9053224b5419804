"""What a study writes (stability.study.outputs): the files output_files names are the files
write_outputs writes, the Dataset labelled with the study and its configuration and readable
back, no figure when [output] figures is false. Interrupted writes are the fault suite's
(tests/test_faults.py)."""

import numpy as np
import xarray as xr

from stability.plotting.style import label, new_figure
from stability.study.outputs import output_files, write_outputs


def config(figures=True):
    return {"title": "A small study", "output": {
        "dataset": "small.nc", "figures": figures, "formats": ["png", "pdf"],
        "compression": "zlib", "table": "small.md"}}


def draw(ds):
    fig = new_figure(3.0, 2.0)
    ax = fig.subplots()
    ax.plot(ds.t, ds.x)
    ax.set_xlabel(label("t", "s"))
    ax.set_ylabel(label("x", "m"))
    return fig


def dataset():
    t = np.linspace(0.0, 1.0, 11)
    return xr.Dataset({"x": ("t", t ** 2, {"long_name": "position", "units": "m"})},
                      coords={"t": ("t", t, {"long_name": "time", "units": "s"})})


def test_the_files_named_are_the_files_written_and_the_dataset_says_what_made_it(tmp_path):
    timings = {}
    ds, files = write_outputs(dataset(), config(), tmp_path, "small", {"path": draw},
                              texts={"small.md": "| x |\n"}, timings=timings)
    named = output_files(config(), ["path"], extra=("table",))
    assert sorted(f.name for f in files) == sorted(named)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(named)
    back = xr.open_dataset(tmp_path / "small.nc").load()
    assert back.attrs["study"] == "small" and back.attrs["title"] == "A small study"
    assert back.attrs["Conventions"] == "CF-1.10" and "stability run (small)" in back.history
    assert 'dataset = "small.nc"' in back.attrs["config_toml"]
    np.testing.assert_array_equal(back.x, ds.x)
    assert (tmp_path / "small.md").read_text() == "| x |\n"
    assert timings["figures"] >= 0 and timings["dataset"] >= 0


def test_no_figure_is_drawn_when_the_study_asks_for_none(tmp_path):
    drawn = []
    _, files = write_outputs(dataset(), config(figures=False), tmp_path, "small",
                             {"path": lambda ds: drawn.append(ds)})
    assert drawn == [] and sorted(f.name for f in files) == ["config.toml", "small.nc"]
    assert output_files(config(figures=False), ["path"]) == ["small.nc", "config.toml"]
