#!/usr/bin/env bash
# Builds the module against Debian's plain VTK 9.1 (no ParaView, no Python)
# and runs its C++ tests: keeps the CMake honest about "any VTK >= 9.1".
# Debian's VTK 9.1 development package conflicts with ParaView's Python
# package, so it is unpacked into build-vtk91/root instead of installed, and
# linked to the installed 9.1 runtime libraries (BUILD-NOTES.md).
set -euo pipefail
DG_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="$DG_ROOT/build-vtk91"
ROOTFS="$OUT/root"
ARCH_LIB="/usr/lib/$(gcc -print-multiarch)"

need=()
for p in libvtk9.1 libtbb-dev libjsoncpp-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || need+=("$p")
done
if [ ${#need[@]} -gt 0 ]; then
  echo "[vtk91] installing: ${need[*]}"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${need[@]}" > /tmp/dg-apt-vtk91.log 2>&1 \
    || { tail -20 /tmp/dg-apt-vtk91.log; exit 1; }
fi

if [ ! -f "$ROOTFS/.unpacked" ]; then
  rm -rf "$ROOTFS" "$OUT/deb"
  mkdir -p "$ROOTFS" "$OUT/deb"
  chmod a+rwx "$OUT/deb" # apt downloads as its _apt user when it can
  (cd "$OUT/deb" && apt-get download libvtk9-dev python3-vtk9 > /dev/null)
  for deb in "$OUT"/deb/*.deb; do dpkg -x "$deb" "$ROOTFS"; done
  ln -sf "$ARCH_LIB"/libvtk*-9.1.so.* "$ROOTFS$ARCH_LIB/"
  mkdir -p "$ROOTFS/usr/bin"
  for t in /usr/bin/vtk*-9.1; do [ -e "$t" ] && ln -sf "$t" "$ROOTFS/usr/bin/"; done
  [ -d "$ARCH_LIB/vtk" ] && ln -sfn "$ARCH_LIB/vtk" "$ROOTFS$ARCH_LIB/vtk"
  touch "$ROOTFS/.unpacked"
fi

if [ ! -f "$OUT/build/build.ninja" ]; then
  cmake -S "$DG_ROOT" -B "$OUT/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DVTK_DIR="$ROOTFS$ARCH_LIB/cmake/vtk-9.1" -DDG_WRAP_PYTHON=OFF -DDG_PARAVIEW_PLUGIN=OFF \
    > "$OUT/configure.log" 2>&1 || { cat "$OUT/configure.log"; exit 1; }
fi
cmake --build "$OUT/build" -- -j"$(nproc)" > "$OUT/build.log" 2>&1 \
  || { grep -E "error|Error" -A3 "$OUT/build.log" | head -40; exit 1; }
grep -m1 "DigitalGeometry: VTK" "$OUT/configure.log" || true
