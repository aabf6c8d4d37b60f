// A user-written segmenter in the Matcher: try a few door widths and keep the first that splits
// the map into rooms, for maps whose door width nobody knows. A segmenter policy is one const
// member function `AreaGraph segment(const OccupancyGrid&) const` (see <areamatch/segmenter.hpp>).
//   build/examples/custom_segmenter
#include <areamatch/areamatch.hpp>
#include <areamatch/synthetic.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

struct FirstSplittingDoorWidth {
  std::vector<double> door_widths_m{1.2, 1.6, 2.0};
  double max_largest_share = 0.5;  // "split": no area holds more than half the covered space

  areamatch::AreaGraph segment(const areamatch::OccupancyGrid& grid) const {
    areamatch::AreaGraph graph;
    for (double width : door_widths_m) {
      areamatch::VoronoiSegmenter segmenter;
      segmenter.params.with_door_width(width);
      graph = segmenter.segment(grid);
      double total = 0.0, largest = 0.0;
      for (const auto& area : graph.areas) total += area.size_m2, largest = std::max(largest, area.size_m2);
      if (total > 0.0 && largest <= max_largest_share * total) break;
    }
    return graph;  // the last try when none splits
  }
};

int main() {
  const auto building = areamatch::generate_building({}, 8);
  areamatch::RobotMapParams robot_params;
  robot_params.rotation_rad = -1.2;
  const auto robot = areamatch::make_robot_map(building, robot_params, 8);

  areamatch::Matcher<FirstSplittingDoorWidth> matcher;
  const areamatch::MatchResult result = matcher.match(robot.grid, building.layout);
  const double error_deg =
      std::abs(areamatch::wrap_angle(result.T_dest_source.rotation - robot.T_dest_source.rotation)) * 180.0 / areamatch::pi;
  std::printf("custom segmenter: %s, %zu / %zu areas, rotation error %.3f deg\n",
              result.ok ? "matched" : result.reason.c_str(), result.statistics.source_areas,
              result.statistics.dest_areas, error_deg);
  return result.ok && error_deg < 3.0 ? 0 : 1;
}
