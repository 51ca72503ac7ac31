#!/usr/bin/env bash
# README command 1: install what is missing, build, and run the bundled example into out/demo.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
# out/demo is the project's own folder: one written before kerfab marked its runs (.kerfab) goes.
if [ -d "$root/out/demo" ] && [ ! -e "$root/out/demo/.kerfab" ]; then rm -rf "$root/out/demo"; fi
"$root/build/kerfab" demo --out "$root/out/demo"
# A picture of the chosen bending directions (bendable edges red).
python3 "$root/scripts/render_bending.py" "$root/out/demo/stages/bending.json" \
  "$root/out/demo/bending.svg" --azimuth 35 --elevation 10
rsvg-convert "$root/out/demo/bending.svg" -o "$root/out/demo/bending.png"
# The strips, each in its own colour (strip borders dark).
python3 "$root/scripts/render_strips.py" "$root/out/demo/model/strips.ply" \
  "$root/out/demo/strips.svg" --azimuth 35 --elevation 10
rsvg-convert "$root/out/demo/strips.svg" -o "$root/out/demo/strips.png"
# A few flattened patches (outlines red, rulings grey).
python3 "$root/scripts/render_patches.py" "$root/out/demo/stages/patches" \
  "$root/out/demo/patches.svg" --first 20 --count 6 --width 900
rsvg-convert "$root/out/demo/patches.svg" -o "$root/out/demo/patches.png"
# Three parts with their box joints (laser path red, tooth regions blue).
python3 "$root/scripts/render_parts.py" "$root/out/demo/stages/parts.json" \
  "$root/out/demo/parts.svg" --first 23 --count 3 --width 1000
rsvg-convert "$root/out/demo/parts.svg" -o "$root/out/demo/parts.png"
# Kerf cut density (viridis; red: cuts would have to be closer than the material allows).
python3 "$root/scripts/render_strips.py" "$root/out/demo/model/kerf_density.ply" \
  "$root/out/demo/kerf_density.svg" --azimuth 35 --elevation 10
rsvg-convert "$root/out/demo/kerf_density.svg" -o "$root/out/demo/kerf_density.png"
echo "kerfab demo: cut sheets (SVG, DXF, PDF, PNG previews, contact sheet) in $root/out/demo/cut/"
echo "kerfab demo: report $root/out/demo/report.json, pictures $root/out/demo/strips.png," \
  "$root/out/demo/bending.png, $root/out/demo/patches.png, $root/out/demo/parts.png and" \
  "$root/out/demo/kerf_density.png"
