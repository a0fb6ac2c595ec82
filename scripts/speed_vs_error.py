#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
"""Speed against error of the muscle pipeline on the hip flexion scene.

Runs models/hip/hip_flexion.xml through build/bin/rbfmuscle once per configuration, changing one
knob at a time from the scene's own settings ("base"):
  centres            scale of each muscle's `centres` (0.5×; 2× only with --full): a refit, cached
                     in WORK/cache as MESHSTEM_N.rbf (+ the fit's JSON line as MESHSTEM_N.json)
                     and given to the run by `--set MUSCLE.surface_file=ABSOLUTE_PATH`; a muscle
                     whose fit comes out in more pieces than the scene's surface keeps its own
                     (fibres cannot be laid through a muscle in pieces; the report says so)
  quadrature_points  `MUSCLE/volume.quadrature_points` (500, 1000, 4000; the base has 2000)
  descent iterations `MUSCLE/descent.iterations` (0, 3; the base has 1)
  frame step         the scene's 1° motion subsampled to 10° (WORK/motions), compared with the
                     reference at the angles both have
and once as the reference: the base with 8000 quadrature points and 10 descent steps (same
centres, same motion as the base). Per configuration: speed = median wall time of a frame (summary.json)
and each muscle's median update_ms; per muscle the errors
  volume drift          max over frames |volume_ratio − 1| (the run's own volume measure)
  fibre ratio error     mean over the frames after the first, at the angles shared with the
                        reference, of |fibre_length_ratio − the reference's|
  fibre deviation       mean (and, in the csv, max) over those frames and the fibres of
                        |fibre_length_mm_K − the reference's| (only when both runs have the
                        same fibres at rest)
  fibre points outside  max over frames of fibre_points_outside
  bone depth            max over frames of surface_bone_depth_max_mm and of
                        surface_vertices_unresolved (only with --bone-depth or --full: a second
                        run with --frames-mesh, whose surface stage takes 0.1–0.25 s a muscle
                        and frame; its meshes are deleted once read)
and the static fit figures of each centres level (Jaccard, mean / max distance to the mesh) from
the fit's JSON line (for the scene's own surfaces: the `metrics` line of their .rbf files).

Writes docs/speed_vs_error.csv, docs/pictures/speed_vs_error.png and the "speed vs error" section
of docs/design.md. Progress (configuration n of N) goes to stderr. Timings depend on the machine
and its load: run it on a quiet machine; the section states the core count and the load. The
sweep stops when the host or a library in its ../lib changes under it (a rebuild); to measure
while the build is in use, copy build/bin and build/lib and give --host COPY/bin/rbfmuscle (the
runs get LD_LIBRARY_PATH=COPY/lib). A failing run prints the host's stderr and stops the sweep.

Usage: /usr/bin/python3 scripts/speed_vs_error.py [--quick | --full] [--bone-depth] [--no-write]
           [--list] [--reuse] [--host build/bin/rbfmuscle] [--work out/speed_vs_error]
  --quick    base, 0.5× centres, 500 quadrature points and the reference, all on the 10° motion:
             checks the script works (< 3 min)
  (default)  the sweep above on the scene's 1° motion, the base run twice (< 20 min on 2 cores)
  --full     also 2× centres (slow fits), descent 6 and the bone depth of every configuration
  --list     print the configurations and exit
  --reuse    re-read the runs (WORK/runs) of an earlier sweep with the same commands and host
             build instead of running them again (e.g. to redraw the report)
Needs python3-numpy and python3-matplotlib (Debian) and a built host.
"""
import argparse
import glob
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import numpy as np

