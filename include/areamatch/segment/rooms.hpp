#pragma once
/// \file segment/rooms.hpp
/// Stage 4 of segmentation: rooms and passages on the skeleton.
///
/// This is the Boost-only equivalent of the paper's α-shape with α tied to the door width W
/// (docs/algorithm.md): a skeleton sample with clearance < W/2 is *narrow*, otherwise *wide*.
/// - Connected wide parts whose clearance somewhere reaches W/2 + `room_margin_m` are room
///   candidates (the margin ignores parts that are barely wider than a door).
/// - A narrow stretch that joins two different rooms is a door: one passage at its clearance
///   minimum — where the opening really is, with its width and the line across it.
/// - Narrow parts that lead nowhere (dead ends, loops around furniture back into the same room)
///   belong to the room they hang from; so does the free end of a pruned spur (a lone node),
///   which would otherwise seed a sliver area of its own.
/// - Narrow parts that are long (a corridor narrower than W) or branch become areas of their own,
///   with a passage at the narrowest point near each room they open into.
///
/// Everything is in pixel-corner lattice units; parameters are in metres.

#include "../detail/adjacency.hpp"
#include "../error.hpp"
#include "skeleton.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

namespace areamatch {

/// Parameters of `detect_rooms`. Lengths in metres.
struct RoomParams {
  /// The widest opening that still separates two areas (the paper's segmentation width). An
  /// opening measured up to one grid cell wider still counts, so a door of exactly W does.
  double door_width_m = 1.2;
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
    if (!(std::isfinite(door_width_m) && door_width_m > 0.0)) {
      throw parameter_error("door width must be a positive number of metres, got " + std::to_string(door_width_m));
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
    g.samples.reserve(skeleton.nodes.size());
    for (const auto& node : skeleton.nodes) g.samples.push_back(node.sample);
    // Links in order: (node or inner sample, next inner sample or node) along every kept branch.
    std::vector<std::pair<int, int>> links;
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

namespace detail {

/// The clearance (metres) a skeleton point needs to lie in a room rather than in a doorway:
/// half the door width plus half a grid cell, because an opening of exactly W drawn on the grid
/// measures up to one cell more (quantisation and wall simplification). `detect_rooms` and the
/// skeleton's spur pruning (`SkeletonParams::keep_clearance_m`) both use it.
inline double room_clearance_m(double door_width_m, double resolution) { return 0.5 * door_width_m + 0.5 * resolution; }

}  // namespace detail

/// Finds rooms, narrow corridors and the passages between them on `skeleton`.
namespace detail {
inline void split_at_junctions(RoomDetection& out, const Skeleton& skeleton, double resolution, const RoomParams& params);
}  // namespace detail

inline RoomDetection detect_rooms(const Skeleton& skeleton, double resolution, const RoomParams& params = {}) {
  params.validate();
  RoomDetection out;
  out.graph = SampleGraph::from(skeleton);
  const SampleGraph& g = out.graph;
  const std::size_t n = g.samples.size();
  // In cells, rounded to a micro-cell: clearances on the grid are often exact half cells, and
  // which side of the threshold they fall on must not depend on floating-point noise.
  const double half_door = std::round(detail::room_clearance_m(params.door_width_m, resolution) / resolution * 1e6) / 1e6;
  const double margin = params.room_margin_m / resolution;
  const double corridor_length = params.narrow_corridor_length_m / resolution;
  const double search = params.door_search_m / resolution;

  // Wide parts that reach W/2 + margin are rooms; everything else is narrow.
  int wide_count = 0;
  const auto wide = detail::components(g, [&](int s) { return g.samples[s].clearance >= half_door; }, wide_count);
  std::vector<double> widest(wide_count, 0.0);
  for (std::size_t s = 0; s < n; ++s)
    if (wide[s] >= 0) widest[wide[s]] = std::max(widest[wide[s]], g.samples[s].clearance);
  std::vector<int> room_of_wide(wide_count, -1);
  for (int c = 0; c < wide_count; ++c) {
    if (widest[c] >= half_door + margin) {
      room_of_wide[c] = static_cast<int>(out.region_is_room.size());
      out.region_is_room.push_back(true);
    }
  }
  out.region_of_sample.assign(n, -1);
  for (std::size_t s = 0; s < n; ++s)
    if (wide[s] >= 0) out.region_of_sample[s] = room_of_wide[wide[s]];
  auto is_room_sample = [&](int s) { return out.region_of_sample[s] >= 0; };

  // A node whose branches were all pruned (the free end of a spur) is a skeleton part of one
  // sample: it belongs to the region its spur led into (below), not to a narrow part of its own.
  auto lone = [&](int s) { return g.neighbours(s).size() == 0; };
  int narrow_count = 0;
  const auto narrow = detail::components(g, [&](int s) { return !is_room_sample(s) && !lone(s); }, narrow_count);
  // Per narrow part: its samples, length, junctions and where it touches rooms.
  struct Attachment {
    int narrow_sample, room;
  };
  std::vector<std::vector<int>> members(narrow_count);
  std::vector<std::vector<Attachment>> attachments(narrow_count);
  std::vector<double> length(narrow_count, 0.0);
  std::vector<bool> branching(narrow_count, false);
  for (std::size_t s = 0; s < n; ++s) {
    const int c = narrow[s];
    if (c < 0) continue;
    members[c].push_back(static_cast<int>(s));
    int narrow_neighbours = 0;
    for (int t : g.neighbours(s)) {
      if (narrow[t] == c) {
        length[c] += 0.5 * g.distance(static_cast<int>(s), t);  // each edge seen from both ends
        ++narrow_neighbours;
      } else if (is_room_sample(t)) {
        length[c] += g.distance(static_cast<int>(s), t);
        attachments[c].push_back({static_cast<int>(s), out.region_of_sample[t]});
      }
    }
    if (narrow_neighbours + 0 >= 3) branching[c] = true;
  }

  // Walks from `start` through part `c` away from `previous`, up to `limit`, and returns the
  // visited samples in order (stops at a junction or the end of the part).
  auto walk = [&](int start, int c, double limit) {
    std::vector<int> path{start};
    int previous = -1, current = start;
    double travelled = 0.0;
    while (travelled < limit) {
      int next = -1, options = 0;
      for (int t : g.neighbours(current))
        if (t != previous && narrow[t] == c) ++options, next = t;
      if (options != 1) break;
      travelled += g.distance(current, next);
      previous = current;
      current = next;
      path.push_back(current);
    }
    return path;
  };
  auto narrowest = [&](const std::vector<int>& path) {
    return *std::min_element(path.begin(), path.end(), [&](int a, int b) {
      return g.samples[a].clearance < g.samples[b].clearance || (g.samples[a].clearance == g.samples[b].clearance && a < b);
    });
  };

  for (int c = 0; c < narrow_count; ++c) {
    auto& atts = attachments[c];
    std::sort(atts.begin(), atts.end(), [](const Attachment& a, const Attachment& b) {
      return a.narrow_sample < b.narrow_sample || (a.narrow_sample == b.narrow_sample && a.room < b.room);
    });
    std::vector<int> rooms;
    for (const auto& a : atts) rooms.push_back(a.room);
    std::sort(rooms.begin(), rooms.end());
    rooms.erase(std::unique(rooms.begin(), rooms.end()), rooms.end());
    const bool long_or_branching = length[c] >= corridor_length || branching[c];

    if (!rooms.empty() && rooms.size() == 1 && !long_or_branching) {
      for (int s : members[c]) out.region_of_sample[s] = rooms.front();  // dead end or loop of one room
      continue;
    }
    if (rooms.size() == 2 && atts.size() == 2 && !long_or_branching) {
      // A door between two rooms: split the stretch at its narrowest sample.
      const std::vector<int> path = walk(atts[0].narrow_sample, c, 1e300);
      const int door = narrowest(path);
      bool before = true;
      for (int s : path) {
        out.region_of_sample[s] = before ? atts[0].room : atts[1].room;
        if (s == door) before = false;
      }
      for (int s : members[c])
        if (out.region_of_sample[s] < 0) out.region_of_sample[s] = atts[1].room;
      out.passages.push_back({door, atts[0].room, atts[1].room, false, g.samples[door].foot_a, g.samples[door].foot_b});
      continue;
    }
    // A narrow corridor of its own, with a door near every room it opens into.
    const int corridor = static_cast<int>(out.region_is_room.size());
    out.region_is_room.push_back(false);
    for (int s : members[c]) out.region_of_sample[s] = corridor;
    for (const auto& a : atts) {
      const std::vector<int> path = walk(a.narrow_sample, c, search);
      const int door = narrowest(path);
      for (int s : path) {
        if (s == door) break;
        out.region_of_sample[s] = a.room;
      }
      out.passages.push_back({door, a.room, corridor, false, g.samples[door].foot_a, g.samples[door].foot_b});
    }
  }
  // Lone nodes take the region of the nearest node (in branches) their pruned spurs lead to:
  // pruning always leaves one branch of every skeleton piece, so there is one.
  for (std::size_t j = 0; j < skeleton.nodes.size(); ++j) {
    if (out.region_of_sample[j] >= 0) continue;
    std::vector<int> queue{static_cast<int>(j)};
    for (std::size_t head = 0; head < queue.size() && out.region_of_sample[j] < 0; ++head) {
      for (int b : skeleton.nodes[queue[head]].branches) {
        const auto& branch = skeleton.branches[b];
        const int other = branch.from == queue[head] ? branch.to : branch.from;
        if (std::find(queue.begin(), queue.end(), other) != queue.end()) continue;
        if (out.region_of_sample[other] >= 0) {
          out.region_of_sample[j] = out.region_of_sample[other];
          break;
        }
        queue.push_back(other);
      }
    }
  }
  if (params.split_at_junctions) detail::split_at_junctions(out, skeleton, resolution, params);
  return out;
}

namespace detail {

/// Splits regions at corridor junctions (see RoomParams::split_at_junctions). The junction's
/// largest free disc touches the walls at three or more feet; the spokes from the junction to
/// them cut the junction into sectors, and each sector goes to the long arm that leaves through
/// it (short arms — door stubs, spurs — go with their sector).
inline void split_at_junctions(RoomDetection& out, const Skeleton& skeleton, double resolution, const RoomParams& params) {
  const SampleGraph& g = out.graph;
  auto& region = out.region_of_sample;
  const double arm_length = params.junction_arm_length_m / resolution;
  struct Arm {
    int first = -1;
    double angle = 0.0;
  };
  for (std::size_t j = 0; j < skeleton.nodes.size(); ++j) {
    const int J = static_cast<int>(j);
    const int R = region[J];
    if (R < 0 || g.neighbours(J).size() < 3) continue;
    const Eigen::Vector2d centre = g.samples[J].position;
    const double r_junction = g.samples[J].clearance;
    std::vector<Arm> arms;
    for (int first : g.neighbours(J)) {
      const Eigen::Vector2d d = g.samples[first].position - centre;
      arms.push_back({first, std::atan2(d.y(), d.x())});
    }
    // What each arm leads into once the junction is removed: a part of the region. An arm is
    // long when that part is long (skeleton length) and corridor-shaped (length ≥ 5× its widest
    // clearance); arms whose parts are joined elsewhere (a loop) cannot be split here.
    std::vector<int> component(g.samples.size(), -1);
    auto flood = [&](int start, int label) {
      std::vector<int> stack{start};
      component[start] = label;
      while (!stack.empty()) {
        const int u = stack.back();
        stack.pop_back();
        for (int v : g.neighbours(u))
          if (v != J && component[v] < 0 && region[v] == R) component[v] = label, stack.push_back(v);
      }
    };
    std::vector<double> part_length(arms.size(), 0.0), part_width(arms.size(), 0.0);
    for (std::size_t a = 0; a < arms.size(); ++a)
      if (region[arms[a].first] == R && component[arms[a].first] < 0) flood(arms[a].first, static_cast<int>(a));
    for (std::size_t s = 0; s < g.samples.size(); ++s) {
      const int c = component[s];
      if (c < 0) continue;
      part_width[c] = std::max(part_width[c], g.samples[s].clearance);
      for (int t : g.neighbours(s))
        if (component[t] == c) part_length[c] += 0.5 * g.distance(static_cast<int>(s), t);
    }
    const double needed = std::max(arm_length, params.junction_arm_clearances * r_junction);
    std::vector<int> long_arms;
    std::vector<bool> part_taken(arms.size(), false);
    bool shared_part = false;
    for (std::size_t a = 0; a < arms.size(); ++a) {
      const int c = component[arms[a].first];
      if (c < 0 || part_length[c] < needed || part_length[c] < params.junction_arm_elongation * part_width[c]) continue;
      if (part_taken[c]) shared_part = true;
      part_taken[c] = true;
      long_arms.push_back(static_cast<int>(a));
    }
    if (shared_part || long_arms.size() < 3) continue;

    // The feet of the junction's largest disc, from the skeleton branches that end at it.
    std::vector<Eigen::Vector2d> feet;
    for (int b : skeleton.nodes[j].branches) {
      const auto& branch = skeleton.branches[b];
      if (branch.removed) continue;
      const SkeletonSample& at = branch.from == J ? branch.samples.front() : branch.samples.back();
      for (const Eigen::Vector2d& f : {at.foot_a, at.foot_b}) {
        if (std::none_of(feet.begin(), feet.end(), [&](const Eigen::Vector2d& e) { return (e - f).norm() < 0.5; }))
          feet.push_back(f);
      }
    }
    if (feet.size() < 3) continue;
    std::vector<double> spoke_angle;
    for (const auto& f : feet) spoke_angle.push_back(std::atan2(f.y() - centre.y(), f.x() - centre.x()));
    std::vector<int> order(feet.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return spoke_angle[a] < spoke_angle[b]; });
    // Sector k lies between spokes order[k] and order[k + 1] (counter-clockwise).
    auto sector_of = [&](double angle) {
      for (std::size_t k = 0; k < order.size(); ++k) {
        const double from = spoke_angle[order[k]], to = spoke_angle[order[(k + 1) % order.size()]];
        const double span = std::fmod(to - from + 4.0 * 3.14159265358979323846, 2.0 * 3.14159265358979323846);
        const double offset = std::fmod(angle - from + 4.0 * 3.14159265358979323846, 2.0 * 3.14159265358979323846);
        if (offset < span) return static_cast<int>(k);
      }
      return 0;
    };
    std::vector<int> owner(order.size(), -1);  // sector → long arm
    bool ambiguous = false;
    for (int a : long_arms) {
      int& o = owner[sector_of(arms[a].angle)];
      if (o >= 0) ambiguous = true;
      o = a;
    }
    if (ambiguous) continue;
    // Sectors without a long arm go with the nearest owned sector before them.
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
    // New regions for every long arm but the first; short arms follow their sector's owner.
    std::vector<int> region_of_arm(arms.size(), R);
    for (std::size_t i = 1; i < long_arms.size(); ++i) {
      region_of_arm[long_arms[i]] = static_cast<int>(out.region_is_room.size());
      out.region_is_room.push_back(out.region_is_room[R]);
    }
    std::vector<int> new_region_of_component(arms.size(), R);
    for (std::size_t a = 0; a < arms.size(); ++a) {
      if (region[arms[a].first] != R || component[arms[a].first] < 0) continue;
      new_region_of_component[component[arms[a].first]] = region_of_arm[owner[sector_of(arms[a].angle)]];
    }
    for (std::size_t s = 0; s < g.samples.size(); ++s)
      if (component[s] >= 0) region[s] = new_region_of_component[component[s]];
    for (std::size_t k = 0; k < order.size(); ++k) {
      const int before = region_of_arm[owner[(k + order.size() - 1) % order.size()]], after = region_of_arm[owner[k]];
      if (before == after) continue;
      out.passages.push_back({J, std::min(before, after), std::max(before, after), true, centre, feet[order[k]]});
    }
  }
  // Doors keep the regions actually on their two sides.
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
