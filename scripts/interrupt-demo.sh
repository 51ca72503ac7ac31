#!/usr/bin/env bash
# SIGINT at a random moment of N demo runs (default 20) into a folder holding a previous good
# demo run: each run must either stop at once (exit 130, one error line, the folder byte for
# byte as it was) or have finished (exit 0, a complete new run). Needs a built build/kerfab.
#   scripts/interrupt-demo.sh [N]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
kerfab="$root/build/kerfab"
runs=${1:-20}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out="$work/demo"
since() { awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }'; }
fingerprint() { (cd "$out" && find . -type f -print0 | sort -z | xargs -0 sha256sum) }
start=$(date +%s.%N)
"$kerfab" demo --quiet --out "$out" 2>/dev/null
full=$(since "$start")
before=$(fingerprint)
echo "a whole demo run takes ${full} s; $runs runs interrupted at random moments in it"
failures=0 interrupted=0 finished=0
for i in $(seq 1 "$runs"); do
  delay=$(awk -v f="$full" -v s="$RANDOM" 'BEGIN { srand(s); printf "%.2f", rand() * f * 1.05 }')
  "$kerfab" demo --quiet --out "$out" 2>"$work/err" &
  pid=$!
  sleep "$delay"
  sent=$(date +%s.%N)
  kill -INT "$pid" 2>/dev/null || true
  code=0
  wait "$pid" || code=$?
  took=$(since "$sent")
  if [ "$code" = 0 ]; then
    finished=$((finished + 1))
    before=$(fingerprint)  # a complete new run is the state to keep from now on
    echo "run $i: SIGINT after $delay s: had finished (exit 0)"
    continue
  fi
  interrupted=$((interrupted + 1))
  lines=$(grep -cv '^\[\|^  ' "$work/err" || true)
  same=yes
  [ "$(fingerprint)" = "$before" ] || same=no
  echo "run $i: SIGINT after $delay s: exit $code in $took s, $lines error line(s), folder unchanged: $same"
  if [ "$code" != 130 ] || [ "$same" != yes ] || [ "$lines" != 1 ] ||
     awk -v t="$took" 'BEGIN { exit !(t > 1) }'; then
    failures=$((failures + 1))
  fi
done
echo "$interrupted interrupted, $finished finished, $failures failed"
[ "$failures" = 0 ]
