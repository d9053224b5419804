"""A scene's ensemble run (stability.ensemble.scene_run, stability.run_scene): parameters by name,
the level coordinate, the wall and chunk times of a stored run, and what each registered scene
tracks."""

import numpy as np
import pytest
import stability
from stability import RunOptions
from stability.registry import SCENES
from ..helpers import assert_declared


def test_a_registered_scene_takes_its_parameters_by_name_as_a_users_scene_does():
    """sphere_damper names (I1, I2, I3, J, c): a mapping by name is the numbers in that order,
    and one that names them wrong is one line giving the order."""
    scene = SCENES["sphere_damper"]
    x0, sets = scene.example(3)
    by_name = dict(zip(scene.parameters, sets[0]))
    kwargs = dict(h=0.05, n_steps=20, options=RunOptions(progress=False))
    named = stability.run_scene(scene, "rk4", x0, by_name, **kwargs)
    ordered = stability.run_scene(scene, "rk4", x0, sets[0], **kwargs)
    for name in ordered.variables:
        assert np.array_equal(named[name].values, ordered[name].values, equal_nan=True), name
    assert named.J.item() == sets[0][3]
    with pytest.raises(ValueError) as info:
        stability.run_scene(scene, "rk4", x0, {**by_name, "K": 1.0}, **kwargs)
    assert str(info.value) == (
        "parameter set 0: scene 'sphere_damper': the parameter set must name exactly I1, I2, "
        "I3, J, c (or give those numbers in that order); unknown: K")
    with pytest.raises(ValueError, match="scene 'heavy_top' does not name its parameters"):
        stability.run_scene("heavy_top", "lp2", SCENES["heavy_top"].example(2)[0],
                            {"I1": 1.0}, **kwargs)


def test_the_level_coordinate_of_a_scenes_run_holds_the_levels(tmp_path):
    """As run_ensemble's: the values in the tracked units, not 0, 1, 2; levels given per group
    are all of them, a member's passage times NaN at the other groups' levels."""
    scene = SCENES["heavy_top"]
    x0, tops = scene.example(5)
    kwargs = dict(h=0.05, n_steps=40, axes=[1, 0, 2], tracked_units="1",
                  options=RunOptions(progress=False))
    one = stability.run_scene(scene, "lp2", x0, tops[0], levels=[1e-2, 5e-2, 0.3], **kwargs)
    assert one.level.values.tolist() == [1e-2, 5e-2, 0.3]
    assert one.level.attrs["units"] == "1" and "levels" not in one
    assert_declared(stability.save(one, tmp_path / "top.nc"), "scene_run")
    two = stability.run_scene(scene, "lp2", x0, tops[:2], sizes=[3, 2],
                              levels=[[1e-2, 0.3], [5e-2, 0.3]], **kwargs)
    assert two.level.values.tolist() == [1e-2, 5e-2, 0.3]
    passage = two.passage_time.values
    assert np.isnan(passage[:3, 1]).all() and np.isnan(passage[3:, 0]).all()
    assert np.array_equal(passage[:3, [0, 2]], one.passage_time.values[:3, [0, 2]],
                          equal_nan=True)
    assert not np.isnan(passage[:, 2]).all()


