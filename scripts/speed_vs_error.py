#!/usr/bin/python3
"""Speed against error on the hip scene (issue 7): sweep the accuracy knobs, measure
time per frame and the errors, write report/speed_vs_error.{csv,png} and the generated
section of report/README.md.

Needs python3-numpy, python3-matplotlib, python3-scipy (Debian) and a built host:
    /usr/bin/python3 scripts/speed_vs_error.py            # default sweep (10-degree motion, <= 15 min)
    /usr/bin/python3 scripts/speed_vs_error.py --quick    # checks the script works (< 2 min)
    /usr/bin/python3 scripts/speed_vs_error.py --full     # more levels, 1-degree reference, restore runs
    /usr/bin/python3 scripts/speed_vs_error.py --reuse    # re-read earlier runs, only redo the report

The sweep is one knob at a time around the model's own settings ("base"):
  centres per muscle   (scale of each muscle's `centres`; fits cached in --cache as
                        MESHSTEM_N.rbf, reused by later sweeps)
  quadrature_points, cost_tolerance, frame step (10 deg vs 1 deg motion), contact_probes
  (only when the RBFMuscle class has that property: `rbfmuscle info`).
Errors, per muscle (the plot uses the worse muscle):
  surface_mean_mm / surface_max_mm  static fit: symmetric distance f = 0 <-> input mesh (.rbf metrics)
  volume_drift                      max over frames |volume_ratio - 1|
  fibre_dev                         mean over the reference's angles |fiber_length_normalised - reference|
  penetration_mm                    max over frames of max_penetration_mm (when the output exists)
  restore_*                         flexion 0 -> 80 -> 0: |fibre length - rest|, |V/V0 - 1| and the mean
                                    distance between the first and last surfaces (base; all in --full)
The reference run has twice the centres and quadrature points, cost_tolerance 1e-8 and
max_iterations 500 (--full: on the 1-degree motion).
"""
import argparse
import datetime
import json
import math
import os
import platform
import re
import shutil
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_io  # noqa: E402
import bench_report  # noqa: E402

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def parse_args():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    mode = p.add_mutually_exclusive_group()
    mode.add_argument("--quick", action="store_true", help="tiny sweep to check the script (< 2 min)")
    mode.add_argument("--full", action="store_true", help="more levels, 1-degree reference, restore for all")
    p.add_argument("--host", default=os.path.join(ROOT, "build/bin/rbfmuscle"), help="rbfmuscle executable")
    p.add_argument("--model", default=os.path.join(ROOT, "models/hip/hip_flexion.xml"))
    p.add_argument("--cache", default=os.path.join(ROOT, "out/bench_cache"), help="fitted .rbf per centre count")
    p.add_argument("--work", default=os.path.join(ROOT, "out/bench"), help="run output directories")
    p.add_argument("--report", default=os.path.join(ROOT, "report"), help="where the csv, png and README go")
    p.add_argument("--repeats", type=int, default=None, help="runs of the base configuration (spread)")
    p.add_argument("--reuse", action="store_true", help="reuse finished runs in --work with the same command")
    p.add_argument("--note", default="", help="text put at the top of the generated report section")
    return p.parse_args()


def log(text):
    print(f"[{datetime.datetime.now().strftime('%H:%M:%S')}] {text}", flush=True)


def run_command(cmd, what):
    """Runs cmd; returns (seconds, stdout). Raises with the stderr tail on failure."""
    start = time.monotonic()
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    seconds = time.monotonic() - start
    if r.returncode != 0:
        raise RuntimeError(f"{what} failed ({r.returncode}): {' '.join(cmd)}\n{r.stderr[-2000:]}")
    return seconds, r.stdout


def class_properties(host):
    """{property: default text} of the RBFMuscle class (`rbfmuscle info -L librbfmuscle_plugin.so RBFMuscle`)."""
    _, out = run_command([host, "info", "-L", "librbfmuscle_plugin.so", "RBFMuscle"], "rbfmuscle info")
    props = {}
    for name, inside in re.findall(r"^\s+(\w+) \(([^)]*)\)", out.split("sockets:")[0], flags=re.M):
        found = re.search(r"default ([^,]*)", inside)
        props[name] = found.group(1).strip().strip('"') if found else ""
    return props


