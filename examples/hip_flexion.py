#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
"""Hip flexion from Python: runs the flexion scene (models/hip/hip_flexion.xml, 0 to 80 degrees)
and plots each muscle's fibre length and moment arm against the hip angle into a PNG.

    export PYTHONPATH=$PWD/build/python
    /usr/bin/python3 examples/hip_flexion.py [--motion FILE] [--output PNG]

The moment arm is the muscle's output moment_arm_<coordinate>_mm when it has one; otherwise
−∂l/∂q of its mean fibre length l over the angle q (numpy.gradient), beside that of its
via-point line of action for comparison.
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import rbfmuscle  # noqa: E402

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
COLOURS = ["#c0392b", "#e67e22", "#8e44ad", "#16a085"]
DERIVATIVE = "−∂l/∂q"


def parse_args():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--model", default=os.path.join(ROOT, "models/hip/hip_flexion.xml"))
    p.add_argument("--motion", default=None, help="a motion file instead of the model's")
    p.add_argument("--output", default=os.path.join(ROOT, "docs/pictures/hip_flexion_python.png"))
    return p.parse_args()


def moment_arm_mm(table, muscle, coordinate, length_column):
    """(moment arm in mm per frame, how it was obtained)."""
    output = f"{muscle}.moment_arm_{coordinate}_mm"
    if output in table:
        return table[output], f"output moment_arm_{coordinate}_mm"
    # Moment arm = −∂l/∂q (virtual work): a muscle that shortens as q grows turns q positive.
    return -np.gradient(table[length_column], table[coordinate]), DERIVATIVE


def draw(model, table, output):
    """Draws the fibre lengths and moment arms of a run (model.run()'s table) into `output`."""
    # The coordinate the motion moves most.
    coordinate = max(model.coordinate_names, key=lambda name: np.ptp(table[name]))
    angle_deg = np.degrees(table[coordinate])
    muscles = [name for name in model.component_names if f"{name}.fibre_length_mean_mm" in table]

    fig, (lengths, arms) = plt.subplots(1, 2, figsize=(13, 5.6))
    labels = set()
    for muscle, colour in zip(muscles, COLOURS * len(muscles)):
        mean = table[f"{muscle}.fibre_length_mean_mm"]
        lengths.plot(angle_deg, mean, "-o", ms=3, color=colour, label=f"{muscle} mean fibre")
        lengths.fill_between(angle_deg, table[f"{muscle}.fibre_length_min_mm"],
                             table[f"{muscle}.fibre_length_max_mm"], color=colour, alpha=0.15,
                             label=f"{muscle} min-max")
        arm, how = moment_arm_mm(table, muscle, coordinate, f"{muscle}.fibre_length_mean_mm")
        labels.add(how)
        arms.plot(angle_deg, arm, "-o", ms=3, color=colour, label=f"{muscle} fibres ({how})")
        path, _ = moment_arm_mm(table, muscle, coordinate, f"{muscle}.line_of_action_length_mm")
        if how == DERIVATIVE:
            arms.plot(angle_deg, path, "--", color=colour, label=f"{muscle} via-point path ({DERIVATIVE})")
    lengths.set(xlabel=f"{coordinate} (deg)", ylabel="fibre length (mm)", title="Fibre length")
    arms.set(xlabel=f"{coordinate} (deg)", ylabel="moment arm (mm)",
             title=f"Moment arm about {coordinate}" +
             (f" ({DERIVATIVE}, l: mean fibre length)" if DERIVATIVE in labels else ""))
    arms.axhline(0.0, color="0.6", lw=0.8)
    for axes in (lengths, arms):
        axes.grid(alpha=0.3)
        axes.legend(fontsize=8, ncol=3, loc="upper center", bbox_to_anchor=(0.5, -0.13))
    fig.suptitle(f"{model.name}: {len(angle_deg)} frames run from Python (rbfmuscle.Model)")
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(output)), exist_ok=True)
    fig.savefig(output, dpi=100)
    plt.close(fig)


def main():
    args = parse_args()
    model = rbfmuscle.Model(args.model, motion=args.motion)
    draw(model, model.run(), args.output)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