from readme_section import replace_readme_section
from scene_bones import out_of_argument
from speed_vs_error_report import bone_depth, compare, fmt, measure, plot, rows_of, section, write_csv

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
HOST = os.path.join(ROOT, "build", "bin", "rbfmuscle")
MODEL = os.path.join(ROOT, "models", "hip", "hip_flexion.xml")
WORK = os.path.join(ROOT, "out", "speed_vs_error")
DESIGN = os.path.join("docs", "design.md")
CSV_PATH = os.path.join(ROOT, "docs", "speed_vs_error.csv")
PICTURE = os.path.join(ROOT, "docs", "pictures", "speed_vs_error.png")
SECTION = "speed vs error"
COARSE_STEP_DEG = 10.0
# The knobs (rbfmuscle info -L librbfmuscle_plugin.so RBFMuscle): property names as --set takes them.
CENTRES, QUADRATURE, DESCENT = "centres", "volume/quadrature_points", "descent/iterations"
REFERENCE = {QUADRATURE: 8000, DESCENT: 10}
# Fit settings that do not change the surface (or are the centre count itself).
FIT_SETTINGS_IGNORED = {"max_centres", "metric_points", "metric_sigma", "surface_cell_mm"}


def say(text):
    print(text, file=sys.stderr, flush=True)


def fail(text):
    sys.exit(f"speed_vs_error: {text}")


def host_environment(host):
    """The environment of the host's runs: its own ../lib first, so that a copied build loads its
    own libraries (the build's RUNPATH names the directory it was built in)."""
    env = dict(os.environ)
    lib = os.path.normpath(os.path.join(os.path.dirname(host), "..", "lib"))
    if os.path.isdir(lib):
        env["LD_LIBRARY_PATH"] = lib + (os.pathsep + env["LD_LIBRARY_PATH"] if env.get("LD_LIBRARY_PATH") else "")
    return env


def host_signature(host):
    """Size and modification time of the host and of the libraries in its ../lib: a rebuild during
    the sweep would make its runs incomparable."""
    files = [host] + sorted(glob.glob(os.path.join(os.path.dirname(host), "..", "lib", "*.so*")))
    return [(os.path.basename(f), os.stat(f).st_size, os.stat(f).st_mtime_ns) for f in files if os.path.exists(f)]


def run_host(cmd, what, may_fail=False):
    """Runs the host; on failure prints its stderr and stops with a message naming the command
    (with may_fail, returns the failed result instead)."""
    try:
        result = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                env=host_environment(cmd[0]))
    except OSError as e:
        fail(f"cannot start {cmd[0]} ({e.strerror}); build the host or give --host")
    if result.returncode != 0 and not may_fail:
        fail_run(result, cmd, what)
    return result


def fail_run(result, cmd, what):
    """Prints a failed run's stderr and stops with a message naming the command."""
    sys.stderr.write(result.stderr)
    fail(f"{what} failed (exit {result.returncode}); the host's stderr is above.\n  command: {shlex.join(cmd)}")


# ---- the model, its knobs and its motion -------------------------------------------------------

def class_defaults(host):
    """{property: default number} of the RBFMuscle class, subcomponent properties as 'sub/name'."""
    text = run_host([host, "info", "-L", "librbfmuscle_plugin.so", "RBFMuscle"], "rbfmuscle info").stdout
    defaults = {name: float(value) for name, value in
                re.findall(r"^\s+([\w/]+) \((?:int|double), default ([-+0-9.eE]+)", text, flags=re.M)}
    missing = [k for k in (CENTRES, QUADRATURE, DESCENT) if k not in defaults]
    if missing:
        fail(f"the RBFMuscle class has no property {', '.join(missing)} (the knobs changed? see "
             f"`{host} info -L librbfmuscle_plugin.so RBFMuscle`)")
    return defaults