def effective_settings(model, props, config, centres):
    """{muscle: {property: value text}}: class default, then the model file, then the run's --set."""
    out = {}
    for muscle in model["muscles"]:
        s = dict(props)
        s.update(muscle["properties"])
        s.update({k: str(v) for k, v in config["props"].items()})
        s["centres"] = str(centres[muscle["name"]])
        out[muscle["name"]] = s
    return out


class SurfaceCache:
    """Fitted surfaces per (mesh, centres) in a directory; fits what is missing."""

    def __init__(self, host, directory):
        self.host, self.directory = host, directory
        self.fit_seconds = {}
        os.makedirs(directory, exist_ok=True)

    def path(self, muscle, centres):
        stem = os.path.splitext(os.path.basename(muscle["mesh"]))[0]
        target = os.path.join(self.directory, f"{stem}_{centres}.rbf")
        if os.path.exists(target):
            # Refit when the model's own surface was fitted with other settings (the fit
            # defaults changed): the sweep compares surfaces from one fitting method.
            if not muscle["surface"] or not os.path.exists(muscle["surface"]) or \
                    bench_io.read_rbf_settings(target) == bench_io.read_rbf_settings(muscle["surface"]):
                return target
            log(f"  {os.path.relpath(target, ROOT)} was fitted with other settings than "
                f"{os.path.relpath(muscle['surface'], ROOT)}: refitting")
            os.remove(target)
        if centres == muscle["centres"] and muscle["surface"] and os.path.exists(muscle["surface"]):
            shutil.copyfile(muscle["surface"], target)  # the model's own cached fit
            return target
        log(f"  fitting {stem} with {centres} centres (cached as {os.path.relpath(target, ROOT)}) ...")
        partial = target + ".partial.rbf"
        seconds, _ = run_command([self.host, "fit", muscle["mesh"], "--centres", str(centres), "-o", partial,
                                  "--quiet"], "fit")
        os.replace(partial, target)
        self.fit_seconds[os.path.basename(target)] = seconds
        log(f"  fitted in {seconds:.1f} s")
        return target


def make_motions(work, quick, full):
    """The motions of the sweep (flexion, degrees), written as .mot files in WORK/motions:
    coarse (10-degree steps; the runs), fine (1-degree steps: the frame-step knob) and
    restore (out and back). Short by default because a run's initialisation alone takes
    tens of seconds on this machine."""
    top = 10 if quick else (80 if full else 40)
    fine_top = 80 if full else 20
    angles = {"coarse": list(range(0, top + 1, 10)),
              "restore": list(range(0, top + 1, 10)) + list(range(top - 10, -1, -10))}
    if not quick:
        angles["fine"] = list(range(0, fine_top + 1, 1))
    motions = os.path.join(work, "motions")
    os.makedirs(motions, exist_ok=True)
    paths = {}
    for name, a in angles.items():
        stem = f"flexion_{name}_{a[0]}_{max(a)}" + ("_0" if name == "restore" else "")
        paths[name] = os.path.join(motions, stem + ".mot")
        bench_io.write_motion(paths[name], stem, a)
    return paths


