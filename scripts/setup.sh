#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs what a fresh Debian machine lacks, then configures and builds rbfmuscle.
# Idempotent and non-interactive: installed packages are skipped, the build is incremental.
# Usage: scripts/setup.sh [BUILD_DIR]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${1:-build}

packages=(build-essential cmake ninja-build pkg-config
          libsimbody-dev libeigen3-dev libfcl-dev liburdfdom-dev libassimp-dev
          libtinyxml2-dev zlib1g-dev nlohmann-json3-dev libgtest-dev libbenchmark-dev
          python3-numpy python3-matplotlib python3-scipy
          python3-dev pybind11-dev python3-pytest)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=()
  [[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "setup: all packages present"
fi

generator=()
[[ -f "$build_dir/CMakeCache.txt" ]] || generator=(-G Ninja)
# The Python module is built: its packages are installed above.
cmake -S . -B "$build_dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DRBFMUSCLE_BUILD_PYTHON=ON
cmake --build "$build_dir" -j "$(nproc)"
echo "setup: built into $build_dir"
