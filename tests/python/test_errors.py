# SPDX-License-Identifier: Apache-2.0
"""Errors raise rbfmuscle.Error with the message the command line prints after
`rbfmuscle: error: ` (rbfmuscle.UsageError where the command line adds its usage)."""
import pytest

import rbfmuscle
from conftest import FLEXION, HOST_DATA, SHAPES, SHORT_MOTION, host_error

BAD_MODELS = sorted(path.name for path in HOST_DATA.glob("bad_*.xml"))


def python_error(error_type, call):
    with pytest.raises(error_type) as raised:
        call()
    return str(raised.value)


@pytest.mark.parametrize("name", BAD_MODELS)
def test_a_bad_model_raises_the_hosts_message(name, tmp_path):
    model = HOST_DATA / name
    expected = host_error("run", model, "-o", tmp_path / "out", "--quiet")
    assert python_error(rbfmuscle.Error, lambda: rbfmuscle.Model(model)) == expected


def test_a_missing_model_file_raises_the_hosts_message(tmp_path):
    missing = tmp_path / "no_such_model.xml"
    expected = host_error("run", missing, "-o", tmp_path / "out")
    assert python_error(rbfmuscle.Error, lambda: rbfmuscle.Model(missing)) == expected


@pytest.mark.parametrize("assignment", ["iliacus_r/fibres.count=-3", "iliacus_r.no_such_property=1",
                                        "nobody.centres=3", "iliacus_r/fibres.count=many",
                                        "iliacus_r.fibres=3"])
def test_a_bad_override_raises_the_hosts_message(assignment, tmp_path):
    expected = host_error("run", FLEXION, "-o", tmp_path / "out", "--set", assignment)
    actual = python_error(rbfmuscle.Error, lambda: rbfmuscle.Model(FLEXION, overrides=[assignment]))
    assert actual == expected


def test_a_malformed_override_is_a_usage_error(tmp_path):
    expected = host_error("run", FLEXION, "-o", tmp_path / "out", "--set", "fibres=3")
    assert python_error(rbfmuscle.UsageError, lambda: rbfmuscle.Model(FLEXION, overrides="fibres=3")) == expected


def test_a_missing_motion_raises_the_hosts_message(tmp_path):
    motion = tmp_path / "missing.mot"
    expected = host_error("run", FLEXION, "-o", tmp_path / "out", "--motion", motion)
    assert python_error(rbfmuscle.Error, lambda: rbfmuscle.Model(FLEXION, motion=motion)) == expected


def test_a_missing_plugin_raises_the_hosts_message(tmp_path):
    expected = host_error("run", HOST_DATA / "femur_point.xml", "-o", tmp_path / "out", "-L", "no_such_plugin")
    actual = python_error(rbfmuscle.Error,
                          lambda: rbfmuscle.Model(HOST_DATA / "femur_point.xml", plugins=["no_such_plugin"]))
    assert actual == expected


@pytest.mark.parametrize("options, arguments", [
    (dict(clamp_mm=0.0), ["--clamp-mm", "0.0"]),
    (dict(centres=0), ["--centres", "0"]),
    (dict(gamma=2.0), ["--gamma", "2.0"]),
    (dict(crumb_margin_mm=-0.5), ["--crumb-margin-mm", "-0.5"]),
    (dict(check_slope=1.5), ["--check-slope", "1.5"]),
    (dict(global_search=(0.01, 0.1)), ["--global-search", "0.01,0.1"]),
])
def test_bad_fit_options_are_usage_errors_with_the_commands_message(options, arguments, tmp_path):
    mesh = SHAPES / "box.ply"
    expected = host_error("fit", mesh, "-o", tmp_path / "box.rbf", *arguments)
    actual = python_error(rbfmuscle.UsageError, lambda: rbfmuscle.fit(mesh, tmp_path / "box.rbf", **options))
    assert actual == expected


def test_a_missing_mesh_raises_the_fit_commands_message(tmp_path):
    mesh = tmp_path / "missing.ply"
    expected = host_error("fit", mesh, "-o", tmp_path / "out.rbf")
    assert python_error(rbfmuscle.Error, lambda: rbfmuscle.fit(mesh, tmp_path / "out.rbf")) == expected
    assert not (tmp_path / "out.rbf").exists()


def test_the_model_runs_after_a_femur_point_scene_with_the_test_plugin():
    """The test plugin is found in the build's lib directory, as the host finds it."""
    model = rbfmuscle.Model(HOST_DATA / "femur_point.xml", motion=SHORT_MOTION)
    table = model.run()
    assert len(table["time"]) == 9
