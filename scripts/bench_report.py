"""Writes the results of scripts/speed_vs_error.py: report/speed_vs_error.csv, the plot
report/speed_vs_error.png (time per frame against each error, Pareto fronts marked) and the
generated section of report/README.md (between the BEGIN/END markers; text outside them is
kept). numpy + matplotlib (Agg, offscreen)."""
import csv
import math
import os

import numpy as np

import bench_io

BEGIN = "<!-- BEGIN speed_vs_error.py (generated: edits inside are overwritten) -->"
END = "<!-- END speed_vs_error.py -->"
BUDGET_MS = 1000.0 / 60.0  # 60 frames/s

# (key, label, target) of the errors; the plot takes the worse muscle.
ERRORS = [("surface_mean_mm", "static surface error, mean (mm)", 1.0),
          ("surface_max_mm", "static surface error, max (mm)", None),
          ("volume_drift", "volume drift max |V/V0 - 1|", None),
          ("fibre_dev", "fibre length deviation from reference\nmean |Δ normalised length|", None),
          ("penetration_mm", "max penetration (mm)", 0.5)]
MUSCLE_KEYS = ["centres", "update_ms", "descent_ms", "other_ms", "iterations", "surface_mean_mm", "surface_max_mm",
               "jaccard", "volume_drift", "fibre_dev", "penetration_mm", "fibre_points_outside", "restore_fibre",
               "restore_volume", "restore_surface_mm"]


def worst(row, key):
    values = [m.get(key, float("nan")) for m in row["muscles"].values()]
    values = [v for v in values if not math.isnan(v)]
    return max(values) if values else float("nan")


def pareto(points):
    """Indices of the (time, error) points no other point beats in both (lower is better)."""
    front, best = [], float("inf")
    for k in sorted(range(len(points)), key=lambda k: (points[k][0], points[k][1])):
        if points[k][1] < best:
            front.append(k)
            best = points[k][1]
    return front


def fmt(v, digits=3):
    if isinstance(v, str):
        return v
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "–"
    if isinstance(v, int):
        return str(v)
    if v != 0 and abs(v) < 1e-3:
        return f"{v:.2e}"
    if abs(v) >= 100:
        return f"{v:.0f}"
    return f"{v:.{digits}g}"


def write_csv(results, path):
    muscles = list(results[0]["muscles"])
    extra = sorted({k for r in results for m in r["muscles"].values() for k in m
                    if not k.startswith("_") and k not in MUSCLE_KEYS})
    stages = sorted({k for r in results for k in r if k.startswith("stage_")})
    head = ["id", "kind", "knob", "value", "motion", "frames", "frame_mean_ms", "fps", "deg_per_frame", "ms_per_deg", "first_frame_ms",
            "loop_mean_ms", "frame_median_ms", "frame_max_ms", "initialize_s", "wall_s"] + stages
    cols = head + [f"{n}.{k}" for n in muscles for k in MUSCLE_KEYS + extra] + ["command"]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for r in results:
            line = [r.get(c, "") for c in head]
            line += [r["muscles"][n].get(k, float("nan")) for n in muscles for k in MUSCLE_KEYS + extra]
            w.writerow(line + [r["command"]])


