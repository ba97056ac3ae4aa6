#!/usr/bin/env bash
# Shared set-up of the two README commands: installs the Debian packages that
# are missing (quiet and quick when everything is there), then configures and
# builds into build/. Sourced by run.sh and test.sh.
set -euo pipefail
DG_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
DG_BUILD="${DG_BUILD:-$DG_ROOT/build}"

DG_PACKAGES=(
  build-essential cmake ninja-build pkg-config
  paraview paraview-dev python3-paraview libopenmpi-dev
  libeigen3-dev libsuitesparse-dev zlib1g-dev libgtest-dev
  xvfb xauth python3-numpy python3-pydicom python3-nibabel clang
  # The program's DICOM reader (4 packages, 2.6 MiB download, 15 MiB
  # installed; 9-30 s of apt-get install here, docs/world-geometry.md).
  # Optional in CMake: without it the program refuses DICOM input.
  libgdcm-dev
  # find_package(ParaView) loads ParaView's whole VTK, whose CMake config
  # looks for these development packages (paraview-dev does not pull them).
  libdouble-conversion-dev liblz4-dev liblzma-dev libexpat1-dev libutfcpp-dev
  libpng-dev libjpeg-dev libtiff-dev libfreetype-dev libxml2-dev libglew-dev
  libgl-dev libx11-dev libxt-dev
  # The plugin's in-application help pages (XML_DOCUMENTATION): ParaView's
  # CMake looks for Qt5 Help and runs xmlpatterns and qhelpgenerator; the
  # panel test (Testing/ParaView/TestPanels.cxx) builds on Qt5 Widgets.
  qtbase5-dev qttools5-dev qttools5-dev-tools qtxmlpatterns5-dev-tools
)

dg_missing_packages() {
  local p
  for p in "${DG_PACKAGES[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      echo "$p"
    fi
  done
}

missing="$(dg_missing_packages | tr '\n' ' ')"
if [ -n "${missing// /}" ]; then
  echo "[setup] installing: $missing"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  # shellcheck disable=SC2086
  $SUDO apt-get install -y -qq --no-install-recommends $missing > /tmp/dg-apt.log 2>&1 \
    || { tail -30 /tmp/dg-apt.log; echo "[setup] apt-get install failed" >&2; exit 1; }
fi

if [ ! -f "$DG_BUILD/build.ninja" ]; then
  cmake -S "$DG_ROOT" -B "$DG_BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DPython3_EXECUTABLE=/usr/bin/python3 > "$DG_BUILD.configure.log" 2>&1 \
    || { cat "$DG_BUILD.configure.log"; echo "[setup] configure failed" >&2; exit 1; }
fi
cmake --build "$DG_BUILD" -- -j"$(nproc)" > "$DG_BUILD.build.log" 2>&1 \
  || { grep -E "error|Error" -A3 "$DG_BUILD.build.log" | head -60; echo "[setup] build failed (full log: $DG_BUILD.build.log)" >&2; exit 1; }
