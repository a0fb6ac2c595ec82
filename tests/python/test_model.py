# SPDX-License-Identifier: Apache-2.0
"""rbfmuscle.Model on the flexion scene: a run from Python is the host's run, stepping with
the motion's angles is the run, and the arrays have their shapes and no NaN."""
import _thread
import importlib.util
import threading
import time

import numpy as np
import pytest

import rbfmuscle
from conftest import SOURCE, read_csv


def timing(label):
    """Wall-time columns: the only ones two runs may differ in."""
    return label.endswith("_ms")


def assert_same_table(actual, expected):
    assert list(actual) == list(expected)
    differing = [label for label in expected if not timing(label)
                 and not np.array_equal(actual[label], expected[label], equal_nan=True)]
    assert differing == []


def test_run_gives_the_hosts_outputs_bitwise(flexion, host_flexion_run):
    table = flexion.run()
    process, out = host_flexion_run
    _, err = process.communicate(timeout=300)
    assert process.returncode == 0, err
    host = read_csv(out / "outputs.csv")
    assert len(host["time"]) == 9
    assert_same_table(table, host)


def test_stepping_the_motions_angles_is_the_run(flexion):
    run = flexion.run()
    flexion.reset()
    for time_s, q in zip(flexion.motion_times, flexion.motion_coordinates):
        flexion.step(q, time=time_s)
    assert flexion.frame == 9
    assert_same_table(flexion.table(), run)
    # A frame depends on its angles only: one frame at 40 degrees, by name, is the run's fifth.
    flexion.reset()
    flexion.step({"hip_flexion_r": np.radians(40.0)}, time=run["time"][4])
    stepped = flexion.table()
    assert all(np.array_equal(stepped[c], run[c][4:5], equal_nan=True) for c in run if not timing(c))


def test_arrays_have_their_shapes_and_no_nan(flexion):
    table = flexion.run()
    names = flexion.coordinate_names
    assert names == ["hip_flexion_r", "hip_adduction_r", "hip_rotation_r"]
    assert flexion.motion_coordinates.shape == (9, 3)
    assert flexion.motion_times.shape == (9,)
    assert np.allclose(np.degrees(table["hip_flexion_r"]), np.arange(0, 81, 10))
    assert all(column.shape == (9,) and column.dtype == np.float64 for column in table.values())
    # Without geometry the surface stage does not run, and the pieces check is off: their
    # figures are NaN, and only they.
    with_nan = sorted(c for c in table if np.isnan(table[c]).any())
    assert all(".surface_" in c or c.endswith((".pieces", ".stray_volume_mm3")) or ".stray_centre_mm_" in c
               for c in with_nan)
    lengths = rbfmuscle.stack_columns(table, "iliacus_r.fibre_length_mm")
    assert lengths.shape == (9, 100)
    assert np.allclose(lengths.mean(axis=1), table["iliacus_r.fibre_length_mean_mm"], rtol=1e-12)

    outputs = flexion.outputs()
    assert set(outputs) == set(flexion.output_units)
    assert outputs["iliacus_r.fibre_length_mm"].shape == (100,)
    assert isinstance(outputs["iliacus_r.volume_ratio"], np.float64)
    assert flexion.output_units["iliacus_r.fibre_length_mm"] == "mm"
    # The outputs are the last frame's.
    assert np.array_equal(flexion.output("psoas_r.fibre_length_mm"),
                          rbfmuscle.stack_columns(table, "psoas_r.fibre_length_mm")[-1])


def test_surface_and_fibres_of_a_frame(flexion):
    flexion.reset()
    with pytest.raises(rbfmuscle.Error, match="geometry=True"):
        flexion.surface("iliacus_r")
    flexion.step({"hip_flexion_r": 0.5}, geometry=True)
    vertices, triangles = flexion.surface("iliacus_r")
    assert vertices.ndim == 2 and vertices.shape[1] == 3 and len(vertices) > 1000
    assert triangles.shape[1] == 3 and triangles.dtype == np.int32
    assert triangles.min() >= 0 and triangles.max() < len(vertices)
    assert np.isfinite(vertices).all()
    fibres = flexion.fibres("iliacus_r")
    # 15 segments per fibre, and its attachments on the areas at both ends
    assert fibres.shape == (100, 18, 3) and np.isfinite(fibres).all()
    # The fibres' lengths are the fibre_length_mm output.
    lengths = np.linalg.norm(np.diff(fibres, axis=1), axis=2).sum(axis=1)
    assert np.allclose(lengths, flexion.output("iliacus_r.fibre_length_mm"), rtol=1e-9)
    assert sorted(flexion.geometry()) == ["glmax_r", "glmax_r_fibres", "iliacus_r", "iliacus_r_fibres",
                                          "psoas_r", "psoas_r_fibres"]
    # With geometry the surface stage reports too: no NaN left but the pieces check's (off).
    assert not any(np.isnan(v).any() for k, v in flexion.outputs().items()
                   if not k.endswith((".pieces", ".stray_volume_mm3", ".stray_centre_mm")))
    with pytest.raises(KeyError, match="iliacus_r_fibres"):
        flexion.surface("nothing")


