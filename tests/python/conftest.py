# SPDX-License-Identifier: Apache-2.0
"""Shared by the Python tests: where the sources and the build are, the host as a subprocess,
and the flexion scene loaded once per test run (its components take ~20 s to initialise)."""
import csv
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

SOURCE = Path(__file__).resolve().parents[2]
BINARY = Path(os.environ.get("RBFMUSCLE_BINARY_DIR", SOURCE / "build"))
HOST = BINARY / "bin" / "rbfmuscle"
FLEXION = SOURCE / "models/hip/hip_flexion.xml"
SHORT_MOTION = SOURCE / "models/hip/motions/hip_flexion_0_80_step10.mot"  # 9 frames, 0-80 deg
HOST_DATA = SOURCE / "tests/integration/host/data"
SHAPES = SOURCE / "models/shapes"


def run_host(*args, check=False):
    """`rbfmuscle ARGS`: the finished process, its output as text."""
    return subprocess.run([str(HOST), *map(str, args)], capture_output=True, text=True, check=check)


def host_error(*args):
    """The message the host prints after `rbfmuscle: error: ` for failing ARGS (the usage text it
    adds after a bad command line left out)."""
    result = run_host(*args)
    assert result.returncode != 0, result.stderr
    prefix = "rbfmuscle: error: "
    assert prefix in result.stderr, result.stderr
    message = result.stderr[result.stderr.index(prefix) + len(prefix):]
    usage = message.find("\nusage: rbfmuscle COMMAND")
    return (message[:usage] if usage >= 0 else message).rstrip("\n")


def read_csv(path):
    """outputs.csv as a dict column -> array, as the host wrote it (%.17g: exact)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    values = np.array([[float(v) for v in row] for row in rows[1:]])
    return {label: values[:, c] for c, label in enumerate(rows[0])}


@pytest.fixture(scope="session")
def host_flexion_run(tmp_path_factory):
    """The host running the flexion scene over the short motion, started first so that it runs
    while the Python module loads the same scene."""
    out = tmp_path_factory.mktemp("host") / "flexion"
    process = subprocess.Popen([str(HOST), "run", str(FLEXION), "-o", str(out), "--motion", str(SHORT_MOTION),
                                "--quiet"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    yield process, out
    if process.poll() is None:
        process.kill()
        process.wait()


@pytest.fixture(scope="session")
def flexion(host_flexion_run):
    import rbfmuscle
    return rbfmuscle.Model(FLEXION, motion=SHORT_MOTION)
