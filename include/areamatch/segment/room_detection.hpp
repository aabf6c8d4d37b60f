#pragma once
/// \file segment/room_detection.hpp
/// What `detect_rooms` (segment/rooms.hpp) is asked for and finds: the skeleton as a sample graph,
/// each sample's region, and the passages (doors, junction spokes) between regions.

#include "../detail/adjacency.hpp"
#include "../detail/format.hpp"
#include "../error.hpp"
#include "skeleton.hpp"

#include <algorithm>
#include <string>
#include <vector>

namespace areamatch {

/// Parameters of `detect_rooms`. Lengths in metres.
struct RoomParams {
  /// The widest opening that still separates two areas (the paper's segmentation width). An
  /// opening measured up to one grid cell wider still counts, so a door of exactly W does.
  double door_width_m = 1.2;
  /// The door width's upper bound: an opening wider than this is no door or junction but a hall,
  /// and a door width this large joins whole floors into one area (a typo, not a setting).
  static constexpr double max_door_width_m = 20.0;
  /// A wide part is a room only if its clearance exceeds W/2 by this much somewhere.
  double room_margin_m = 0.05;
  /// Narrow parts longer than this (or branching) are areas of their own (narrow corridors).
  double narrow_corridor_length_m = 3.0;
  /// How far into a narrow corridor the passage to a room is looked for.
  double door_search_m = 1.5;
  /// Split areas where three or more corridors meet, as the paper's Area Graph does: a skeleton
  /// junction with at least three arms, each leading into a corridor-shaped part longer than
  /// `junction_arm_length_m` and `junction_arm_clearances` times the junction's clearance, and
  /// `junction_arm_elongation` times its own width (so a room's bulge is no arm). Off by default:
  /// it lowered cross-modal consistency on the shared maps (docs/segmentation.md).
  bool split_at_junctions = false;
  double junction_arm_length_m = 2.0;
  double junction_arm_clearances = 2.5;
  double junction_arm_elongation = 5.0;

  void validate() const {
    if (!(std::isfinite(door_width_m) && door_width_m > 0.0 && door_width_m <= max_door_width_m)) {
      throw parameter_error("door width must be a positive number of metres up to " + detail::format_fixed(max_door_width_m, 0) +
                            " (a door or junction, not a hall), got " + detail::format_double(door_width_m));
    }
    detail::require_non_negative(room_margin_m, "RoomParams::room_margin_m");
    detail::require_non_negative(narrow_corridor_length_m, "RoomParams::narrow_corridor_length_m");
    detail::require_non_negative(door_search_m, "RoomParams::door_search_m");
    detail::require_non_negative(junction_arm_length_m, "RoomParams::junction_arm_length_m");
    detail::require_non_negative(junction_arm_clearances, "RoomParams::junction_arm_clearances");
    detail::require_non_negative(junction_arm_elongation, "RoomParams::junction_arm_elongation");
  }
};

/// The skeleton flattened to a graph of samples: node samples first (index = node id), then the
/// inner samples of every kept branch. Adjacency is stored compactly (one list for all samples,
/// each sample's neighbours in the order their links were made): a furnished map has ~10^5
/// samples, and a vector per sample cost more than the rest of room detection.
struct SampleGraph {
  std::vector<SkeletonSample> samples;

  /// A sample's neighbours, as a range of sample ids.
  struct Neighbours {
    const int* first;
    const int* last;
    const int* begin() const { return first; }
    const int* end() const { return last; }
    std::size_t size() const { return static_cast<std::size_t>(last - first); }
  };
  Neighbours neighbours(int s) const {
    const auto node = static_cast<std::size_t>(s);
    return {adjacency.begin(node), adjacency.end(node)};
  }

  static SampleGraph from(const Skeleton& skeleton) {
    SampleGraph g;
    // Sized exactly: a large floor has millions of samples, and growing by doubling held up to
    // three copies at once.
    std::size_t inner = 0, link_count = 0;
    for (const auto& branch : skeleton.branches) {
      if (branch.removed) continue;
      inner += branch.samples.size() > 2 ? branch.samples.size() - 2 : 0;
      link_count += branch.samples.size() > 2 ? branch.samples.size() - 1 : 1;
    }
    g.samples.reserve(skeleton.nodes.size() + inner);
    for (const auto& node : skeleton.nodes) g.samples.push_back(node.sample);
    // Links in order: (node or inner sample, next inner sample or node) along every kept branch.
    std::vector<std::pair<int, int>> links;
    links.reserve(link_count);
    for (const auto& branch : skeleton.branches) {
      if (branch.removed) continue;
      int previous = branch.from;
      for (std::size_t i = 1; i + 1 < branch.samples.size(); ++i) {
        const int id = static_cast<int>(g.samples.size());
        g.samples.push_back(branch.samples[i]);
        links.emplace_back(previous, id);
        previous = id;
      }
      links.emplace_back(previous, branch.to);
    }
    g.adjacency = detail::build_adjacency<int>(g.samples.size(), links.size(), [&](std::size_t k) {
      const auto [a, b] = links[k];
      return detail::LinkEnds<int>{static_cast<std::size_t>(a), b, static_cast<std::size_t>(b), a};
    });
    return g;
  }
  double distance(int a, int b) const { return (samples[a].position - samples[b].position).norm(); }

 private:
  detail::AdjacencyLists<int> adjacency;  ///< neighbours of each sample, by sample id
};

/// A passage found on the skeleton: a door (at the clearance minimum of a narrow stretch) or one
/// spoke of a corridor junction, with the two regions it separates and the barrier line that
/// separates them (lattice units: wall to wall for a door, junction to wall for a spoke).
struct DetectedPassage {
  int sample = -1;
  int region_a = -1;
  int region_b = -1;
  bool junction = false;
  Eigen::Vector2d line_a = Eigen::Vector2d::Zero();
  Eigen::Vector2d line_b = Eigen::Vector2d::Zero();
};

/// Regions of the skeleton (rooms and narrow corridors) and the passages between them.
struct RoomDetection {
  SampleGraph graph;
  std::vector<int> region_of_sample;  ///< −1 for samples in no region (none at present)
  std::vector<bool> region_is_room;   ///< wide region (true) or narrow corridor (false)
  std::vector<DetectedPassage> passages;
  int region_count() const { return static_cast<int>(region_is_room.size()); }
};

namespace detail {

/// Connected components of the samples for which `member` holds; −1 for the others.
template <class Member>
std::vector<int> components(const SampleGraph& g, Member&& member, int& count) {
  std::vector<int> comp(g.samples.size(), -1);
  count = 0;
  std::vector<int> stack;
  for (std::size_t s = 0; s < g.samples.size(); ++s) {
    if (comp[s] >= 0 || !member(static_cast<int>(s))) continue;
    comp[s] = count;
    stack.assign(1, static_cast<int>(s));
    while (!stack.empty()) {
      const int u = stack.back();
      stack.pop_back();
      for (int v : g.neighbours(u))
        if (comp[v] < 0 && member(v)) {
          comp[v] = count;
          stack.push_back(v);
        }
    }
    ++count;
  }
  return comp;
}

}  // namespace detail

}  // namespace areamatch
