# SPDX-License-Identifier: Apache-2.0
"""The moment-arm validation's geometry: the part of a fibre that a line of action's path spans."""
import json
import sys

import numpy as np
import pytest

from conftest import SOURCE

sys.path.insert(0, str(SOURCE / "scripts"))
import validate_moment_arms as validation  # noqa: E402


def test_a_straight_fibre_across_a_tilted_plane_keeps_the_length_beyond_it():
    fibre = np.array([[0.0, 0.0, 10.0 * k] for k in range(6)])  # 0 … 50 mm along z
    normal = np.array([0.0, 0.6, 0.8])  # the plane meets the z axis at z = 23 mm
    assert validation.length_past(fibre, np.array([0.0, 0.0, 23.0]), normal) == pytest.approx(27.0, abs=1e-12)


def test_a_fibre_that_leaves_and_reenters_the_far_side_counts_both_parts():
    fibre = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 4.0], [0.0, 0.0, -2.0], [0.0, 0.0, 6.0]])
    # beyond z = 1: 3 mm up to z = 4, 3 mm back down to the plane, 5 mm from it up to z = 6
    assert validation.length_past(fibre, np.array([0.0, 0.0, 1.0]), np.array([0.0, 0.0, 1.0])) == pytest.approx(11.0)


def test_a_fibre_wholly_before_the_plane_spans_nothing():
    fibre = np.array([[0.0, 0.0, -5.0], [1.0, 0.0, -3.0]])
    assert validation.length_past(fibre, np.zeros(3), np.array([0.0, 0.0, 1.0])) == 0.0


def test_the_scenes_lines_of_action_start_at_their_myoleg_paths_first_points():
    with open(SOURCE / "models/hip/landmarks/line_of_action_paths.json") as f:
        paths = json.load(f)["paths"]
    starts = validation.line_starts()
    assert set(starts) == set(validation.MUSCLES)
    body, point, normal = starts["psoas_r"]
    assert body == "pelvis"
    np.testing.assert_allclose(point, paths["psoas_r"][0])
    second = np.array(paths["psoas_r"][1])
    np.testing.assert_allclose(normal, (second - point) / np.linalg.norm(second - point))
