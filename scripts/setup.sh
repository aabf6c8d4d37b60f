#!/usr/bin/env bash
# Installs what areamatch needs on Debian 12 (skipped when already there), then configures and
# builds it in Release mode into ./build (or $AREAMATCH_BUILD_DIR); with --sanitize, a Debug build
# with AddressSanitizer and UndefinedBehaviorSanitizer instead; with --deps-only, packages only.
# Used by demo.sh, test.sh, sanitize.sh and fuzz.sh.
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

[ "${1:-}" = "--deps-only" ] && exit 0

build_dir="${AREAMATCH_BUILD_DIR:-build}"
if [ "${1:-}" = "--sanitize" ]; then
  # ASan + UBSan, every report fatal. -O1 (what ASan's docs advise): it doubles the compile time,
  # but at -O0 the unoptimised Eigen and Boost code ran the tests ~10x slower (test_matcher:
  # over the 1500 s timeout at -O0, 118 s at -O1), far more than the compile costs.
  flags="-O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=all"
  cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS="$flags" \
        -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DAREAMATCH_BUILD_BENCHMARKS=OFF -DAREAMATCH_BUILD_EXAMPLES=OFF \
        -DAREAMATCH_SHARED_TESTS=OFF ${AREAMATCH_CMAKE_ARGS:-}
else
  cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release ${AREAMATCH_CMAKE_ARGS:-}
fi
cmake --build "$build_dir" -j "$(nproc)"
