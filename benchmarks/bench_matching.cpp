// Matching speed. Per pair of ../shared/pairs.json (when present), as in the paper's setting
// (YAML resolutions, the pair's door width, reflection allowed):
//   match/<pair>   the matching stage alone, on Area Graphs segmented beforehand
//   pair/<pair>    the whole pair: load both map files, segment both, match
// and the matching stage on synthetic pairs of growing size (10 m to 200 m square).
//   build/benchmarks/bench_matching --benchmark_out=matching.json --benchmark_out_format=json
#include <areamatch/areamatch.hpp>
#include <areamatch/io.hpp>
#include <areamatch/io/manifest.hpp>

#include <benchmark/benchmark.h>

#include <memory>
#include <string>

namespace {

struct Prepared {
  areamatch::OccupancyGrid source, dest;
  areamatch::AreaGraph source_graph, dest_graph;
  areamatch::Matcher<> matcher;
};

void match_stage(benchmark::State& state, const Prepared& p) {
  areamatch::MatchResult result;
  for (auto _ : state) {
    result = p.matcher.match(p.source, p.source_graph, p.dest, p.dest_graph);
    benchmark::DoNotOptimize(result.score);
  }
  state.counters["hypotheses"] = static_cast<double>(result.statistics.hypotheses);
  state.counters["areas"] = static_cast<double>(result.statistics.source_areas + result.statistics.dest_areas);
}

std::shared_ptr<Prepared> prepare(areamatch::OccupancyGrid source, areamatch::OccupancyGrid dest,
                                  const areamatch::Matcher<>& matcher) {
  auto p = std::make_shared<Prepared>();
  p->source = std::move(source);
  p->dest = std::move(dest);
  p->matcher = matcher;
  p->source_graph = matcher.segmenter.segment(p->source);
  p->dest_graph = matcher.segmenter.segment(p->dest);
  return p;
}

void register_synthetic() {
  for (int side : {10, 25, 50, 100, 200}) {
    areamatch::BuildingParams building_params;
    building_params.width_m = side;
    building_params.height_m = side;
    const auto building = areamatch::generate_building(building_params, 1);
    areamatch::RobotMapParams robot_params;
    robot_params.rotation_rad = 1.0;
    robot_params.max_clutter_per_room = 2;
    const auto robot = areamatch::make_robot_map(building, robot_params, 1);
    areamatch::Matcher<> matcher;
    matcher.params.allow_reflection = true;
    auto p = prepare(robot.grid, building.layout, matcher);
    benchmark::RegisterBenchmark(("match/synthetic_" + std::to_string(side) + "m").c_str(),
                                 [p](benchmark::State& state) { match_stage(state, *p); })
        ->Unit(benchmark::kMillisecond);
  }
}

void register_shared_pairs() {
  const std::string manifest_path = std::string(AREAMATCH_SHARED_DIR) + "/pairs.json";
  areamatch::Manifest manifest;
  try {
    manifest = areamatch::load_manifest(manifest_path);
  } catch (const areamatch::io_error&) {
    return;  // no shared data: synthetic benchmarks only
  }
  for (const auto& pair : manifest.pairs) {
    areamatch::Matcher<> matcher;
    matcher.params.allow_reflection = true;
    if (pair.door_width_m) matcher.segmenter.params.with_door_width(*pair.door_width_m);
    auto p = prepare(areamatch::load_map(pair.source), areamatch::load_map(pair.destination), matcher);
    benchmark::RegisterBenchmark(("match/" + pair.name).c_str(), [p](benchmark::State& state) { match_stage(state, *p); })
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("pair/" + pair.name).c_str(), [pair, matcher](benchmark::State& state) {
      for (auto _ : state) {
        const auto result = matcher.match(areamatch::load_map(pair.source), areamatch::load_map(pair.destination));
        benchmark::DoNotOptimize(result.score);
      }
    })->Unit(benchmark::kMillisecond);
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_synthetic();
  register_shared_pairs();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
