#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
"""Hip-flexion moment arms of the flexion scene's muscles against published ones.

Runs models/hip/hip_flexion.xml once through the Python module with every muscle's moment arms
about hip_flexion_r (as scripts/moment_arms.py asks the host for them), reads the published
curves of models/reference/hip_flexion_moment_arms.json (their sources, and how each was read,
are in that file), then
- draws one panel per muscle: our mean over fibres and the range of the middle 80 % of fibres, the
  line of action, and the published spread or mean (docs/pictures/moment_arms_literature.png);
- writes into README.md, between the "moment arm validation" markers, a table over 0–60° of flexion
  in 10° steps: ours, the line of action's, the published spread (Blemker & Delp 2005, fibres of an
  image-based model) or else mean (Németh & Ohlsén 1985, in vivo), and whether ours lies within the
  spread, or within 25 % of the mean where only a mean is given; and a table of each muscle's
  length change over 0–80°, ours (also over the part of our fibres that the line of action spans), the
  line of action's and the one the published spread of arms gives.
All in OpenSim's sign, r = −∂l/∂q (mm per rad; positive: the muscle shortens as the hip flexes).

Usage: /usr/bin/python3 scripts/validate_moment_arms.py [--no-write]
Needs python3-numpy and python3-matplotlib (Debian) and the built Python module (scripts/setup.sh).
"""
import argparse
import json
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np

from moment_arms import MUSCLES, ROOT, moment_arm_sets, read_arms
from readme_section import replace_readme_section

SCENE = os.path.join(ROOT, "models", "hip", "hip_flexion.xml")
REFERENCE = os.path.join(ROOT, "models", "reference", "hip_flexion_moment_arms.json")
PICTURE = os.path.join(ROOT, "docs", "pictures", "moment_arms_literature.png")
COORDINATE = "hip_flexion_r"
TABLE_ANGLES_DEG = range(0, 61, 10)
LENGTH_RANGE_DEG = (0, 80)  # the main job's motion
DIGITISED_END_DEG = 1.0  # a digitised curve may begin or end this close to the range, read as its end
MEAN_TOLERANCE = 0.25  # relative, where a source gives only a mean
UNIT_MM = {"mm": 1.0, "cm": 10.0}


def curve(points, unit, sign):
    """Sorted angles (deg) and values (mm, OpenSim's sign) of a digitised series."""
    a = np.array(sorted(points))
    return a[:, 0], sign * UNIT_MM[unit] * a[:, 1]


def load_reference():
    """{muscle: {"spread": [(source, angles, low, high)], "mean": [(source, angles, values)]}}."""
    with open(REFERENCE) as f:
        sources = json.load(f)["sources"]
    reference = {m: {"spread": [], "mean": []} for m in MUSCLES}
    for s in sources:
        name = short_name(s)
        for m, series in s.get("mean", {}).items():
            angles, values = curve(series, s["unit"], s["to_opensim_sign"])
            reference[m]["mean"].append((name, angles, values))
        for m, bounds in s.get("spread", {}).items():
            sign = s["to_opensim_sign_by_muscle"][m]
            a_up, up = curve(bounds["upper"], s["unit"], sign)
            a_lo, lo = curve(bounds["lower"], s["unit"], sign)
            start, stop = max(a_up[0], a_lo[0]), min(a_up[-1], a_lo[-1])
            angles = np.linspace(start, stop, 200)
            one, two = np.interp(angles, a_up, up), np.interp(angles, a_lo, lo)
            reference[m]["spread"].append((name, angles, np.minimum(one, two), np.maximum(one, two)))
    return reference


def short_name(source):
    """'Blemker & Delp 2005' from the citation's authors and the key's year."""
    authors = [a.strip().split(" ")[0] for a in source["citation"].split(".")[0].split(",")]
    year = source["key"][-4:]
    return (authors[0] + (" & " + authors[1] if len(authors) == 2 else " et al.")) + " " + year