def configurations(model, args, props):
    """List of dicts: id, knob, value, kind, centres scale, props {property: value} set on
    every muscle, motion name, frames_mesh."""
    quick, full = args.quick, args.full
    configs = []

    def add(cid, knob, value, scale=1.0, props_all=None, motion="coarse", kind="sweep", frames_mesh=False):
        configs.append({"id": cid, "knob": knob, "value": value, "scale": scale, "props": props_all or {},
                        "motion": motion, "kind": kind, "frames_mesh": frames_mesh})

    repeats = args.repeats if args.repeats is not None else (1 if quick else (3 if full else 2))
    add("base", "base", "model", kind="base")
    for r in range(2, repeats + 1):
        add(f"base_rep{r}", "base", "model", kind="repeat")
    for s in ([] if quick else ([0.25, 0.5, 2.0] if full else [0.25, 0.5])):
        add(f"centres_x{s:g}", "centres", s, scale=s)
    for q in ([] if quick else ([500, 1000, 2000, 8000] if full else [1000, 2000])):
        add(f"quadrature_{q}", "quadrature_points", q, props_all={"quadrature_points": q})
    for t in ([] if quick else ([1e-2, 1e-3, 1e-4, 1e-6] if full else [1e-3, 1e-4])):
        add(f"tolerance_{t:g}", "cost_tolerance", t, props_all={"cost_tolerance": t})
    if not quick:
        add("step_1deg", "frame_step_deg", 1, motion="fine")
    if "contact_probes" in props:
        # 0 switches contacts off (the cost of contacts); the base run has the class default.
        for n in ([] if quick else ([0, 250, 500, 1000, 4000, 8000] if full else [0, 500, 1000])):
            add(f"probes_{n}", "contact_probes", n, props_all={"contact_probes": n})
    # High fidelity: tight tolerance and a high iteration cap; more quadrature (and, in
    # --full, twice the centres and 1-degree frames).
    ref = {"cost_tolerance": 1e-7, "max_iterations": 150 if not full else 500}
    if not quick:
        ref["quadrature_points"] = 8000
    add("reference", "reference", ", ".join(f"{k}={v:g}" for k, v in ref.items()) +
        (", centres x2, 1-degree frames" if full else ""), scale=2.0 if full else 1.0,
        motion="fine" if full else "coarse", kind="reference", props_all=ref)
    for c in [c for c in configs if c["kind"] == "base" or (full and c["kind"] == "sweep")]:
        add(f"restore_{c['id']}", c["knob"], c["value"], scale=c["scale"], props_all=c["props"], motion="restore",
            kind="restore", frames_mesh=True)
    return configs


def build_command(args, model, cache, config, motions, outdir):
    cmd = [args.host, "run", args.model, "-o", outdir, "--quiet", "--motion", motions[config["motion"]]]
    centres = {}
    for muscle in model["muscles"]:
        n = max(10, int(round(muscle["centres"] * config["scale"])))
        centres[muscle["name"]] = n
        if config["scale"] != 1.0:
            cmd += ["--set", f"{muscle['name']}.surface_file={cache.path(muscle, n)}",
                    "--set", f"{muscle['name']}.centres={n}"]
        for prop, value in config["props"].items():
            cmd += ["--set", f"{muscle['name']}.{prop}={value}"]
    if config["frames_mesh"]:
        cmd.append("--frames-mesh")
    return cmd, centres


def surface_metrics(model, cache, config):
    """{muscle: rbf metrics} of the surfaces a configuration uses."""
    out = {}
    for muscle in model["muscles"]:
        n = max(10, int(round(muscle["centres"] * config["scale"])))
        path = cache.path(muscle, n) if config["scale"] != 1.0 else muscle["surface"]
        out[muscle["name"]] = bench_io.read_rbf_metrics(path) if path else {}
    return out


def restore_surface_distance(outdir, name):
    """Mean symmetric distance (mm) between the first and last per-frame surfaces of `name`."""
    from scipy.spatial import cKDTree
    meshes = sorted(f for f in os.listdir(os.path.join(outdir, "meshes"))
                    if re.fullmatch(re.escape(name) + r"_\d+\.vtp", f))
    if len(meshes) < 2:
        return float("nan")
    a, _, _ = bench_io.read_vtp(os.path.join(outdir, "meshes", meshes[0]))
    b, _, _ = bench_io.read_vtp(os.path.join(outdir, "meshes", meshes[-1]))
    if len(a) == 0 or len(b) == 0:
        return float("nan")
    return 0.5 * (cKDTree(b).query(a)[0].mean() + cKDTree(a).query(b)[0].mean())


