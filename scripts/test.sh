#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Command 2 of the README: build (if needed) and run the whole test suite, image tests included,
# under a virtual X server; in CI (CI=true) or with SANITIZERS=1 also the AddressSanitizer /
# UndefinedBehaviorSanitizer build with the core tests, the bad-input corpus and libFuzzer
# (scripts/sanitizers.sh, a second build: about 15 more minutes on 2 cores). Exits non-zero on any
# failure.
#   BUILD_DIR   build directory (default: build)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$here/build}"
if [[ ! -f "$build/CMakeCache.txt" ]]; then
  cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$build" -j "$(nproc)"
cd "$build"
# Both parts run even when the first fails, so that one run shows every failure.
status=0
# The ParaView plugin (built by the set-up command) is rebuilt against the current sources; its
# tests (label paraview) fail when it was never built.
if [[ -f "$build/paraview-plugin/CMakeCache.txt" ]]; then
  cmake --build "$build/paraview-plugin" -j "$(nproc)" || status=$?
fi
# Every label runs, `mpi` included: the distributed tests start mpiexec themselves (openmpi-bin, from
# the set-up command) and fail, never skip, when it is missing.
# -noreset: Xvfb resets itself whenever its last client disconnects, and a test connecting during
# that reset fails with "bad X server connection" (measured: 9 of 200 back-to-back XOpenDisplay
# calls failed without it, 0 of 200 with it).
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" ctest --output-on-failure -j 2 --timeout 1200 || status=$?
if [[ "${CI:-}" == "true" || "${SANITIZERS:-0}" == "1" ]]; then
  SANITIZER_BUILD_DIR="${SANITIZER_BUILD_DIR:-$build-sanitizers}" bash "$here/scripts/sanitizers.sh" || status=$?
fi
exit "$status"
