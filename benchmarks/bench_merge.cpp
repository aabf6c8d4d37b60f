// Merging speed (merge_maps on maps prepared beforehand: every pair matched, the poses fitted,
// the merged map fused), and how it grows with the number of maps:
//   merge/synthetic/<N>  N robot maps of one generated building (tests/synthetic_cases.hpp's
//                        merge_case: 30-60 % of the rooms each, one mirrored, allow_reflection);
//                        the same building for every N, the N maps the first N of one sequence
//   merge/synthetic/15/threads:2  the same, pairs matched on two threads (MergeParams::threads)
//   merge/F5             the 14 hand-held scans of ../shared/handheld and the F5 layout (when
//                        present), the layout as reference, door width 1.0 m
// Counters: matching_ms, refine_ms (MergeParams::refine_same_side), fit_ms, fuse_ms (per merge) and prepare_ms (all N preparations, once:
// merging N maps needs N of them, done before the timed loop).
//   build/benchmarks/areamatch_bench --benchmark_filter='^merge/' --benchmark_out=merge.json --benchmark_out_format=json
#include "synthetic_cases.hpp"

#include <areamatch/areamatch.hpp>
#include <areamatch/io.hpp>
#include <areamatch/merge.hpp>

#include <benchmark/benchmark.h>

#include "bench_support.hpp"

#include <chrono>
#include <cstdlib>
#include <string>
#include <sys/stat.h>
#include <vector>

namespace areamatch_bench::merging {

using Prepared = areamatch::Matcher<>::PreparedMap;

void run_merge(benchmark::State& state, const areamatch::Matcher<>& matcher, const std::vector<areamatch::OccupancyGrid>& grids,
               unsigned threads = 1) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<Prepared> maps;
  for (const auto& grid : grids) maps.push_back(matcher.prepare(grid));
  const double prepare_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  areamatch::MergeTimings sum;
  std::size_t placed = 0;
  for (auto _ : state) {
    areamatch::MergeParams params;
    params.threads = threads;
    const areamatch::MergeResult result = areamatch::merge_maps(matcher, maps, params);
    benchmark::DoNotOptimize(result.merged.cells().data());
    sum.matching_s += result.timings.matching_s;
    sum.refine_s += result.timings.refine_s;
    sum.fit_s += result.timings.fit_s;
    sum.fuse_s += result.timings.fuse_s;
    placed = 0;
    for (const auto& m : result.maps) placed += m.placed;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["matching_ms"] = 1000.0 * sum.matching_s / n;
  state.counters["refine_ms"] = 1000.0 * sum.refine_s / n;
  state.counters["fit_ms"] = 1000.0 * sum.fit_s / n;
  state.counters["fuse_ms"] = 1000.0 * sum.fuse_s / n;
  state.counters["prepare_ms"] = 1000.0 * prepare_s;
  state.counters["maps"] = static_cast<double>(grids.size());
  state.counters["placed"] = static_cast<double>(placed);
}

std::string shared_dir() {
  const char* env = std::getenv("AREAMATCH_SHARED_DIR");
  const std::string dir = env && *env ? env : AREAMATCH_SHARED_DIR;
  struct stat info {};
  return ::stat((dir + "/handheld/pairs.json").c_str(), &info) == 0 ? dir : "";
}

}  // namespace areamatch_bench::merging

void areamatch_bench::register_merge() {
  using namespace merging;
  for (const auto& [n, threads] : {std::pair<std::size_t, unsigned>{2, 1}, {5, 1}, {10, 1}, {15, 1}, {15, 2}}) {
    const std::string name = "merge/synthetic/" + std::to_string(n) + (threads > 1 ? "/threads:" + std::to_string(threads) : "");
    benchmark::RegisterBenchmark(name.c_str(), [n = n, threads = threads](benchmark::State& state) {
      const auto c = areamatch_test::merge_case(500, n, /*mirror_one=*/true);
      std::vector<areamatch::OccupancyGrid> grids;
      for (const auto& robot : c.robots) grids.push_back(robot.grid);
      areamatch::Matcher<> matcher;
      matcher.params.allow_reflection = true;
      run_merge(state, matcher, grids, threads);
    })->Unit(benchmark::kMillisecond)->UseRealTime();
  }
  if (const std::string dir = shared_dir(); !dir.empty()) {
    benchmark::RegisterBenchmark("merge/F5", [dir](benchmark::State& state) {
      std::vector<areamatch::OccupancyGrid> grids{areamatch::load_map(dir + "/handheld/maps/F5_layout.yaml")};
      for (int i = 1; i <= 14; ++i) {
        grids.push_back(areamatch::load_map(dir + "/handheld/maps/F5_" + (i < 10 ? "0" : "") + std::to_string(i) + ".yaml"));
      }
      areamatch::Matcher<> matcher;
      matcher.segmenter.params.with_door_width(1.0);
      run_merge(state, matcher, grids);
    })->Unit(benchmark::kMillisecond)->UseRealTime();
  }
}
