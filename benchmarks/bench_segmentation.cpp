// Segmentation speed: every map of ../shared/maps (when present) and synthetic buildings from
// 10 m to 200 m square at 0.05 m. Maps are loaded once; only segmentation is timed. For the
// shared maps also the Voronoi builder alone on the traced boundary, ours (`voronoi/`, with the
// corner circle events of detail/voronoi_circles.hpp) and Boost.Polygon's `construct_voronoi`
// (`voronoi_boost/`).
// Inputs are built on first use (a filtered run loads only what it selects).
//   build/benchmarks/areamatch_bench --benchmark_filter='^(segment|voronoi|voronoi_boost)/' --benchmark_out=segmentation.json --benchmark_out_format=json
#include <areamatch/areamatch.hpp>
#include <areamatch/synthetic.hpp>
#include <areamatch/detail/voronoi_circles.hpp>
#include <areamatch/io.hpp>

#include <benchmark/benchmark.h>

#include "bench_support.hpp"

#include <dirent.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace areamatch_bench::segmentation {

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

/// The segmenter's Voronoi input for `grid` (default parameters).
areamatch::BoundarySegments voronoi_input(const areamatch::OccupancyGrid& grid) {
  const areamatch::VoronoiSegmenter::Params params;
  return areamatch::trace_boundary(areamatch::binarize(grid, params.binarize), grid.resolution(), params.boundary);
}

template <class Build>
void build_voronoi(benchmark::State& state, const areamatch::BoundarySegments& input, Build&& build) {
  std::size_t vertices = 0;
  for (auto _ : state) {
    boost::polygon::voronoi_diagram<double> diagram;
    build(input.segments, &diagram);
    vertices = diagram.vertices().size();
    benchmark::DoNotOptimize(vertices);
  }
  state.counters["segments"] = static_cast<double>(input.segments.size());
  state.counters["vertices"] = static_cast<double>(vertices);
}

void register_synthetic() {
  for (int side : {10, 25, 50, 100, 200}) {
    areamatch::BuildingParams params;
    params.width_m = side;
    params.height_m = side;
    auto grid = lazy<areamatch::OccupancyGrid>([params] { return areamatch::generate_building(params, 1).layout; });
    benchmark::RegisterBenchmark(("segment/synthetic_" + std::to_string(side) + "m").c_str(),
                                 [grid](benchmark::State& state) { segment_map(state, grid->get()); })
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
    auto grid = lazy<areamatch::OccupancyGrid>([path = folder + "/" + name] { return areamatch::load_map(path); });
    const std::string map = name.substr(0, name.size() - 5);
    benchmark::RegisterBenchmark(("segment/" + map).c_str(), [grid](benchmark::State& state) { segment_map(state, grid->get()); })
        ->Unit(benchmark::kMillisecond);
    auto input = lazy<areamatch::BoundarySegments>([grid] { return voronoi_input(grid->get()); });
    using Segments = std::vector<areamatch::LatticeSegment>;
    using Diagram = boost::polygon::voronoi_diagram<double>;
    benchmark::RegisterBenchmark(("voronoi/" + map).c_str(), [input](benchmark::State& state) {
      build_voronoi(state, input->get(), [](const Segments& s, Diagram* d) { areamatch::detail::construct_segment_voronoi(s.begin(), s.end(), d); });
    })->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("voronoi_boost/" + map).c_str(), [input](benchmark::State& state) {
      build_voronoi(state, input->get(), [](const Segments& s, Diagram* d) { boost::polygon::construct_voronoi(s.begin(), s.end(), d); });
    })->Unit(benchmark::kMillisecond);
  }
}

}  // namespace areamatch_bench::segmentation

void areamatch_bench::register_segmentation() {
  segmentation::register_synthetic();
  segmentation::register_shared_maps();
}
