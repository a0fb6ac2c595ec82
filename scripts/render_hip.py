#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
"""Pictures of the hip scene: the muscles with the bones at 0, 40 and 80 degrees of
flexion (offscreen PNG, matplotlib Poly3DCollection, meshes decimated by vertex
clustering) and the fibre length curves against the hip angle.

Needs python3-numpy and python3-matplotlib (Debian) and a built host.
    /usr/bin/python3 scripts/render_hip.py                    # runs the 10-degree motion with --frames-mesh
    /usr/bin/python3 scripts/render_hip.py --run out/flexion  # uses an earlier run (needs meshes/ for the 3-D picture)
Writes REPORT/hip_flexion_0_40_80.png and REPORT/fibre_lengths.png (REPORT: docs/pictures).

Bones: the pelvis mesh as is (pelvis welded to ground) and the femur mesh moved by the
hip joints of the URDF at each frame's coordinates (read from outputs.sto). Muscles:
the per-frame surfaces the host writes (OUTDIR/meshes/NAME_#####.vtp, ground frame, mm).
"""
import argparse
import os
import re
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_io  # noqa: E402

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
MUSCLE_COLOURS = ["#c0392b", "#e67e22", "#8e44ad", "#16a085"]
BONE_COLOUR = "#e8e2d0"


def parse_args():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--host", default=os.path.join(ROOT, "build/bin/rbfmuscle"))
    p.add_argument("--model", default=os.path.join(ROOT, "models/hip/hip_flexion.xml"))
    p.add_argument("--motion", default=os.path.join(ROOT, "models/hip/motions/hip_flexion_0_80_step10.mot"),
                   help="motion of the run this script makes (ignored with --run)")
    p.add_argument("--run", default=None, help="an earlier run's OUTDIR instead of running the host")
    p.add_argument("--out", default=os.path.join(ROOT, "out/render_hip"), help="OUTDIR of the run made here")
    p.add_argument("--report", default=os.path.join(ROOT, "docs", "pictures"), help="directory of the pictures")
    p.add_argument("--angles", default="0,40,80", help="flexion angles (deg) of the 3-D pictures")
    p.add_argument("--cell-mm", type=float, default=4.0, help="decimation cell of the bone meshes (mm)")
    p.add_argument("--fibres", type=int, default=0, help="draw every N-th fibre over the muscles (0 = none)")
    p.add_argument("--views", default="-10,-70",
                   help="azimuths (deg) of the picture rows: -10 from the medial side (the CT +x), -70 from "
                        "anterior-medial (the CT -y is anterior)")
    return p.parse_args()


def decimate(vertices, triangles, cell_mm):
    """Vertex clustering: vertices in one cubic cell of size cell_mm become their mean;
    triangles that collapse are dropped. Returns (vertices, triangles)."""
    if cell_mm <= 0 or len(triangles) == 0:
        return vertices, triangles
    keys = np.floor((vertices - vertices.min(axis=0)) / cell_mm).astype(np.int64)
    _, cluster, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    cluster = cluster.reshape(-1)
    sums = np.zeros((counts.size, 3))
    np.add.at(sums, cluster, vertices)
    new_vertices = sums / counts[:, None]
    t = cluster[triangles]
    keep = (t[:, 0] != t[:, 1]) & (t[:, 1] != t[:, 2]) & (t[:, 0] != t[:, 2])
    t = t[keep]
    first = np.unique(np.sort(t, axis=1), axis=0, return_index=True)[1]  # one of each duplicate
    return new_vertices, t[np.sort(first)]


def shaded(vertices, triangles, colour, light=(0.6, 0.3, 0.75)):
    """Per-triangle RGBA colours: Lambert shading (two-sided) with an ambient term."""
    from matplotlib.colors import to_rgb
    a, b, c = (vertices[triangles[:, k]] for k in range(3))
    n = np.cross(b - a, c - a)
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)
    lam = np.abs(n @ (np.array(light) / np.linalg.norm(light)))
    shade = 0.35 + 0.65 * lam
    rgb = np.clip(np.array(to_rgb(colour))[None, :] * shade[:, None], 0, 1)
    return np.hstack([rgb, np.ones((len(rgb), 1))])


