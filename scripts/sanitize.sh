#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Runs the test suite built with AddressSanitizer and UndefinedBehaviorSanitizer
# (scripts/sanitized_build.sh: clang, build-san/): a memory error, a leak or undefined behaviour
# fails the test that met it. The packages of scripts/setup.sh must be installed.
#
# Usage: scripts/sanitize.sh [CTEST_ARGS...]     e.g. scripts/sanitize.sh -R host_
# The sanitizers' run-time settings are in scripts/sanitizers.env (source it to run one test
# binary of build-san by hand).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/sanitized_build.sh
# shellcheck source=sanitizers.env
source scripts/sanitizers.env
ctest --test-dir "${SAN_BUILD_DIR:-build-san}" --output-on-failure -j2 "$@"
