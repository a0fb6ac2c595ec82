#!/usr/bin/env python3
"""Surface jumps between consecutive frames of a hip flexion run written with --frames-mesh.

For every vertex of frame k: its distance to frame k-1's surface (triangles sampled at a
quarter of their edges) minus the femur's own move there, 2 r sin(step/2) + 1 mm, r its
distance from the flexion axis (the check of tests/stability/dynamics/hip_muscle_dynamics_test.cpp).
Prints the worst excess and, per frame with an excess, (frame, worst mm, vertices over).
    surface_jumps.py OUTDIR MUSCLE STEP_DEG      e.g. surface_jumps.py out/flexion iliacus_r 1
CT frame, mm; needs numpy and scipy.
"""
import os
import sys

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_io  # noqa: E402

HIP_MM = np.array([143.225, 243.37, -432.499])  # hip joint centre (models/hip/landmarks)
AXIS = np.array([-0.9924778435393229, 0.11879490607095865, 0.029588855590025775])  # pelvis Z


def sampled(vertices, triangles, n=4):
    """Vertices plus points on every triangle at barycentric steps of 1/n."""
    points = [vertices]
    for i in range(1, n):
        for j in range(0, n - i + 1):
            a, b = i / n, j / n
            points.append(vertices[triangles[:, 0]] * (1 - a - b) + vertices[triangles[:, 1]] * a +
                          vertices[triangles[:, 2]] * b)
    return np.vstack(points)


def main():
    out, name, step_deg = sys.argv[1], sys.argv[2], float(sys.argv[3])
    axis = AXIS / np.linalg.norm(AXIS)
    previous, worst, frames = None, 0.0, []
    for k, (_, path) in enumerate(bench_io.frame_meshes(out, name)):
        vertices, triangles = bench_io.read_vtp(path)[:2]
        if previous is not None:
            d = cKDTree(previous).query(vertices)[0]
            u = vertices - HIP_MM
            r = np.linalg.norm(u - np.outer(u @ axis, axis), axis=1)
            excess = d - (2 * r * np.sin(0.5 * np.radians(step_deg)) + 1.0)
            if excess.max() > 0:
                frames.append((k, round(float(excess.max()), 2), int((excess > 0).sum())))
            worst = max(worst, float(excess.max()))
        previous = sampled(vertices, triangles)
    print(f"{name}: worst jump beyond the femur's move + 1 mm: {worst:.2f} mm; frames (frame, mm, vertices): {frames}")


if __name__ == "__main__":
    main()
