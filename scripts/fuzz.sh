#!/usr/bin/env bash
# Fuzz the readers with libFuzzer (clang from Debian, AddressSanitizer + UBSan): one target per
# mesh format and one for the guidance parser, all in parallel, each for SECONDS (default 60).
# Seeds: the repository's own meshes. Findings (crashing inputs) go to build-fuzz/findings/;
# keep each as a regression input in tests/data/fuzz/ once fixed.
#   scripts/fuzz.sh [SECONDS]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-60}
"$root/scripts/deps.sh"
if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: installing clang and libFuzzer (Debian packages clang, libclang-rt-dev)" >&2
  ${SUDO:-$( [ "$(id -u)" = 0 ] || echo sudo )} apt-get install -y -qq clang libclang-rt-dev >/dev/null
fi
out="$root/build-fuzz"
mkdir -p "$out/findings"
flags=(-std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined
       -I"$root/src" -I/usr/include/eigen3 -DNDEBUG)
sources=("$root/src/kerfab/io/mesh_io.cpp" "$root/src/kerfab/core/mesh.cpp")
pids=()
build_and_run() {  # name, extra flags..., then seeds after --
  local name=$1; shift
  local extra=() seeds=()
  while [ "$1" != "--" ]; do extra+=("$1"); shift; done; shift
  seeds=("$@")
  clang++ "${flags[@]}" "${extra[@]}" -o "$out/$name" 2>"$out/$name.build.log"
  mkdir -p "$out/corpus-$name" "$out/findings/$name"
  for s in "${seeds[@]}"; do [ -f "$s" ] && cp "$s" "$out/corpus-$name/" || true; done
  LSAN_OPTIONS="suppressions=$root/fuzz/lsan.supp:print_suppressions=0" \
    "$out/$name" -max_total_time="$seconds" -max_len=65536 -rss_limit_mb=2048 -timeout=10 \
    -print_final_stats=1 -artifact_prefix="$out/findings/$name/" "$out/corpus-$name" >"$out/$name.log" 2>&1
}
for ext in obj off ply stl; do
  seeds=("$root"/examples/spot/*."$ext" "$root"/tests/data/*."$ext")
  build_and_run "fuzz_$ext" -DKERFAB_FUZZ_EXT="\".$ext\"" "$root/fuzz/fuzz_mesh_reader.cpp" \
    "${sources[@]}" -lOpenMeshCore -- "${seeds[@]}" &
  pids+=($!)
done
build_and_run fuzz_guidance "$root/fuzz/fuzz_guidance.cpp" "$root/src/kerfab/io/guidance.cpp" \
  -- "$root"/tests/data/*.json &
pids+=($!)
status=0
for p in "${pids[@]}"; do wait "$p" || status=1; done
for name in fuzz_obj fuzz_off fuzz_ply fuzz_stl fuzz_guidance; do
  runs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$out/$name.log" | awk '{print $2}')
  found=$(ls "$out/findings/$name" | wc -l)
  echo "$name: ${runs:-?} inputs in ${seconds} s, $found findings" \
       "(log: $out/$name.log${found:+, inputs: $out/findings/$name/})"
done
exit $status
