#!/usr/bin/env bash
# Installs the Debian 12 packages reel needs, only those that are missing.
# Run as root (or with sudo available); does nothing when everything is present.
# With --fuzz, also what the fuzz, asan and tsan presets need (clang; docs/fuzzing.md).
set -euo pipefail
pkgs=(build-essential cmake ninja-build ccache pkg-config
      libeigen3-dev nlohmann-json3-dev libcli11-dev doctest-dev
      libpng-dev libassimp-dev libavcodec-dev libavformat-dev libswscale-dev libavutil-dev libzstd-dev libopenexr-dev
      libgl-dev libegl-dev libosmesa6 libegl1 libegl-mesa0 libgl1-mesa-dri
      chromium-headless-shell)  # the golden report's browser test (docs/testing.md)
# `install-deps.sh --fuzz`: also clang with libFuzzer and its OpenMP, for the fuzz, asan and tsan presets.
if [ "${1:-}" = "--fuzz" ]; then pkgs+=(clang libclang-rt-14-dev libomp-14-dev); fi
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "reel: installing missing packages: ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "reel: need root to install: ${missing[*]}" >&2; exit 1; }
  sudo=sudo
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
