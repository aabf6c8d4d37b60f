// A user-written clusterer in the Matcher: group hypotheses into 10-degree rotation bins.
// A clusterer policy is one const member function returning clusters best first (see
// <areamatch/match/proposal/clusterer.hpp>); it must be deterministic and keep the two sides of the
// mirror apart.
//   build/examples/custom_clusterer
#include <areamatch/areamatch.hpp>
#include <areamatch/synthetic.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <utility>
#include <vector>

struct RotationBins {
  double bin_rad = 10.0 * areamatch::pi / 180.0;

  std::vector<areamatch::Cluster> cluster(const std::vector<areamatch::Hypothesis>& hypotheses) const {
    std::map<std::pair<bool, int>, areamatch::Cluster> bins;  // ordered: deterministic
    for (int i = 0; i < static_cast<int>(hypotheses.size()); ++i) {
      const auto& T = hypotheses[static_cast<std::size_t>(i)].T_dest_source;
      auto& c = bins[{T.reflected, static_cast<int>(std::floor(T.rotation / bin_rad))}];
      c.members.push_back(i);
      c.total_overlap += hypotheses[static_cast<std::size_t>(i)].area_overlap;
    }
    std::vector<areamatch::Cluster> out;
    for (auto& [key, c] : bins) {
      // Best member first, so the matcher verifies the most promising hypothesis of each bin.
      std::stable_sort(c.members.begin(), c.members.end(), [&](int a, int b) {
        return hypotheses[static_cast<std::size_t>(a)].area_overlap > hypotheses[static_cast<std::size_t>(b)].area_overlap;
      });
      c.rotation = hypotheses[static_cast<std::size_t>(c.members.front())].T_dest_source.rotation;
      out.push_back(std::move(c));
    }
    std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.total_overlap > b.total_overlap; });
    return out;
  }
};

int main() {
  const auto building = areamatch::generate_building({}, 8);
  areamatch::RobotMapParams robot_params;
  robot_params.rotation_rad = -1.2;
  robot_params.mirror = true;
  const auto robot = areamatch::make_robot_map(building, robot_params, 8);

  areamatch::Matcher<areamatch::VoronoiSegmenter, areamatch::PaperFeatures, areamatch::PaperWeights, RotationBins> matcher;
  matcher.params.allow_reflection = true;
  // Coarse bins hold many different poses: verify more of each (with 8 the best was 3.9 m off).
  matcher.selection.params.members_per_cluster = 64;
  const areamatch::MatchResult result = matcher.match(robot.grid, building.layout);
  const double error_deg =
      std::abs(areamatch::wrap_angle(result.T_dest_source.rotation - robot.T_dest_source.rotation)) * 180.0 / areamatch::pi;
  const double offset_m = (result.T_dest_source.translation - robot.T_dest_source.translation).norm();
  std::printf("custom clusterer: %s, %zu clusters, rotation error %.3f deg, translation error %.3f m, reflected %s\n",
              result.ok ? "matched" : result.reason.c_str(), result.statistics.clusters, error_deg, offset_m,
              result.T_dest_source.reflected ? "yes" : "no");
  return result.ok && error_deg < 3.0 && offset_m < 0.5 && result.T_dest_source.reflected ? 0 : 1;
}