def run_host(args):
    cmd = [args.host, "run", args.model, "-o", args.out, "--quiet", "--frames-mesh", "--motion", args.motion]
    print("render_hip: " + " ".join(cmd), flush=True)
    subprocess.run(cmd, check=True)
    return args.out


def frame_of_angle(angles_deg, angle):
    k = int(np.argmin(np.abs(angles_deg - angle)))
    if abs(angles_deg[k] - angle) > 0.51:
        raise SystemExit(f"render_hip: no frame at {angle} deg (frames at {angles_deg.tolist()})")
    return k


def render_scene(run_dir, model, sto, angles, views, report, cell_mm, fibre_every):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    mesh_dir = os.path.join(model["directory"], "meshes")
    # The subject's pelvis: right ilium and sacrum (the muscles' bones) and the left ilium.
    pelvis_parts = [decimate(*bench_io.read_ply(os.path.join(mesh_dir, f"pelvis_{part}.ply")), cell_mm)
                    for part in ("iliac_r", "sacrum", "iliac_l")]
    offsets = np.cumsum([0] + [len(v) for v, _ in pelvis_parts[:-1]])
    pelvis = (np.vstack([v for v, _ in pelvis_parts]), np.vstack([t + o for (_, t), o in zip(pelvis_parts, offsets)]))
    femur = decimate(*bench_io.read_ply(os.path.join(mesh_dir, "femur_r.ply")), cell_mm)
    flexion = sto.angle_deg("hip_flexion_r")
    adduction = sto.angle_deg("hip_adduction_r") if sto.has("hip_adduction_r") else 0 * flexion
    rotation = sto.angle_deg("hip_rotation_r") if sto.has("hip_rotation_r") else 0 * flexion
    names = [m["name"] for m in model["muscles"]]
    fig = plt.figure(figsize=(5.0 * len(angles), 5.4 * len(views) + 0.6))
    bounds = None
    for p, (azimuth, angle) in enumerate((a, b) for a in views for b in angles):
        k = frame_of_angle(flexion, angle)
        R, c = bench_io.urdf_hip_rotation(model["skeleton"], flexion[k], adduction[k], rotation[k])
        ax = fig.add_subplot(len(views), len(angles), p + 1, projection="3d")
        parts = [(pelvis[0], pelvis[1], BONE_COLOUR), ((femur[0] - c) @ R.T + c, femur[1], BONE_COLOUR)]
        for j, name in enumerate(names):
            path = os.path.join(run_dir, "meshes", f"{name}_{k:05d}.vtp")
            if not os.path.exists(path):
                raise SystemExit(f"render_hip: {path} missing (run with --frames-mesh)")
            v, t, _ = bench_io.read_vtp(path)
            parts.append((*decimate(v, t, cell_mm * 0.5), MUSCLE_COLOURS[j % len(MUSCLE_COLOURS)]))
        for v, t, colour in parts:
            ax.add_collection3d(Poly3DCollection(v[t], facecolors=shaded(v, t, colour), linewidths=0))
        if fibre_every > 0:
            for j, name in enumerate(names):
                path = os.path.join(run_dir, "meshes", f"{name}_fibres_{k:05d}.vtp")
                if os.path.exists(path):
                    v, _, lines = bench_io.read_vtp(path)
                    segs = [v[line] for line in lines[::fibre_every]]
                    ax.add_collection3d(Line3DCollection(segs, colors="k", linewidths=0.4, alpha=0.6))
        if bounds is None:  # the same box for every panel: the rest pose plus the swing of the femur
            allv = np.vstack([parts[0][0], parts[1][0]] + [q[0] for q in parts[2:]])
            lo, hi = allv.min(axis=0), allv.max(axis=0)
            centre, half = (lo + hi) / 2, (hi - lo).max() / 2 * 0.85
            bounds = (centre, half)
        centre, half = bounds
        ax.set_xlim(centre[0] - half, centre[0] + half)
        ax.set_ylim(centre[1] - half, centre[1] + half)
        ax.set_zlim(centre[2] - half, centre[2] + half)
        ax.set_box_aspect((1, 1, 1))
        ax.view_init(elev=5, azim=azimuth)  # z (superior) up
        ax.set_axis_off()
        ax.set_title(f"hip flexion {flexion[k]:.0f}° (view azimuth {azimuth:g}°)")
    handles = [plt.Rectangle((0, 0), 1, 1, color=MUSCLE_COLOURS[j % len(MUSCLE_COLOURS)]) for j in range(len(names))]
    fig.legend(handles + [plt.Rectangle((0, 0), 1, 1, color=BONE_COLOUR)], names + ["bones"], loc="lower center",
               ncol=len(names) + 1)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    out = os.path.join(report, "hip_flexion_0_40_80.png")
    fig.savefig(out, dpi=100)
    plt.close(fig)
    return out


