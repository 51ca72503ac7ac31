#!/usr/bin/env bash
# README command 1: install what is missing, build, and run the bundled example into out/demo.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
"$root/build/kerfab" demo --out "$root/out/demo"
# A picture of the chosen bending directions (bendable edges red).
python3 "$root/scripts/render_bending.py" "$root/out/demo/stages/bending.json" \
  "$root/out/demo/bending.svg" --azimuth 35 --elevation 10
rsvg-convert "$root/out/demo/bending.svg" -o "$root/out/demo/bending.png"
echo "kerfab demo: report $root/out/demo/report.json, picture $root/out/demo/bending.png"
