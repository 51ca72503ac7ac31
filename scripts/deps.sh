#!/usr/bin/env bash
# Installs the Debian 12 packages kerfab needs to build, test and render previews.
# Idempotent: prints nothing and touches nothing when every package is already present.
set -euo pipefail
packages=(
  cmake ninja-build g++ pkg-config
  libeigen3-dev libopenmesh-dev coinor-libcbc-dev libcgal-dev libpolyclipping-dev libcairo2-dev
  libcli11-dev nlohmann-json3-dev libgtest-dev libbenchmark-dev
  libjs-three librsvg2-bin
)
# --browser: also Debian's chromium (the tests open the assembly guide in it, headless).
if [[ "${1:-}" == "--browser" ]]; then packages+=(chromium); fi
missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
[[ ${#missing[@]} -eq 0 ]] && exit 0
echo "kerfab: installing missing Debian packages: ${missing[*]}" >&2
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "kerfab: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
