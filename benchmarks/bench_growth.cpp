// How the cost grows with the floor (issue 44): generated buildings (`generate_building`, seed 7,
// the robot map turned 37° as `areamatch generate` does, the largest unturned as
// scripts/growth.py has it).
//   growth/pair/<W>x<H>   segment both maps and match, one process's view of `areamatch match`;
//                         counters: m2 (the footprint), areas (robot / layout), us_per_m2 (per m² of
//                         footprint), us_per_mapped_m2 (per m² of the robot map's areas), and the
//                         stages' ms (segment_robot_ms, segment_layout_ms, prepare_ms, pairs_ms =
//                         features + hypotheses + clustering, selection_ms)
//   growth/onto_prepared/240x160_third  a robot map of a third of the 240 x 160 m floor (its
//                         grid cropped to the middle third of its columns) onto the layout
//                         prepared beforehand (Matcher::prepare); us_per_mapped_m2 per square
//                         metre of the robot map's areas, to compare with growth/pair's: onto a
//                         prepared layout the cost should follow the robot map, not the layout.
// Buildings are generated on first use: 240 x 160 m takes about half a minute, 400 x 300 m
// several minutes, so select with --benchmark_filter. Peak memory per size: scripts/growth.py.
//   build/benchmarks/areamatch_bench --benchmark_filter='^growth/' --benchmark_min_time=1
#include <areamatch/areamatch.hpp>
#include <areamatch/synthetic.hpp>

#include <benchmark/benchmark.h>

#include "bench_support.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace areamatch_bench::growth {

struct Floor {
  double width_m = 0.0, height_m = 0.0;
  areamatch::OccupancyGrid robot, layout;
  double robot_mapped_m2 = 0.0;  ///< the robot map's areas
};

double mapped_m2(const areamatch::OccupancyGrid& grid) {
  double sum = 0.0;
  for (const auto& area : areamatch::VoronoiSegmenter{}.segment(grid).areas) sum += area.size_m2;
  return sum;
}

/// µs per square metre: time / (iterations · m2 · 1e-6).
benchmark::Counter per_m2(double m2) {
  return benchmark::Counter(m2 * 1e-6, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

Floor make_floor(double width_m, double height_m, bool turned) {
  areamatch::BuildingParams building_params;
  building_params.width_m = width_m;
  building_params.height_m = height_m;
  building_params.door_width_m = 0.9;
  areamatch::RobotMapParams robot_params;  // as `areamatch generate` makes them
  robot_params.wall_noise_m = 0.03;
  robot_params.max_clutter_per_room = 3;
  robot_params.speckle_per_m2 = 0.02;
  robot_params.rotation_rad = turned ? 37.0 * areamatch::pi / 180.0 : 0.0;
  const auto building = areamatch::generate_building(building_params, 7);
  Floor floor{width_m, height_m, areamatch::make_robot_map(building, robot_params, 7).grid, building.layout, 0.0};
  floor.robot_mapped_m2 = mapped_m2(floor.robot);
  return floor;
}

/// Columns [first, last) of `grid`, with the origin moved so the cells keep their world positions.
areamatch::OccupancyGrid columns_of(const areamatch::OccupancyGrid& grid, int first, int last) {
  areamatch::Pose2 origin = grid.origin();
  origin.x += first * grid.resolution() * std::cos(origin.yaw);
  origin.y += first * grid.resolution() * std::sin(origin.yaw);
  areamatch::OccupancyGrid out(last - first, grid.height(), grid.resolution(), origin);
  for (int row = 0; row < grid.height(); ++row) {
    for (int col = first; col < last; ++col) out.set(col - first, row, grid.at(col, row));
  }
  return out;
}

/// The stages' times of a match, summed over a benchmark's iterations.
struct StageTimes {
  double segment_robot = 0, segment_layout = 0, prepare = 0, pairs = 0, selection = 0;
  void add(const areamatch::MatchTimings& t) {
    segment_robot += t.segment_source_s;
    segment_layout += t.segment_dest_s;
    prepare += t.prepare_s;
    pairs += t.features_s + t.hypotheses_s + t.clustering_s;
    selection += t.selection_s;
  }
  /// Per-iteration milliseconds as counters.
  void report(benchmark::State& state) const {
    const double ms = 1000.0 / static_cast<double>(state.iterations());
    state.counters["segment_robot_ms"] = ms * segment_robot;
    state.counters["segment_layout_ms"] = ms * segment_layout;
    state.counters["prepare_ms"] = ms * prepare;
    state.counters["pairs_ms"] = ms * pairs;
    state.counters["selection_ms"] = ms * selection;
  }
};

void pair(benchmark::State& state, const Floor& floor) {
  const areamatch::Matcher<> matcher;
  areamatch::MatchResult result;
  StageTimes stages;
  for (auto _ : state) {
    result = matcher.match(floor.robot, floor.layout);
    benchmark::DoNotOptimize(result.score);
    stages.add(result.timings);
  }
  if (!result.ok) state.SkipWithError(("not matched: " + result.reason).c_str());
  const double m2 = floor.width_m * floor.height_m;
  state.counters["m2"] = m2;
  state.counters["areas_robot"] = static_cast<double>(result.statistics.source_areas);
  state.counters["areas_layout"] = static_cast<double>(result.statistics.dest_areas);
  state.counters["us_per_m2"] = per_m2(m2);
  state.counters["us_per_mapped_m2"] = per_m2(floor.robot_mapped_m2);
  stages.report(state);
}

}  // namespace areamatch_bench::growth

namespace areamatch_bench {

void register_growth() {
  using namespace growth;
  struct Size {
    int width, height;
  };
  for (const Size size : {Size{30, 20}, Size{60, 40}, Size{120, 80}, Size{240, 160}, Size{400, 300}}) {
    const std::string name = std::to_string(size.width) + "x" + std::to_string(size.height);
    const bool turned = size.width * size.height <= 240 * 160;
    auto floor = lazy<Floor>([size, turned] { return make_floor(size.width, size.height, turned); });
    benchmark::RegisterBenchmark(("growth/pair/" + name).c_str(), [floor](benchmark::State& state) {
      pair(state, floor->get());
    })->Unit(benchmark::kMillisecond)->UseRealTime();
  }
  auto third = lazy<Floor>([] {
    Floor floor = make_floor(240, 160, true);
    const int w = floor.robot.width();
    floor.robot = columns_of(floor.robot, w / 3, 2 * w / 3);
    floor.robot_mapped_m2 = mapped_m2(floor.robot);
    return floor;
  });
  benchmark::RegisterBenchmark("growth/onto_prepared/240x160_third", [third](benchmark::State& state) {
    const Floor& floor = third->get();
    const areamatch::Matcher<> matcher;
    const auto layout = matcher.prepare(floor.layout);
    areamatch::MatchResult result;
    StageTimes stages;
    for (auto _ : state) {
      result = matcher.match(floor.robot, layout);
      benchmark::DoNotOptimize(result.score);
      stages.add(result.timings);
    }
    if (!result.ok) state.SkipWithError(("not matched: " + result.reason).c_str());
    state.counters["mapped_m2"] = floor.robot_mapped_m2;
    state.counters["areas_robot"] = static_cast<double>(result.statistics.source_areas);
    state.counters["us_per_mapped_m2"] = per_m2(floor.robot_mapped_m2);
    stages.report(state);
  })->Unit(benchmark::kMillisecond)->UseRealTime();
}

}  // namespace areamatch_bench