def read_model(path, defaults):
    """{'motion': path, 'muscles': [{name, mesh, surface, settings {knob: int}}]} of the model file."""
    root = ET.parse(path).getroot()
    directory = os.path.dirname(os.path.abspath(path))
    resolve = lambda p: p if not p or os.path.isabs(p) else os.path.normpath(os.path.join(directory, p))
    motion = root.find("motion")
    if motion is None:
        fail(f"{path}: no <motion> element")
    muscles = []
    for element in root.iter("RBFMuscle"):
        settings = {}
        for knob in (CENTRES, QUADRATURE, DESCENT):
            text = (element.findtext(knob) or "").strip()
            settings[knob] = int(float(text)) if text else int(defaults[knob])
        muscles.append({"name": element.get("name"), "mesh": resolve((element.findtext("mesh_file") or "").strip()),
                        "surface": resolve((element.findtext("surface_file") or "").strip()), "settings": settings})
    if not muscles:
        fail(f"{path}: no RBFMuscle component")
    return {"motion": resolve(motion.get("file")), "muscles": muscles}


def read_motion(path):
    """(header lines up to endheader, column labels, rows 2-D array, in degrees) of a .mot file."""
    with open(path) as f:
        lines = f.read().splitlines()
    end = next((i for i, line in enumerate(lines) if line.strip() == "endheader"), None)
    if end is None:
        fail(f"{path}: no 'endheader' line (expected an OpenSim motion file)")
    header, labels = lines[:end + 1], lines[end + 1].split("\t")
    rows = np.array([[float(x) for x in line.split("\t")] for line in lines[end + 2:] if line.strip()])
    in_degrees = any(line.strip().lower() == "indegrees=yes" for line in header)
    return header, labels, rows, in_degrees


def moving_coordinate(labels, rows):
    """The column (other than time) whose range is largest."""
    spans = [np.ptp(rows[:, k]) if labels[k] != "time" else -1.0 for k in range(len(labels))]
    return labels[int(np.argmax(spans))]


def write_coarse_motion(source, target, step_deg):
    """The source motion at every k-th frame (k = step / its step; the last frame kept), one frame
    time apart, in the same format."""
    header, labels, rows, in_degrees = read_motion(source)
    coordinate = moving_coordinate(labels, rows)
    angles = rows[:, labels.index(coordinate)]
    fine = float(np.median(np.abs(np.diff(angles))))
    stride = max(1, int(round((step_deg if in_degrees else np.radians(step_deg)) / fine)))
    keep = list(range(0, len(rows), stride))
    if keep[-1] != len(rows) - 1:
        keep.append(len(rows) - 1)
    coarse = rows[keep].copy()
    time_column = labels.index("time")
    coarse[:, time_column] = np.arange(len(keep)) * (rows[1, time_column] - rows[0, time_column])
    name = os.path.splitext(os.path.basename(target))[0]
    note = f"Every {stride}th frame of {os.path.basename(source)}, written by scripts/speed_vs_error.py."
    out = [name] + [re.sub(r"^nRows=\d+", f"nRows={len(keep)}", line) if "=" in line or line == "endheader" else note
                    for line in header[1:]]
    os.makedirs(os.path.dirname(target), exist_ok=True)
    with open(target + ".tmp", "w") as f:
        f.write("\n".join(out + ["\t".join(labels)] + ["\t".join(repr(float(x)) for x in r) for r in coarse]) + "\n")
    os.replace(target + ".tmp", target)
    return coordinate


# ---- fitted surfaces ---------------------------------------------------------------------------

def rbf_lines(path):
    """{'source_hash': text, 'settings': {k: v}, 'metrics': dict} from the header of a .rbf file."""
    found = {"source_hash": "", "settings": {}, "metrics": {}}
    with open(path) as f:
        for line in f:
            key, _, rest = line.strip().partition(" ")
            if key == "source_hash":
                found["source_hash"] = rest.strip()
            elif key == "settings":
                found["settings"] = dict(w.split("=", 1) for w in rest.split() if "=" in w)
            elif key == "metrics":
                found["metrics"] = json.loads(rest)
            elif key == "centres":
                break
    return found


