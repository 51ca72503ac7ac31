#!/usr/bin/env bash
# README command 1: install what is missing, build, and run the bundled example into out/demo.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
"$root/build/kerfab" demo --out "$root/out/demo"
