#pragma once
/// \file segment/rooms.hpp
/// Stage 4 of segmentation: rooms and passages on the skeleton.
///
/// This is the Boost-only equivalent of the paper's α-shape with α tied to the door width W
/// (ALGORITHM.md §1.5): a skeleton sample with clearance < W/2 is *narrow*, otherwise *wide*.
/// - Connected wide parts whose clearance somewhere reaches W/2 + `room_margin_m` are room
///   candidates (the margin ignores parts that are barely wider than a door).
/// - A narrow stretch that joins two different rooms is a door: one passage at its clearance
///   minimum — where the opening really is, with its width and the line across it.
/// - Narrow parts that lead nowhere (dead ends, loops around furniture back into the same room)
///   belong to the room they hang from.
/// - Narrow parts that are long (a corridor narrower than W) or branch become areas of their own,
///   with a passage at the narrowest point near each room they open into.
///
/// Everything is in pixel-corner lattice units; parameters are in metres.

#include "../error.hpp"
#include "skeleton.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace areamatch {

/// Parameters of `detect_rooms`. Lengths in metres.
struct RoomParams {
  /// The widest opening that still separates two areas (the paper's segmentation width).
  double door_width_m = 1.25;
  /// A wide part is a room only if its clearance exceeds W/2 by this much somewhere.
  double room_margin_m = 0.05;
  /// Narrow parts longer than this (or branching) are areas of their own (narrow corridors).
  double narrow_corridor_length_m = 3.0;
  /// How far into a narrow corridor the passage to a room is looked for.
  double door_search_m = 1.5;

  void validate() const {
    if (!(std::isfinite(door_width_m) && door_width_m > 0.0)) {
      throw parameter_error("door width must be a positive number of metres, got " + std::to_string(door_width_m));
    }
    for (double v : {room_margin_m, narrow_corridor_length_m, door_search_m}) {
      if (!(std::isfinite(v) && v >= 0.0)) throw parameter_error("RoomParams: lengths must be >= 0");
    }
  }
};

/// The skeleton flattened to a graph of samples: node samples first (index = node id), then the
/// inner samples of every kept branch.
struct SampleGraph {
  std::vector<SkeletonSample> samples;
  std::vector<std::vector<int>> neighbours;

  static SampleGraph from(const Skeleton& skeleton) {
    SampleGraph g;
    for (const auto& node : skeleton.nodes) g.samples.push_back(node.sample);
    g.neighbours.resize(g.samples.size());
    auto link = [&g](int a, int b) {
      g.neighbours[a].push_back(b);
      g.neighbours[b].push_back(a);
    };
    for (const auto& branch : skeleton.branches) {
      if (branch.removed) continue;
      int previous = branch.from;
      for (std::size_t i = 1; i + 1 < branch.samples.size(); ++i) {
        const int id = static_cast<int>(g.samples.size());
        g.samples.push_back(branch.samples[i]);
        g.neighbours.emplace_back();
        link(previous, id);
        previous = id;
      }
      link(previous, branch.to);
    }
    return g;
  }
  double distance(int a, int b) const { return (samples[a].position - samples[b].position).norm(); }
};

/// A door found on the skeleton: the sample at the clearance minimum and the two regions.
struct DetectedPassage {
  int sample = -1;
  int region_a = -1;
  int region_b = -1;
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
      for (int v : g.neighbours[u])
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

/// Finds rooms, narrow corridors and the passages between them on `skeleton`.
inline RoomDetection detect_rooms(const Skeleton& skeleton, double resolution, const RoomParams& params = {}) {
  params.validate();
  RoomDetection out;
  out.graph = SampleGraph::from(skeleton);
  const SampleGraph& g = out.graph;
  const std::size_t n = g.samples.size();
  const double half_door = 0.5 * params.door_width_m / resolution;
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

  int narrow_count = 0;
  const auto narrow = detail::components(g, [&](int s) { return !is_room_sample(s); }, narrow_count);
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
    for (int t : g.neighbours[s]) {
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
      for (int t : g.neighbours[current])
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
      out.passages.push_back({door, atts[0].room, atts[1].room});
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
      out.passages.push_back({door, a.room, corridor});
    }
  }
  return out;
}

}  // namespace areamatch
