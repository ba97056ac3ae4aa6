#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite: the main
# build (ParaView's VTK 9.2: C++, Python, plugin), then the same module built
# against Debian's plain VTK 9.1 with its C++ tests (DG_SKIP_VTK91=1 skips it),
# then the C++ tests under ASan + UBSan (DG_SKIP_SANITIZERS=1 skips them)
# and short libFuzzer runs (DG_SKIP_FUZZ=1 skips them).
set -euo pipefail
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/setup.sh"
export VTK_SMP_BACKEND_IN_USE="${VTK_SMP_BACKEND_IN_USE:-STDThread}"
status=0
# Tests that render start their own X server (Testing/with-own-display.sh).
(cd "$DG_BUILD" && ctest --output-on-failure -j2 "$@") || status=1
if [ "${DG_SKIP_VTK91:-0}" != "1" ]; then
  echo "[test] module against Debian's VTK 9.1 (no ParaView, no Python)"
  bash "$DG_ROOT/scripts/build-vtk91.sh"
  (cd "$DG_ROOT/build-vtk91/build" && ctest --output-on-failure -j2 "$@") || status=1
fi
if [ "${DG_SKIP_SANITIZERS:-0}" != "1" ]; then
  echo "[test] C++ tests under AddressSanitizer + UndefinedBehaviorSanitizer"
  bash "$DG_ROOT/scripts/test-sanitizers.sh" "$@" || status=1
fi
if [ "${DG_SKIP_FUZZ:-0}" != "1" ]; then
  echo "[test] short libFuzzer runs (clang)"
  bash "$DG_ROOT/scripts/fuzz.sh" || status=1
fi
exit $status
