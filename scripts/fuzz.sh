#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (-fsanitize=fuzzer,address,undefined)
# into build-fuzz/ and runs each for DG_FUZZ_SECONDS (default 60) from the
# seed corpus committed under Testing/Fuzz. A crash fails the run and leaves
# the reproducer in build-fuzz/.
set -euo pipefail
DG_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="$DG_ROOT/build-fuzz"
SECONDS_EACH="${DG_FUZZ_SECONDS:-60}"
command -v clang++ > /dev/null || DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends clang > /dev/null
mkdir -p "$OUT"
VTK_INC=/usr/include/paraview-5.11
FLAGS=(-std=c++17 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all
  -I"$DG_ROOT/Filters" -I"$VTK_INC")
clang++ "${FLAGS[@]}" "$DG_ROOT/Testing/Fuzz/fuzz_vol.cxx" "$DG_ROOT/Filters/dgVolFormat.cxx" \
  -lz -o "$OUT/fuzz_vol"
# The filters' target compiles the module's sources with the fuzzer's
# instrumentation and links ParaView's VTK; the export header comes from a
# configured build tree.
GEN="$DG_ROOT/build/Filters"
if [ -f "$GEN/vtkDigitalGeometryModule.h" ]; then
  # The module's sources but its image readers (vtkNIfTIVolumeReader and
  # vtkOrientedImageReader need VTK's IOImage, which no fuzz target uses).
  SOURCES=()
  for f in "$DG_ROOT"/Filters/*.cxx; do
    case "$(basename "$f")" in
      vtkNIfTIVolumeReader.cxx | vtkOrientedImageReader.cxx) ;;
      *) SOURCES+=("$f") ;;
    esac
  done
  clang++ "${FLAGS[@]}" -I"$GEN" -I/usr/include/eigen3 -DNDEBUG \
    "$DG_ROOT/Testing/Fuzz/fuzz_filters.cxx" "${SOURCES[@]}" \
    -L/usr/lib/$(gcc -print-multiarch) -lvtkCommonCore-pv5.11 -lvtkCommonDataModel-pv5.11 \
    -lvtkCommonExecutionModel-pv5.11 -lvtkCommonMath-pv5.11 -lvtkCommonSystem-pv5.11 \
    -lvtkCommonMisc-pv5.11 -lvtksys-pv5.11 -lvtkParallelCore-pv5.11 -lz -o "$OUT/fuzz_filters"
fi
status=0
run() {
  local name="$1" corpus="$2"
  mkdir -p "$OUT/corpus_$name"
  cp -n "$corpus"/* "$OUT/corpus_$name/" 2>/dev/null || true
  echo "[fuzz] $name for ${SECONDS_EACH}s"
  (cd "$OUT" && "./$name" -max_total_time="$SECONDS_EACH" -max_len=4096 -rss_limit_mb=4096 \
    -print_final_stats=1 "corpus_$name" > "$name.log" 2>&1) \
    || { tail -40 "$OUT/$name.log"; status=1; }
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$OUT/$name.log" || true
}
run fuzz_vol "$DG_ROOT/Testing/Fuzz/corpus_vol"
if [ -x "$OUT/fuzz_filters" ]; then
  run fuzz_filters "$DG_ROOT/Testing/Fuzz/corpus_filters"
fi
exit $status
