"""RunOptions: one frozen object for how and where a run goes, refusing nonsense in one line."""

import dataclasses
import os

import pytest

import stability
from stability import RunOptions
from stability.registry import SCENES


@pytest.mark.parametrize("kwargs, message", [
    (dict(store=123), "store must be a folder path (a str or pathlib.Path), got 123"),
    (dict(resume="yes"), "resume must be True or False, got 'yes'"),
    (dict(device="tpu"), "device must be 'cpu' or 'gpu', got 'tpu'"),
])
def test_run_options_refuse_nonsense_in_one_line(kwargs, message):
    with pytest.raises(ValueError) as caught:
        RunOptions(**kwargs)
    assert str(caught.value) == message


def test_run_options_are_frozen_and_a_sub_run_gets_its_own_folder(tmp_path):
    options = RunOptions(store=tmp_path, chunk_members=7, progress=False)
    with pytest.raises(dataclasses.FrozenInstanceError):
        options.store = "elsewhere"
    inner = options.within("sphere")
    assert inner.store == tmp_path / "sphere" and inner.chunk_members == 7
    assert RunOptions().within("sphere") == RunOptions()  # no store: nothing to place
    os.symlink(tmp_path / "outside", tmp_path / "whips")
    with pytest.raises(ValueError, match="whips is a symbolic link; a run keeps its chunks only"):
        options.within("whips")


def test_a_run_with_anything_but_run_options_is_refused_in_one_line():
    scene = SCENES["heavy_top"]
    x0, tops = scene.example(2)
    with pytest.raises(ValueError) as caught:
        stability.run_scene(scene, "lp2", x0, tops[0], h=0.05, n_steps=2,
                            options={"progress": False})
    assert str(caught.value) == ("options must be a stability.RunOptions, got dict; e.g. "
                                 "RunOptions(store='work', progress=False)")