def plot(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    rows = [r for r in results if r["kind"] in ("base", "sweep", "reference")]
    panels = [e for e in ERRORS if any(not math.isnan(worst(r, e[0])) for r in rows)]
    cols = 3
    nrows = int(math.ceil(len(panels) / cols))
    fig, axes = plt.subplots(nrows, cols, figsize=(5.2 * cols, 4.4 * nrows), squeeze=False)
    colours = {"base": "black", "centres": "tab:blue", "quadrature_points": "tab:orange",
               "cost_tolerance": "tab:green", "frame_step_deg": "tab:purple", "contact_probes": "tab:brown",
               "reference": "tab:red"}
    for ax, (key, label, target) in zip(axes.flat, panels):
        pts = [(r["frame_mean_ms"], worst(r, key), r) for r in rows if not math.isnan(worst(r, key))]
        # A zero error cannot sit on a log axis: draw it at a floor below the smallest positive one.
        positive = [p[1] for p in pts if p[1] > 0]
        floor = min(positive) / 10 if positive else 1e-12
        xy = [(t, max(e, floor)) for t, e, _ in pts]
        for (t, e), (_, _, r) in zip(xy, pts):
            ax.scatter(e, t, color=colours.get(r["knob"], "grey"), s=28, zorder=3)
            ax.annotate(r["id"], (e, t), fontsize=6.5, xytext=(3, 3), textcoords="offset points")
        front = pareto([(t, e) for t, e in xy])
        fx = [xy[k][1] for k in front]
        fy = [xy[k][0] for k in front]
        ax.step(fx, fy, where="post", color="red", lw=1.2, alpha=0.7, label="Pareto front")
        ax.scatter(fx, fy, facecolors="none", edgecolors="red", s=90, zorder=4)
        ax.axhline(BUDGET_MS, color="grey", ls="--", lw=1, label="60 frames/s")
        if target is not None:
            ax.axvline(target, color="grey", ls=":", lw=1, label=f"target {target:g}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(label + " (worse muscle)")
        ax.set_ylabel("time per frame (ms)")
        ax.grid(True, which="both", alpha=0.25)
        ax.legend(fontsize=7, loc="best")
    for j, ax in enumerate(list(axes.flat)[len(panels):]):
        if j == 0:
            handles = [plt.Line2D([], [], marker="o", ls="", color=c, label=k) for k, c in colours.items()]
            ax.legend(handles=handles, loc="center", title="knob (zero errors drawn at a floor)")
        ax.axis("off")
    fig.suptitle("Speed against error: hip flexion, gluteus maximus + iliacus (wall time, shared machine)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def slope(xs, ys):
    """Least-squares slope of log y against log x (NaN with fewer than two distinct x)."""
    pairs = [(x, y) for x, y in zip(xs, ys) if x > 0 and y > 0 and not math.isnan(y)]
    if len({p[0] for p in pairs}) < 2:
        return float("nan")
    lx, ly = np.log([p[0] for p in pairs]), np.log([p[1] for p in pairs])
    return float(np.polyfit(lx, ly, 1)[0])


def table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(fmt(v) for v in row) + " |" for row in rows]
    return "\n".join(out)


def section(results, machine, root):
    muscles = list(results[0]["muscles"])
    base = next(r for r in results if r["kind"] == "base")
    lines = [BEGIN, "", f"## Speed against error ({machine['mode']} sweep, {machine['date']})", ""]
    if machine.get("note"):
        lines += [f"**{machine['note']}**", ""]
    la, lb = machine["load_start"], machine["load_end"]
    lines += ["Machine: " + f"{machine['cpu']}, {machine['nproc']} hardware threads, Linux {machine['kernel']}; "
              f"load average {la[0]:.2f} at the start, {lb[0]:.2f} at the end "
              "(the frame loop is single-threaded; with load > 1 the times are upper bounds). "
              f"Working tree at commit {machine['commit']}, host `{machine['host']}` built "
              f"{machine.get('host_built', '(time unknown)')}. "
              f"The sweep took {machine['sweep_minutes']:.1f} min.", "",
              "Reproduce: `" + machine["command"] + "` (then `/usr/bin/python3 scripts/render_hip.py` for the "
              "pictures). Every run's command line is in the `command` column of "
              "[speed_vs_error.csv](speed_vs_error.csv); the knobs are `--set MUSCLE.PROPERTY=VALUE` "
              "overrides of `rbfmuscle run`.", "", "![speed against error](speed_vs_error.png)", ""]

    # Target.
    frame = base["frame_mean_ms"]
    surf = worst(base, "surface_mean_mm")
    pen = worst(base, "penetration_mm")
    lines += ["### Target: ≥ 60 frames/s, surface error ≤ 1 mm, penetration ≤ 0.5 mm", "",
              table(["", "measured (model settings, " + base["motion"] + ")", "target", "reached"],
                    [["time per frame (ms)", frame, BUDGET_MS, "yes" if frame <= BUDGET_MS else
                      f"no: {frame / BUDGET_MS:.0f}× too slow"],
                     ["frames/s", base["fps"], 60.0, "yes" if base["fps"] >= 60 else "no"],
                     ["static surface error, mean (mm, worse muscle)", surf, 1.0,
                      "yes" if surf <= 1.0 else "no"],
                     ["max penetration (mm)", pen, 0.5, "not measured (no max_penetration_mm output)"
                      if math.isnan(pen) else ("yes" if pen <= 0.5 else "no")]]), ""]

    # Where the time goes.
    rows = []
    for name in muscles:
        m = base["muscles"][name]
        timings = [k for k in m if k.endswith("_ms") and k not in ("update_ms", "other_ms", "descent_ms",
                                                                     "surface_mean_mm", "surface_max_mm",
                                                                     "penetration_mm", "restore_surface_mm")]
        rows.append([f"{name}: descent (curvature cost gradient steps)", m["descent_ms"],
                     100 * m["descent_ms"] / frame])
        for k in timings:
            rows.append([f"{name}: {k[:-3]}", m[k], 100 * m[k] / frame])
        rows.append([f"{name}: rest of update", m["other_ms"],
                     100 * m["other_ms"] / frame])
    for k, v in base.items():
        if k.startswith("stage_") and not any(k == f"stage_{n}_ms" for n in muscles):
            rows.append([f"host stage: {k[6:-3]}", v, 100 * v / frame])
    rows.append(["frame total (moving frames)", frame, 100.0])
    extra_timers = sorted({k[:-3] for n in muscles for k in base["muscles"][n]
                           if k.endswith("_ms") and k not in ("update_ms", "descent_ms", "other_ms", "surface_mean_mm",
                                                              "surface_max_mm", "penetration_mm",
                                                              "restore_surface_mm")})
    timed_note = ("Timed apart by the component: descent" + "".join(f", {t}" for t in extra_timers) +
                  "; 'rest of update' is everything else (prediction, volume correction, fibres, line of action"
                  + ("" if "collision" in extra_timers else ", contacts") + ").")
    lines += ["### Where a frame's time goes (model settings)", "",
              f"Mean over the {max(1, base['frames'] - 1)} moving frames of `{base['motion']}`; the component reports "
              "`update_ms` and `descent_ms` per frame, the host the stages in summary.json. "
              f"Mean descent iterations per frame: " +
              ", ".join(f"{n} {base['muscles'][n]['iterations']:.1f}" for n in muscles) +
              f". Frame 0 (the rest pose) is left out of the means: its one-time setup took "
              f"{base['first_frame_ms']:.0f} ms. Initialisation (load the cached fit, attachments, quadrature, "
              f"fibres): {base['initialize_s']:.2f} s, not in the frame time. " + timed_note, "",
              table(["part", "ms per frame", "% of frame"], rows), ""]

    # Cost growth.
    growth = []
    sweeps = [r for r in results if r["kind"] in ("base", "sweep") and r["motion"] == base["motion"]]
    for knob, label in [("centres", "centres"), ("quadrature_points", "quadrature points"),
                        ("contact_probes", "contact probes")]:
        group = [r for r in sweeps if r["knob"] == knob or r["kind"] == "base"]
        if not any(r["knob"] == knob for r in group):
            continue
        for name in muscles:
            xs = [float(r["settings"][name].get(knob, "nan")) for r in group]
            ys = [r["muscles"][name]["update_ms"] for r in group]
            ds = [r["muscles"][name]["descent_ms"] for r in group]
            growth.append([name, label, ", ".join(f"{x:g}" for x in sorted(set(xs))), slope(xs, ys),
                           slope(xs, ds)])
    if growth:
        lines += ["### Cost growth (log-log slope of time per frame against the knob)", "",
                  "A slope of 1 is linear growth (the design's limit), 2 quadratic. From the one-knob sweeps "
                  "on the same motion as the base run.", "",
                  table(["muscle", "knob", "levels", "slope of update_ms", "slope of descent_ms"], growth), ""]

    # Main table.
    rows = []
    for r in results:
        if r["kind"] == "restore":
            continue
        rows.append([r["id"], r["knob"], str(r["value"]), r["frames"], r["frame_mean_ms"], r["fps"],
                     r.get("ms_per_deg", float("nan"))] +
                    [r["muscles"][n]["update_ms"] for n in muscles] +
                    ["/".join(f"{r['muscles'][n]['iterations']:.0f}" for n in muscles)] +
                    [worst(r, k) for k in ("surface_mean_mm", "surface_max_mm", "volume_drift", "fibre_dev",
                                           "penetration_mm")])
    lines += ["### Sweep (errors: worse muscle; per-muscle values in the csv)", "",
              "One knob at a time around the model's settings; `reference` is the high-fidelity run the fibre "
              "deviation is measured against (at its frames' angles). Under load the wall times of runs made "
              "minutes apart differ by more than the repeat spread below; the descent iterations (capped by "
              "`max_iterations`) are the machine-independent measure of work.", "",
              table(["run", "knob", "value", "frames", "ms/frame", "frames/s", "ms per degree of motion"] +
                    [f"{n} update ms" for n in muscles] + ["mean iterations (" + "/".join(muscles) + ")"] +
                    ["surface mean mm", "surface max mm", "volume drift", "fibre dev", "penetration mm"], rows), ""]

    # Restore.
    rest = [r for r in results if r["kind"] == "restore"]
    if rest:
        rows = [[r["id"][len("restore_"):], n, r["muscles"][n]["restore_fibre"], r["muscles"][n]["restore_volume"],
                 r["muscles"][n]["restore_surface_mm"]] for r in rest for n in muscles]
        lines += ["### Restore after flexion and back (`" + rest[0]["motion"] + "`)", "",
                  "Difference between the first (rest) and last frame after flexing to the motion's largest angle "
                  "and back. "
                  "The hip scene has a welded pelvis, so the rigid-motion error comes from the core "
                  "benchmark below.", "",
                  table(["run", "muscle", "abs Δ normalised fibre length", "abs Δ V/V0",
                         "mean surface distance (mm)"], rows), ""]

    # Core benchmarks.
    bench = machine.get("core_benchmarks") or []
    if bench:
        rows = []
        for b in bench:
            errs = "; ".join(f"{k} = {fmt(v)}" for k, v in b.items()
                             if k.endswith(("_mm", "_error")))
            parts = " / ".join(fmt(b.get(k, float("nan"))) for k in ("predict_ms", "descent_ms", "volume_ms",
                                                                      "topology_ms"))
            rows.append([b["muscle"], b["benchmark"], b["time_ms"], parts, b.get("iterations", float("nan")), errs])
        lines += ["### Rigid motion and restore (core benchmark `rbfmuscle_bench`)", "",
                  "From benchmarks/deformer_bench.cpp on each muscle's cached surface (argument: quadrature points; "
                  "attachments at the highest and lowest centres). Rigid: both bones move by one rigid motion "
                  "(20° and 15 mm); the muscle must move rigidly. Restore: the insertion bone swings 30° in one "
                  "frame and back in the next; the centres must return to rest. Time: wall time of the measured "
                  "frame. Executable built " + bench[0].get("built", "(time unknown)") + " from the working tree "
                  "(the dynamics may be newer than the host's).", "",
                  table(["muscle", "benchmark/quadrature", "ms", "predict / descent / volume / topology ms",
                         "iterations", "errors"], rows), ""]

    # Spread.
    reps = [r for r in results if r["kind"] in ("base", "repeat")]
    if len(reps) > 1:
        t = np.array([r["frame_mean_ms"] for r in reps])
        fib = max(abs(a["muscles"][n]["fibre_dev"] - reps[0]["muscles"][n]["fibre_dev"])
                  for a in reps for n in muscles)
        vol = max(abs(a["muscles"][n]["volume_drift"] - reps[0]["muscles"][n]["volume_drift"])
                  for a in reps for n in muscles)
        lines += ["### Spread of repeated runs (model settings)", "",
                  f"{len(reps)} runs: time per frame {', '.join(f'{x:.1f}' for x in t)} ms; "
                  f"spread (max − min) / median = {100 * (t.max() - t.min()) / np.median(t):.1f} %. "
                  f"Errors between repeats differ by at most {fmt(fib)} (fibre deviation) and {fmt(vol)} "
                  "(volume drift): the outputs are deterministic, the times are not.", ""]

    if machine.get("fit_seconds"):
        lines += ["Fits made for this sweep (cached for later sweeps): " +
                  ", ".join(f"{k} {v:.0f} s" for k, v in sorted(machine["fit_seconds"].items())) + ".", ""]
    lines += [END]
    return "\n".join(lines)


def write_all(results, machine, report_dir, root):
    write_csv(results, os.path.join(report_dir, "speed_vs_error.csv"))
    plot(results, os.path.join(report_dir, "speed_vs_error.png"))
    bench_io.replace_marked_section(
        os.path.join(report_dir, "README.md"), BEGIN, END, section(results, machine, root),
        "# rbfmuscle report\n\nGenerated by `scripts/speed_vs_error.py` and `scripts/render_hip.py`; "
        "rerun them to refresh.\n\n")
