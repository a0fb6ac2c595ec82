#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
"""Moment arms of the hip scenes' muscles over their motion, against their lines of action.

Runs each scene once through build/bin/rbfmuscle with every muscle's `moment_arms` set to the
scene's coordinate (a central difference that re-runs each frame at q ± 0.01 rad), then draws per
muscle the mean over fibres, the range of the middle 80 % of fibres and the line of action's moment
arm against the angle (against the frame where the angle goes back and forth, as in the gait cycle;
docs/pictures/moment_arms_<scene>.png), and writes a table of the values at a few frames into
docs/moment_arms.md (scripts/validate_moment_arms.py sets the flexion's beside published ones in
README.md).
Moment arms follow OpenSim's sign:
r = −∂l/∂q, mm per rad (positive: the muscle shortens as the angle grows).

Usage: /usr/bin/python3 scripts/moment_arms.py [--scenes hip_flexion:hip_flexion_r,...] [--no-write] [--set C.P=V]...
(the default: every hip scene about its own coordinate, the gait cycle about the flexion)
Needs python3-numpy and python3-matplotlib (Debian) and a built host.
"""
import argparse
import os
import subprocess
import tempfile

import numpy as np

from readme_section import replace_readme_section
from run_outputs import read_outputs, stack_vector


ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
HOST = os.path.join(ROOT, "build", "bin", "rbfmuscle")
MUSCLES = ["glmax_r", "iliacus_r", "psoas_r"]
TABLE_FRAMES = 5  # evenly spaced over the motion


def moment_arm_sets(coordinate):
    """The overrides that make every muscle report its moment arms about `coordinate`."""
    return [f"{m}.moment_arms={coordinate}" for m in MUSCLES]


def run_scene(scene, coordinate, out_root, extra_sets=()):
    out = os.path.join(out_root, scene)
    sets = [a for v in list(extra_sets) + moment_arm_sets(coordinate) for a in ("--set", v)]
    subprocess.run([HOST, "run", os.path.join(ROOT, "models", "hip", scene + ".xml"), "-o", out, "--quiet"] + sets,
                   check=True)
    return read_arms(read_outputs(out), coordinate)


def read_arms(columns, coordinate):
    """The angles (deg) and, per muscle, its arms and lengths, from a run's columns (read_outputs)."""
    column = lambda name: columns[name]
    angle_deg = np.degrees(column(coordinate))
    result = {}
    for m in MUSCLES:
        fibres = stack_vector(columns, f"{m}.fibre_moment_arm_{coordinate}_mm").T  # frames × fibres
        result[m] = {
            "mean": column(f"{m}.moment_arm_{coordinate}_mm"),
            "fibres": fibres,
            "p10": np.percentile(fibres, 10, axis=1),
            "p90": np.percentile(fibres, 90, axis=1),
            "line": column(f"{m}.line_of_action_moment_arm_{coordinate}_mm"),
            "length": stack_vector(columns, f"{m}.fibre_length_mm").mean(axis=0),
            "line_length": column(f"{m}.line_of_action_length_mm"),
        }
    return angle_deg, result


def draw(scene, coordinate, angle_deg, result, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    steps = np.diff(angle_deg)
    by_angle = bool(np.all(steps > 0) or np.all(steps < 0))
    x = angle_deg if by_angle else np.arange(len(angle_deg))
    fig, axes = plt.subplots(1, len(MUSCLES), figsize=(4.2 * len(MUSCLES), 3.6), sharex=True)
    for ax, m in zip(axes, MUSCLES):
        r = result[m]
        ax.fill_between(x, r["p10"], r["p90"], color="#c0392b", alpha=0.2, label="fibres, 10–90 %")
        ax.plot(x, r["mean"], color="#c0392b", label="fibres, mean")
        ax.plot(x, r["line"], color="#34495e", linestyle="--", label="line of action")
        ax.axhline(0.0, color="#999999", linewidth=0.5)
        ax.set_title(m)
        ax.set_xlabel(f"{coordinate} (deg)" if by_angle else f"frame ({coordinate} goes back and forth)")
    axes[0].set_ylabel("moment arm −∂l/∂q (mm)")
    axes[0].legend(fontsize=8)
    fig.suptitle(f"{scene}: moment arms about {coordinate}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def table(results):
    lines = ["Moment arms (mm, OpenSim's sign: positive where the muscle shortens as the angle grows) at five "
             "frames evenly spaced over each motion, as angle: mean over fibres / line of action, by "
             "`scripts/moment_arms.py`:", "",
             "| scene | muscle |" + " |" * TABLE_FRAMES, "|---|---|" + "---|" * TABLE_FRAMES]
    for scene, (coordinate, angle_deg, result) in results.items():
        frames = np.linspace(0, len(angle_deg) - 1, TABLE_FRAMES).round().astype(int)
        for i, m in enumerate(MUSCLES):
            cells = [f"{angle_deg[j]:.0f}°: {round(result[m]['mean'][j])} / {round(result[m]['line'][j])}" for j in frames]
            lines.append(f"| {scene + ' (' + coordinate + ')' if i == 0 else ''} | {m} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def smoothness(results):
    """How much the arms change from one frame to the next: the mean over fibres, and each fibre's."""
    lines = ["Change of the moment arms from one frame to the next (mm), by `scripts/moment_arms.py`: the "
             "mean over fibres (largest), and each fibre's (median / 99th percentile / largest over fibres "
             "and frames):", "",
             "| scene | frame step (median) | muscle | mean over fibres | each fibre |", "|---|---|---|---|---|"]
    for scene, (coordinate, angle_deg, result) in results.items():
        step = np.median(np.abs(np.diff(angle_deg)))
        for i, m in enumerate(MUSCLES):
            mean = np.abs(np.diff(result[m]["mean"])).max()
            each = np.abs(np.diff(result[m]["fibres"], axis=0))
            lead = f"{scene} | {step:.2g}°" if i == 0 else " | "
            lines.append(f"| {lead} | {m} | {mean:.1f} | {np.median(each):.2f} / {np.percentile(each, 99):.1f} / "
                         f"{each.max():.1f} |")
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", default="hip_flexion:hip_flexion_r,hip_adduction:hip_adduction_r,"
                        "hip_rotation:hip_rotation_r,hip_gait:hip_flexion_r")
    parser.add_argument("--no-write", action="store_true", help="print the table, draw no picture")
    parser.add_argument("--set", action="append", default=[], metavar="C.P=V",
                        help="passed to rbfmuscle run, e.g. psoas_r.contacts=false (implies --no-write)")
    args = parser.parse_args()
    args.no_write = args.no_write or bool(args.set)
    results = {}
    with tempfile.TemporaryDirectory() as out_root:
        for item in args.scenes.split(","):
            scene, coordinate = item.split(":")
            angle_deg, result = run_scene(scene, coordinate, out_root, args.set)
            results[scene] = (coordinate, angle_deg, result)
            picture = os.path.join(ROOT, "docs", "pictures", f"moment_arms_{scene}.png")
            if not args.no_write:
                draw(scene, coordinate, angle_deg, result, picture)
                print("wrote", os.path.relpath(picture, ROOT))
    text = table(results) + "\n\n" + smoothness(results)
    print(text)
    if not args.no_write:
        replace_readme_section("moment arms", text, "docs/moment_arms.md")
        print("wrote docs/moment_arms.md")


if __name__ == "__main__":
    main()
