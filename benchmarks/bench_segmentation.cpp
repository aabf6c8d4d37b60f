// Segmentation speed: every map of ../shared/maps (when present) and synthetic buildings from
// 10 m to 200 m square at 0.05 m. Maps are loaded once; only segmentation is timed.
//   build/benchmarks/bench_segmentation --benchmark_out=segmentation.json --benchmark_out_format=json
#include <areamatch/areamatch.hpp>
#include <areamatch/io.hpp>

#include <benchmark/benchmark.h>

#include <dirent.h>

#include <algorithm>
#include <string>
#include <vector>

namespace {

void segment_map(benchmark::State& state, const areamatch::OccupancyGrid& grid) {
  const areamatch::VoronoiSegmenter segmenter;
  std::size_t areas = 0;
  for (auto _ : state) {
    const auto graph = segmenter.segment(grid);
    areas = graph.areas.size();
    benchmark::DoNotOptimize(areas);
  }
  state.counters["areas"] = static_cast<double>(areas);
  state.counters["cells"] = static_cast<double>(grid.width()) * grid.height();
}

void register_synthetic() {
  for (int side : {10, 25, 50, 100, 200}) {
    areamatch::BuildingParams params;
    params.width_m = side;
    params.height_m = side;
    auto grid = std::make_shared<areamatch::OccupancyGrid>(areamatch::generate_building(params, 1).layout);
    benchmark::RegisterBenchmark(("segment/synthetic_" + std::to_string(side) + "m").c_str(),
                                 [grid](benchmark::State& state) { segment_map(state, *grid); })
        ->Unit(benchmark::kMillisecond);
  }
}

void register_shared_maps() {
  const std::string folder = std::string(AREAMATCH_SHARED_DIR) + "/maps";
  DIR* dir = ::opendir(folder.c_str());
  if (!dir) return;
  std::vector<std::string> names;
  while (const dirent* entry = ::readdir(dir)) {
    const std::string name = entry->d_name;
    if (name.size() > 5 && name.compare(name.size() - 5, 5, ".yaml") == 0) names.push_back(name);
  }
  ::closedir(dir);
  std::sort(names.begin(), names.end());
  for (const auto& name : names) {
    auto grid = std::make_shared<areamatch::OccupancyGrid>(areamatch::load_map(folder + "/" + name));
    benchmark::RegisterBenchmark(("segment/" + name.substr(0, name.size() - 5)).c_str(),
                                 [grid](benchmark::State& state) { segment_map(state, *grid); })
        ->Unit(benchmark::kMillisecond);
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_synthetic();
  register_shared_maps();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
