// A user's project: builds a synthetic building, saves and reloads it (the headers and the io
// target link), then matches a robot map of it onto its layout from files with a matcher whose
// every policy is the user's own — segmenter, feature set with a feature of its own, weights,
// clusterer and selection — through the installed io/match_files.hpp.
#include <areamatch/areamatch.hpp>
#include <areamatch/synthetic.hpp>
#include <areamatch/io.hpp>
#include <areamatch/io/match_files.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

// Segmenter: the stock one at a door width of the user's choosing.
struct WideDoorSegmenter {
  double door_width_m = 1.0;
  areamatch::AreaGraph segment(const areamatch::OccupancyGrid& grid) const {
    areamatch::VoronoiSegmenter segmenter;
    segmenter.params.with_door_width(door_width_m);
    return segmenter.segment(grid);
  }
};

// Feature: the widest free disc in the area (its largest clearance), compared as a ratio.
struct WidestDisc {
  using descriptor_type = double;
  descriptor_type describe(const areamatch::AreaGraph&, const areamatch::Area& area) const { return area.max_clearance_m; }
  double cost(const descriptor_type& source, const descriptor_type& dest) const {
    return areamatch::relative_difference(source, dest);
  }
};

// Weights: one per feature, in the FeatureSet's order, summing to one.
struct MyWeights {
  std::array<double, 4> values{0.2, 0.1, 0.5, 0.2};
};

// Clusterer: none — every hypothesis its own cluster, the most overlapping first (ties by index,
// so the order is deterministic); the matcher's whole-map check then decides.
struct EveryHypothesis {
  std::vector<areamatch::Cluster> cluster(const std::vector<areamatch::Hypothesis>& hypotheses) const {
    std::vector<areamatch::Cluster> out(hypotheses.size());
    for (std::size_t i = 0; i < hypotheses.size(); ++i) {
      out[i].members = {static_cast<int>(i)};
      out[i].rotation = hypotheses[i].T_dest_source.rotation;
      out[i].total_overlap = hypotheses[i].area_overlap;
    }
    std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.total_overlap > b.total_overlap; });
    return out;
  }
};

// Selection: the stock whole-map verification, its mirrored finalists dropped (this user's maps
// are never mirrored, whatever the matcher's parameters say).
struct NeverMirrored {
  areamatch::Selected select(const areamatch::SelectionInputs& in, areamatch::MatchStatistics& statistics) const {
    areamatch::Selected out = areamatch::WholeMapSelection{}.select(in, statistics);
    auto& finalists = out.finalists;
    finalists.erase(std::remove_if(finalists.begin(), finalists.end(), [](const auto& f) { return f.T.reflected; }),
                    finalists.end());
    return out;
  }
};

using MyMatcher = areamatch::Matcher<WideDoorSegmenter,
                                     areamatch::FeatureSet<areamatch::AreaSize, areamatch::PassageDistances,
                                                           areamatch::HullDiameter, WidestDisc>,
                                     MyWeights, EveryHypothesis, NeverMirrored>;

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : ".";
  areamatch::BuildingParams params;
  params.width_m = 24.0;
  params.height_m = 16.0;
  const auto building = areamatch::generate_building(params, 3);
  const std::string layout_yaml = areamatch::save_map(building.layout, dir + "/consumer_map.png");
  const auto loaded = areamatch::load_map(layout_yaml);
  if (loaded != building.layout) {
    std::puts("round trip differs");
    return 1;
  }

  areamatch::RobotMapParams robot_params;
  robot_params.rotation_rad = 0.7;
  const auto robot = areamatch::make_robot_map(building, robot_params, 3);
  const std::string robot_yaml = areamatch::save_map(robot.grid, dir + "/consumer_robot.png");
  const MyMatcher matcher;
  const areamatch::MapPairRun run = areamatch::match_map_files(matcher, robot_yaml, layout_yaml);
  const auto& T = run.result.T_dest_source;
  const double error_deg = std::abs(areamatch::wrap_angle(T.rotation - robot.T_dest_source.rotation)) * 180.0 / areamatch::pi;
  const double offset_m = (T.translation - robot.T_dest_source.translation).norm();
  std::printf("areamatch %s consumer: %dx%d cells; own policies: %s, %zu areas, rotation error %.3f deg, offset %.3f m\n",
              areamatch::version_string, loaded.width(), loaded.height(), run.result.ok ? "matched" : run.result.reason.c_str(),
              run.source_graph.areas.size(), error_deg, offset_m);
  return run.result.ok && error_deg < 1.0 && offset_m < 0.2 ? 0 : 1;
}