def settings_difference(a, b):
    """Names of the fit settings that differ between two .rbf files (centre count aside)."""
    sa, sb = rbf_lines(a)["settings"], rbf_lines(b)["settings"]
    return sorted(k for k in set(sa) | set(sb) if k not in FIT_SETTINGS_IGNORED and sa.get(k) != sb.get(k))


class Surfaces:
    """The surface of each muscle at each centre count: the model's own .rbf at the model's count,
    else a fit cached in `directory` (fitted when missing or fitted to another mesh), of the mesh
    moved out of the model's bones as the scene does (`out_of`, scene_bones.out_of_argument)."""

    def __init__(self, host, directory, out_of):
        self.host, self.directory, self.out_of = host, directory, out_of
        self.fit_seconds = {}

    def own(self, muscle, centres):
        s = muscle["surface"]
        return s if centres == muscle["settings"][CENTRES] and s and os.path.isfile(s) else None

    def path(self, muscle, centres):
        own = self.own(muscle, centres)
        if own:
            return own
        stem = os.path.splitext(os.path.basename(muscle["mesh"]))[0]
        target = os.path.join(self.directory, f"{stem}_{centres}{'_out_of_bones' if self.out_of else ''}.rbf")
        if os.path.isfile(target) and os.path.isfile(target[:-4] + ".json"):
            model_surface = muscle["surface"] if muscle["surface"] and os.path.isfile(muscle["surface"]) else None
            if model_surface is None or rbf_lines(target)["source_hash"] == rbf_lines(model_surface)["source_hash"]:
                return target
            say(f"  {os.path.relpath(target, ROOT)} was fitted to another mesh: refitting")
        os.makedirs(self.directory, exist_ok=True)
        say(f"  fitting {stem} with {centres} centres (cached as {os.path.relpath(target, ROOT)}) ...")
        partial = target[:-4] + ".partial.rbf"
        start = time.monotonic()
        result = run_host([self.host, "fit", muscle["mesh"], "--centres", str(centres), "-o", partial, "--quiet"]
                          + self.out_of,
                          f"fitting {stem} with {centres} centres")
        seconds = time.monotonic() - start
        lines = result.stdout.strip().splitlines()
        try:
            figures = json.loads(lines[-1])
        except (IndexError, ValueError):
            fail(f"the fit of {stem} printed no JSON line on stdout:\n{result.stdout}")
        for line in result.stderr.splitlines():
            if "warning" in line:
                say("    " + line)
        with open(target[:-4] + ".json", "w") as f:
            f.write(json.dumps(figures) + "\n")
        os.replace(partial, target)
        self.fit_seconds[os.path.basename(target)] = seconds
        say(f"  fitted in {seconds:.0f} s: Jaccard {figures.get('jaccard', float('nan')):.3f}, "
            f"mean / max distance {figures.get('mean_distance_mm', float('nan')):.2f} / "
            f"{figures.get('max_distance_mm', float('nan')):.2f} mm")
        return target

    def own_pieces(self, muscle):
        own = self.own(muscle, muscle["settings"][CENTRES])
        return rbf_lines(own)["metrics"].get("components", 1) if own else 1

    def figures(self, muscle, centres):
        """The fit's figures: its JSON line (cached fits) or the .rbf's metrics line (the model's own)."""
        path = self.path(muscle, centres)
        if path.startswith(self.directory):
            with open(path[:-4] + ".json") as f:
                return json.loads(f.read())
        return rbf_lines(path)["metrics"]


# ---- configurations ----------------------------------------------------------------------------

