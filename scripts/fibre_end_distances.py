#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
"""How far each muscle's fibres reach their attachment areas, at rest.

Loads a scene (default models/hip/hip_flexion.xml) through the Python module, steps it at rest
with geometry, and for every muscle whose origin_area and insertion_area name clouds of a
landmark file (`FILE: NAME, NAME`) prints, over the fibres (minimum / median / maximum, mm):
the distance from each fibre's attachment (its first or last point) to the nearest point of its
area's clouds, and the length of its tendon, from that attachment to the fibre's last point
inside the muscle. The attachments and those points move rigidly with their bones (the hip
scenes' tests hold them there), so the distances at rest hold at every frame.

Usage: PYTHONPATH=build/python /usr/bin/python3 scripts/fibre_end_distances.py [MODEL.xml]
"""
import json
import os
import sys
import xml.etree.ElementTree as ElementTree

import numpy as np

import rbfmuscle

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def read_area(model_dir, spec):
    """The points (n×3, mm) of the clouds `FILE: NAME, NAME` names, or None for another kind of area."""
    if ":" not in spec or not spec.split(":")[0].strip().endswith(".json"):
        return None
    file, names = spec.split(":", 1)
    path = os.path.join(model_dir, file.strip())
    with open(path) as f:
        clouds = json.load(f)["clouds"]
    missing = [name.strip() for name in names.split(",") if name.strip() not in clouds]
    if missing:
        sys.exit(f"fibre_end_distances.py: error: {path} has no cloud named {', '.join(missing)}")
    return np.array([p["mm"] for name in names.split(",") for p in clouds[name.strip()]], dtype=float)


def summary(values):
    """min / median / max, to 0.1 mm."""
    return f"{values.min():.1f} / {np.median(values):.1f} / {values.max():.1f}"


def main():
    model_path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "models", "hip", "hip_flexion.xml")
    model_dir = os.path.dirname(os.path.abspath(model_path))
    model = rbfmuscle.Model(model_path)
    model.step({}, geometry=True)
    print("| muscle | end | attachment to the nearest area point, min / median / max (mm) | tendon length, min / median / max (mm) |")
    print("|---|---|---|---|")
    for muscle in ElementTree.parse(model_path).getroot().iter("RBFMuscle"):
        name = muscle.get("name")
        fibres = model.fibres(name)
        for end, column, inside in (("origin", 0, 1), ("insertion", -1, -2)):
            area = read_area(model_dir, muscle.findtext(end + "_area", ""))
            if area is None:
                continue
            ends = fibres[:, column, :]
            distances = np.sqrt(((ends[:, None, :] - area[None, :, :]) ** 2).sum(axis=2)).min(axis=1)
            tendons = np.linalg.norm(fibres[:, inside, :] - ends, axis=1)
            print(f"| {name} | {end} | {summary(distances)} | {summary(tendons)} |")


if __name__ == "__main__":
    main()
