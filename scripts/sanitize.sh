#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Runs the test suite built with AddressSanitizer and UndefinedBehaviorSanitizer
# (scripts/sanitized_build.sh: clang, build-san/): a memory error, a leak or undefined behaviour
# fails the test that met it. The packages of scripts/setup.sh must be installed.
#
# Usage: scripts/sanitize.sh            the suite less its heaviest tests (what CI runs)
#        scripts/sanitize.sh --all      the whole suite (hours on a 2-core machine)
#        scripts/sanitize.sh -R host_   any other ctest arguments select tests themselves
# The heaviest tests run the main job or whole fits, 3-10 times slower instrumented: the four
# hip scenes over every frame, the interrupt tests (the main job over 6400 frames), the plugin's
# 16-frame runs, the scenes that fit a surface in each test process (the moment-arm rod, the
# OpenSim iliacus), and the fits of the fit command, the long shapes and the near-crumb checks
# of the psoas and the gluteus (23 and 13 minutes instrumented). What they exercise (the
# pipeline stages, the fitter, the host) is also run instrumented by lighter tests of the set.
# The sanitizers' run-time settings are in scripts/sanitizers.env (source it to run one test
# binary of build-san by hand).
set -euo pipefail
cd "$(dirname "$0")/.."
heavy='^(HipScenes|Interrupt|LongThinShapes|PsoasMajor|FitCommand|FitCommandWarnings|MomentArmScene|OsimScene)\.|^RBFMusclePlugin\.(GluteusFollowsFlexionWithVolumeKept|RunsOnOneAndTwoThreadsGiveIdenticalOutputs)$|^GreedyFitter\.(MoreCentresFitBetter|IsDeterministic|BoxIsFittedCloselyAndClosed|StopsAtTheTolerance)$|^NearCrumbs\.(ThePsoasFit|TheGluteusFit)'
args=("$@")
if ((${#args[@]} == 0)); then
  args=(-E "$heavy")
elif [[ "${args[0]}" == "--all" ]]; then
  args=("${args[@]:1}")
fi
scripts/sanitized_build.sh
# shellcheck source=sanitizers.env
source scripts/sanitizers.env
ctest --test-dir "${SAN_BUILD_DIR:-build-san}" --output-on-failure -j2 "${args[@]}"
