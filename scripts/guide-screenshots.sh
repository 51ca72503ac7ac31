#!/usr/bin/env bash
# Screenshots of a run's assembly guide in headless Chromium (Debian's chromium, installed if
# missing): the first, a middle and the last step.
# Usage: scripts/guide-screenshots.sh RUN_DIR OUT_PREFIX   (writes OUT_PREFIX-step-K.png)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
[ $# -eq 2 ] || { echo "usage: $0 RUN_DIR OUT_PREFIX" >&2; exit 1; }
run=$(cd "$1" && pwd)
"$root/scripts/deps.sh" --browser
steps=$(grep -o '"step": [0-9]*' "$run/report.json" | awk '{print $2}' | sort -n | tail -1)
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
for k in 1 $((steps / 2)) "$steps"; do
  chromium --headless=new --no-sandbox --disable-gpu --enable-unsafe-swiftshader \
    --use-angle=swiftshader --window-size=1280,800 --virtual-time-budget=10000 --no-first-run \
    --user-data-dir="$profile" --screenshot="$2-step-$k.png" \
    "file://$run/assembly/index.html#step=$k" 2>/dev/null
  echo "$2-step-$k.png"
done
