#pragma once
/// \file segment/room_detection.hpp
/// What `detect_rooms` (segment/rooms.hpp) is asked for and finds: the skeleton as a sample graph,
/// each sample's region, and the passages (doors, junction spokes) between regions.

#include "../detail/adjacency.hpp"
#include "../detail/format.hpp"
#include "../error.hpp"
#include "skeleton.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
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

/// The samples of a `SampleGraph` by id: node samples first (id = node id), then the inner
/// samples of every kept branch in branch order. Copies in one array, or (from a skeleton that is
/// let go next) the skeleton's own array taken over, with where each inner sample lies in it: on
/// a large floor the samples are tens of megabytes, and a copy beside the skeleton's was the
/// segmentation's peak.
class SampleStore {
 public:
  const SkeletonSample& operator[](std::size_t s) const {
    if (s < leading_.size()) return leading_[s];
    return taken_[inner_at_[s - leading_.size()]];
  }
  std::size_t size() const { return leading_.size() + inner_at_.size(); }
  bool empty() const { return size() == 0; }

 private:
  friend struct SampleGraph;
  std::vector<SkeletonSample> leading_;     ///< every sample (copies), or only the nodes' (taken)
  std::vector<SkeletonSample> taken_;       ///< the skeleton's array (taken); empty with copies
  std::vector<std::uint32_t> inner_at_;     ///< per inner sample, its place in `taken_`
};

/// The skeleton flattened to a graph of samples: node samples first (index = node id), then the
/// inner samples of every kept branch. Adjacency is stored compactly (one list for all samples,
/// each sample's neighbours in the order their links were made): a furnished map has ~10^5
/// samples, and a vector per sample cost more than the rest of room detection.
struct SampleGraph {
  SampleStore samples;

  /// A sample's neighbours, as a range of sample ids.
  using Neighbours = detail::ConstSpan<int>;
  Neighbours neighbours(int s) const {
    const auto node = static_cast<std::size_t>(s);
    return {adjacency.begin(node), adjacency.end(node)};
  }

  /// The graph of `skeleton`'s samples, copied (sized exactly: a large floor has millions of
  /// samples, and growing by doubling held up to three copies at once).
  static SampleGraph from(const Skeleton& skeleton) {
    SampleGraph g;
    std::vector<SkeletonSample>& all = g.samples.leading_;
    all.reserve(skeleton.nodes.size() + inner_sample_count(skeleton));
    for (const auto& node : skeleton.nodes) all.push_back(node.sample);
    for (const auto& branch : skeleton.branches) {
      if (branch.removed || branch.sample_count <= 2) continue;
      const SkeletonSamples samples = skeleton.samples_of(branch);
      all.insert(all.end(), samples.begin() + 1, samples.end() - 1);
    }
    g.link(skeleton);
    return g;
  }

  /// The same graph, with the same ids and samples, taking `skeleton.samples` over instead of
  /// copying them: the skeleton has no samples afterwards (its nodes, node samples and branches
  /// stay, each branch with none).
  static SampleGraph taking_samples(Skeleton& skeleton) {
    if (skeleton.samples.size() >= std::numeric_limits<std::uint32_t>::max()) return from(skeleton);
    SampleGraph g;
    g.samples.leading_.reserve(skeleton.nodes.size());
    for (const auto& node : skeleton.nodes) g.samples.leading_.push_back(node.sample);
    g.samples.inner_at_.reserve(inner_sample_count(skeleton));
    for (const auto& branch : skeleton.branches) {
      if (branch.removed) continue;
      for (std::size_t i = 1; i + 1 < branch.sample_count; ++i)
        g.samples.inner_at_.push_back(static_cast<std::uint32_t>(branch.first_sample + i));
    }
    g.link(skeleton);
    g.samples.taken_ = std::move(skeleton.samples);
    skeleton.samples = {};
    for (auto& branch : skeleton.branches) branch.first_sample = branch.sample_count = 0;  // nothing left to point into
    return g;
  }

  double distance(int a, int b) const { return (samples[a].position - samples[b].position).norm(); }

 private:
  detail::AdjacencyLists<int> adjacency;  ///< neighbours of each sample, by sample id

  static std::size_t inner_sample_count(const Skeleton& skeleton) {
    std::size_t inner = 0;
    for (const auto& branch : skeleton.branches) {
      if (!branch.removed && branch.sample_count > 2) inner += branch.sample_count - 2;
    }
    return inner;
  }

  /// Links in order: (node or inner sample, next inner sample or node) along every kept branch,
  /// inner samples numbered from the node count on, branch after branch.
  void link(const Skeleton& skeleton) {
    std::size_t link_count = 0;
    for (const auto& branch : skeleton.branches) {
      if (!branch.removed) link_count += branch.sample_count > 2 ? branch.sample_count - 1 : 1;
    }
    std::vector<std::pair<int, int>> links;
    links.reserve(link_count);
    int next_id = static_cast<int>(skeleton.nodes.size());
    for (const auto& branch : skeleton.branches) {
      if (branch.removed) continue;
      int previous = branch.from;
      for (std::size_t i = 1; i + 1 < branch.sample_count; ++i) {
        links.emplace_back(previous, next_id);
        previous = next_id++;
      }
      links.emplace_back(previous, branch.to);
    }
    adjacency = detail::build_adjacency<int>(static_cast<std::size_t>(next_id), links.size(), [&](std::size_t k) {
      const auto [a, b] = links[k];
      return detail::LinkEnds<int>{static_cast<std::size_t>(a), b, static_cast<std::size_t>(b), a};
    });
  }
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
