// Warp and map assessment speed against the match they build on (issue: warp ≤ 2× a match,
// assess ≤ 3× a match on the same pair). Per pair of ../shared/pairs.json (when present, as
// `areamatch eval` runs them: load, segment, match), the hand-held F5 and HIH scans onto their
// layouts (../shared/handheld), and generated bent and broken robot maps of growing size:
//   warp/<pair>     a match, then `fit_warp` from its transform (`areamatch warp`)
//   assess/<pair>   a match, then `assess_match` (`areamatch assess --same-building`: pairs that
//                   are not accepted are assessed all the same, so every pair costs its full time)
// Counters: match_ms (load + segment both + match), extra_ms (the warp, or the assessment with its
// warp), times_match = (match_ms + extra_ms) / match_ms — the figure the targets are about.
//   build/benchmarks/areamatch_bench --benchmark_filter='^(warp|assess)/' --benchmark_out=assess.json --benchmark_out_format=json
#include <areamatch/areamatch.hpp>
#include <areamatch/synthetic.hpp>
#include <areamatch/io.hpp>
#include <eval/evaluate.hpp>

#include <benchmark/benchmark.h>

#include "bench_support.hpp"

#include <chrono>
#include <functional>
#include <string>

namespace areamatch_bench::assessing {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// One pair: how to match it from scratch (the timed baseline) — a run with maps, graphs, result.
using MatchRun = std::function<areamatch::MapPairRun()>;

/// Times `run` and then `extra` on its output, each iteration; reports both and their ratio.
void timed(benchmark::State& state, const MatchRun& run, const std::function<double(const areamatch::MapPairRun&)>& extra) {
  double match_s = 0.0, extra_s = 0.0;
  for (auto _ : state) {
    const auto start = Clock::now();
    const areamatch::MapPairRun r = run();
    match_s += seconds_since(start);
    const auto after = Clock::now();
    benchmark::DoNotOptimize(extra(r));
    extra_s += seconds_since(after);
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["match_ms"] = 1000.0 * match_s / n;
  state.counters["extra_ms"] = 1000.0 * extra_s / n;
  state.counters["times_match"] = match_s > 0.0 ? (match_s + extra_s) / match_s : 0.0;
}

void register_pair(const std::string& name, MatchRun run) {
  benchmark::RegisterBenchmark(("warp/" + name).c_str(), [run](benchmark::State& state) {
    timed(state, run, [](const areamatch::MapPairRun& r) {
      return areamatch::fit_warp(r.source, r.dest, r.result.T_dest_source).warped_median_m;
    });
  })->Unit(benchmark::kMillisecond)->UseRealTime();
  benchmark::RegisterBenchmark(("assess/" + name).c_str(), [run](benchmark::State& state) {
    areamatch::AssessParams params;
    params.assume_same_building = true;
    timed(state, run, [params](const areamatch::MapPairRun& r) {
      return areamatch::assess_match(r.source, r.source_graph, r.dest, r.dest_graph, r.result, params).coverage.explored_share;
    });
  })->Unit(benchmark::kMillisecond)->UseRealTime();
}

/// Generated robot maps of a `side` m square building, bent by 0.5 m and broken once.
void register_generated() {
  for (int side : {25, 50, 100}) {
    auto maps = areamatch_bench::lazy<std::pair<areamatch::OccupancyGrid, areamatch::OccupancyGrid>>([side] {
      areamatch::BuildingParams building_params;
      building_params.width_m = side;
      building_params.height_m = side;
      const auto building = areamatch::generate_building(building_params, 1);
      areamatch::RobotMapParams robot_params;
      robot_params.rotation_rad = 1.0;
      robot_params.max_clutter_per_room = 2;
      robot_params.wall_noise_m = 0.03;
      robot_params.wall_bend_m = 0.5;
      robot_params.break_count = 1;
      return std::make_pair(areamatch::make_robot_map(building, robot_params, 1).grid, building.layout);
    });
    register_pair("synthetic_" + std::to_string(side) + "m", [maps] {
      const auto& [source, dest] = maps->get();
      areamatch::MapPairRun r;
      r.source = source;
      r.dest = dest;
      const areamatch::Matcher<> matcher;
      r.source_graph = matcher.segmenter.segment(r.source);
      r.dest_graph = matcher.segmenter.segment(r.dest);
      r.result = matcher.match(r.source, r.source_graph, r.dest, r.dest_graph);
      return r;
    });
  }
}

void register_manifest(const std::string& path, const std::function<bool(const std::string&)>& wanted) {
  areamatch::Manifest manifest;
  try {
    manifest = areamatch::load_manifest(path);
  } catch (const areamatch::io_error&) {
    return;  // no shared data: generated maps only
  }
  for (const auto& pair : manifest.pairs) {
    if (!wanted(pair.name)) continue;
    const auto options = areamatch::pair_options(pair, areamatch::EvalOptions{});
    register_pair(pair.name, [pair, options] { return areamatch::match_map_files(pair.source, pair.destination, options); });
  }
}

}  // namespace areamatch_bench::assessing

void areamatch_bench::register_assessing() {
  assessing::register_generated();
  const std::string shared = AREAMATCH_SHARED_DIR;
  assessing::register_manifest(shared + "/pairs.json", [](const std::string&) { return true; });
  // The hand-held scans onto their layouts (one per place is enough to see the cost).
  assessing::register_manifest(shared + "/handheld/pairs.json", [](const std::string& name) {
    return name == "F5_01_to_layout" || name == "HIH_01_to_layout" || name == "KPT4A_01_to_layout";
  });
}