def plot_fibres(model, sto, report):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    angle = sto.angle_deg("hip_flexion_r")
    names = [m["name"] for m in model["muscles"]]
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6))
    for j, name in enumerate(names):
        colour = MUSCLE_COLOURS[j % len(MUSCLE_COLOURS)]
        if sto.has(f"{name}.fibre_length_mean_mm"):
            mean = sto[f"{name}.fibre_length_mean_mm"]
            axes[0].plot(angle, mean, color=colour, marker=".", label=f"{name} mean fibre")
            if sto.has(f"{name}.fibre_length_min_mm"):
                axes[0].fill_between(angle, sto[f"{name}.fibre_length_min_mm"], sto[f"{name}.fibre_length_max_mm"],
                                     color=colour, alpha=0.15, label=f"{name} min–max")
            axes[1].plot(angle, mean / mean[0], color=colour, marker=".", label=f"{name} mean fibre")
        if sto.has(f"{name}.line_of_action_length_mm"):
            loa = sto[f"{name}.line_of_action_length_mm"]
            axes[0].plot(angle, loa, color=colour, ls="--", label=f"{name} via-point line of action")
            axes[1].plot(angle, loa / loa[0], color=colour, ls="--", label=f"{name} line of action")
    axes[0].set_ylabel("length (mm)")
    axes[1].set_ylabel("length / length at 0°")
    for ax in axes:
        ax.set_xlabel("hip flexion (°)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Fibre lengths against hip flexion (RBF muscle fibres vs via-point paths)")
    fig.tight_layout()
    out = os.path.join(report, "fibre_lengths.png")
    fig.savefig(out, dpi=100)
    plt.close(fig)
    return out


def main():
    args = parse_args()
    model = bench_io.read_model(args.model)
    run_dir = args.run or run_host(args)
    sto = bench_io.Storage(os.path.join(run_dir, "outputs.sto"))
    os.makedirs(args.report, exist_ok=True)
    pictures = []
    if os.path.isdir(os.path.join(run_dir, "meshes")) and os.listdir(os.path.join(run_dir, "meshes")):
        angles = [float(a) for a in args.angles.split(",")]
        views = [float(v) for v in args.views.split(",")]
        pictures.append(render_scene(run_dir, model, sto, angles, views, args.report, args.cell_mm, args.fibres))
    else:
        print(f"render_hip: {run_dir} has no meshes/: 3-D picture skipped (run with --frames-mesh)")
    pictures.append(plot_fibres(model, sto, args.report))
    argv, skip = [], False
    for a in sys.argv[1:]:  # the command that makes the run too: without --run DIR
        if skip or a == "--run":
            skip = a == "--run"
            continue
        argv.append(a)
    command = "/usr/bin/python3 " + " ".join([os.path.relpath(os.path.abspath(sys.argv[0]), ROOT)] + argv)
    flexion = sto.angle_deg("hip_flexion_r")
    motion = f"{len(flexion)} frames, flexion {flexion.min():.0f}–{flexion.max():.0f}°"
    for p in pictures:
        print("render_hip: wrote " + os.path.relpath(p, ROOT))


if __name__ == "__main__":
    main()
