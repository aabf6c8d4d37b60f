#pragma once
/// \file segment/junctions.hpp
/// The last step of `detect_rooms` (segment/rooms.hpp): a region whose skeleton branches into long
/// arms (corridors meeting, a room opening into two corridors) is cut at its junctions, one region
/// per long arm, with a junction passage on each cut.

#include "../transform.hpp"
#include "room_detection.hpp"
#include "skeleton.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <utility>
#include <vector>

namespace areamatch {

namespace detail {

/// The arms of junction `J` (a node of region `R` with three or more skeleton neighbours): the
/// sample each starts at, its direction, and the part of the region it leads into once the
/// junction is removed (−1: another region).
struct JunctionArms {
  struct Arm {
    int first = -1;
    double angle = 0.0;
  };
  std::vector<Arm> arms;
  std::vector<int> part_of_sample;  ///< per sample: the arm index whose part it is in, else −1
  std::vector<int> long_arms;       ///< arms whose part is long and corridor-shaped, in arm order

  int part_of_arm(std::size_t a) const { return part_of_sample[static_cast<std::size_t>(arms[a].first)]; }
};

/// `J`'s arms, and which are long: an arm is long when its part is at least `needed` long
/// (skeleton length, cells) and corridor-shaped (length ≥ `elongation` × its widest clearance).
/// Empty `long_arms` when fewer than three are long or two long arms share a part (joined
/// elsewhere, a loop): such a junction cannot be split.
inline JunctionArms junction_arms(const RoomDetection& out, int J, double needed, double elongation) {
  const SampleGraph& g = out.graph;
  const auto& region = out.region_of_sample;
  const int R = region[J];
  const Eigen::Vector2d centre = g.samples[J].position;
  JunctionArms result;
  for (int first : g.neighbours(J)) {
    const Eigen::Vector2d d = g.samples[first].position - centre;
    result.arms.push_back({first, std::atan2(d.y(), d.x())});
  }
  const auto& arms = result.arms;
  // The region's parts once the junction is removed, each named by the first arm leading into it.
  int count = 0;
  const std::vector<int> piece = components(g, [&](int s) { return s != J && region[s] == R; }, count);
  std::vector<int> arm_of_piece(static_cast<std::size_t>(count), -1);
  for (std::size_t a = 0; a < arms.size(); ++a) {
    const int p = piece[arms[a].first];
    if (p >= 0 && arm_of_piece[p] < 0) arm_of_piece[p] = static_cast<int>(a);
  }
  std::vector<int>& component = result.part_of_sample;
  component.assign(g.samples.size(), -1);
  for (std::size_t s = 0; s < g.samples.size(); ++s)
    if (piece[s] >= 0) component[s] = arm_of_piece[piece[s]];
  std::vector<double> part_length(arms.size(), 0.0), part_width(arms.size(), 0.0);
  for (std::size_t s = 0; s < g.samples.size(); ++s) {
    const int c = component[s];
    if (c < 0) continue;
    part_width[c] = std::max(part_width[c], g.samples[s].clearance);
    for (int t : g.neighbours(s))
      if (component[t] == c) part_length[c] += 0.5 * g.distance(static_cast<int>(s), t);
  }
  std::vector<bool> part_taken(arms.size(), false);
  bool shared_part = false;
  for (std::size_t a = 0; a < arms.size(); ++a) {
    const int c = component[arms[a].first];
    if (c < 0 || part_length[c] < needed || part_length[c] < elongation * part_width[c]) continue;
    if (part_taken[c]) shared_part = true;
    part_taken[c] = true;
    result.long_arms.push_back(static_cast<int>(a));
  }
  if (shared_part || result.long_arms.size() < 3) result.long_arms.clear();
  return result;
}

/// The feet of node `j`'s largest free disc (where it touches the walls), from the kept skeleton
/// branches that end at it; feet within half a cell of one another count once.
inline std::vector<Eigen::Vector2d> junction_feet(const Skeleton& skeleton, std::size_t j) {
  const int J = static_cast<int>(j);
  std::vector<Eigen::Vector2d> feet;
  for (int b : skeleton.nodes[j].branches) {
    const auto& branch = skeleton.branches[b];
    if (branch.removed) continue;
    const SkeletonSamples samples = skeleton.samples_of(branch);
    const SkeletonSample& at = branch.from == J ? samples.front() : samples.back();
    for (const Eigen::Vector2d& f : {at.foot_a, at.foot_b}) {
      if (std::none_of(feet.begin(), feet.end(), [&](const Eigen::Vector2d& e) { return (e - f).norm() < 0.5; }))
        feet.push_back(f);
    }
  }
  return feet;
}

/// Splits junction `J` along the spokes from its centre to its `feet` (three or more): each
/// long arm owns the sector it leaves through (false when two share one: ambiguous, nothing
/// split); sectors without a long arm go with the nearest owned sector before them; every long
/// arm but the first gets a new region, and short arms follow their sector's owner. A junction
/// passage is added wherever neighbouring sectors differ.
inline bool split_junction(RoomDetection& out, int J, const JunctionArms& junction, const std::vector<Eigen::Vector2d>& feet) {
  const SampleGraph& g = out.graph;
  auto& region = out.region_of_sample;
  const int R = region[J];
  const Eigen::Vector2d centre = g.samples[J].position;
  const auto& arms = junction.arms;
  std::vector<double> spoke_angle;
  for (const auto& f : feet) spoke_angle.push_back(std::atan2(f.y() - centre.y(), f.x() - centre.x()));
  std::vector<int> order(feet.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return spoke_angle[a] < spoke_angle[b]; });
  // Sector k lies between spokes order[k] and order[k + 1] (counter-clockwise).
  auto sector_of = [&](double angle) {
    for (std::size_t k = 0; k < order.size(); ++k) {
      const double from = spoke_angle[order[k]], to = spoke_angle[order[(k + 1) % order.size()]];
      const double span = std::fmod(to - from + 4.0 * pi, 2.0 * pi);
      const double offset = std::fmod(angle - from + 4.0 * pi, 2.0 * pi);
      if (offset < span) return static_cast<int>(k);
    }
    return 0;
  };
  std::vector<int> owner(order.size(), -1);  // sector → long arm
  for (int a : junction.long_arms) {
    int& o = owner[sector_of(arms[a].angle)];
    if (o >= 0) return false;
    o = a;
  }
  for (std::size_t k = 0; k < owner.size(); ++k) {
    if (owner[k] >= 0) continue;
    for (std::size_t back = 1; back < owner.size(); ++back) {
      const int o = owner[(k + owner.size() - back) % owner.size()];
      if (o >= 0) {
        owner[k] = o;
        break;
      }
    }
  }
  std::vector<int> region_of_arm(arms.size(), R);
  for (std::size_t i = 1; i < junction.long_arms.size(); ++i) {
    region_of_arm[junction.long_arms[i]] = static_cast<int>(out.region_is_room.size());
    out.region_is_room.push_back(out.region_is_room[R]);
  }
  std::vector<int> new_region_of_part(arms.size(), R);
  for (std::size_t a = 0; a < arms.size(); ++a) {
    if (region[arms[a].first] != R || junction.part_of_arm(a) < 0) continue;
    new_region_of_part[junction.part_of_arm(a)] = region_of_arm[owner[sector_of(arms[a].angle)]];
  }
  for (std::size_t s = 0; s < g.samples.size(); ++s)
    if (junction.part_of_sample[s] >= 0) region[s] = new_region_of_part[junction.part_of_sample[s]];
  for (std::size_t k = 0; k < order.size(); ++k) {
    const int before = region_of_arm[owner[(k + order.size() - 1) % order.size()]], after = region_of_arm[owner[k]];
    if (before == after) continue;
    out.passages.push_back({J, std::min(before, after), std::max(before, after), true, centre, feet[order[k]]});
  }
  return true;
}

/// Splits regions at corridor junctions (see RoomParams::split_at_junctions). The junction's
/// largest free disc touches the walls at three or more feet; the spokes from the junction to
/// them cut the junction into sectors, and each sector goes to the long arm that leaves through
/// it (short arms — door stubs, spurs — go with their sector). Doors then keep the regions
/// actually on their two sides.
inline void split_at_junctions(RoomDetection& out, const Skeleton& skeleton, double resolution, const RoomParams& params) {
  const SampleGraph& g = out.graph;
  auto& region = out.region_of_sample;
  const double arm_length = params.junction_arm_length_m / resolution;
  for (std::size_t j = 0; j < skeleton.nodes.size(); ++j) {
    const int J = static_cast<int>(j);
    if (region[J] < 0 || g.neighbours(J).size() < 3) continue;
    const double needed = std::max(arm_length, params.junction_arm_clearances * g.samples[J].clearance);
    const JunctionArms junction = junction_arms(out, J, needed, params.junction_arm_elongation);
    if (junction.long_arms.empty()) continue;
    const std::vector<Eigen::Vector2d> feet = junction_feet(skeleton, j);
    if (feet.size() < 3) continue;
    split_junction(out, J, junction, feet);
  }
  for (auto& p : out.passages) {
    if (p.junction) continue;
    std::vector<int> sides{region[p.sample]};
    for (int n : g.neighbours(p.sample)) sides.push_back(region[n]);
    std::sort(sides.begin(), sides.end());
    sides.erase(std::unique(sides.begin(), sides.end()), sides.end());
    if (sides.size() == 2) p.region_a = sides[0], p.region_b = sides[1];
  }
}

}  // namespace detail

}  // namespace areamatch
