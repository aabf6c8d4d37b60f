#!/usr/bin/env bash
# Installs what areamatch needs on Debian 12 (skipped when already there), then configures and
# builds it in Release mode into ./build (or $AREAMATCH_BUILD_DIR).
#   --sanitize     a Debug build with AddressSanitizer and UndefinedBehaviorSanitizer instead
#   --deps-only    packages only
#   --target T     build only target T (and what it needs), e.g. demo; may be repeated
#   --no-python    skip the Python module's packages and the module
# Used by demo.sh, test.sh, sanitize.sh and fuzz.sh.
set -euo pipefail
cd "$(dirname "$0")/.."

mode=release
python=yes
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --sanitize) mode=sanitize ;;
    --deps-only) mode=deps ;;
    --no-python) python=no ;;
    --target) targets+=(--target "$2"); shift ;;
    *) echo "setup.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done

packages=(libboost1.81-dev libeigen3-dev libstb-dev libyaml-cpp-dev doctest-dev libbenchmark-dev cmake g++ make)
if [ "$python" = yes ] && [ "$mode" != sanitize ]; then
  packages+=(pybind11-dev python3-dev python3-numpy python3-pytest)
fi
# The sanitizer build uses clang (and its sanitizer runtimes), as the fuzzers do.
if [ "$mode" = sanitize ]; then packages+=(clang libclang-rt-14-dev); fi
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

[ "$mode" = deps ] && exit 0

build_dir="${AREAMATCH_BUILD_DIR:-build}"
if [ "$mode" = sanitize ]; then
  # ASan + UBSan, every report fatal. -O1 (what ASan's docs advise): it doubles the compile time,
  # but at -O0 the unoptimised Eigen and Boost code ran the tests ~10x slower (test_matcher:
  # over the 1500 s timeout at -O0, 118 s at -O1), far more than the compile costs.
  # -g1: line tables only, all a sanitizer report's stack needs; full -g made each unit ~40 %
  # slower to compile (test_decision.cpp: 209 s with -g, 151 s with -g1).
  # clang, not GCC: the same sanitizers, and a third less compile time for our template-heavy
  # units (examples/quickstart.cpp: 80 s against 121 s with these flags); the Release build
  # stays GCC's, so CI compiles the library with both.
  flags="-O1 -g1 -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=all"
  # A build folder configured with another compiler (GCC, before 2026-12-02): CMake would wipe its
  # cache on the compiler change and drop every option below with it, leaving a Release build
  # without sanitizers. Configure it afresh instead.
  cache="$build_dir/CMakeCache.txt"
  if [ -f "$cache" ] && ! grep -q '^CMAKE_CXX_COMPILER:.*clang++$' "$cache"; then
    echo "setup: $build_dir was configured with another compiler; configuring it afresh with clang++"
    rm -rf "$cache" "$build_dir/CMakeFiles"
  fi
  # CMAKE_CXX_FLAGS_DEBUG emptied: CMake's Debug default, -g, comes after these flags and would
  # overrule -g1 (it did until 2026-12-06: the unit tests' compile 287 s with it, 233 s without).
  cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_CXX_FLAGS_DEBUG= \
        -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DAREAMATCH_BUILD_BENCHMARKS=OFF -DAREAMATCH_BUILD_EXAMPLES=OFF \
        -DAREAMATCH_SHARED_TESTS=OFF -DAREAMATCH_BUILD_PYTHON=OFF -DAREAMATCH_BUILD_FUZZERS=ON \
        -DAREAMATCH_BUILD_RESEARCH_TOOLS=OFF -DAREAMATCH_STOCK_VORONOI_TEST=OFF ${AREAMATCH_CMAKE_ARGS:-}
else
  # The Python module is built for Debian's interpreter, the one the python3-* packages above
  # serve (another python3 may come first on PATH, e.g. pyenv's, without numpy or pytest).
  python_args=(-DAREAMATCH_BUILD_PYTHON=OFF)
  if [ "$python" = yes ]; then
    python_args=(-DAREAMATCH_BUILD_PYTHON=ON)
    if [ -x /usr/bin/python3 ]; then python_args+=(-DPython3_EXECUTABLE=/usr/bin/python3); fi
  fi
  cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "${python_args[@]}" ${AREAMATCH_CMAKE_ARGS:-}
fi
cmake --build "$build_dir" -j "$(nproc)" "${targets[@]}"
