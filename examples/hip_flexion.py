#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
"""Hip flexion from Python: runs the flexion scene (models/hip/hip_flexion.xml, 0 to 80 degrees)
and plots each muscle's fibre length and moment arm against the hip angle into a PNG.

    export PYTHONPATH=$PWD/build/python
    /usr/bin/python3 examples/hip_flexion.py [--motion FILE] [--moment-arms COORDINATE] [--output PNG]

The muscles report their moment arms about COORDINATE (their `moment_arms` property, outputs
moment_arm_<coordinate>_mm and line_of_action_moment_arm_<coordinate>_mm). Without those outputs
(--moment-arms ''), the moment arm is -dl/dq of the run's lengths over the angle (numpy.gradient).
"""
import argparse
import os
import xml.etree.ElementTree as ElementTree

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
    p.add_argument("--moment-arms", default="hip_flexion_r",
                   help="coordinate the muscles report moment arms about ('' = none: -dl/dq of the run)")
    p.add_argument("--output", default=os.path.join(ROOT, "docs/pictures/hip_flexion_python.png"))
    return p.parse_args()


def moment_arm_mm(table, output, length_column, coordinate):
    """(moment arm in mm per frame, how it was obtained): the output when the table has it, else
    −∂l/∂q of the length column (virtual work; positive: the muscle shortens as q grows)."""
    if output in table:
        return table[output], "output"
    return -np.gradient(table[length_column], table[coordinate]), DERIVATIVE


def draw(model, table, output):
    """Draws the fibre lengths and moment arms of a run (model.run()'s table) into `output`."""
    # The coordinate the motion moves most.
    coordinate = max(model.coordinate_names, key=lambda name: np.ptp(table[name]))
    angle_deg = np.degrees(table[coordinate])
    muscles = [name for name in model.component_names if f"{name}.fibre_length_mean_mm" in table]

    fig, (lengths, arms) = plt.subplots(1, 2, figsize=(13, 5.6))
    sources = set()
    for muscle, colour in zip(muscles, COLOURS * len(muscles)):
        lengths.plot(angle_deg, table[f"{muscle}.fibre_length_mean_mm"], "-o", ms=3, color=colour,
                     label=f"{muscle} mean fibre")
        lengths.fill_between(angle_deg, table[f"{muscle}.fibre_length_min_mm"],
                             table[f"{muscle}.fibre_length_max_mm"], color=colour, alpha=0.15,
                             label=f"{muscle} min-max")
        arm, how = moment_arm_mm(table, f"{muscle}.moment_arm_{coordinate}_mm",
                                 f"{muscle}.fibre_length_mean_mm", coordinate)
        path, _ = moment_arm_mm(table, f"{muscle}.line_of_action_moment_arm_{coordinate}_mm",
                                f"{muscle}.line_of_action_length_mm", coordinate)
        sources.add(how)
        arms.plot(angle_deg, arm, "-o", ms=3, color=colour, label=f"{muscle} mean over fibres")
        arms.plot(angle_deg, path, "--", color=colour, label=f"{muscle} via-point line of action")
    lengths.set(xlabel=f"{coordinate} (deg)", ylabel="fibre length (mm)", title="Fibre length")
    how = "outputs" if sources == {"output"} else f"{DERIVATIVE} of the run's lengths"
    arms.set(xlabel=f"{coordinate} (deg)", ylabel="moment arm (mm)",
             title=f"Moment arm about {coordinate} ({how})")
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
    overrides = {}
    if args.moment_arms:
        for muscle in ElementTree.parse(args.model).getroot().iter("RBFMuscle"):
            overrides[f"{muscle.get('name')}.moment_arms"] = args.moment_arms
    model = rbfmuscle.Model(args.model, motion=args.motion, overrides=overrides)
    draw(model, model.run(), args.output)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