def draw(angle_deg, result, reference):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(MUSCLES), figsize=(4.4 * len(MUSCLES), 3.8), sharex=True)
    for ax, m in zip(axes, MUSCLES):
        r = result[m]
        for name, a, lo, hi in reference[m]["spread"]:
            ax.fill_between(a, lo, hi, color="#2e86c1", alpha=0.15, label=f"{name}, fibres")
        for name, a, v in reference[m]["mean"]:
            ax.plot(a, v, "o", color="#1b4f72", markersize=3, label=f"{name}, mean")
        ax.fill_between(angle_deg, r["p10"], r["p90"], color="#c0392b", alpha=0.2, label="ours, fibres 10–90 %")
        ax.plot(angle_deg, r["mean"], color="#c0392b", label="ours, mean")
        ax.plot(angle_deg, r["line"], color="#34495e", linestyle="--", label="our line of action")
        ax.axhline(0.0, color="#999999", linewidth=0.5)
        ax.set_xlim(-10, 100)
        ax.set_title(m)
        ax.set_xlabel("hip flexion (deg)")
        ax.legend(fontsize=7)
    axes[0].set_ylabel("moment arm −∂l/∂q (mm)")
    fig.suptitle("Hip-flexion moment arms: the flexion scene against published ones")
    fig.tight_layout()
    fig.savefig(PICTURE, dpi=110)
    plt.close(fig)


def judge(value, spread, mean):
    """'yes'/'no' by the spread when there is one at this angle, else by the mean ± 25 %; '–' without either."""
    if spread is not None:
        return "yes" if spread[0] <= value <= spread[1] else "no"
    if mean is not None:
        return "yes" if abs(value - mean) <= MEAN_TOLERANCE * abs(mean) else "no"
    return "–"


def at(angle, angles, values):
    """The series at `angle` (linear interpolation), or None outside its angles."""
    return float(np.interp(angle, angles, values)) if angles[0] <= angle <= angles[-1] else None


def table(angle_deg, result, reference):
    lines = ["Hip-flexion moment arms (mm) of `hip_flexion.xml` against published ones, by "
             "`scripts/validate_moment_arms.py`; per angle: ours (mean over fibres) / line of action, "
             "then the published spread over fibres (Blemker & Delp 2005, image-based) or, where there is "
             "none, the mean ± 25 % (Németh & Ohlsén 1985, in vivo), and ✓ where ours lies within. "
             "`models/reference/` names the sources.", "",
             "| muscle |" + "".join(f" {a}° |" for a in TABLE_ANGLES_DEG),
             "|---|" + "---|" * len(TABLE_ANGLES_DEG)]
    counts = {}
    for m in MUSCLES:
        cells = []
        for angle in TABLE_ANGLES_DEG:
            ours = at(angle, angle_deg, result[m]["mean"])
            line = at(angle, angle_deg, result[m]["line"])
            spread = next(((at(angle, a, lo), at(angle, a, hi)) for _, a, lo, hi in reference[m]["spread"]
                           if at(angle, a, lo) is not None), None)
            mean = next((at(angle, a, v) for _, a, v in reference[m]["mean"] if at(angle, a, v) is not None), None)
            verdict = judge(ours, spread, mean if spread is None else None)
            counts.setdefault(m, [0, 0])
            counts[m][0] += verdict == "yes"
            counts[m][1] += verdict in ("yes", "no")
            published = f"{spread[0]:.0f} to {spread[1]:.0f}" if spread else (f"{mean:.0f}" if mean is not None else None)
            cells.append(f"{ours:.0f} / {line:.0f}" + (f" in {published}" if published else ", none published")
                         + (" ✓" if verdict == "yes" else ""))
        lines.append(f"| {m} | " + " | ".join(cells) + " |")
    lines[0] += (" Within, over 0–60°: " + "; ".join(f"{m} {c[0]} of {c[1]} angles" for m, c in counts.items())
                 + ". " + trend(angle_deg, result, reference))
    return "\n".join(lines)


