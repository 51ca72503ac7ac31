#!/usr/bin/env bash
# README command 2: install what is missing, build, and run the whole test suite with CTest;
# then the unit tests again in a second build under AddressSanitizer and
# UndefinedBehaviorSanitizer (build-sanitize/, any finding fails its test). The sanitized pass
# leaves out the end-to-end runs of real meshes, the quad sphere's joints and the longer
# quad-meshing tests (minutes each when sanitized; the fuzzers in scripts/fuzz.sh cover the
# readers). KERFAB_NO_SANITIZE=1
# skips it. The assembly guide's page is opened in headless Chromium (Debian's chromium).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
# Debian's chromium too: the assembly guide's page is tested in it (headless).
"$root/scripts/deps.sh" --browser
"$root/scripts/build.sh"
ctest --test-dir "$root/build" --output-on-failure -j "$(nproc)" "$@"

if [ "${KERFAB_NO_SANITIZE:-0}" != 1 ]; then
  cmake -S "$root" -B "$root/build-sanitize" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" -DKERFAB_SANITIZE=ON -DKERFAB_BUILD_BENCH=OFF \
    >/dev/null
  cmake --build "$root/build-sanitize"
  slow='^(Cli\.|OutputSafety\.|HostileInput\.MemoryLimits|Layout\.(EveryTestShape|Oversized)'
  slow+='|Bending\.Spot|Flatten\.RealMeshes|Strips\.(CylinderRings|RealMeshes)|Joints\.(RealMeshes|StubTeethPinch)'
  slow+='|Kerf\.Spot|Quads\.(RealMeshes|ClosedShapes|Deterministic|SizeRule|TriangleTarget'
  slow+='|QuadsTooNarrow|SpotsQuads|FandisksSharpEdges|TorusComesOut|ANoisyTarget|ATriangleWalledIn)|SurfaceDistance\.TheSearchAgreesWithADense'
  slow+='|Assembly\.EveryStep|Guide\.)'
  ctest --test-dir "$root/build-sanitize" --output-on-failure -j "$(nproc)" --timeout 900 \
    -E "$slow" "$@"
fi
