#!/usr/bin/env bash
# README command 1: install what is missing, build, and run the bundled example into out/demo.
# Everything the README shows comes from kerfab itself: cut sheets and previews (cut/), pictures
# (pictures/), the assembly guide (assembly/index.html, steps.pdf) and the report.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
# out/demo is the project's own folder: one written before kerfab marked its runs (.kerfab) goes.
if [ -d "$root/out/demo" ] && [ ! -e "$root/out/demo/.kerfab" ]; then rm -rf "$root/out/demo"; fi
"$root/build/kerfab" demo --out "$root/out/demo"
echo "kerfab demo: cut sheets (SVG, DXF, PDF, PNG previews, contact sheet) in $root/out/demo/cut/"
echo "kerfab demo: assembly guide $root/out/demo/assembly/index.html (open it in a browser)," \
  "steps to print $root/out/demo/assembly/steps.pdf"
echo "kerfab demo: report $root/out/demo/report.json, pictures in $root/out/demo/pictures/"
