# SPDX-License-Identifier: Apache-2.0
"""rbfmuscle from Python: load a scene, run it or step it with your own joint angles, read its
outputs, surfaces and fibres as NumPy arrays, and fit muscle surfaces.

Everything is in millimetres and radians, as in the command line. Errors raise
rbfmuscle.Error (a RuntimeError) with the command line's message; frames and fits run without
the GIL.

    import rbfmuscle
    model = rbfmuscle.Model("models/hip/hip_flexion.xml", overrides={"iliacus_r/fibres.count": 50})
    table = model.run()                    # dict column -> 1-D array, as outputs.csv
    model.step({"hip_flexion_r": 0.5}, geometry=True)
    vertices, triangles = model.surface("iliacus_r")
"""
import json
import os

import numpy

from ._rbfmuscle import Error, UsageError, _fit
from ._rbfmuscle import Model as _Model

__all__ = ["Error", "UsageError", "Model", "fit", "stack_columns"]


def _property_text(value):
    """A property value as the model file writes it."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


def _assignments(overrides):
    """COMPONENT[/SUBCOMPONENT].PROPERTY=VALUE strings from a dict or a sequence of such strings."""
    if overrides is None:
        return []
    if isinstance(overrides, str):
        return [overrides]
    if isinstance(overrides, dict):
        return [f"{key}={_property_text(value)}" for key, value in overrides.items()]
    return [str(item) for item in overrides]


class Model(_Model):
    """A model file loaded as `rbfmuscle run` loads it, its components initialised.

    overrides: {"COMPONENT.PROPERTY": value} or ["COMPONENT.PROPERTY=VALUE", ...] (--set; a
    subcomponent's property is COMPONENT/SUBCOMPONENT.PROPERTY);
    motion: a motion file that replaces the model's (--motion, relative to the working
    directory); plugins: plugins loaded before the model's own (-L).
    """

    def __init__(self, path, *, overrides=None, motion=None, plugins=()):
        super().__init__(os.fspath(path), _assignments(overrides),
                         "" if motion is None else os.fspath(motion),
                         [os.fspath(p) for p in plugins])


# Keyword -> option of `rbfmuscle fit` (None: the command's default).
_FIT_OPTIONS = {
    "centres": "--centres", "tolerance_mm": "--tolerance-mm", "clamp_mm": "--clamp-mm",
    "normal_offset_mm": "--normal-offset-mm", "halton": "--halton", "check_band": "--check-band",
    "check_start": "--check-start", "check_slope": "--check-slope", "crumb_margin_mm": "--crumb-margin-mm", "shapes": "--shapes", "gamma": "--gamma",
    "batch_fraction": "--batch-fraction", "cell_mm": "--cell-mm", "metric_points": "--metric-points",
    "global_shape": "--global-shape", "global_search": "--global-search",
}


def _option_text(value):
    if isinstance(value, (list, tuple, numpy.ndarray)):
        return ",".join(_option_text(v) for v in value)
    if isinstance(value, float):
        return repr(value)
    return str(value)


def fit(mesh, output=None, *, surface=None, centres=None, tolerance_mm=None, clamp_mm=None,
        normal_offset_mm=None, halton=None, check_band=None, check_layers=True, check_start=None,
        check_slope=None, crumb_margin_mm=None, shapes=None, gamma=None, batch_fraction=None, cell_mm=None, metric_points=None,
        global_shape=None, global_search=None, fix_winding=False):
    """Fits a Gaussian RBF surface to a closed mesh, as `rbfmuscle fit` does (the keywords are
    its options; None keeps the command's default; `rbfmuscle fit --help` lists them).

    output: the .rbf file to write (None: nothing written); surface: the extracted surface as
    PLY. Returns a dict: the command's JSON figures (jaccard, mean_distance_mm, volume_ratio,
    centres, ...), "warnings", "stop_reason", "rounds", and the extracted surface in the mesh's
    frame, "surface_vertices_mm" (n×3) and "surface_triangles" (m×3).
    """
    args = [os.fspath(mesh)]
    if output is not None:
        args += ["-o", os.fspath(output)]
    if surface is not None:
        args += ["--surface", os.fspath(surface)]
    given = dict(centres=centres, tolerance_mm=tolerance_mm, clamp_mm=clamp_mm,
                 normal_offset_mm=normal_offset_mm, halton=halton, check_band=check_band,
                 check_start=check_start, check_slope=check_slope, crumb_margin_mm=crumb_margin_mm, shapes=shapes, gamma=gamma, batch_fraction=batch_fraction,
                 cell_mm=cell_mm, metric_points=metric_points, global_shape=global_shape,
                 global_search=global_search)
    for key, value in given.items():
        if value is not None:
            args += [_FIT_OPTIONS[key], _option_text(value)]
    if not check_layers:
        args.append("--no-check-layers")
    if fix_winding:
        args.append("--fix-winding")
    raw = _fit(args)
    result = json.loads(raw.pop("metrics_json"))
    result.update(raw)
    return result


def stack_columns(table, output):
    """The columns OUTPUT_0, OUTPUT_1, ... of a table (a vector output over the frames) as one
    frames × elements array, e.g. stack_columns(model.run(), "iliacus_r.fibre_length_mm")."""
    columns = []
    while f"{output}_{len(columns)}" in table:
        columns.append(table[f"{output}_{len(columns)}"])
    if not columns:
        raise KeyError(f"no columns {output}_0, {output}_1, ... in the table")
    return numpy.column_stack(columns)
