#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
"""Soak test: a long gait run of the main job, checked for NaN, drift and memory growth.

Repeats the gait cycle of models/hip/hip_gait.xml (motions/gait_cycle.mot, 100 frames a cycle)
up to FRAMES frames, runs `rbfmuscle run --strict` on it (a broken invariant fails the run)
recording each muscle's volume and fibre lengths, and samples the host's resident memory
(VmRSS of /proc/PID/status) while it runs. Checks:
  - no NaN or infinity in any recorded output;
  - no drift from cycle to cycle: each frame's volume and mean fibre length differ from the
    same frame of the first cycle by less than 0.1 %;
  - flat memory: RSS at the last frame within 5 % of RSS at the end of cycle 2.
Frames are mapped to times by the host's progress lines (frames take equal time).

Usage: /usr/bin/python3 scripts/soak.py [--frames 10000] [--host build/bin/rbfmuscle] [--work build/soak]
Exit status 0 when every check passes; prints the figures either way.
"""
import argparse
import math
import os
import pathlib
import re
import subprocess
import sys
import threading
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
MODEL = ROOT / "models/hip/hip_gait.xml"
CYCLE_MOTION = ROOT / "models/hip/motions/gait_cycle.mot"
QUANTITIES = ("volume_mm3", "volume_ratio", "fibre_length_mean_mm", "fibre_length_min_mm", "fibre_length_max_mm")
DRIFT_QUANTITIES = ("volume_mm3", "fibre_length_mean_mm")
MAX_DRIFT = 1e-3       # 0.1 %
MAX_RSS_GROWTH = 0.05  # 5 %


def read_storage(path):
    """Labels and rows (numpy array) of an OpenSim storage file."""
    lines = pathlib.Path(path).read_text().splitlines()
    end = next(i for i, line in enumerate(lines) if line.strip() == "endheader")
    labels = lines[end + 1].split("\t")
    rows = np.array([[float(v) for v in line.split()] for line in lines[end + 2:] if line.strip()])
    return lines[:end + 1], labels, rows


def write_repeated_motion(path, frames):
    """The gait cycle repeated to `frames` frames, 1/30 s apart; the cycle's last row repeats its
    first, so a cycle is its other rows."""
    header, labels, rows = read_storage(CYCLE_MOTION)
    cycle = rows[:-1]
    assert np.allclose(rows[0, 1:], rows[-1, 1:]), "gait_cycle.mot no longer ends where it starts"
    step = rows[1, 0] - rows[0, 0]
    out = ["gait_cycle_repeated", "version=1", f"nRows={frames}", f"nColumns={len(labels)}", "inDegrees=yes",
           f"The gait cycle of {CYCLE_MOTION.name} repeated ({len(cycle)} frames a cycle) by scripts/soak.py.",
           "endheader", "\t".join(labels)]
    for i in range(frames):
        values = cycle[i % len(cycle), 1:]
        out.append("\t".join([repr(i * step)] + [repr(v) for v in values]))
    pathlib.Path(path).write_text("\n".join(out) + "\n")
    return len(cycle)


def rss_kib(pid):
    try:
        for line in pathlib.Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    except OSError:
        pass
    return None


def run_host(host, motion, out_dir, log_path):
    """Runs the host; returns (exit code, [(t, rss KiB)], [(t, frame)])."""
    patterns = [f"*.{q}" for q in QUANTITIES]
    command = [str(host), "run", str(MODEL), "-o", str(out_dir), "--motion", str(motion), "--strict"]
    for p in patterns:
        command += ["--report", p]
    samples, progress = [], []
    with open(log_path, "w") as log:
        process = subprocess.Popen(command, stderr=subprocess.PIPE, stdout=log, text=True, bufsize=1)
        start = time.monotonic()

        def read_progress():
            for line in process.stderr:
                log.write(line)
                found = re.search(r"frame (\d+)/(\d+)", line)
                if found:
                    progress.append((time.monotonic() - start, int(found.group(1))))

        reader = threading.Thread(target=read_progress)
        reader.start()
        while process.poll() is None:
            value = rss_kib(process.pid)
            if value is not None:
                samples.append((time.monotonic() - start, value))
            time.sleep(0.2)
        reader.join()
    return process.returncode, samples, progress


def rss_at_frame(samples, progress, frame):
    """RSS sampled closest to the time the loop reached `frame` (linear between progress lines)."""
    times = [t for t, _ in progress]
    frames = [f for _, f in progress]
    if len(progress) < 2:
        raise SystemExit("soak: too few progress lines to place frames in time")
    when = float(np.interp(frame, frames, times))
    return min(samples, key=lambda s: abs(s[0] - when))[1], when


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--frames", type=int, default=10000)
    parser.add_argument("--host", default=str(ROOT / "build/bin/rbfmuscle"))
    parser.add_argument("--work", default=str(ROOT / "build/soak"))
    args = parser.parse_args()

    work = pathlib.Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    motion = work / "gait_repeated.mot"
    cycle = write_repeated_motion(motion, args.frames)
    out_dir = work / "run"
    started = time.monotonic()
    code, samples, progress = run_host(args.host, motion, out_dir, work / "host.log")
    seconds = time.monotonic() - started
    print(f"soak: {args.frames} frames ({args.frames // cycle} gait cycles of {cycle}) in {seconds:.0f} s, exit {code}")
    if code != 0:
        print((work / "host.log").read_text()[-2000:])
        return 1

    _, labels, rows = read_storage(out_dir / "outputs.sto")
    failures = []
    finite = np.isfinite(rows)
    if not finite.all():
        bad = np.argwhere(~finite)[0]
        failures.append(f"non-finite value: frame {bad[0]}, column {labels[bad[1]]}")
    print(f"soak: NaN or infinite values: {int((~finite).sum())} of {rows.size}")

    cycles = rows.shape[0] // cycle
    worst = 0.0
    for c, label in enumerate(labels):
        if not any(label.endswith("." + q) for q in DRIFT_QUANTITIES):
            continue
        x = rows[: cycles * cycle, c].reshape(cycles, cycle)
        drift = np.abs(x - x[0]) / np.abs(x[0])
        worst_here = float(drift.max())
        worst = max(worst, worst_here)
        print(f"soak: {label}: largest difference from cycle 1 at the same frame of a cycle "
              f"{100 * worst_here:.2e} %")
    if not worst < MAX_DRIFT:
        failures.append(f"drift {100 * worst:.3g} % of a value from cycle to cycle (at most {100 * MAX_DRIFT} %)")

    rss2, t2 = rss_at_frame(samples, progress, 2 * cycle)
    rss_end, t_end = rss_at_frame(samples, progress, args.frames)
    peak = max(r for t, r in samples if t2 <= t <= t_end)
    growth = (rss_end - rss2) / rss2
    print(f"soak: RSS at the end of cycle 2 {rss2 / 1024:.1f} MiB, at frame {args.frames} {rss_end / 1024:.1f} MiB "
          f"({100 * growth:+.2f} %), highest in between {peak / 1024:.1f} MiB")
    if not abs(growth) <= MAX_RSS_GROWTH:
        failures.append(f"RSS grew by {100 * growth:.1f} % from cycle 2 to the end (at most {100 * MAX_RSS_GROWTH} %)")

    for failure in failures:
        print("soak: FAILED: " + failure)
    if not failures:
        print("soak: passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
