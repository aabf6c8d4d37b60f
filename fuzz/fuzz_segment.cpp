// Fuzz target: the segmenter on arbitrary small grids. Besides not crashing, its output must
// hold the Area Graph's invariants: valid polygons, labels in range, passages joining two
// existing, different areas.
#include <areamatch/areamatch.hpp>

#include "fuzz_support.hpp"

#include <boost/geometry.hpp>

#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const areamatch::OccupancyGrid grid = areamatch_fuzz::grid_from_bytes(data, size);
  if (grid.empty()) return 0;
  try {
    const areamatch::AreaGraph graph = areamatch::VoronoiSegmenter{}.segment(grid);
    const int n = static_cast<int>(graph.areas.size());
    for (const auto& area : graph.areas) {
      if (!boost::geometry::is_valid(area.polygon) || !(area.size_m2 > 0.0)) std::abort();
    }
    for (int label : graph.labels) {
      if (label < -1 || label >= n) std::abort();
    }
    for (const auto& p : graph.passages) {
      if (p.area_a < 0 || p.area_b >= n || p.area_a >= p.area_b || !(p.width_m > 0.0)) std::abort();
    }
  } catch (const areamatch::error&) {
  }
  return 0;
}
