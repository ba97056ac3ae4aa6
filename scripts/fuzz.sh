#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (-fsanitize=fuzzer,address,undefined)
# into build-fuzz/ and runs each for DG_FUZZ_SECONDS (default 30) from the
# seed corpus committed under Testing/Fuzz/corpus_<name>:
#   fuzz_vol      the .vol decoder (Filters/dgVolFormat)
#   fuzz_header   the MetaImage / NRRD header parsers (Filters/dgImageHeader) and the
#                 DICOM series geometry (Applications/dgDicomGeometry)
#   fuzz_filters  surface, II, AT, sharp features and islands on small volumes
#   fuzz_nifti    vtkNIfTIVolumeReader (header pre-check, qform / sform geometry) on .nii
#                 bytes, through VTK 9.2's vtkNIFTIImageReader
# 4 targets x 30 s = 120 s of fuzzing. A crash fails the run and leaves the
# reproducer in build-fuzz/ (crash-*, oom-*, timeout-*).
# fuzz_filters and fuzz_nifti compile the module's sources and link
# ParaView's VTK; the export header comes from a configured build tree
# (DG_FUZZ_GEN, default build/Filters); without it they are skipped.
# DG_FUZZ_DICOM=1 also builds and runs fuzz_dicom (the program's DICOM
# series reader through GDCM; not by default: GDCM itself asserts on
# corrupt meta headers within seconds, see Testing/Fuzz/fuzz_dicom.cxx).
set -euo pipefail
DG_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
OUT="$DG_ROOT/build-fuzz"
SECONDS_EACH="${DG_FUZZ_SECONDS:-30}"
command -v clang++ > /dev/null || DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends clang > /dev/null
mkdir -p "$OUT/obj"
VTK_INC=/usr/include/paraview-5.11
LIB="/usr/lib/$(gcc -print-multiarch)"
SAN=(-fsanitize=address,undefined -fno-sanitize-recover=all)
FLAGS=(-std=c++17 -O1 -g "${SAN[@]}" -fsanitize=fuzzer -I"$DG_ROOT/Filters" -I"$VTK_INC")
VTK_LIBS=(-L"$LIB" -lvtkCommonCore-pv5.11 -lvtkCommonDataModel-pv5.11
  -lvtkCommonExecutionModel-pv5.11 -lvtkCommonMath-pv5.11 -lvtkCommonSystem-pv5.11
  -lvtkCommonMisc-pv5.11 -lvtksys-pv5.11 -lvtkParallelCore-pv5.11 -lz)
TARGETS=(fuzz_vol fuzz_header)
clang++ "${FLAGS[@]}" "$DG_ROOT/Testing/Fuzz/fuzz_vol.cxx" "$DG_ROOT/Filters/dgVolFormat.cxx" \
  -lz -o "$OUT/fuzz_vol"
clang++ "${FLAGS[@]}" -I"$DG_ROOT/Applications" "$DG_ROOT/Testing/Fuzz/fuzz_header.cxx" \
  "$DG_ROOT/Filters/dgImageHeader.cxx" "$DG_ROOT/Applications/dgDicomGeometry.cxx" -o "$OUT/fuzz_header"
GEN="${DG_FUZZ_GEN:-$DG_ROOT/build/Filters}"
if [ -f "$GEN/vtkDigitalGeometryModule.h" ]; then
  # The module's sources, compiled once (in parallel) with the fuzzer's
  # instrumentation, then linked into both targets. vtkOrientedImageReader
  # (VTK's MetaImage/NRRD readers) is in no target; its header code is
  # fuzz_header's.
  OBJ_FLAGS=(-std=c++17 -O1 -g "${SAN[@]}" -fsanitize=fuzzer-no-link -I"$DG_ROOT/Filters"
    -I"$VTK_INC" -I"$GEN" -I/usr/include/eigen3 -DNDEBUG)
  rm -f "$OUT"/obj/*.o
  for f in "$DG_ROOT"/Filters/*.cxx; do
    [ "$(basename "$f")" = vtkOrientedImageReader.cxx ] || echo "$f"
  done | xargs -P "$(nproc)" -I{} sh -c \
    'clang++ "$@" -c "{}" -o "'"$OUT"'/obj/$(basename "{}" .cxx).o"' _ "${OBJ_FLAGS[@]}"
  FILTER_OBJS=()
  for o in "$OUT"/obj/*.o; do
    [ "$(basename "$o")" = vtkNIfTIVolumeReader.o ] || FILTER_OBJS+=("$o")
  done
  clang++ "${FLAGS[@]}" -I"$GEN" -I/usr/include/eigen3 -DNDEBUG \
    "$DG_ROOT/Testing/Fuzz/fuzz_filters.cxx" "${FILTER_OBJS[@]}" "${VTK_LIBS[@]}" \
    -o "$OUT/fuzz_filters"
  clang++ "${FLAGS[@]}" -I"$GEN" "$DG_ROOT/Testing/Fuzz/fuzz_nifti.cxx" \
    "$OUT/obj/vtkNIfTIVolumeReader.o" "$OUT/obj/dgPieces.o" \
    -lvtkIOImage-pv5.11 -lvtkImagingCore-pv5.11 -lvtkCommonTransforms-pv5.11 "${VTK_LIBS[@]}" \
    -o "$OUT/fuzz_nifti"
  TARGETS+=(fuzz_filters fuzz_nifti)
else
  echo "[fuzz] no $GEN/vtkDigitalGeometryModule.h: fuzz_filters and fuzz_nifti skipped"
fi
if [ "${DG_FUZZ_DICOM:-0}" = "1" ]; then
  clang++ "${FLAGS[@]}" -I"$DG_ROOT/Applications" -I/usr/include/gdcm-3.0 -DDG_HAVE_GDCM \
    "$DG_ROOT/Testing/Fuzz/fuzz_dicom.cxx" "$DG_ROOT/Applications/dgDicomSeries.cxx" "$DG_ROOT/Applications/dgDicomGeometry.cxx" \
    "$DG_ROOT/Filters/dgImageHeader.cxx" -L"$LIB" -lgdcmMSFF -lgdcmDSED -lgdcmDICT -lgdcmIOD \
    -lgdcmCommon "${VTK_LIBS[@]}" -o "$OUT/fuzz_dicom"
  TARGETS+=(fuzz_dicom)
fi
status=0
run() {
  local name="$1" corpus="$DG_ROOT/Testing/Fuzz/corpus_${1#fuzz_}"
  mkdir -p "$OUT/corpus_$name"
  cp -n "$corpus"/* "$OUT/corpus_$name/" 2>/dev/null || true
  echo "[fuzz] $name for ${SECONDS_EACH}s"
  # A fixed seed (DG_FUZZ_SEED, default 1): the test command's runs mutate
  # the same way each time (up to the time limit), so a failure reproduces;
  # DG_FUZZ_SEED=0 lets libFuzzer pick one for longer exploratory runs.
  (cd "$OUT" && "./$name" -seed="${DG_FUZZ_SEED:-1}" -max_total_time="$SECONDS_EACH" -max_len=4096 \
    -rss_limit_mb=4096 -timeout=20 -print_final_stats=1 "corpus_$name" > "$name.log" 2>&1) \
    || { tail -40 "$OUT/$name.log"; status=1; }
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$OUT/$name.log" || true
}
for t in "${TARGETS[@]}"; do
  run "$t"
done
exit $status
