#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
"""How the main job's figures change with the numerical resolution: each setting halved and
doubled for all three muscles (fibres, their segments, the quadrature points that also set the
tissue map's lattice, and the fitted centres), against the defaults.

Runs build/bin/rbfmuscle on models/hip/hip_flexion.xml once per row (fitting the surfaces a row
needs into OUTDIR/fits first) and writes the table into docs/design.md ("Resolution").

Usage: /usr/bin/python3 scripts/resolution_table.py [OUTDIR] [--no-write]   (default out/resolution;
about ten minutes on a 2-core machine). Needs python3-numpy (Debian) and a built host.
"""
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np

from readme_section import replace_readme_section
from run_outputs import read_outputs, stack_vector
from scene_bones import out_of_argument

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
HOST = os.path.join(ROOT, "build", "bin", "rbfmuscle")
SCENE = os.path.join(ROOT, "models", "hip", "hip_flexion.xml")
# Each muscle of the scene: its mesh (relative to the scene) and its centres.
MUSCLES = {m.get("name"): (m.findtext("mesh_file"), int(m.findtext("centres")))
           for m in ET.parse(SCENE).getroot().iter("RBFMuscle")}
ARM_FRAME = 40  # 40° of flexion, 1° frames


def for_all(setting, value):
    return [a for m in MUSCLES for a in ("--set", f"{m}{setting}={value}")]


def fitted_centres(out, muscle, factor):
    """--set arguments that give `muscle` `factor` times its scene's centres, fitting them first."""
    mesh, centres = MUSCLES[muscle]
    n = int(centres * factor)
    path = os.path.join(out, "fits", f"{muscle}_{n}.rbf")
    if not os.path.exists(path):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        print(f"resolution: fitting {mesh} with {n} centres", file=sys.stderr)
        subprocess.run([HOST, "fit", os.path.join(os.path.dirname(SCENE), mesh), "--centres", str(n),
                        "-o", path, "--quiet"] + out_of_argument(SCENE), check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return ["--set", f"{muscle}.centres={n}", "--set", f"{muscle}.surface_file={path}"]


def measure(out, name, args):
    """The row's cells (one per muscle), or the host's error when it refuses the scene."""
    run = os.path.join(out, name)
    print(f"resolution: {name}", file=sys.stderr)
    done = subprocess.run([HOST, "run", SCENE, "-o", run, "--quiet"] + for_all(".moment_arms", "hip_flexion_r") + args,
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        errors = [line for line in done.stderr.splitlines() if "error:" in line]
        return errors[-1] if errors else done.stderr.strip()
    o = read_outputs(run)
    cells = []
    for m in MUSCLES:
        lengths = stack_vector(o, m + ".fibre_length_mm")  # fibres × frames
        step = 100 * np.max(np.abs(np.diff(lengths, axis=1)) / lengths[:, :-1])
        cells.append(f"{o[m + '.fibre_length_ratio'][-1]:.3f} / {step:.2f} % / "
                     f"{o[m + '.moment_arm_hip_flexion_r_mm'][ARM_FRAME]:.1f}")
    return cells


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    out = os.path.abspath(args[0] if args else os.path.join(ROOT, "out", "resolution"))
    centres = " / ".join(str(c) for _, c in MUSCLES.values())
    rows = [(f"defaults (100 fibres of 15 segments, 2000 quadrature points, {centres} centres)", [])]
    rows += [(f"fibres {n}", for_all("/fibres.count", n)) for n in (50, 200)]
    rows += [(f"segments {n}", for_all("/fibres.segments", n)) for n in (30, 60)]
    rows += [(f"quadrature points {n}", for_all("/volume.quadrature_points", n)) for n in (1000, 4000)]
    # Centres: one muscle at a time, so that a muscle the host refuses leaves the others' cells.
    rows += [(f"centres ×{f:g}", {m: fitted_centres(out, m, f) for m in MUSCLES}) for f in (0.5, 2)]
    lines = ["The main job (`hip_flexion.xml`, 0 → 80° in 1° frames) with one setting changed for all three "
             "muscles (the centres for one muscle at a time), by `scripts/resolution_table.py`. Per muscle: fibre length ratio at 80° / largest fibre "
             "step between 1° frames / flexion moment arm at 40° (mm).",
             "",
             "| setting | " + " | ".join(MUSCLES) + " |",
             "|---|" + "---|" * len(MUSCLES)]
    refusals = []

    def cells_of(name, label, extra):
        cells = measure(out, name, extra)
        if isinstance(cells, str):
            refusals.append(f"- {label}: `{cells.split('error: ', 1)[-1].split(': ', 1)[-1]}`")
            return ["refused (below)"] * len(MUSCLES)
        return cells

    for i, (label, extra) in enumerate(rows):
        if isinstance(extra, dict):  # per muscle: its cell from its own run
            cells = [cells_of(f"row{i}_{m}", f"{label}, {m}", args)[k] for k, (m, args) in enumerate(extra.items())]
        else:
            cells = cells_of(f"row{i}", label, extra)
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    if refusals:
        lines += ["", "The host refused:"] + refusals
    text = "\n".join(lines)
    print(text)
    if "--no-write" not in sys.argv:
        replace_readme_section("resolution", text, "docs/design.md")


if __name__ == "__main__":
    main()