@pytest.mark.parametrize("kind", ["scene", "free body"])
def test_a_stored_runs_wall_time_is_its_elapsed_time_and_chunk_time_the_chunks_sum(tmp_path,
                                                                                   kind):
    """wall_time is the seconds from the first chunk's start to the last one's end (here, in
    turn, at least the chunks' loop times together), chunk_time those loop times summed, the
    rate over wall_time; a finished store opened again keeps what it recorded."""
    import time

    import xarray as xr

    store = tmp_path / "store"
    if kind == "scene":
        scene = SCENES["heavy_top"]
        x0, tops = scene.example(12)
        run = lambda resume=False: stability.run_scene(  # noqa: E731
            scene, "lp2", x0, tops[0], h=0.05, n_steps=200, options=stability.RunOptions(
                store=store, chunk_members=3, progress=False, resume=resume))
        steps = 12 * 200
    else:
        body = stability.RigidBody(1.0, 2.0, 3.0)
        run = lambda resume=False: stability.run_ensemble(  # noqa: E731
            body, 2, 1.0, 0.1, 12, h=0.1, t_end=20.0, keep=stability.Keep(save_every=0),
            options=stability.RunOptions(store=store, chunk_members=3, progress=False,
                                         resume=resume))
        steps = 12 * 200
    t0 = time.perf_counter()
    ds = run()
    outer = time.perf_counter() - t0
    attrs = ds.attrs
    loops = [float(xr.open_dataset(path, decode_times=False).attrs["wall_time"])
             for path in sorted(store.glob("chunk-*.nc"))]
    assert len(loops) == 4 and attrs["chunks"] == 4
    assert attrs["chunk_time"] == pytest.approx(sum(loops), rel=1e-12)
    assert attrs["chunk_time"] <= attrs["wall_time"] <= outer
    assert attrs["member_steps_per_second"] == pytest.approx(steps / attrs["wall_time"])
    again = run(resume=True)
    assert again.attrs["wall_time"] == attrs["wall_time"]
    assert again.attrs["member_steps_per_second"] == attrs["member_steps_per_second"]


def test_every_registered_scene_declares_what_it_tracks_and_a_tracked_run_takes_it():
    """A tracked run of a damper scene needs no tracked_units=: the scene declares them (the
    sine of the nutation angle, dimensionless)."""
    assert all(scene.tracked_units for scene in SCENES.values())
    scene = SCENES["sphere_damper"]
    x0, sets = scene.example(3)
    ds = stability.run_scene(scene, "rk4", x0, sets[0], h=0.05, n_steps=20, axes=[0, 1, 2],
                             levels=[0.1], options=stability.RunOptions(progress=False))
    assert ds.max_perp_amplitude.attrs["units"] == ds.level.attrs["units"] == "1"
    assert ds.attrs["tracked_units"] == "1"


def test_a_scenes_run_with_events_keeps_them_as_declared_and_the_same_in_a_chunked_store(
        tmp_path):
    """Events through run_scene: the crossings and a stop in the Dataset as the register
    declares them, the stopped members' final states and series ending at their stop, and a
    store in chunks bitwise the run in one piece."""
    from stability.engine.events import Event
    from stability.free_body.scene import FREE_BODY, flip_event
    from tests.engine.test_adaptive import MOMENTS, free_body_starts
    from tests.helpers import assert_cf_compliant

    m0 = free_body_starts(20, seed=6)
    events = [Event(flip_event, count=3, name="flips"),
              Event(flip_event, action="stop", count=2, name="second_flip")]

    def run(**options):
        return stability.run_scene(FREE_BODY, "exact", m0, MOMENTS, h=0.2, n_steps=300,
                                   save_every=5, events=events,
                                   options=stability.RunOptions(progress=False, **options))

    whole = run()
    assert_declared(stability.save(whole, tmp_path / "events.nc"), "scene_run")
    assert_cf_compliant(tmp_path / "events.nc")
    assert whole.event.values.tolist() == ["flips", "second_flip"]
    assert np.all(whole.stop_event == 1) and np.all(whole.event_count.sel(event="flips") == 2)
    assert np.array_equal(whole.t_final, whole.event_time.sel(event="flips")[:, 1])
    assert np.max(np.abs(whole.m2_final)) < 1e-12  # each member ends at its second flip
    after = whole.time > whole.t_final
    assert after.any() and bool(np.isnan(whole.m1.where(after, np.nan)).all())  # past it
    assert not np.isnan(whole.m1.where(~after, 0.0)).any()
    stored = run(store=tmp_path / "store", chunk_members=6)
    for name in whole.variables:
        assert whole[name].equals(stored[name]), name
