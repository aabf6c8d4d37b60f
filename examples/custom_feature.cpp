// A user-written feature in the Matcher: the number of passages of an area, added to the
// paper's three features with its own weight. A feature policy is a small struct: a descriptor
// type, `describe` and `cost` (see <areamatch/match/proposal/features.hpp>).
//   build/examples/custom_feature
#include <areamatch/areamatch.hpp>
#include <areamatch/synthetic.hpp>

#include <array>
#include <cmath>
#include <cstdio>

struct PassageCount {
  using descriptor_type = double;
  descriptor_type describe(const areamatch::AreaGraph&, const areamatch::Area& area) const {
    return static_cast<double>(area.passages.size());
  }
  double cost(const descriptor_type& source, const descriptor_type& dest) const {
    return areamatch::relative_difference(source, dest);
  }
};

// One weight per feature, in the FeatureSet's order; they sum to one.
struct MyWeights {
  std::array<double, 4> values{0.1, 0.1, 0.6, 0.2};
};

using MyMatcher = areamatch::Matcher<areamatch::VoronoiSegmenter,
                                     areamatch::FeatureSet<areamatch::AreaSize, areamatch::PassageDistances,
                                                           areamatch::HullDiameter, PassageCount>,
                                     MyWeights>;

int main() {
  const auto building = areamatch::generate_building({}, 21);
  areamatch::RobotMapParams robot_params;
  robot_params.rotation_rad = 2.0;
  robot_params.max_clutter_per_room = 2;
  const auto robot = areamatch::make_robot_map(building, robot_params, 21);

  const MyMatcher matcher;
  const areamatch::MatchResult result = matcher.match(robot.grid, building.layout);
  const double error_deg =
      std::abs(areamatch::wrap_angle(result.T_dest_source.rotation - robot.T_dest_source.rotation)) * 180.0 / areamatch::pi;
  std::printf("custom feature: %s, rotation error %.3f deg, %zu mutual pairs, %zu matched areas\n",
              result.ok ? "matched" : result.reason.c_str(), error_deg, result.statistics.mutual_pairs,
              result.matched_areas.size());
  return result.ok && error_deg < 3.0 ? 0 : 1;
}