def configurations(mode, model):
    """[{id, knob, value, scale, sets {knob: value}, motion 'base'|'coarse', kind}] of a mode. The
    levels equal to the scene's own setting are left out (the base has them)."""
    quick, full = mode == "quick", mode == "full"
    base_motion = "coarse" if quick else "base"
    own = lambda knob: {m["settings"][knob] for m in model["muscles"]}
    configs = []

    def add(cid, knob, value, scale=1.0, sets=None, motion=base_motion, kind="sweep"):
        configs.append({"id": cid, "knob": knob, "value": value, "scale": scale, "sets": sets or {},
                        "motion": motion, "kind": kind})

    add("base", "base", "scene", kind="base")
    for scale in [0.5] + ([2.0] if full else []):
        add(f"centres ×{scale:g}", "centres", f"×{scale:g}", scale=scale)
    for n in ([500] if quick else [500, 1000, 4000]):
        if {n} != own(QUADRATURE):
            add(f"quadrature {n}", "quadrature_points", n, sets={QUADRATURE: n})
    for n in ([] if quick else [0, 3] + ([6] if full else [])):
        if {n} != own(DESCENT):
            add(f"descent {n}", "descent iterations", n, sets={DESCENT: n})
    if not quick:
        add(f"step {COARSE_STEP_DEG:g}°", "frame step", f"{COARSE_STEP_DEG:g}°", motion="coarse")
    label = {QUADRATURE: "quadrature_points", DESCENT: "descent iterations"}
    add("reference", "reference", ", ".join(f"{label[k]} {v}" for k, v in REFERENCE.items()),
        sets=dict(REFERENCE), kind="reference")
    if not quick:  # the spread of the timings: the base once more, minutes after the first
        add("base (again)", "base", "scene", kind="repeat")
    return configs


def command(args, model, surfaces, config, motions, out, frames_mesh=False):
    cmd = [args.host, "run", args.model, "-o", out, "--quiet"]
    if config["motion"] == "coarse":
        cmd += ["--motion", motions["coarse"]]
    for m in model["muscles"]:
        n = config["centres"][m["name"]]
        if n != m["settings"][CENTRES] or not surfaces.own(m, n):
            cmd += ["--set", f"{m['name']}.surface_file={surfaces.path(m, n)}", "--set", f"{m['name']}.centres={n}"]
        for knob, value in config["sets"].items():
            cmd += ["--set", f"{m['name']}{'/' if '/' in knob else '.'}{knob.replace('/', '.')}={value}"]
    if frames_mesh:
        cmd.append("--frames-mesh")
    return cmd


def scaled(muscle, scale):
    return max(10, int(round(muscle["settings"][CENTRES] * scale)))


def choose_centres(model, surfaces, config):
    """Each muscle's centre count in a configuration: the scaled count, fitted first; but a fit
    in more pieces than the scene's surface keeps the scene's count (the run could not lay fibres
    through a muscle in pieces); config["unused_fits"] keeps its count, figures and why, for the report."""
    config["centres"], config["unused_fits"] = {}, {}
    for m in model["muscles"]:
        n = scaled(m, config["scale"])
        if n != m["settings"][CENTRES]:
            figures = surfaces.figures(m, n)
            own_pieces = surfaces.own_pieces(m)
            if figures.get("components", 1) > own_pieces:
                config["unused_fits"][m["name"]] = (n, figures, f"its fit with {n} comes out in {figures['components']} "
                                                    "pieces, through which the run cannot lay its fibres")
                say(f"  {m['name']}: its fit with {n} centres comes out in {figures['components']} pieces (the scene's "
                    f"surface in {own_pieces}): this configuration keeps its {m['settings'][CENTRES]} centres")
                n = m["settings"][CENTRES]
        config["centres"][m["name"]] = n


# The host refuses a muscle whose inside no fibre can cross (its fit in one piece, but a part of
# it thinner than the fibres' grid): the configuration then keeps that muscle's own surface.
REFUSED_FIBRES = re.compile(r'<RBFMuscle name="([^"]+)">: initialize: generateFibres: (.*)')


