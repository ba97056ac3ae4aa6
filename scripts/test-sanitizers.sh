#!/usr/bin/env bash
# Builds the module and its C++ tests with AddressSanitizer and
# UndefinedBehaviorSanitizer (gcc) in build-asan/ and runs them; any report
# fails the run. Python, ParaView and the program are left out (their
# interpreters are not instrumented).
set -euo pipefail
DG_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="$DG_ROOT/build-asan"
if [ ! -f "$OUT/build.ninja" ]; then
  cmake -S "$DG_ROOT" -B "$OUT" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DPython3_EXECUTABLE=/usr/bin/python3 -DDG_ENABLE_SANITIZERS=ON \
    -DDG_WRAP_PYTHON=OFF -DDG_PARAVIEW_PLUGIN=OFF > "$OUT.configure.log" 2>&1 \
    || { cat "$OUT.configure.log"; exit 1; }
fi
cmake --build "$OUT" -- -j"$(nproc)" > "$OUT.build.log" 2>&1 \
  || { grep -E "error|Error" -A3 "$OUT.build.log" | head -40; exit 1; }
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:halt_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$DG_ROOT/Testing/lsan.supp"
cd "$OUT" && ctest --output-on-failure -j2 -E "^python\." "$@"