def test_bad_coordinates_raise_before_the_frame(flexion):
    flexion.reset()
    with pytest.raises(ValueError, match="expected 3 values"):
        flexion.step([0.1, 0.2])
    with pytest.raises(KeyError, match="hip_flexion_r"):
        flexion.step({"knee": 0.1})
    with pytest.raises(ValueError, match="hip_adduction_r"):
        flexion.step([0.0, np.nan, 0.0])
    with pytest.raises(TypeError, match="coordinate 'hip_flexion_r': expected a number, got str"):
        flexion.step({"hip_flexion_r": "0.5"})
    assert flexion.frame == 0


def test_body_transform_turns_the_femur_by_the_flexion_angle():
    """The bare skeleton: flexing the hip by 0.5 rad turns the femur by 0.5 rad about a fixed
    axis and leaves the pelvis where it was."""
    skeleton = rbfmuscle.Model(str(SOURCE / "models" / "hip" / "skeleton_flexion.xml"))
    pelvis_rest, femur_rest = skeleton.body_transform("pelvis"), skeleton.body_transform("femur_r")
    skeleton.step({"hip_flexion_r": 0.5})
    np.testing.assert_allclose(skeleton.body_transform("pelvis"), pelvis_rest, rtol=0, atol=1e-12)
    turn = skeleton.body_transform("femur_r") @ np.linalg.inv(femur_rest)
    rotation = turn[:3, :3]
    np.testing.assert_allclose(rotation @ rotation.T, np.eye(3), rtol=0, atol=1e-12)
    assert np.arccos((np.trace(rotation) - 1.0) / 2.0) == pytest.approx(0.5, abs=1e-9)
    np.testing.assert_array_equal(turn[3], [0.0, 0.0, 0.0, 1.0])
    with pytest.raises(KeyError, match="no body 'tibia_r'.*femur_r"):
        skeleton.body_transform("tibia_r")


def test_frames_release_the_gil(flexion):
    """While a run computes its frames in another thread, this thread keeps running Python."""
    span = {}

    def run():
        span["start"] = time.perf_counter()
        flexion.run()
        span["end"] = time.perf_counter()

    worker = threading.Thread(target=run)
    ticks = []
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())
    worker.join()
    start, end = span["start"], span["end"]
    quarter = (end - start) / 4
    assert any(start + quarter < t < end - quarter for t in ticks)


def test_ctrl_c_stops_a_run_between_frames(flexion):
    """KeyboardInterrupt (here simulated: SIGINT's handler in the main thread) stops a run at the
    next frame; the model runs again afterwards."""
    timer = threading.Timer(0.05, _thread.interrupt_main)
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        for _ in range(1000):  # until the interrupt arrives
            flexion.run()
    timer.join()
    assert len(flexion.run()["time"]) == 9


def test_the_example_draws_its_picture(flexion, tmp_path):
    """examples/hip_flexion.py's drawing, on this run: without moment-arm outputs it plots −∂l/∂q
    of the run's lengths, with them the outputs."""
    spec = importlib.util.spec_from_file_location("hip_flexion", SOURCE / "examples/hip_flexion.py")
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    table = flexion.run()
    example.draw(flexion, table, tmp_path / "derivative.png")
    output = "iliacus_r.moment_arm_hip_flexion_r_mm"
    arm, how = example.moment_arm_mm(table, output, "iliacus_r.fibre_length_mean_mm", "hip_flexion_r")
    assert how == example.DERIVATIVE and arm.shape == (9,) and np.isfinite(arm).all()
    assert arm[0] > 0  # the iliacus flexes the hip: it shortens as the hip flexes
    table[output] = np.full(9, 30.0)
    arm, how = example.moment_arm_mm(table, output, "iliacus_r.fibre_length_mean_mm", "hip_flexion_r")
    assert how == "output" and np.all(arm == 30.0)
    example.draw(flexion, table, tmp_path / "output.png")
    for name in ("derivative.png", "output.png"):
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
