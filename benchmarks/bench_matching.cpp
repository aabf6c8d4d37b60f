// Matching speed, per pair of ../shared/pairs.json (when present; YAML resolutions, the pair's
// door width, reflection allowed, as `areamatch eval` runs them) and per synthetic pair of
// growing size (10 m to 200 m square, seed 1):
//   match/<pair>   the matching stage alone on Area Graphs segmented beforehand; counters give
//                  the mean time of each stage inside it (features = descriptors + costs +
//                  mutual pairs, hypotheses, clustering, selection = verification + refinement)
//   pair/<pair>    the whole pair: segment both maps and match (shared pairs: load the files too)
//   onto_prepared/<pair>  the source's grid onto the destination prepared beforehand
//                  (Matcher::prepare): segment the source and match, as when localising robot
//                  maps against a floor plan; counters: segment_ms, prepare_ms (the source's match
//                  data), hypotheses_ms (with pairs and clustering), selection_ms, answer_ms (the rest)
//   onto_prepared_2t/<pair>  the same with MatcherParams::threads = 2 (wall-clock time)
// Pairs are prepared on first use, so a --benchmark_filter run pays only for what it selects.
//   build/benchmarks/areamatch_bench --benchmark_filter='^(match|pair|onto_prepared)/' --benchmark_out=matching.json --benchmark_out_format=json
#include <areamatch/areamatch.hpp>
#include <areamatch/synthetic.hpp>
#include <areamatch/io.hpp>
#include <eval/evaluate.hpp>

#include <benchmark/benchmark.h>

#include "bench_support.hpp"

#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace areamatch_bench::matching {

struct Prepared {
  areamatch::OccupancyGrid source, dest;
  areamatch::AreaGraph source_graph, dest_graph;
  areamatch::MapPairOptions options;
};

areamatch::Matcher<> matcher_for(const areamatch::MapPairOptions& options) {
  return areamatch::detail::configured_matcher(areamatch::Matcher<>{}, options);
}

