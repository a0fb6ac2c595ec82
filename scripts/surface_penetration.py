#!/usr/bin/env python3
"""Penetration of a muscle's extracted surface into the femur, every frame of a flexion run
written with --frames-mesh: an independent check of the contact probes' max_penetration_mm.

Each frame, the femur mesh (models/hip/meshes/femur_r.ply, CT frame, mm) is posed by the
frame's hip_flexion_r (outputs.sto) about the hip centre and the pelvis Z axis, as the scene
does; every surface vertex within 6 mm of the femur and behind the normal of the femur's closest
sample is tested inside/outside by its winding number, and the depth of those inside is their distance to the femur's triangles sampled at a
quarter of their edges (within about 0.3 mm).
Prints the deepest over the frames and, per frame deeper than 0.5 mm (the contacts'
tolerance): (frame, vertices inside, deepest mm). Rest overlap counts too (the iliacus's
insertion lies up to 0.6 mm inside the femur at rest).
    surface_penetration.py OUTDIR MUSCLE      e.g. surface_penetration.py out/flexion iliacus_r
Flexion only (adduction and rotation must be 0); needs numpy and scipy.
"""
import os
import sys

import numpy as np
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_io  # noqa: E402
from surface_jumps import AXIS, HIP_MM, sampled  # noqa: E402

FEMUR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "models", "hip", "meshes", "femur_r.ply")
NEAR_MM = 6.0
REPORT_MM = 0.5  # frames listed: deeper than the contacts' tolerance


def winding_numbers(points, vertices, triangles):
    """Generalised winding number of a closed mesh at each point (1 inside, 0 outside)."""
    out = np.empty(len(points))
    for n, p in enumerate(points):
        a, b, c = (vertices[triangles[:, i]] - p for i in range(3))
        la, lb, lc = (np.linalg.norm(x, axis=1) for x in (a, b, c))
        numerator = np.einsum("ij,ij->i", a, np.cross(b, c))
        denominator = (la * lb * lc + np.einsum("ij,ij->i", a, b) * lc + np.einsum("ij,ij->i", b, c) * la +
                       np.einsum("ij,ij->i", c, a) * lb)
        out[n] = np.arctan2(numerator, denominator).sum() / (2.0 * np.pi)
    return out


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    out, name = sys.argv[1], sys.argv[2]
    sto = os.path.join(out, "outputs.sto")
    if not os.path.isfile(sto):
        sys.exit(f"{sto}: not found (the output directory of a flexion run)")
    table = bench_io.Storage(sto)
    for column in ("hip_adduction_r", "hip_rotation_r"):
        if table.has(column) and np.any(np.abs(table.angle_deg(column)) > 1e-9):
            sys.exit(f"{out}/outputs.sto: {column} is not 0; this check poses the femur by flexion only")
    flexion_rad = np.radians(table.angle_deg("hip_flexion_r"))
    files = bench_io.frame_meshes(out, name)
    femur_v, femur_t = bench_io.read_ply(FEMUR)[:2]
    femur_samples = sampled(femur_v, femur_t)
    # The triangle of every sample (sampled() stacks the vertices, then the triangles once per
    # barycentric step), for a quick inside test by the closest sample's triangle normal.
    normals_t = np.cross(femur_v[femur_t[:, 1]] - femur_v[femur_t[:, 0]], femur_v[femur_t[:, 2]] - femur_v[femur_t[:, 0]])
    vertex_normals = np.zeros_like(femur_v)
    for i in range(3):
        np.add.at(vertex_normals, femur_t[:, i], normals_t)
    repeats = (len(femur_samples) - len(femur_v)) // len(femur_t)
    sample_normals = np.vstack([vertex_normals] + [normals_t] * repeats)
    axis = AXIS / np.linalg.norm(AXIS)
    worst, frames = 0.0, []
    for k, path in files:
        rotation = Rotation.from_rotvec(axis * flexion_rad[k]).as_matrix()
        pose = lambda x: (x - HIP_MM) @ rotation.T + HIP_MM  # noqa: E731
        posed_v, posed_samples = pose(femur_v), pose(femur_samples)
        tree = cKDTree(posed_samples)
        vertices = bench_io.read_vtp(path)[0]
        distance, closest = tree.query(vertices)
        # Candidates: near, and behind the closest sample's normal; the winding number decides.
        behind = np.einsum("ij,ij->i", vertices - posed_samples[closest], sample_normals[closest] @ rotation.T) < 0.0
        near = vertices[(distance < NEAR_MM) & behind]
        inside = near[winding_numbers(near, posed_v, femur_t) > 0.5] if len(near) else near
        depth = float(tree.query(inside)[0].max()) if len(inside) else 0.0
        if depth > REPORT_MM:
            frames.append((k, len(inside), round(depth, 2)))
        worst = max(worst, depth)
    print(f"{name}: deepest surface vertex inside the femur: {worst:.2f} mm; "
          f"frames deeper than {REPORT_MM} mm (frame, vertices inside, deepest mm): {frames}")


if __name__ == "__main__":
    main()
