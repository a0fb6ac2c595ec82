# SPDX-License-Identifier: Apache-2.0
"""The speed-against-error report of scripts/speed_vs_error.py: the figures of each run (speed,
errors against the reference), then the csv rows, the markdown section and the picture."""
import csv
import json
import os
import statistics

import numpy as np

from run_outputs import read_outputs, stack_vector


# ---- one run -----------------------------------------------------------------------------------

def measure(out, model, coordinate):
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    columns = read_outputs(out)
    reported = {r["output"]: r for r in summary.get("reported_ms", [])}
    run = {"frames": summary["frames"], "frame_ms": summary["frame_wall_ms"]["median"],
           "initialize_s": summary["seconds"]["initialize"], "invariants_broken": summary.get("invariants_broken", []),
           "angle_deg": np.round(np.degrees(columns[coordinate]), 6), "muscles": {}}
    for m in model["muscles"]:
        n = m["name"]
        fibres = stack_vector(columns, f"{n}.fibre_length_mm")  # fibres × frames
        update = reported.get(f"{n}.update_ms", {}).get("median")
        run["muscles"][n] = {
            "update_ms": update if update is not None else statistics.median(columns[f"{n}.update_ms"]),
            "volume_drift": float(np.nanmax(np.abs(columns[f"{n}.volume_ratio"] - 1.0))),
            "fibre_points_outside": float(np.nanmax(columns[f"{n}.fibre_points_outside"])),
            "fibre_ratio": columns[f"{n}.fibre_length_ratio"],
            "fibre_mm": fibres.T if len(fibres) else np.zeros((summary["frames"], 0)),
        }
    return run


def bone_depth(out, model):
    columns = read_outputs(out)
    nanmax = lambda v: float(np.nanmax(v)) if np.any(~np.isnan(v)) else float("nan")
    return {m["name"]: (nanmax(columns[f"{m['name']}.surface_bone_depth_max_mm"]),
                        nanmax(columns[f"{m['name']}.surface_vertices_unresolved"])) for m in model["muscles"]}


def compare(run, reference):
    """Per muscle: the fibre errors against the reference at the angles both runs have, the first
    frame (rest) left out."""
    shared = [(i, j) for i, a in enumerate(run["angle_deg"]) if i > 0
              for j in np.flatnonzero(reference["angle_deg"] == a)[:1]]
    i, j = [p[0] for p in shared], [p[1] for p in shared]
    errors = {}
    for name, mine in run["muscles"].items():
        ref = reference["muscles"][name]
        ratio = float(np.mean(np.abs(mine["fibre_ratio"][i] - ref["fibre_ratio"][j]))) if shared else float("nan")
        same_fibres = (mine["fibre_mm"].shape[1] == ref["fibre_mm"].shape[1] > 0 and
                       np.allclose(mine["fibre_mm"][0], ref["fibre_mm"][0], rtol=0, atol=1e-6))
        difference = np.abs(mine["fibre_mm"][i] - ref["fibre_mm"][j]) if shared and same_fibres else None
        errors[name] = {"fibre_ratio_error": ratio, "shared_frames": len(shared),
                        "fibre_deviation_mm": float(np.nanmean(difference)) if difference is not None else float("nan"),
                        "fibre_deviation_max_mm": float(np.nanmax(difference)) if difference is not None else float("nan")}
    return errors


FIELDS = ["configuration", "knob", "value", "motion_step_deg", "frames", "frame_median_ms", "frames_per_s",
          "initialize_s", "muscle", "centres", "update_median_ms", "volume_drift_max", "fibre_length_ratio_error_mean",
          "fibre_length_deviation_mean_mm", "fibre_length_deviation_max_mm", "fibre_points_outside_max", "surface_bone_depth_max_mm",
          "surface_vertices_unresolved_max", "fit_jaccard", "fit_mean_distance_mm", "fit_p95_distance_mm",
          "fit_max_distance_mm", "fit_components", "note"]