def line_starts():
    """{muscle: (body, first point, unit normal)}: where each line of action starts on its origin body (mm, in
    the body's rest frame) and the plane there, normal to its first segment."""
    starts = {}
    for muscle in ET.parse(SCENE).getroot().iter("RBFMuscle"):
        text = muscle.findtext("line_of_action")
        if muscle.get("name") not in MUSCLES or not text:
            continue
        points = [p.split("@") for p in text.split(";")]
        first, second = (np.array(p[0].split(), float) for p in points[:2])
        starts[muscle.get("name")] = (points[0][1].strip(), first, (second - first) / np.linalg.norm(second - first))
    return starts


def length_past(fibre_mm, point_mm, normal):
    """The length of a fibre polyline on the far side of the plane through `point_mm` normal to `normal`."""
    side = (fibre_mm - point_mm) @ normal
    total = 0.0
    for a, b, sa, sb in zip(fibre_mm[:-1], fibre_mm[1:], side[:-1], side[1:]):
        if sa <= 0.0 and sb <= 0.0:
            continue
        t = 0.0 if sa > 0.0 else sa / (sa - sb)  # where the segment enters the far side
        u = 1.0 if sb > 0.0 else sa / (sa - sb)
        total += (u - t) * np.linalg.norm(b - a)
    return total


def run_flexion(angles_deg):
    """Runs the flexion scene through the Python module, with every muscle's moment arms and the
    fibres' geometry at `angles_deg`: the angles and arms (moment_arms.read_arms), and {muscle:
    [mean length past its line of action's start at each of `angles_deg`]} for the muscles whose
    fibres all start before that plane, the part of our fibres that the line of action's path spans."""
    sys.path.insert(0, os.path.join(ROOT, "build", "python"))
    import rbfmuscle
    model = rbfmuscle.Model(SCENE, overrides=moment_arm_sets(COORDINATE))
    column = model.coordinate_names.index(COORDINATE)
    starts = line_starts()
    rest = {body: model.body_transform(body) for body, _, _ in starts.values()}
    found = {m: [] for m in starts}
    for coordinates in model.motion_coordinates:
        angle = np.degrees(coordinates[column])
        wanted = any(abs(angle - a) < 1e-6 for a in angles_deg)
        model.step(coordinates, geometry=wanted)
        if not wanted:
            continue
        for m, (body, point, normal) in starts.items():
            to_rest = rest[body] @ np.linalg.inv(model.body_transform(body))  # ground → body at rest
            fibres = np.asarray(model.fibres(m)) @ to_rest[:3, :3].T + to_rest[:3, 3]
            if np.any((fibres[:, 0] - point) @ normal >= 0.0):
                found[m] = None
            elif found[m] is not None:
                found[m].append(np.mean([length_past(f, point, normal) for f in fibres]))
    past = {m: v for m, v in found.items() if v is not None and len(v) == len(angles_deg)}
    return read_arms(model.table(), COORDINATE) + (past,)


