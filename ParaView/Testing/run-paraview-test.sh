#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# ctest driver of the `paraview` tests: runs a script of this folder in ParaView's own pvpython or
# pvbatch, unpacked by scripts/paraview-plugin.sh. A missing ParaView or plugin fails the test
# with the command that builds them: the tests are never skipped.
#   run-paraview-test.sh <pvpython|pvbatch> <ParaView root> <script> <script arguments...>
set -euo pipefail
program="$2/usr/bin/$1"
script="$(dirname "${BASH_SOURCE[0]}")/$3"
shift 3
if [[ ! -x "$program" ]]; then
  echo "FAIL  $program is missing: ParaView was not unpacked (run scripts/paraview-plugin.sh, or the README's set-up command)"
  exit 1
fi
# pvbatch is an MPI program: let OpenMPI start as root (CI containers) as a single process.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
exec "$program" "$script" "$@"