def run_configuration(args, model, surfaces, config, motions, out):
    """Runs a configuration; a refit the host refuses to lay fibres through is replaced by the
    scene's own surface, and the run repeated. Returns the command that ran."""
    while True:
        cmd = command(args, model, surfaces, config, motions, out)
        result = run_host(cmd, f"configuration '{config['id']}'", may_fail=True)
        if result.returncode == 0:
            return cmd
        refused = REFUSED_FIBRES.search(result.stderr)
        muscle = next((m for m in model["muscles"] if refused and m["name"] == refused.group(1)), None)
        if muscle is None or config["centres"][muscle["name"]] == muscle["settings"][CENTRES]:
            fail_run(result, cmd, f"configuration '{config['id']}'")
        n = config["centres"][muscle["name"]]
        config["unused_fits"][muscle["name"]] = (n, surfaces.figures(muscle, n), f"the host lays no fibres through its "
                                                 f"fit with {n} ({refused.group(2).split(':')[0]})")
        say(f"  {muscle['name']}: the host lays no fibres through its fit with {n} centres: this configuration "
            f"keeps its {muscle['settings'][CENTRES]} centres")
        config["centres"][muscle["name"]] = muscle["settings"][CENTRES]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--quick", action="store_true", help="few configurations on the 10° motion (< 3 min)")
    mode.add_argument("--full", action="store_true", help="also 2× centres, descent 6 and the bone depth")
    parser.add_argument("--bone-depth", action="store_true",
                        help="also run each configuration with --frames-mesh for surface_bone_depth_max_mm (slow)")
    parser.add_argument("--no-write", action="store_true", help="print the table, write nothing under docs/")
    parser.add_argument("--list", action="store_true", help="print the configurations and exit")
    parser.add_argument("--reuse", action="store_true",
                        help="re-read runs of an earlier sweep made with the same command and host build")
    parser.add_argument("--host", default=HOST, help="the rbfmuscle executable [build/bin/rbfmuscle]")
    parser.add_argument("--model", default=MODEL, help=argparse.SUPPRESS)
    parser.add_argument("--work", default=WORK, help="cache and run directories [out/speed_vs_error]")
    args = parser.parse_args()
    args.host, args.model, args.work = (os.path.abspath(p) for p in (args.host, args.model, args.work))
    mode = "quick" if args.quick else ("full" if args.full else "default")
    with_depth = args.bone_depth or args.full
    if not os.path.isfile(args.host):
        fail(f"no host at {args.host}: build it (cmake --build build) or give --host")

    model = read_model(args.model, class_defaults(args.host))
    configs = configurations(mode, model)
    if args.list:
        for k, c in enumerate(configs, 1):
            print(f"{k:2d}. {c['id']}: {c['knob']} = {c['value']}, motion {c['motion']}")
        return
    motions = {"base": model["motion"], "coarse": os.path.join(args.work, "motions",
                                                               f"flexion_step{COARSE_STEP_DEG:g}.mot")}
    coordinate = write_coarse_motion(model["motion"], motions["coarse"], COARSE_STEP_DEG)
    surfaces = Surfaces(args.host, os.path.join(args.work, "cache"), out_of_argument(args.model))
    runs_dir = os.path.join(args.work, "runs", mode)
    load_start, started, signature = os.getloadavg()[0], time.monotonic(), host_signature(args.host)
    results = []
    for k, config in enumerate(configs, 1):
        say(f"[{k}/{len(configs)}] {config['id']} ({config['knob']} = {config['value']}, "
            f"{'10° motion' if config['motion'] == 'coarse' else 'the scene motion'})")
        out = os.path.join(runs_dir, re.sub(r"[^\w.]+", "_", config["id"]).strip("_"))
        choose_centres(model, surfaces, config)  # fits missing surfaces first
        cmd = command(args, model, surfaces, config, motions, out)
        t = time.monotonic()
        stamp = json.dumps({"command": cmd, "host": signature})
        if args.reuse and os.path.isfile(os.path.join(out, "summary.json")) and os.path.isfile(out + ".run.json") \
                and open(out + ".run.json").read() == stamp:
            say("  reusing the earlier run (same command, same host build)")
        else:
            cmd = run_configuration(args, model, surfaces, config, motions, out)
            stamp = json.dumps({"command": cmd, "host": signature})
            with open(out + ".run.json", "w") as f:
                f.write(stamp)
        changed = [a[0] for a, b in zip(host_signature(args.host), signature) if a != b]
        if changed or len(host_signature(args.host)) != len(signature):
            fail(f"the host changed during the sweep ({', '.join(changed) or 'its libraries'} rebuilt?): its runs "
                 "are not comparable; rerun when the build is finished (or copy the build and give --host)")
        run = measure(out, model, coordinate)
        say(f"  {time.monotonic() - t:.0f} s: {run['frames']} frames, frame median {run['frame_ms']:.1f} ms, "
            f"initialisation {run['initialize_s']:.0f} s")
        if run["invariants_broken"]:
            say(f"  invariants broken: {json.dumps(run['invariants_broken'])[:300]}")
        depth = {m["name"]: (float("nan"), float("nan")) for m in model["muscles"]}
        if with_depth:
            t = time.monotonic()
            mesh_out = out + "_meshes"
            run_host(command(args, model, surfaces, config, motions, mesh_out, frames_mesh=True),
                     f"configuration '{config['id']}' with --frames-mesh")
            depth = bone_depth(mesh_out, model)
            shutil.rmtree(mesh_out)
            say(f"  with --frames-mesh {time.monotonic() - t:.0f} s: surface bone depth max "
                + " / ".join(fmt(d[0], ".3f") for d in depth.values()) + " mm")
        run["config"] = config
        run["step_deg"] = float(np.median(np.abs(np.diff(run["angle_deg"])))) if run["frames"] > 1 else float("nan")
        for m in model["muscles"]:
            x = run["muscles"][m["name"]]
            x["centres"] = config["centres"][m["name"]]
            x["fit"] = surfaces.figures(m, x["centres"])
            x["fit_mean_mm"] = float(x["fit"].get("mean_distance_mm", float("nan")))
            x["bone_depth_mm"], x["unresolved"] = depth[m["name"]]
        results.append(run)
    reference = next(r for r in results if r["config"]["kind"] == "reference")
    for r in results:
        for name, errors in compare(r, reference).items():
            r["muscles"][name].update(errors)
    load_end = os.getloadavg()[0]

    notes = []
    scales = sorted({c["scale"] for c in configs if c["scale"] != 1.0})
    for m in model["muscles"]:
        own = surfaces.own(m, m["settings"][CENTRES])
        diff = settings_difference(own, surfaces.path(m, scaled(m, scales[0]))) if own and scales else []
        if diff:
            notes.append(f"- {m['name']}: the scene's surface ({m['settings'][CENTRES]} centres) was fitted with other "
                         f"fit settings ({', '.join(diff)}) than the current `rbfmuscle fit` made the other levels with.")
    for c in configs:
        for name, (_, _, why) in c["unused_fits"].items():
            notes.append(f"- {c['id']}: {name} keeps the scene's {c['centres'][name]} centres: {why}.")
    if surfaces.fit_seconds:
        notes.append("- Fits made for this report (cached in out/): " +
                     ", ".join(f"{k} {v:.0f} s" for k, v in sorted(surfaces.fit_seconds.items())) + ".")
    text = section(results, model, mode, notes, (load_start, load_end))
    print(text)
    say(f"{len(configs)} configurations in {time.monotonic() - started:.0f} s")
    if args.no_write:
        return
    write_csv(rows_of(results, model), CSV_PATH)
    plot(results, PICTURE)
    replace_readme_section(SECTION, text, DESIGN)
    print(f"wrote {os.path.relpath(CSV_PATH, ROOT)}, {os.path.relpath(PICTURE, ROOT)} and the "
          f"{SECTION} section of {DESIGN}")


if __name__ == "__main__":
    try:
        main()
    except KeyboardInterrupt:
        sys.exit("speed_vs_error: interrupted")
