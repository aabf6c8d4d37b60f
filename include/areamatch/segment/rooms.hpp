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
#include "../detail/format.hpp"
#include "../error.hpp"
#include "../transform.hpp"
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

/// The clearance (metres) a skeleton point needs to lie in a room rather than in a doorway:
/// half the door width plus half a grid cell, because an opening of exactly W drawn on the grid
/// measures up to one cell more (quantisation and wall simplification). `detect_rooms` and the
/// skeleton's spur pruning (`SkeletonParams::keep_clearance_m`) both use it.
inline double room_clearance_m(double door_width_m, double resolution) { return 0.5 * door_width_m + 0.5 * resolution; }

/// Rooms are the connected wide parts (clearance ≥ `half_door`, cells) whose widest sample
/// reaches `half_door + margin`: each becomes a region, its samples labelled.
inline void mark_rooms(RoomDetection& out, double half_door, double margin) {
  const SampleGraph& g = out.graph;
  const std::size_t n = g.samples.size();
  int wide_count = 0;
  const auto wide = components(g, [&](int s) { return g.samples[s].clearance >= half_door; }, wide_count);
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
}

/// A connected part of the skeleton outside the rooms: its samples, its length (cells, with
/// the links into rooms), whether it branches, and where it touches which room.
struct NarrowPart {
  struct Attachment {
    int narrow_sample, room;
  };
  std::vector<int> members;
  std::vector<Attachment> attachments;  ///< sorted by sample, then room
  double length = 0.0;
  bool branching = false;
};

/// The narrow parts after `mark_rooms`; `part_of_sample` receives each sample's part (−1: in
/// a room, or a lone node). A node whose branches were all pruned (the free end of a spur) is a
/// skeleton part of one sample: it belongs to the region its spur led into
/// (`assign_lone_nodes`), not to a narrow part of its own.
inline std::vector<NarrowPart> narrow_parts(const RoomDetection& out, std::vector<int>& part_of_sample) {
  const SampleGraph& g = out.graph;
  auto is_room_sample = [&](int s) { return out.region_of_sample[s] >= 0; };
  auto lone = [&](int s) { return g.neighbours(s).size() == 0; };
  int count = 0;
  part_of_sample = components(g, [&](int s) { return !is_room_sample(s) && !lone(s); }, count);
  std::vector<NarrowPart> parts(static_cast<std::size_t>(count));
  for (std::size_t s = 0; s < g.samples.size(); ++s) {
    const int c = part_of_sample[s];
    if (c < 0) continue;
    NarrowPart& part = parts[static_cast<std::size_t>(c)];
    part.members.push_back(static_cast<int>(s));
    int narrow_neighbours = 0;
    for (int t : g.neighbours(s)) {
      if (part_of_sample[t] == c) {
        part.length += 0.5 * g.distance(static_cast<int>(s), t);  // each edge seen from both ends
        ++narrow_neighbours;
      } else if (is_room_sample(t)) {
        part.length += g.distance(static_cast<int>(s), t);
        part.attachments.push_back({static_cast<int>(s), out.region_of_sample[t]});
      }
    }
    if (narrow_neighbours >= 3) part.branching = true;
  }
  for (NarrowPart& part : parts) {
    std::sort(part.attachments.begin(), part.attachments.end(), [](const auto& a, const auto& b) {
      return a.narrow_sample < b.narrow_sample || (a.narrow_sample == b.narrow_sample && a.room < b.room);
    });
  }
  return parts;
}

