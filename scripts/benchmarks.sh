#!/usr/bin/env bash
# The full benchmark run: every benchmark (synthetic buildings 10-200 m, and every shared map and
# pair when ../shared is present), 5 repetitions each, medians. Writes into OUTDIR (default
# build/benchmark-results): segmentation.json, matching.json, io.json (Google Benchmark JSON),
# benchmarks.csv and scaling.svg. Takes about 10 minutes on 2 cores. Pass extra Google Benchmark
# flags after OUTDIR (a --benchmark_filter given there replaces each group's own filter).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-build/benchmark-results}"
shift || true
scripts/setup.sh >/dev/null
mkdir -p "$out"
bench="${AREAMATCH_BUILD_DIR:-build}/benchmarks"
common=(--benchmark_repetitions=5 --benchmark_report_aggregates_only=true "$@")
"$bench/areamatch_bench" "${common[@]}" --benchmark_filter='^(segment|voronoi|voronoi_boost)/' --benchmark_out="$out/segmentation.json" --benchmark_out_format=json
"$bench/areamatch_bench" "${common[@]}" --benchmark_filter='^(match|pair|onto_prepared|onto_prepared_2t)/' --benchmark_out="$out/matching.json" --benchmark_out_format=json
"$bench/areamatch_bench" "${common[@]}" --benchmark_filter='^BM_' --benchmark_out="$out/io.json" --benchmark_out_format=json
python3 scripts/plot_benchmarks.py "$out" "$out/segmentation.json" "$out/matching.json" "$out/io.json"
