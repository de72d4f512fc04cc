#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Builds the SurfaceLOD ParaView plugin (ParaView/, Documentation/ParaView.md) against Debian 12's
# ParaView 5.11 without installing ParaView: python3-paraview conflicts with python3-vtk9 (both
# ship dist-packages/vtkmodules), so the ParaView packages are downloaded with `apt-get download`
# and unpacked into a private root; only their dependencies that install without removing
# anything are installed with apt (`--no-remove`). Safe to run again: the download, the unpacking
# and the configuration are done once, the build is incremental.
#   BUILD_DIR       the main build directory (default: build)
#   PARAVIEW_ROOT   where the packages are unpacked (default: $BUILD_DIR/paraview-root)
#   PLUGIN_BUILD_DIR  the plugin's build directory (default: $BUILD_DIR/paraview-plugin)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$here/build}"
root="${PARAVIEW_ROOT:-$build/paraview-root}"
plugin_build="${PLUGIN_BUILD_DIR:-$build/paraview-plugin}"
libdir=usr/lib/x86_64-linux-gnu

# The packages unpacked into the root (qttools5 and Qt5Help: ParaView's CMake package needs them).
unpacked=(paraview paraview-dev python3-paraview qttools5-dev qttools5-dev-tools qhelpgenerator-qt5
  libqt5help5 libqt5designer5 libqt5designercomponents5)
# Whose dependencies are installed: what pvpython, pvbatch and the plugin build use. The Qt tools'
# own dependencies (assistant, qdoc, WebKit) are left out: no Qt tool is run (XML docs are off).
runtime=(paraview python3-paraview paraview-dev libqt5help5 qttools5-dev)
# Left out too: ParaView's optional Python extras (web server, matplotlib text rendering) and Tcl,
# which pvpython, pvbatch and the tests do not use; matplotlib alone pulls in about 80 packages
# (scipy, sympy, ...).
not_needed=(python3-matplotlib python3-autobahn python3-twisted tclsh)

sudo_cmd=""
[[ $(id -u) -ne 0 ]] && sudo_cmd="sudo"

is_installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }

download_and_unpack() {
  [[ -f "$root/.unpacked" ]] && return 0
  echo "== downloading and unpacking ParaView's Debian packages into $root"
  rm -rf "$root"
  mkdir -p "$root/debs"
  if ! (cd "$root/debs" && apt-get download -qq "${unpacked[@]}"); then
    $sudo_cmd apt-get update -qq
    (cd "$root/debs" && apt-get download -qq "${unpacked[@]}")
  fi
  for deb in "$root"/debs/*.deb; do
    dpkg-deb -x "$deb" "$root"
  done
  touch "$root/.unpacked"
}

# The first alternative of every dependency of the runtime packages, without the unpacked
# packages themselves, the extras above and the virtual Qt ABI packages (provided by the
# installed Qt libraries).
dependencies() {
  local package deb
  for package in "${runtime[@]}"; do
    deb=("$root"/debs/"${package}"_*.deb)
    dpkg-deb -f "${deb[0]}" Depends
  done | tr ',' '\n' | sed -E 's/^ +//; s/ *\|.*//; s/ *\(.*//; s/:any$//' | sort -u |
    grep -vxF -f <(printf '%s\n' "${unpacked[@]}" "${not_needed[@]}") | grep -v -- '-abi-' || true
}

install_dependencies() {
  local missing=() package
  for package in $(dependencies); do
    is_installed "$package" || missing+=("$package")
  done
  if ((${#missing[@]})); then
    echo "== installing ParaView's dependencies: ${missing[*]}"
    DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-remove "${missing[@]}"
  fi
  # Every library pvpython and pvbatch need must now resolve.
  local program unresolved
  for program in pvpython pvbatch; do
    unresolved="$(ldd "$root/usr/bin/$program" | grep "not found" || true)"
    if [[ -n "$unresolved" ]]; then
      echo "$unresolved" >&2
      echo "error: $program misses libraries (above)" >&2
      exit 1
    fi
  done
}

configure_and_build() {
  if [[ ! -f "$plugin_build/CMakeCache.txt" ]]; then
    echo "== configuring the plugin in $plugin_build"
    cmake -S "$here/ParaView" -B "$plugin_build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DParaView_DIR="$root/$libdir/cmake/paraview-5.11" \
      -DQt5Help_DIR="$root/$libdir/cmake/Qt5Help" \
      -DQt5Sql_DIR="/$libdir/cmake/Qt5Sql" \
      -DPython3_EXECUTABLE=/usr/bin/python3
  fi
  echo "== building the plugin"
  cmake --build "$plugin_build" -j "$(nproc)"
  ls "$plugin_build"/lib/paraview-5.11/plugins/SurfaceLOD/SurfaceLOD.so
}

download_and_unpack
install_dependencies
configure_and_build
