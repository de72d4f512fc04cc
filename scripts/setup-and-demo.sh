#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Command 1 of the README: install every Debian dependency, configure, build, build the ParaView
# plugin (scripts/paraview-plugin.sh), and run the main job (`surfacelod demo` on its built-in
# synthetic marching-cubes isosurface of about a million triangles).
#   BUILD_DIR   build directory (default: build)
#   DEMO_ARGS   extra arguments for `surfacelod demo`
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$here/build}"

packages=(build-essential cmake ninja-build ccache pkg-config
  libvtk9-dev python3-vtk9 python3-dev libeigen3-dev libgtest-dev libbenchmark-dev libcli11-dev nlohmann-json3-dev
  libcgal-demo xvfb xauth openmpi-bin)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "== installing: ${missing[*]}"
  sudo_cmd=""
  [[ $(id -u) -ne 0 ]] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq "${missing[@]}"
fi

echo "== configuring and building in $build"
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$build" -j "$(nproc)"

echo "== ParaView plugin"
BUILD_DIR="$build" bash "$here/scripts/paraview-plugin.sh"

echo "== surfacelod demo"
mkdir -p "$build/demo"
# Rendering the side-by-side PNG needs an X server: use a virtual one.
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" "$build/bin/surfacelod" demo --output-dir "$build/demo" ${DEMO_ARGS:-}