def length_table(angle_deg, result, reference, past):
    """Each muscle's length change over the motion: ours, the line of action's, and the change that
    the published spread of arms implies (l(b) − l(a) = −∫ r dq), also as a ratio to our l(a); where our
    fibres start before the line of action does, the same for the part of them its path spans (`past`)."""
    a, b = LENGTH_RANGE_DEG
    q = np.radians(np.linspace(a, b, 161))
    lines = [f"Length change from {a}° to {b}° of flexion: the mean fibre length, the line of action's, "
             f"and the change the published spread of moment arms gives, l({b}°) − l({a}°) = −∫ r dq, also as a "
             "ratio to our fibres' mean length at rest. A line of action's length is its own path's: "
             "MyoLeg's psoas starts at the pelvic brim, our fibres at the lumbar vertebrae "
             "(`models/hip/README.md`). Where our fibres start before the line of action does, the second "
             "column measures the part of them beyond the plane through its first point normal to its first "
             "segment, the span its path covers.", "",
             f"| muscle | ours: l({a}°) (mm), l({b}°) − l({a}°) (mm), ratio | ours over the line of action's span: the same "
             f"| line of action: the same | l({b}°) − l({a}°) by the published arms (mm) "
             "| the ratio they give our fibres (over the line of action's span) |",
             "|---|---|---|---|---|---|"]
    notes = []
    for m in MUSCLES:
        ends = {key: (at(a, angle_deg, result[m][key]), at(b, angle_deg, result[m][key]))
                for key in ("length", "line_length")}
        cells = [f"{l_a:.0f}, {l_b - l_a:+.1f}, {l_b / l_a:.3f}" for l_a, l_b in ends.values()]
        cells.insert(1, f"{past[m][0]:.0f}, {past[m][1] - past[m][0]:+.1f}, {past[m][1] / past[m][0]:.3f}"
                     if m in past else "–")
        bases = [ends["length"][0]] + ([past[m][0]] if m in past else [])
        published, ratios = [], []
        for name, angles, low, high in reference[m]["spread"]:
            if angles[0] > a + DIGITISED_END_DEG or angles[-1] < b - DIGITISED_END_DEG:
                continue
            changes = sorted(-np.trapz(np.interp(np.degrees(q), angles, bound), q) for bound in (low, high))
            published.append(f"{changes[0]:+.1f} to {changes[1]:+.1f} ({name})")
            spans = [f"{1 + changes[0] / base:.3f} to {1 + changes[1] / base:.3f}" for base in bases]
            ratios.append(spans[0] + (f" ({spans[1]})" if len(spans) > 1 else ""))
            if m in past:
                ratio = past[m][1] / past[m][0]
                low_ratio, high_ratio = (1 + c / past[m][0] for c in changes)
                above, shared = count_above(angle_deg, result[m]["line"], angles, high)
                notes.append(f"{m}'s fibres over the line of action's span shorten to {ratio:.3f} of their length, "
                             f"{'within' if low_ratio <= ratio <= high_ratio else 'outside'} the {low_ratio:.3f} to "
                             f"{high_ratio:.3f} that {name}'s arms give them. Its line of action shortens to "
                             f"{ends['line_length'][1] / ends['line_length'][0]:.3f}: its arm lies above the published "
                             f"spread at {above} of {shared} angles 1° apart over {a}–{b}°.")
        lines.append(f"| {m} | " + " | ".join(cells) + f" | {'; '.join(published) or '–'} | {'; '.join(ratios) or '–'} |")
    return "\n".join(lines + ([""] + notes if notes else []))


def count_above(angle_deg, series, angles, bound):
    """At how many whole degrees of the length range `series` lies above `bound`, and of how many both have."""
    a, b = LENGTH_RANGE_DEG
    shared = [x for x in range(a, b + 1) if at(x, angles, bound) is not None and at(x, angle_deg, series) is not None]
    return sum(at(x, angle_deg, series) > at(x, angles, bound) for x in shared), len(shared)


def trend(angle_deg, result, reference):
    """The gluteus maximus's extension moment arm from 40° to 60°: published studies see it shrink."""
    ours = [abs(at(a, angle_deg, result["glmax_r"]["mean"])) for a in (40, 60)]
    text = f"The gluteus maximus's extension moment arm from 40° to 60°: ours {ours[0]:.0f} → {ours[1]:.0f} mm"
    for name, a, v in reference["glmax_r"]["mean"]:
        text += f", {name} {abs(at(40, a, v)):.0f} → {abs(at(60, a, v)):.0f} mm"
    return text + "."


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-write", action="store_true", help="print the table, leave README.md and the picture alone")
    args = parser.parse_args()
    reference = load_reference()
    angle_deg, result, past = run_flexion(LENGTH_RANGE_DEG)
    text = table(angle_deg, result, reference) + "\n\n" + length_table(angle_deg, result, reference, past)
    print(text)
    if args.no_write:
        return
    draw(angle_deg, result, reference)
    print("wrote", os.path.relpath(PICTURE, ROOT))
    replace_readme_section("moment arm validation", text)
    print("wrote the moment arm validation table of README.md")


if __name__ == "__main__":
    main()
