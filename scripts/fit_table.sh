#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Reproduces the static-fit table of docs/design.md ("Fits"): fits every mesh with `rbfmuscle fit`
# and prints one Markdown row per fit from the JSON line each fit prints last.
# Usage: scripts/fit_table.sh [OUTDIR] [--long]   (--long adds 10000 centres and the global-shape search)
# Timing: run on an otherwise idle machine; `seconds` is sampling + fit, wall_s the whole command.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-out/fit_table}
long=${2:-}
host=build/bin/rbfmuscle
[[ -x $host ]] || { echo "fit_table: build first (scripts/setup.sh)" >&2; exit 1; }
mkdir -p "$out"
: > "$out/rows.jsonl"

fit() {  # fit NAME MESH ARGS...
  local name=$1 mesh=$2; shift 2
  echo "fit_table: $name" >&2
  local start end
  start=$(date +%s.%N)
  "$host" fit "$mesh" -o "$out/$name.rbf" --quiet "$@" > "$out/$name.log"
  end=$(date +%s.%N)
  python3 - "$name" "$(tail -n 1 "$out/$name.log")" "$start" "$end" >> "$out/rows.jsonl" <<'PY'
import json, sys
row = json.loads(sys.argv[2]); row["name"] = sys.argv[1]; row["wall_s"] = float(sys.argv[4]) - float(sys.argv[3])
print(json.dumps(row))
PY
}

hip=models/hip/meshes
shapes=models/shapes
# The scenes' muscles are fitted moved out of the bones at rest, as the scenes fit them.
bones=$hip/pelvis_iliac_r.ply,$hip/pelvis_sacrum.ply,$hip/femur_r.ply
fit glmax_1000 $hip/gluteus_maximus_r.ply --centres 1000 --out-of $bones --surface "$out/glmax_1000.ply"
fit iliacus_2000 $hip/iliacus_r.ply --centres 2000 --out-of $bones --surface "$out/iliacus_2000.ply"
fit psoas_1000 $hip/psoas_major_r.ply --centres 1000 --out-of $bones --surface "$out/psoas_1000.ply"
fit glmax_50 $hip/gluteus_maximus_r.ply --centres 50
fit box_500 $shapes/box.ply --centres 500
fit rod_500 $shapes/rod.ply --centres 500
fit block_500 $shapes/block.ply --centres 500
# The tetrahedron is 1 mm across: scale clamp, offsets, cell and shapes to it.
fit tetrahedron_200 $shapes/tetrahedron.ply --centres 200 --clamp-mm 0.1 --normal-offset-mm 0.02 \
    --cell-mm 0.02 --shapes 5,10,20,50,100,200,500,1000
# The dissertation's best global shape for the gluteus maximus.
fit glmax_global_0.35263 $hip/gluteus_maximus_r.ply --centres 1000 --global-shape 0.35263
if [[ $long == --long ]]; then
  fit glmax_global_search $hip/gluteus_maximus_r.ply --centres 1000 --global-search 0.001,1,10
  fit glmax_10000 $hip/gluteus_maximus_r.ply --centres 10000 --surface "$out/glmax_10000.ply"
fi

python3 - "$out/rows.jsonl" <<'PY'
import json, sys
print("| fit | centres | jaccard | mean mm | p95 mm | max mm | volume ratio | components | fit s | wall s |")
print("|---|---|---|---|---|---|---|---|---|---|")
for line in open(sys.argv[1]):
    r = json.loads(line)
    f = lambda k, d=3: "—" if r.get(k) is None else f"{r[k]:.{d}f}"
    print(f"| {r['name']} | {r['centres']} | {f('jaccard')} | {f('mean_distance_mm')} | {f('p95_distance_mm')} | "
          f"{f('max_distance_mm')} | {f('volume_ratio')} | {r['components']} | {f('seconds',1)} | {r['wall_s']:.1f} |")
PY
