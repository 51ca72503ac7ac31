#!/usr/bin/env bash
# The benchmark (README): installs what is missing (gnuplot for the plots, GNU time for peak
# memory, python3 for the driver), builds kerfab (Release) and writes docs/benchmarks.md with
# docs/images/bench-*.svg from one run on this machine. Takes ~30 min on 2 cores.
#   scripts/benchmarks.sh [--quick] [--limit S] [--from-runs]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
missing=()
for p in gnuplot-nox time python3; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
if [[ ${#missing[@]} -gt 0 ]]; then
  echo "kerfab: installing for the benchmark: ${missing[*]}" >&2
  sudo_cmd=()
  [[ $(id -u) -eq 0 ]] || sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
exec python3 "$root/scripts/benchmarks.py" "$@"
