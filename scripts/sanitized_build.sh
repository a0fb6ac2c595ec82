#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The instrumented build shared by scripts/sanitize.sh (the test suite under ASan and UBSan) and
# scripts/fuzz.sh (the libFuzzer targets): clang, RBFMUSCLE_SANITIZE=ON and
# RBFMUSCLE_BUILD_FUZZERS=ON in build-san/, so one build serves both. Installs clang, its
# sanitizer and fuzzer runtimes (libclang-rt-14-dev: Debian's clang package lacks them) and its
# OpenMP runtime (libomp-14-dev) when missing, configures once, then builds TARGETs (default: all).
#
# Usage: scripts/sanitized_build.sh [TARGET...]     (SAN_BUILD_DIR overrides build-san)
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${SAN_BUILD_DIR:-build-san}

packages=(clang libclang-rt-14-dev libomp-14-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "sanitized build: installing ${missing[*]}"
  sudo_cmd=()
  [[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# No Python module: Debian's python3 is not instrumented, so it cannot load instrumented libraries
# (the module and its tests run in the plain build).
if [[ ! -f "$build_dir/CMakeCache.txt" ]]; then
  CC=clang CXX=clang++ cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DRBFMUSCLE_SANITIZE=ON -DRBFMUSCLE_BUILD_FUZZERS=ON -DRBFMUSCLE_BUILD_BENCHMARKS=OFF \
    -DRBFMUSCLE_BUILD_PYTHON=OFF
fi
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build "$build_dir" "${targets[@]}" -j 2
