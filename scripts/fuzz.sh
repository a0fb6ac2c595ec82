#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Builds the libFuzzer targets of fuzz/ (scripts/sanitized_build.sh: clang, ASan + UBSan,
# build-san/) and runs each for SECONDS (default 30), one after the other; fails when any target
# finds a crash, a leak, undefined behaviour, a hang or a broken promise.
#
# Usage: scripts/fuzz.sh [SECONDS] [TARGET...]       e.g. scripts/fuzz.sh 30, scripts/fuzz.sh 60 fuzz_ply
#        FUZZ_RUNS=1000000 scripts/fuzz.sh 0 …       run a fixed number of inputs instead of a time
# Each target starts from its committed seeds (fuzz/corpus/TARGET) and grows its own corpus in
# build-san/corpus/TARGET; a crashing input is saved as build-san/artifacts/TARGET/crash-*.
# Per-target logs: build-san/logs/TARGET.log; the last line of each run is its executions.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
shift || true
build_dir=${SAN_BUILD_DIR:-build-san}
all_targets=(fuzz_ply fuzz_vtp fuzz_rbf fuzz_model_xml fuzz_urdf fuzz_osim fuzz_motion)
targets=("$@")
((${#targets[@]})) || targets=("${all_targets[@]}")

SAN_BUILD_DIR="$build_dir" scripts/sanitized_build.sh fuzzers

mkdir -p "$build_dir/logs"
failed=()
for target in "${targets[@]}"; do
  corpus="$build_dir/corpus/$target"
  artifacts="$build_dir/artifacts/$target/"
  log="$build_dir/logs/$target.log"
  mkdir -p "$corpus" "$artifacts"
  limit=(-max_total_time="$seconds")
  [[ -n "${FUZZ_RUNS:-}" ]] && limit=(-runs="$FUZZ_RUNS")
  # Inputs up to 16 KB (the seeds are under 6 KB); a single input taking over 20 s is a hang.
  if "$build_dir/bin/$target" "${limit[@]}" -max_len=16384 -timeout=20 -rss_limit_mb=2048 \
       -print_final_stats=1 -artifact_prefix="$artifacts" "$corpus" "fuzz/corpus/$target" >"$log" 2>&1; then
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    echo "fuzz: $target: ${runs:-?} executions, no finding"
  else
    echo "fuzz: $target: FAILED (log: $log; reproducer in $artifacts)"
    grep -m 5 -E "ERROR|runtime error|fuzz: accepted|terminate called|what\(\)" "$log" || tail -n 20 "$log"
    failed+=("$target")
  fi
done
if ((${#failed[@]})); then
  echo "fuzz: findings in ${failed[*]}"
  exit 1
fi
echo "fuzz: ${#targets[@]} targets ran without a finding"
