# SPDX-License-Identifier: Apache-2.0
"""rbfmuscle.fit: the fit command from Python, on a small test shape (a 28 × 63 × 62 mm block)."""
import re
import subprocess

import numpy as np

import rbfmuscle
from conftest import HOST, SHAPES

MESH = SHAPES / "block.ply"
SMALL = dict(centres=60, halton=2000, check_band=2000, metric_points=100000, cell_mm=2.0)
SMALL_ARGUMENTS = ["--centres", "60", "--halton", "2000", "--check-band", "2000", "--metric-points", "100000",
                   "--cell-mm", "2.0"]


def without_times(rbf_text):
    """An .rbf file's text without the wall time its figures record."""
    return re.sub(r'"seconds": [0-9.e+-]+', '"seconds": _', rbf_text)


def test_fit_writes_the_commands_surface_and_returns_its_figures(tmp_path):
    # The command with the same options runs meanwhile: the fit releases the GIL.
    host = subprocess.Popen([str(HOST), "fit", str(MESH), "-o", str(tmp_path / "host.rbf"), "--quiet",
                             *SMALL_ARGUMENTS], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    result = rbfmuscle.fit(MESH, tmp_path / "block.rbf", surface=tmp_path / "block_surface.ply", **SMALL)
    _, err = host.communicate(timeout=300)
    assert host.returncode == 0, err
    assert without_times((tmp_path / "host.rbf").read_text()) == without_times((tmp_path / "block.rbf").read_text())

    assert result["centres"] == 60
    assert result["jaccard"] > 0.9
    for key in ("mean_distance_mm", "p95_distance_mm", "max_distance_mm", "volume_ratio", "seconds"):
        assert np.isfinite(result[key]), key
    assert result["warnings"] == []
    vertices, triangles = result["surface_vertices_mm"], result["surface_triangles"]
    assert vertices.shape[1] == 3 and triangles.shape[1] == 3 and len(triangles) > 100
    assert np.isfinite(vertices).all() and 0 <= triangles.min() and triangles.max() < len(vertices)
    # In the mesh's frame: the block spans y and z in [-31, 31] mm.
    assert np.all(np.abs(vertices[:, 1:].mean(axis=0)) < 2.0)
    assert (tmp_path / "block_surface.ply").stat().st_size > 0


def test_fit_without_output_writes_nothing(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = rbfmuscle.fit(MESH, **SMALL)
    assert result["centres"] == 60 and len(result["surface_triangles"]) > 100
    assert list(tmp_path.iterdir()) == []