def rows_of(results, model):
    rows = []
    for r in results:
        for m in model["muscles"]:
            x = r["muscles"][m["name"]]
            fit = x["fit"]
            rows.append([r["config"]["id"], r["config"]["knob"], r["config"]["value"], r["step_deg"], r["frames"],
                         r["frame_ms"], 1000.0 / r["frame_ms"], r["initialize_s"], m["name"], x["centres"],
                         x["update_ms"], x["volume_drift"], x["fibre_ratio_error"], x["fibre_deviation_mm"], x["fibre_deviation_max_mm"],
                         x["fibre_points_outside"], x["bone_depth_mm"], x["unresolved"], fit.get("jaccard"),
                         fit.get("mean_distance_mm"), fit.get("p95_distance_mm"), fit.get("max_distance_mm"),
                         fit.get("components"), note(r["config"], m["name"])])
    return rows


def note(config, name):
    if name not in config["unused_fits"]:
        return ""
    n, figures = config["unused_fits"][name][:2]
    return (f"the fit with {n} centres has {figures.get('components')} pieces (Jaccard {figures.get('jaccard')}): "
            "the scene's surface kept")


def write_csv(rows, path):
    def cell(v):
        if isinstance(v, float):
            return "" if np.isnan(v) else f"{v:.6g}"
        return "" if v is None else str(v)
    with open(path + ".tmp", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(FIELDS)
        w.writerows([[cell(v) for v in row] for row in rows])
    os.replace(path + ".tmp", path)


def fmt(value, spec):
    if value is None or (isinstance(value, float) and np.isnan(value)):
        return "–"
    return format(value, spec)


def worst(result, key):
    values = [m[key] for m in result["muscles"].values() if not np.isnan(m[key])]
    return max(values) if values else float("nan")


def section(results, model, mode, notes, load):
    names = [m["name"] for m in model["muscles"]]
    per = lambda r, key, spec: " / ".join(fmt(r["muscles"][n][key], spec) for n in names)
    reference = next(r for r in results if r["config"]["kind"] == "reference")
    depth = any(not np.isnan(worst(r, "bone_depth_mm")) for r in results)
    lines = [f"Measured by `scripts/speed_vs_error.py{' --' + mode if mode != 'default' else ''}` on a "
             f"{os.cpu_count()}-core machine (load {load[0]:.1f} when it began, {load[1]:.1f} when it ended) on "
             f"`models/hip/hip_flexion.xml`, the base and the reference over {reference['frames']} frames of "
             f"{reference['step_deg']:g}°. Each cell lists the muscles in the order {' / '.join(names)}: the median "
             "`update_ms`; against the reference (" + reference["config"]["value"] + "; same centres and motion), "
             "over the frames after the rest frame at the angles both runs have, the mean |fibre_length_ratio − "
             "reference's| and the mean |fibre length − reference's| over the fibres (mm; only when both runs have "
             "the same fibres at rest); the largest |volume_ratio − 1| (by the run's own volume measure); the most "
             "fibre points left outside the muscle in a frame." +
             (" With `--frames-mesh`: the deepest vertex of the tracked surface inside a bone and the most "
              "vertices that found no surface (the muscle there lies wholly in a bone)." if depth else
              " (The surface's depth in the bones: with `--bone-depth`, runs with `--frames-mesh`.)") +
             " All figures per muscle, the largest fibre deviations and the fits' figures: `docs/speed_vs_error.csv`.",
             "",
             "| configuration | frame median (ms) | frames/s | update median (ms) | fibre length ratio error | "
             "fibre length deviation (mm) | volume drift max | fibre points outside max |" +
             (" surface bone depth max (mm) | surface vertices unresolved max |" if depth else ""),
             "|---|---|---|---|---|---|---|---|" + ("---|---|" if depth else "")]
    for r in results:
        lines.append(f"| {r['config']['id']} | {r['frame_ms']:.1f} | {1000.0 / r['frame_ms']:.1f} | "
                     f"{per(r, 'update_ms', '.1f')} | {per(r, 'fibre_ratio_error', '.4f')} | "
                     f"{per(r, 'fibre_deviation_mm', '.2f')} | {per(r, 'volume_drift', '.5f')} | "
                     f"{per(r, 'fibre_points_outside', '.0f')} |" +
                     (f" {per(r, 'bone_depth_mm', '.3f')} | {per(r, 'unresolved', '.0f')} |" if depth else ""))
    lines += ["", "Static fit of each centres level (`rbfmuscle fit`'s figures against the mesh: centres: Jaccard "
              "index, mean / max distance in mm, pieces):", "",
              "| centres | " + " | ".join(names) + " |", "|---|" + "---|" * len(names)]
    for r in results:
        if r["config"]["knob"] in ("base", "centres") and r["config"]["kind"] != "repeat":
            cells = []
            for n in names:
                centres, f = r["config"]["unused_fits"].get(n, (r["muscles"][n]["centres"], r["muscles"][n]["fit"]))[:2]
                cells.append(f"{centres}: {fmt(f.get('jaccard'), '.3f')}, {fmt(f.get('mean_distance_mm'), '.2f')} / "
                             f"{fmt(f.get('max_distance_mm'), '.2f')}, {fmt(f.get('components'), '.0f')}" +
                             (" (not run)" if n in r["config"]["unused_fits"] else ""))
            lines.append(f"| {r['config']['value'] if r['config']['knob'] == 'centres' else '×1 (scene)'} | " +
                         " | ".join(cells) + " |")
    lines += [""] + notes + ([""] if notes else [])
    lines.append("![Frame time against each error, one marker per configuration](pictures/speed_vs_error.png)")
    return "\n".join(lines)


def plot(results, path):
    """Frame median against each error, the worse muscle's value (a configuration is left out of a
    panel where a muscle has no value); the reference is left out of the panels measured against it."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    panels = [("fibre_ratio_error", "fibre length ratio error, mean", True),
              ("fibre_deviation_mm", "fibre length deviation, mean (mm)", True),
              ("volume_drift", "volume drift, max |V/V₀ − 1|", False),
              ("fibre_points_outside", "fibre points outside, max", False),
              ("bone_depth_mm", "surface bone depth, max (mm)", False),
              ("fit_mean_mm", "static fit: mean distance (mm)", False)]
    knobs = list(dict.fromkeys(r["config"]["knob"] for r in results))
    colours = dict(zip(knobs, plt.rcParams["axes.prop_cycle"].by_key()["color"] * 3))
    reference = next(r for r in results if r["config"]["kind"] == "reference")
    fig, axes = plt.subplots(2, 3, figsize=(14, 8), sharex=True)
    for ax, (key, title, against_reference) in zip(axes.flat, panels):
        shown = 0
        for r in results:
            if against_reference and r is reference:
                continue
            if key == "fit_mean_mm" and r["config"]["knob"] not in ("base", "centres"):
                continue
            values = [m[key] for m in r["muscles"].values()]
            if any(np.isnan(v) for v in values):
                continue
            y = max(values)
            ax.plot(r["frame_ms"], y, "o", color=colours[r["config"]["knob"]])
            ax.annotate(r["config"]["id"], (r["frame_ms"], y), textcoords="offset points", xytext=(4, 3), fontsize=7)
            shown += 1
        if against_reference:
            ax.axvline(reference["frame_ms"], color="#999999", linestyle=":", linewidth=1)
            ax.annotate("reference", (reference["frame_ms"], 1.0), xycoords=("data", "axes fraction"),
                        rotation=90, va="top", ha="right", fontsize=7, color="#777777")
        if shown:
            ax.set_ylim(bottom=0.0, top=ax.get_ylim()[1] * 1.08)
        else:
            ax.text(0.5, 0.5, "not measured", transform=ax.transAxes, ha="center", va="center", color="#777777")
        ax.set_title(title + ", worse muscle", fontsize=9)
        ax.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("frame median (ms)")
    fig.suptitle("hip_flexion: speed against error, one knob at a time (scripts/speed_vs_error.py)")
    fig.tight_layout()
    fig.savefig(path + ".tmp.png", dpi=110)
    plt.close(fig)
    os.replace(path + ".tmp.png", path)


# ---- main --------------------------------------------------------------------------------------