void match_stage(benchmark::State& state, const Prepared& p) {
  const auto matcher = matcher_for(p.options);
  areamatch::MatchResult result;
  areamatch::MatchTimings sum;
  for (auto _ : state) {
    result = matcher.match(p.source, p.source_graph, p.dest, p.dest_graph);
    benchmark::DoNotOptimize(result.score);
    sum.prepare_s += result.timings.prepare_s;
    sum.features_s += result.timings.features_s;
    sum.hypotheses_s += result.timings.hypotheses_s;
    sum.clustering_s += result.timings.clustering_s;
    sum.selection_s += result.timings.selection_s;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["prepare_ms"] = 1000.0 * sum.prepare_s / n;
  state.counters["features_ms"] = 1000.0 * sum.features_s / n;
  state.counters["hypotheses_ms"] = 1000.0 * sum.hypotheses_s / n;
  state.counters["clustering_ms"] = 1000.0 * sum.clustering_s / n;
  state.counters["selection_ms"] = 1000.0 * sum.selection_s / n;
  state.counters["hypotheses"] = static_cast<double>(result.statistics.hypotheses);
  state.counters["areas"] = static_cast<double>(result.statistics.source_areas + result.statistics.dest_areas);
}

/// Segmentation of both maps plus matching, from grids in memory.
void whole_pair_in_memory(benchmark::State& state, const Prepared& p) {
  const auto matcher = matcher_for(p.options);
  for (auto _ : state) {
    const auto result = matcher.match(p.source, p.dest);
    benchmark::DoNotOptimize(result.score);
  }
  state.counters["cells"] = static_cast<double>(p.source.width()) * p.source.height() +
                            static_cast<double>(p.dest.width()) * p.dest.height();
}

void register_pair(const std::string& name, std::function<Prepared()> make,
                   std::function<void(benchmark::State&, const Prepared&)> whole_pair) {
  auto lazy = areamatch_bench::lazy<Prepared>(std::move(make));
  benchmark::RegisterBenchmark(("match/" + name).c_str(), [lazy](benchmark::State& state) { match_stage(state, lazy->get()); })
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark(("pair/" + name).c_str(), [lazy, whole_pair](benchmark::State& state) {
    whole_pair(state, lazy->get());
  })->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark(("onto_prepared/" + name).c_str(), [lazy](benchmark::State& state) {
    const Prepared& p = lazy->get();
    auto matcher = matcher_for(p.options);
    if (p.options.source_door_width_m) matcher.segmenter.params.with_door_width(*p.options.source_door_width_m);
    const auto dest = matcher.prepare(p.dest, p.dest_graph);
    areamatch::MatchTimings sum;
    for (auto _ : state) {
      const auto result = matcher.match(p.source, dest);
      benchmark::DoNotOptimize(result.score);
      const areamatch::MatchTimings& t = result.timings;
      sum.segment_source_s += t.segment_source_s;
      sum.prepare_s += t.prepare_s;
      sum.hypotheses_s += t.features_s + t.hypotheses_s + t.clustering_s;
      sum.selection_s += t.selection_s;
      sum.match_s += t.match_s;
    }
    // Where a robot map's time onto a prepared layout goes (ms per match): segmenting it,
    // building its match data, pairs + hypotheses + clustering, selection, and the rest of the
    // matching stage (evidence, margins, room correspondences, the decision).
    const double ms = 1000.0 / static_cast<double>(state.iterations());
    state.counters["segment_ms"] = ms * sum.segment_source_s;
    state.counters["prepare_ms"] = ms * sum.prepare_s;
    state.counters["hypotheses_ms"] = ms * sum.hypotheses_s;
    state.counters["selection_ms"] = ms * sum.selection_s;
    state.counters["answer_ms"] = ms * (sum.match_s - sum.prepare_s - sum.hypotheses_s - sum.selection_s);
  })->Unit(benchmark::kMillisecond);
  // The same on two threads (`MatcherParams::threads`): the pieces overlap, so only the time.
  benchmark::RegisterBenchmark(("onto_prepared_2t/" + name).c_str(), [lazy](benchmark::State& state) {
    const Prepared& p = lazy->get();
    auto matcher = matcher_for(p.options);
    if (p.options.source_door_width_m) matcher.segmenter.params.with_door_width(*p.options.source_door_width_m);
    matcher.params.threads = 2;
    const auto dest = matcher.prepare(p.dest, p.dest_graph);
    for (auto _ : state) benchmark::DoNotOptimize(matcher.match(p.source, dest).score);
  })->Unit(benchmark::kMillisecond)->UseRealTime();
}

void register_synthetic() {
  for (int side : {10, 25, 50, 100, 200}) {
    register_pair("synthetic_" + std::to_string(side) + "m", [side] {
      areamatch::BuildingParams building_params;
      building_params.width_m = side;
      building_params.height_m = side;
      const auto building = areamatch::generate_building(building_params, 1);
      areamatch::RobotMapParams robot_params;
      robot_params.rotation_rad = 1.0;
      robot_params.max_clutter_per_room = 2;
      Prepared p;
      p.source = areamatch::make_robot_map(building, robot_params, 1).grid;
      p.dest = building.layout;
      p.options.allow_reflection = true;
      const auto matcher = matcher_for(p.options);
      p.source_graph = matcher.segmenter.segment(p.source);
      p.dest_graph = matcher.segmenter.segment(p.dest);
      return p;
    }, whole_pair_in_memory);
  }
}

void register_shared_pairs() {
  areamatch::Manifest manifest;
  try {
    manifest = areamatch::load_manifest(std::string(AREAMATCH_SHARED_DIR) + "/pairs.json");
  } catch (const areamatch::io_error&) {
    return;  // no shared data: synthetic benchmarks only
  }
  for (const auto& pair : manifest.pairs) {
    const auto options = areamatch::pair_options(pair, areamatch::EvalOptions{});
    register_pair(pair.name, [pair, options] {
      const auto run = areamatch::match_map_files(pair.source, pair.destination, options);
      return Prepared{run.source, run.dest, run.source_graph, run.dest_graph, options};
    }, [pair, options](benchmark::State& state, const Prepared&) {
      for (auto _ : state) {
        const auto run = areamatch::match_map_files(pair.source, pair.destination, options);
        benchmark::DoNotOptimize(run.result.score);
      }
    });
  }
}

}  // namespace areamatch_bench::matching

void areamatch_bench::register_matching() {
  matching::register_synthetic();
  matching::register_shared_pairs();
}