def measure(outdir, model, config):
    """Timing and per-muscle figures of one finished run."""
    with open(os.path.join(outdir, "summary.json")) as f:
        summary = json.load(f)
    sto = bench_io.Storage(os.path.join(outdir, "outputs.sto"))
    frames = summary["frames"]
    row = {"frames": frames, "loop_mean_ms": 1000.0 * summary["seconds"]["frame_loop"] / frames,
           "frame_median_ms": summary["frame_wall_ms"]["median"], "frame_max_ms": summary["frame_wall_ms"]["max"],
           "initialize_s": summary["seconds"]["initialize"]}
    muscle_stages = {f"component {m['name']}" for m in model["muscles"]}
    host_ms = 0.0
    for stage in summary["stages_ms"]:
        key = stage["stage"].split(" (")[0]
        row[f"stage_{key.replace('component ', '')}_ms"] = stage["mean_per_frame"]
        if key not in muscle_stages:
            host_ms += stage["mean_per_frame"]
    # Time per frame: the muscles' update_ms over the moving frames (frame 0 is the rest
    # pose, whose one-time setup is reported apart as first_frame_ms) plus the host stages.
    updates = np.array([sto[f"{m['name']}.update_ms"] for m in model["muscles"]]).sum(axis=0)
    row["first_frame_ms"] = float(updates[0])
    row["frame_mean_ms"] = float(np.mean(updates[1:] if frames > 1 else updates)) + host_ms
    row["fps"] = 1000.0 / row["frame_mean_ms"]
    angles = sto.angle_deg()
    row["deg_per_frame"] = float(np.mean(np.abs(np.diff(angles)))) if frames > 1 else float("nan")
    row["ms_per_deg"] = row["frame_mean_ms"] / row["deg_per_frame"] if frames > 1 else float("nan")
    per = {}
    for muscle in model["muscles"]:
        n = muscle["name"]
        get = lambda out: sto[f"{n}.{out}"] if sto.has(f"{n}.{out}") else None
        m = {}
        moving = slice(1, None) if frames > 1 else slice(None)
        for out in ("update_ms", "descent_ms", "iterations"):
            v = get(out)
            m[out] = float(np.mean(v[moving])) if v is not None else float("nan")
        # Optional timing outputs of later versions of the component (ms per frame).
        for label in sto.labels:
            if label.startswith(n + ".") and label.endswith("_ms") and label[len(n) + 1:] not in m:
                m[label[len(n) + 1:]] = float(np.mean(sto[label][moving]))
        extra = [k for k in m if k not in ("update_ms", "descent_ms", "iterations")]
        m["other_ms"] = m["update_ms"] - m["descent_ms"] - sum(m[k] for k in extra if not math.isnan(m[k]))
        v = get("volume_ratio")
        m["volume_drift"] = float(np.max(np.abs(v - 1.0))) if v is not None else float("nan")
        v = get("max_penetration_mm")
        m["penetration_mm"] = float(np.nanmax(v)) if v is not None and np.any(~np.isnan(v)) else float("nan")
        v = get("fiber_points_outside")
        m["fibre_points_outside"] = float(np.max(v)) if v is not None else float("nan")
        fl = get("fiber_length_normalised")
        m["_fibre"] = (angles, fl)
        if config["kind"] == "restore":
            m["restore_fibre"] = float(abs(fl[-1] - fl[0])) if fl is not None else float("nan")
            vr = get("volume_ratio")
            m["restore_volume"] = float(abs(vr[-1] - vr[0])) if vr is not None else float("nan")
            m["restore_surface_mm"] = restore_surface_distance(outdir, n)
        per[n] = m
    return row, per, summary


def fibre_deviation(run_fibre, ref_fibre):
    """Mean |fln - fln_ref| at the reference angles present in the run (NaN if none)."""
    a, fl = run_fibre
    ra, rfl = ref_fibre
    if fl is None or rfl is None:
        return float("nan")
    diffs = []
    for angle, value in zip(a, fl):
        k = np.flatnonzero(np.abs(ra - angle) < 1e-6)
        if k.size:
            diffs.append(abs(value - rfl[k[0]]))
    return float(np.mean(diffs)) if diffs else float("nan")