/// Gives narrow part `c` its regions: a short dead end or loop of one room joins that room; a
/// short stretch between two rooms is a door, split at its narrowest sample; anything else (long,
/// branching, or opening into more rooms) is a corridor of its own with a door near every room
/// it opens into, within `door_search` (cells) of the room.
inline void assign_narrow_part(RoomDetection& out, const NarrowPart& part, int c, const std::vector<int>& part_of_sample,
                               double corridor_length, double door_search) {
  const SampleGraph& g = out.graph;
  // Walks from `start` through the part up to `limit` and returns the visited samples in order
  // (stops at a junction or the end of the part).
  auto walk = [&](int start, double limit) {
    std::vector<int> path{start};
    int previous = -1, current = start;
    double travelled = 0.0;
    while (travelled < limit) {
      int next = -1, options = 0;
      for (int t : g.neighbours(current))
        if (t != previous && part_of_sample[t] == c) ++options, next = t;
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
  const auto& atts = part.attachments;
  std::vector<int> rooms;
  for (const auto& a : atts) rooms.push_back(a.room);
  std::sort(rooms.begin(), rooms.end());
  rooms.erase(std::unique(rooms.begin(), rooms.end()), rooms.end());
  const bool long_or_branching = part.length >= corridor_length || part.branching;

  if (rooms.size() == 1 && !long_or_branching) {
    for (int s : part.members) out.region_of_sample[s] = rooms.front();  // dead end or loop of one room
    return;
  }
  if (rooms.size() == 2 && atts.size() == 2 && !long_or_branching) {
    // A door between two rooms: split the stretch at its narrowest sample.
    const std::vector<int> path = walk(atts[0].narrow_sample, 1e300);
    const int door = narrowest(path);
    bool before = true;
    for (int s : path) {
      out.region_of_sample[s] = before ? atts[0].room : atts[1].room;
      if (s == door) before = false;
    }
    for (int s : part.members)
      if (out.region_of_sample[s] < 0) out.region_of_sample[s] = atts[1].room;
    out.passages.push_back({door, atts[0].room, atts[1].room, false, g.samples[door].foot_a, g.samples[door].foot_b});
    return;
  }
  const int corridor = static_cast<int>(out.region_is_room.size());
  out.region_is_room.push_back(false);
  for (int s : part.members) out.region_of_sample[s] = corridor;
  for (const auto& a : atts) {
    const std::vector<int> path = walk(a.narrow_sample, door_search);
    const int door = narrowest(path);
    for (int s : path) {
      if (s == door) break;
      out.region_of_sample[s] = a.room;
    }
    out.passages.push_back({door, a.room, corridor, false, g.samples[door].foot_a, g.samples[door].foot_b});
  }
}

/// Lone nodes take the region of the nearest node (in branches) their pruned spurs lead to:
/// pruning always leaves one branch of every skeleton piece, so there is one.
inline void assign_lone_nodes(RoomDetection& out, const Skeleton& skeleton) {
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
}

inline void split_at_junctions(RoomDetection& out, const Skeleton& skeleton, double resolution, const RoomParams& params);

}  // namespace detail

/// Finds rooms, narrow corridors and the passages between them on `skeleton` (lattice units
/// inside; `resolution` converts the parameters' metres).
inline RoomDetection detect_rooms(const Skeleton& skeleton, double resolution, const RoomParams& params = {}) {
  params.validate();
  RoomDetection out;
  out.graph = SampleGraph::from(skeleton);
  // In cells, rounded to a micro-cell: clearances on the grid are often exact half cells, and
  // which side of the threshold they fall on must not depend on floating-point noise.
  const double half_door = std::round(detail::room_clearance_m(params.door_width_m, resolution) / resolution * 1e6) / 1e6;
  detail::mark_rooms(out, half_door, params.room_margin_m / resolution);
  std::vector<int> part_of_sample;
  const std::vector<detail::NarrowPart> parts = detail::narrow_parts(out, part_of_sample);
  for (std::size_t c = 0; c < parts.size(); ++c) {
    detail::assign_narrow_part(out, parts[c], static_cast<int>(c), part_of_sample,
                               params.narrow_corridor_length_m / resolution, params.door_search_m / resolution);
  }
  detail::assign_lone_nodes(out, skeleton);
  if (params.split_at_junctions) detail::split_at_junctions(out, skeleton, resolution, params);
  return out;
}

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
    const SkeletonSample& at = branch.from == J ? branch.samples.front() : branch.samples.back();
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
