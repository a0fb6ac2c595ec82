# SPDX-License-Identifier: Apache-2.0
"""What `rbfmuscle run` wrote, for the scripts that measure runs: the columns of OUTDIR/outputs.csv."""
import csv
import os

import numpy as np


def read_outputs(out):
    """{column: 1-D array over the frames} of OUTDIR/outputs.csv (time, coordinates, outputs), in
    the file's column order."""
    with open(os.path.join(out, "outputs.csv")) as f:
        rows = list(csv.reader(f))
    header = rows[0]
    data = np.array([[float(x) for x in r] for r in rows[1:]], dtype=float).reshape(len(rows) - 1, len(header))
    return {name: data[:, k] for k, name in enumerate(header)}


def stack_vector(columns, name):
    """A vector output over the run, elements × frames: the columns NAME_0, NAME_1, … of
    read_outputs, in element order."""
    prefix = name + "_"
    elements = sorted((int(h[len(prefix):]), h) for h in columns
                      if h.startswith(prefix) and h[len(prefix):].isdigit())
    return np.array([columns[h] for _, h in elements])
