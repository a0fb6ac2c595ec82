#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Runs the hip scenes and writes the README's "Measured" section from their outputs.

Usage: scripts/measure_scenes.py [--scenes hip_flexion,hip_adduction,...] [--no-write]
Each scene runs once through build/bin/rbfmuscle (no frame meshes), then its summary.json and
outputs.csv give, per muscle: the median wall time of a frame's update and of each stage, the
volume ratio's range over the frames, the fibre length ratio at the first and last frame, the
fibre length steps of more than 1 % between consecutive frames (fibre-frames, and the largest
step), and the most fibre points left outside. A second run counts every muscle's pieces at
every frame (check_pieces_cell_mm = 2, a grid check that would slow the first run's timings):
the frames not in one piece and the largest volume outside the largest piece. Timings depend on
the machine and its load: the table states the machine's core count and load.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

import numpy as np

from readme_section import replace_readme_section
from run_outputs import read_outputs, stack_vector

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
HOST = os.path.join(ROOT, "build", "bin", "rbfmuscle")
STAGES = ["contacts", "prediction", "descent", "volume", "fibres"]
PIECE_CELL_MM = 2.0


def run_host(scene, out, extra=()):
    subprocess.run([HOST, "run", os.path.join(ROOT, "models", "hip", scene + ".xml"), "-o", out, "--quiet", *extra],
                   check=True)
    return read_outputs(out)


def count_pieces(scene, muscles, out_root):
    """Per muscle: frames not in one piece, and the largest stray volume (mm³), from a run with the check on."""
    checks = [a for m in muscles for a in ("--set", f"{m}.check_pieces_cell_mm={PIECE_CELL_MM}")]
    columns = run_host(scene, os.path.join(out_root, scene + "_pieces"), checks)
    return {m: (int((np.array(columns[m + ".pieces"]) != 1).sum()), max(columns[m + ".stray_volume_mm3"]))
            for m in muscles}


def run_scene(scene, out_root):
    out = os.path.join(out_root, scene)
    columns = run_host(scene, out)
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    column = lambda name: columns[name]
    muscles = sorted({h.split(".")[0] for h in columns if h.endswith(".volume_ratio")})
    pieces = count_pieces(scene, muscles, out_root)
    figures = []
    for m in muscles:
        volume = column(m + ".volume_ratio")
        fibre = column(m + ".fibre_length_ratio")
        lengths = stack_vector(columns, m + ".fibre_length_mm")  # fibres × frames
        steps = np.abs(lengths[:, 1:] / lengths[:, :-1] - 1.0)
        figures.append({
            "muscle": m,
            "update_ms": statistics.median(column(m + ".update_ms")),
            "stages_ms": {s: statistics.median(column(f"{m}.{s}_ms")) for s in STAGES},
            "volume": (min(volume), max(volume)),
            "fibre": (fibre[0], fibre[-1]),
            "steps": (int((steps > 0.01).sum()), float(steps.max()) if steps.size else 0.0),
            "outside": max(column(m + ".fibre_points_outside")),
            "pieces": pieces[m],
        })
    return summary, figures


def table(results):
    lines = [f"Measured by `scripts/measure_scenes.py` on a {os.cpu_count()}-core machine "
             f"(load {os.getloadavg()[0]:.1f} when it ended); a frame updates the muscles in parallel, sharing their per-point loops. Pieces are "
             f"counted on a {PIECE_CELL_MM:g} mm grid in a second run (`check_pieces_cell_mm`).",
             "",
             "| scene | frame median (ms) | frames/s | muscle | update median (ms) | of it: contacts / prediction / descent / volume / fibres (ms) | volume ratio | fibre length ratio, first → last frame | fibre steps > 1 % between frames (largest) | fibre points outside | frames not in one piece (largest stray volume, mm³) |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for scene, (summary, figures) in results.items():
        median = summary["frame_wall_ms"]["median"]
        for i, f in enumerate(figures):
            stages = " / ".join(f"{f['stages_ms'][s]:.1f}" for s in STAGES)
            lines.append(f"| {scene if i == 0 else ''} | {f'{median:.1f}' if i == 0 else ''} | "
                         f"{f'{1000.0 / median:.1f}' if i == 0 else ''} | {f['muscle']} | {f['update_ms']:.1f} | {stages} | "
                         f"{f['volume'][0]:.4f} – {f['volume'][1]:.4f} | {f['fibre'][0]:.3f} → {f['fibre'][1]:.3f} | "
                         f"{f['steps'][0]} ({100.0 * f['steps'][1]:.2f} %) | {f['outside']:.0f} | "
                         f"{f['pieces'][0]} ({f['pieces'][1]:.0f}) |")
    if "hip_flexion" in results and "hip_flexion_osim" in results:
        lines[0] += " " + axes_comparison(results["hip_flexion"][1], results["hip_flexion_osim"][1])
    return "\n".join(lines)


def flexion_axis(skeleton_model):
    """Unit axis (ground) about which hip_flexion_r turns the femur in models/hip/SKELETON_MODEL.xml,
    from the femur's poses at rest and at 0.5 rad by the Python module (build/python)."""
    sys.path.insert(0, os.path.join(ROOT, "build", "python"))
    import rbfmuscle
    model = rbfmuscle.Model(os.path.join(ROOT, "models", "hip", skeleton_model + ".xml"))
    rest = model.body_transform("femur_r")
    model.step({"hip_flexion_r": 0.5})
    turn = (model.body_transform("femur_r") @ np.linalg.inv(rest))[:3, :3]
    axis = np.array([turn[2, 1] - turn[1, 2], turn[0, 2] - turn[2, 0], turn[1, 0] - turn[0, 1]])
    return axis / np.linalg.norm(axis)


def axes_comparison(urdf, osim):
    """The same muscles flexed about the URDF scene's axis and about the subject's own OpenSim
    joint (models/hip/README.md, "The two flexion axes")."""
    pairs = ", ".join(f"{u['muscle']} {u['fibre'][1]:.3f} against {o['fibre'][1]:.3f}"
                      for u, o in zip(urdf, osim) if u["muscle"] == o["muscle"])
    cosine = abs(float(flexion_axis("skeleton_flexion") @ flexion_axis("skeleton_flexion_osim")))
    return ("`hip_flexion_osim` flexes the same muscles about the subject's own OpenSim hip joint, whose "
            f"flexion axis lies {np.degrees(np.arccos(min(cosine, 1.0))):.2f}° from the URDF scene's "
            "(`models/hip/README.md`); fibre length ratio at the last frame, URDF against OpenSim joint: "
            f"{pairs}.")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", default="hip_flexion,hip_flexion_osim,hip_adduction,hip_rotation,hip_gait")
    parser.add_argument("--no-write", action="store_true", help="print the table, leave README.md alone")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as out_root:
        results = {s: run_scene(s, out_root) for s in args.scenes.split(",")}
    text = table(results)
    print(text)
    if args.no_write:
        return
    replace_readme_section("measured", text)
    print("wrote the Measured section of README.md")


if __name__ == "__main__":
    main()
