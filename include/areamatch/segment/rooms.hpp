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
#include "junctions.hpp"
#include "room_detection.hpp"
#include "skeleton.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

namespace areamatch {

namespace detail {

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

/// Rooms, corridors and passages on `graph`, the sample graph of `skeleton` (which may have
/// given the graph its samples, unless `params.split_at_junctions`: that reads them).
inline RoomDetection detect_rooms_on(SampleGraph graph, const Skeleton& skeleton, double resolution, const RoomParams& params) {
  RoomDetection out;
  out.graph = std::move(graph);
  // In cells, rounded to a micro-cell: clearances on the grid are often exact half cells, and
  // which side of the threshold they fall on must not depend on floating-point noise.
  const double half_door = std::round(room_clearance_m(params.door_width_m, resolution) / resolution * 1e6) / 1e6;
  mark_rooms(out, half_door, params.room_margin_m / resolution);
  std::vector<int> part_of_sample;
  const std::vector<NarrowPart> parts = narrow_parts(out, part_of_sample);
  for (std::size_t c = 0; c < parts.size(); ++c) {
    assign_narrow_part(out, parts[c], static_cast<int>(c), part_of_sample, params.narrow_corridor_length_m / resolution,
                       params.door_search_m / resolution);
  }
  assign_lone_nodes(out, skeleton);
  if (params.split_at_junctions) split_at_junctions(out, skeleton, resolution, params);
  return out;
}

/// `detect_rooms` that takes the skeleton's samples over instead of copying them
/// (`SampleGraph::taking_samples`), for a caller that lets the skeleton go next, as
/// `VoronoiSegmenter::segment` does. The same result. Splitting at junctions reads the
/// branches' end samples, so with it they are copied.
inline RoomDetection detect_rooms_taking_samples(Skeleton& skeleton, double resolution, const RoomParams& params = {}) {
  params.validate();
  SampleGraph graph = params.split_at_junctions ? SampleGraph::from(skeleton) : SampleGraph::taking_samples(skeleton);
  return detect_rooms_on(std::move(graph), skeleton, resolution, params);
}

}  // namespace detail

/// Finds rooms, narrow corridors and the passages between them on `skeleton` (lattice units
/// inside; `resolution` converts the parameters' metres).
inline RoomDetection detect_rooms(const Skeleton& skeleton, double resolution, const RoomParams& params = {}) {
  params.validate();
  return detail::detect_rooms_on(SampleGraph::from(skeleton), skeleton, resolution, params);
}
}  // namespace areamatch
