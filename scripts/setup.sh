#!/usr/bin/env bash
# Installs what areamatch needs on Debian 12 (skipped when already there), then configures and
# builds it in Release mode into ./build (or $AREAMATCH_BUILD_DIR). Used by demo.sh and test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(libboost1.81-dev libeigen3-dev libstb-dev libyaml-cpp-dev doctest-dev libbenchmark-dev cmake g++ make)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

build_dir="${AREAMATCH_BUILD_DIR:-build}"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release ${AREAMATCH_CMAKE_ARGS:-}
cmake --build "$build_dir" -j "$(nproc)"