def core_benchmarks(host, model):
    """Rigid-motion and restore errors from benchmarks/deformer_bench.cpp (the executable
    rbfmuscle_bench next to the host), per muscle surface; [] when it is not built."""
    bench = os.path.join(os.path.dirname(host), "rbfmuscle_bench")
    if not os.access(bench, os.X_OK):
        log("rbfmuscle_bench not built (benchmarks/): rigid-motion errors skipped")
        return []
    rows = []
    for muscle in model["muscles"]:
        if not muscle["surface"] or not os.path.exists(muscle["surface"]):
            continue
        log(f"core benchmark on {muscle['name']} ({os.path.relpath(muscle['surface'], ROOT)}) ...")
        env = dict(os.environ, RBFMUSCLE_BENCH_RBF=muscle["surface"])
        r = subprocess.run([bench, "--benchmark_format=json"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                           text=True, env=env)
        if r.returncode != 0:
            raise RuntimeError(f"rbfmuscle_bench failed on {muscle['surface']}:\n{r.stderr[-2000:]}")
        for b in json.loads(r.stdout)["benchmarks"]:
            row = {"muscle": muscle["name"], "benchmark": b["name"].split("/iterations")[0],
                   "built": datetime.datetime.utcfromtimestamp(os.path.getmtime(bench)).strftime("%H:%M UTC"),
                   "time_ms": b["real_time"] if b.get("time_unit") == "ms" else float("nan")}
            row.update({k: v for k, v in b.items() if k.endswith(("_mm", "_error", "_ms")) or k in ("iterations",)})
            rows.append(row)
    return rows


def machine_info(host):
    cpu = "unknown"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    try:
        commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True).stdout.strip()
    except OSError:
        commit, dirty = "unknown", ""
    return {"cpu": cpu, "nproc": os.cpu_count(), "kernel": platform.release(), "python": platform.python_version(),
            "commit": commit + (" (+ uncommitted changes)" if dirty else ""), "host": os.path.relpath(host, ROOT),
            "load_start": os.getloadavg(),
            "host_built": datetime.datetime.utcfromtimestamp(os.path.getmtime(host)).strftime("%Y-%m-%d %H:%M UTC"), "date": datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M UTC")}


def main():
    args = parse_args()
    args.host, args.model = os.path.abspath(args.host), os.path.abspath(args.model)
    if not os.access(args.host, os.X_OK):
        sys.exit(f"speed_vs_error: no host at {args.host} (build first, or give --host)")
    _, help_text = run_command([args.host, "run", "--help"], "rbfmuscle run --help")
    if "--set" not in help_text or "--motion" not in help_text:
        sys.exit(f"speed_vs_error: {args.host} has no --set/--motion options: rebuild it")
    started = time.monotonic()
    machine = machine_info(args.host)
    model = bench_io.read_model(args.model)
    props = class_properties(args.host)
    cache = SurfaceCache(args.host, args.cache)
    motions = make_motions(args.work, args.quick, args.full)
    configs = configurations(model, args, props)
    mode = "quick" if args.quick else ("full" if args.full else "default")
    log(f"{mode} sweep: {len(configs)} runs of {os.path.relpath(args.model, ROOT)} "
        f"({', '.join(m['name'] for m in model['muscles'])}); contact_probes "
        f"{'swept' if 'contact_probes' in props else 'not a property: skipped'}")

    # A run is reused (--reuse) only with the same command and the same host and plugin
    # builds, so a report never mixes runs of different code.
    plugin = os.path.normpath(os.path.join(os.path.dirname(args.host), "..", "lib", "librbfmuscle_plugin.so"))
    build = {os.path.basename(p): os.path.getmtime(p) for p in (args.host, plugin) if os.path.exists(p)}
    results = []
    all_reused = True
    for k, config in enumerate(configs, 1):
        outdir = os.path.join(args.work, "runs", config["id"])
        cmd, centres = build_command(args, model, cache, config, motions, outdir)
        stamp = os.path.join(outdir, "command.json")
        reused = False
        if args.reuse and os.path.exists(stamp):
            with open(stamp) as f:
                old = json.load(f)
            reused = old.get("command") == cmd and old.get("build") == build
            if not reused and old.get("command") == cmd:
                log("      host or plugin rebuilt since this run: running it again")
        elapsed = time.monotonic() - started
        log(f"[{k}/{len(configs)}] {config['id']} ({elapsed / 60:.1f} min so far)" + (" reused" if reused else ""))
        all_reused = all_reused and reused
        if not reused:
            wall, _ = run_command(cmd, f"run {config['id']}")
            with open(stamp, "w") as f:
                # The fit figures of the surfaces this run used, as they were when it ran.
                json.dump({"command": cmd, "wall_s": wall, "build": build,
                           "surfaces": surface_metrics(model, cache, config)}, f)
        with open(stamp) as f:
            stamp_data = json.load(f)
        wall = stamp_data["wall_s"]
        row, per, _ = measure(outdir, model, config)
        row.update({"id": config["id"], "knob": config["knob"], "value": config["value"], "kind": config["kind"],
                    "wall_s": wall, "motion": os.path.basename(motions[config["motion"]]),
                    "command": " ".join(c if " " not in c else f"'{c}'" for c in cmd).replace(ROOT + "/", "")})
        for name, n in centres.items():
            per[name]["centres"] = n
        row["settings"] = effective_settings(model, props, config, centres)
        surfaces = stamp_data["surfaces"] if "surfaces" in stamp_data else surface_metrics(model, cache, config)
        for name, m in surfaces.items():
            per[name]["surface_mean_mm"] = m.get("mean_distance_mm", float("nan"))
            per[name]["surface_max_mm"] = m.get("max_distance_mm", float("nan"))
            per[name]["jaccard"] = m.get("jaccard", float("nan"))
        row["muscles"] = per
        log(f"      {row['frames']} frames, {row['frame_mean_ms']:.0f} ms/frame ({row['fps']:.2f} frames/s), "
            f"run {wall:.1f} s")
        results.append(row)

    bench_file = os.path.join(args.work, f"core_bench_{mode}.json")
    if args.quick:
        bench_rows = []
    elif args.reuse and os.path.exists(bench_file):
        with open(bench_file) as f:
            bench_rows = json.load(f)
    else:
        bench_rows = core_benchmarks(args.host, model)
        with open(bench_file, "w") as f:
            json.dump(bench_rows, f, indent=1)
    machine["core_benchmarks"] = bench_rows
    reference = next(r for r in results if r["kind"] == "reference")
    for r in results:
        for name, m in r["muscles"].items():
            m["fibre_dev"] = fibre_deviation(m["_fibre"], reference["muscles"][name]["_fibre"])
    machine["load_end"] = os.getloadavg()
    machine["sweep_minutes"] = (time.monotonic() - started) / 60.0
    machine["mode"] = mode
    argv, skip = [], False
    for a in sys.argv[1:]:  # the command without --note TEXT and --reuse
        if skip or a in ("--note", "--reuse") or a.startswith("--note="):
            skip = a == "--note"
            continue
        argv.append(a)
    machine["command"] = "/usr/bin/python3 " + " ".join(
        [os.path.relpath(os.path.abspath(sys.argv[0]), ROOT)] + argv)
    machine["fit_seconds"] = cache.fit_seconds
    machine["note"] = args.note
    # The machine figures belong to the sweep that made the runs: a --reuse that ran
    # nothing keeps those of the last real sweep.
    machine_file = os.path.join(args.work, f"machine_{mode}.json")
    if all_reused and os.path.exists(machine_file):
        with open(machine_file) as f:
            machine = json.load(f)
        machine["note"] = args.note or machine.get("note", "")
        machine["core_benchmarks"] = bench_rows
    else:
        with open(machine_file, "w") as f:
            json.dump(machine, f, indent=1)
    os.makedirs(args.report, exist_ok=True)
    bench_report.write_all(results, machine, args.report, ROOT)
    log(f"done in {machine['sweep_minutes']:.1f} min: {os.path.relpath(args.report, ROOT)}/speed_vs_error.csv, "
        f".png, README.md")


if __name__ == "__main__":
    main()
