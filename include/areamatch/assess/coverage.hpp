#pragma once
/// \file assess/coverage.hpp
/// Coverage and topology of a map against a reference, through the warp that lays the map on it
/// (Schwertfeger & Birk, "Map evaluation using matched topology graphs", Autonomous Robots 2016:
/// coverage and the consistency of matched places).
///
/// Coverage: the share of the reference's rooms and corridors (its areas' free space) that the
/// map shows free — each reference area found, partly found or missed; the map's areas that land
/// off the reference's free space (rooms the reference lacks); the reference's passages between
/// found areas with no passage of the map near them. Topology: of the map's passages joining
/// two areas with different counterparts in the reference, how many join those two there too
/// (and the same from the reference's side): a map that is locally right but wrongly connected
/// (a corridor closed by a bad loop closure, a door drawn through a wall) fails here.

#include "../area_graph.hpp"
#include "../grid.hpp"
#include "../match/raster.hpp"
#include "../match/result.hpp"
#include "../warp/field.hpp"
#include "params.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <set>
#include <utility>
#include <vector>

namespace areamatch {

enum class AreaFound { found, partly_found, missed };

inline const char* to_string(AreaFound f) {
  return f == AreaFound::found ? "found" : f == AreaFound::partly_found ? "partly_found" : "missed";
}

/// How much of one reference area the map explored.
struct ReferenceAreaCoverage {
  int area = -1;                 ///< reference area id
  double explored_share = 0.0;   ///< of its free space, the share the map shows free
  AreaFound state = AreaFound::missed;
  std::vector<int> map_areas;    ///< the map's areas whose counterpart it is (the match's), ascending
};

struct Coverage {
  double reference_m2 = 0.0;     ///< the reference's area-covered free space
  double explored_m2 = 0.0;      ///< of it, what the map shows free
  double explored_share = 0.0;   ///< explored_m2 / reference_m2
  std::vector<ReferenceAreaCoverage> reference_areas;  ///< in reference-area order
  std::size_t found = 0, partly_found = 0, missed = 0;
  /// The map's areas that land mostly off the reference's free space (`extra_area_share`).
  std::vector<int> extra_map_areas;
  /// The reference's passages between two found areas with no map passage within
  /// `passage_distance_m` (under the warp).
  std::vector<int> missing_passages;
};

/// Passages joining areas with different counterparts in the other map, and how many of them
/// join the same two areas there.
struct TopologyConsistency {
  std::size_t map_passages = 0;        ///< of the map, between areas with different counterparts
  std::size_t map_consistent = 0;      ///< of those, joining the counterparts in the reference too
  std::size_t reference_passages = 0;  ///< of the reference, between areas both with counterparts in the map
  std::size_t reference_consistent = 0;
  std::vector<int> inconsistent_map_passages;  ///< map passage ids
  /// map_consistent / map_passages (NaN without any).
  double share() const {
    return map_passages ? static_cast<double>(map_consistent) / static_cast<double>(map_passages)
                        : std::numeric_limits<double>::quiet_NaN();
  }
};

/// Coverage of `reference` by `map`, laid on it by `warp`. `reference_raster` samples the
/// reference's areas, `map_raster` the map's; `matched` is the match's area correspondences.
inline Coverage map_coverage(const OccupancyGrid& map, const AreaGraph& map_graph, const AreaRaster& map_raster,
                             const OccupancyGrid& reference, const AreaGraph& reference_graph,
                             const AreaRaster& reference_raster, const std::vector<MatchedAreaPair>& matched,
                             const WarpField& warp, const AssessParams& params) {
  Coverage out;
  const std::size_t n = reference_graph.areas.size();
  std::vector<std::size_t> seen(n, 0);
  for (std::size_t k = 0; k < reference_raster.labelled_count(); ++k) {
    // In a gap between a broken map's pieces no map point lies: not explored.
    const std::optional<Eigen::Vector2d> x = warp.preimage(reference_raster.centre(k), 1e-4);
    if (!x) continue;
    const Eigen::Vector2i cell = map.world_to_cell(*x);
    if (map.contains(cell.x(), cell.y()) && map.at(cell.x(), cell.y()) == CellState::free) {
      ++seen[static_cast<std::size_t>(reference_raster.centre_labels[k])];
    }
  }
  const double cell_m2 = reference_raster.cell_area();
  std::vector<char> found(n, 0);
  for (std::size_t a = 0; a < n; ++a) {
    ReferenceAreaCoverage c;
    c.area = static_cast<int>(a);
    const std::size_t total = reference_raster.area_cells[a].size();
    c.explored_share = total ? static_cast<double>(seen[a]) / static_cast<double>(total) : 0.0;
    c.state = c.explored_share >= params.found_share          ? AreaFound::found
              : c.explored_share >= params.partly_found_share ? AreaFound::partly_found
                                                              : AreaFound::missed;
    for (const auto& m : matched) {
      if (m.dest == c.area) c.map_areas.push_back(m.source);
    }
    std::sort(c.map_areas.begin(), c.map_areas.end());
    out.reference_m2 += static_cast<double>(total) * cell_m2;
    out.explored_m2 += static_cast<double>(seen[a]) * cell_m2;
    (c.state == AreaFound::found ? out.found : c.state == AreaFound::partly_found ? out.partly_found : out.missed) += 1;
    found[a] = c.state == AreaFound::found;
    out.reference_areas.push_back(std::move(c));
  }
  out.explored_share = out.reference_m2 > 0.0 ? out.explored_m2 / out.reference_m2 : 0.0;

  for (std::size_t a = 0; a < map_graph.areas.size(); ++a) {
    const auto& cells = map_raster.area_cells[a];
    if (cells.empty()) continue;
    std::size_t on = 0;
    for (const int k : cells) {
      const Eigen::Vector2i cell = reference.world_to_cell(warp.apply(map_raster.centre(static_cast<std::size_t>(k))));
      on += reference.contains(cell.x(), cell.y()) && reference.at(cell.x(), cell.y()) == CellState::free;
    }
    if (static_cast<double>(on) < params.extra_area_share * static_cast<double>(cells.size())) {
      out.extra_map_areas.push_back(static_cast<int>(a));
    }
  }

  std::vector<Eigen::Vector2d> map_passages;
  for (const Passage& p : map_graph.passages) map_passages.push_back(warp.apply(p.position));
  for (const Passage& p : reference_graph.passages) {
    if (!found[static_cast<std::size_t>(p.area_a)] || !found[static_cast<std::size_t>(p.area_b)]) continue;
    const bool near = std::any_of(map_passages.begin(), map_passages.end(), [&](const Eigen::Vector2d& q) {
      return (q - p.position).norm() <= params.passage_distance_m;
    });
    if (!near) out.missing_passages.push_back(p.id);
  }
  return out;
}

/// Topology consistency of the map's and the reference's passages under the match's area
/// correspondences (`matched`: each map area's counterpart).
inline TopologyConsistency topology_consistency(const AreaGraph& map_graph, const AreaGraph& reference_graph,
                                                const std::vector<MatchedAreaPair>& matched) {
  TopologyConsistency out;
  std::vector<int> counterpart(map_graph.areas.size(), -1);
  for (const auto& m : matched) counterpart[static_cast<std::size_t>(m.source)] = m.dest;
  auto key = [](int a, int b) { return std::make_pair(std::min(a, b), std::max(a, b)); };
  std::set<std::pair<int, int>> reference_joins, map_joins;
  for (const Passage& p : reference_graph.passages) reference_joins.insert(key(p.area_a, p.area_b));
  for (const Passage& p : map_graph.passages) {
    const int a = counterpart[static_cast<std::size_t>(p.area_a)], b = counterpart[static_cast<std::size_t>(p.area_b)];
    if (a < 0 || b < 0 || a == b) continue;
    map_joins.insert(key(a, b));
    ++out.map_passages;
    if (reference_joins.count(key(a, b))) ++out.map_consistent;
    else out.inconsistent_map_passages.push_back(p.id);
  }
  std::vector<char> has_counterpart(reference_graph.areas.size(), 0);
  for (const int c : counterpart) {
    if (c >= 0) has_counterpart[static_cast<std::size_t>(c)] = 1;
  }
  for (const Passage& p : reference_graph.passages) {
    if (!has_counterpart[static_cast<std::size_t>(p.area_a)] || !has_counterpart[static_cast<std::size_t>(p.area_b)]) continue;
    ++out.reference_passages;
    out.reference_consistent += map_joins.count(key(p.area_a, p.area_b));
  }
  return out;
}

}  // namespace areamatch
