#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Measures how far each muscle's field drifts from the tissue map's image of its rest surface in
hip flexion to 120°, and writes the table into docs/design.md ("Kernels that deform with the
tissue").

Usage: scripts/measure_field_drift.py [--no-write]
Runs models/hip/hip_flexion.xml once over 0 → 120° in 1° frames with --frames-mesh (the tracked
surface reports surface_start_residual_max, the largest |f| at a carried vertex before its
projection onto f = 0) and tabulates it every 20°.
"""
import argparse
import os
import subprocess
import sys
import tempfile

from readme_section import replace_readme_section
from run_outputs import read_outputs

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
HOST = os.path.join(ROOT, "build", "bin", "rbfmuscle")
ANGLES_DEG = range(0, 121, 20)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-write", action="store_true", help="print the table, leave docs/design.md alone")
    args = parser.parse_args()
    hip = os.path.join(ROOT, "models", "hip")
    with tempfile.TemporaryDirectory() as out_root:
        out = os.path.join(out_root, "run")
        print("running hip_flexion.xml to 120° with --frames-mesh (about a minute)", file=sys.stderr)
        subprocess.run([HOST, "run", os.path.join(hip, "hip_flexion.xml"), "-o", out, "--motion",
                        os.path.join(hip, "motions", "hip_flexion_0_120.mot"), "--frames-mesh", "--quiet"], check=True)
        columns = read_outputs(out)
    muscles = sorted({h.split(".")[0] for h in columns if h.endswith(".surface_start_residual_max")})
    lines = ["| muscle | " + " | ".join(f"{a}°" for a in ANGLES_DEG) + " |",
             "|---|" + "---|" * len(ANGLES_DEG)]
    for m in muscles:
        drift = columns[m + ".surface_start_residual_max"]
        lines.append(f"| {m} | " + " | ".join(f"{drift[a]:.2g}" if drift[a] < 10 else f"{drift[a]:.0f}"
                                               for a in ANGLES_DEG) + " |")
    text = "\n".join(lines)
    print(text)
    if not args.no_write:
        replace_readme_section("field drift", text, path="docs/design.md")
        print("wrote the field drift table of docs/design.md")


if __name__ == "__main__":
    main()
