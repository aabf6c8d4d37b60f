#pragma once
/// \file match/verification/evidence.hpp
/// How much the two maps agree under one transform, measured several ways, so that whether an
/// answer is good enough to accept can be decided (`DecisionParams::min_agreement`).
///
/// The whole-map score (share of the source's free-space edge lying on the destination's) picks
/// the best transform well but does not say whether it is right: cluttered SLAM maps have edges
/// everywhere, and a corridor-with-rooms building lies well on another one (0.78 between two
/// different buildings of the dataset, 0.38 on a true SLAM-to-layout pair). The measures here
/// look both ways and at the building's structure, which chance agrees with much less.

#include "../../area_graph.hpp"
#include "../../grid.hpp"
#include "../../transform.hpp"
#include "../raster.hpp"
#include "../result.hpp"
#include "occupied_walls.hpp"
#include "refine.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

namespace areamatch {

/// Both maps' free-space edges: the source's sparse points to move (ICP, scores), both maps'
/// sparse walls (edge points without frontiers, `without_frontiers`) and dense lookups to land on.
/// Views of what each map holds (built once per map, `Matcher::prepare`).
struct MapEdges {
  const std::vector<Eigen::Vector2d>& source_points;
  const std::vector<Eigen::Vector2d>& source_sides;  ///< their free sides (empty when not used)
  const std::vector<Eigen::Vector2d>& source_walls;
  const std::vector<Eigen::Vector2d>& dest_walls;
  const BoundaryLookup& source_lookup;
  const BoundaryLookup& dest_lookup;
  const detail::OccupiedWalls& source_occupied;  ///< the occupied cells (walls against walls; internal)
  const detail::OccupiedWalls& dest_occupied;
};

namespace detail {

/// Whether a world point is in, or within one raster cell of, a labelled cell of `raster`.
inline bool near_labelled(const AreaRaster& raster, const Eigen::Vector2d& world) {
  const Eigen::Vector2d c = raster.cell_from_world * world;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      if (raster.label_at_cell(c + Eigen::Vector2d(dx, dy)) >= 0) return true;
    }
  }
  return false;
}

/// The edge points (from `free_boundary_points`) that lie on a wall: those with an occupied
/// 4-neighbour (or the grid's border). Free space ending at unknown cells is where the robot
/// stopped looking (an unexplored room's doorway), not a wall the other map must have.
inline std::vector<Eigen::Vector2d> without_frontiers(const OccupancyGrid& grid, const std::vector<Eigen::Vector2d>& points) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(points.size());
  const Eigen::Affine2d to_pixel = grid.pixel_from_world();
  auto occupied_or_off = [&](int x, int y) {
    return x < 0 || y < 0 || x >= grid.width() || y >= grid.height() || grid.at(x, y) == CellState::occupied;
  };
  for (const auto& p : points) {
    const Eigen::Vector2d px = to_pixel * p;
    const int x = static_cast<int>(std::lround(px.x())), y = static_cast<int>(std::lround(px.y()));
    if (occupied_or_off(x - 1, y) || occupied_or_off(x + 1, y) || occupied_or_off(x, y - 1) || occupied_or_off(x, y + 1)) {
      out.push_back(p);
    }
  }
  return out;
}

}  // namespace detail

/// `MatchEvidence::forward_wall_agreement` and `reverse_wall_agreement` alone: each map's walls
/// near the other's free space that lie on the other's free-space edge.
inline std::pair<double, double> overlap_wall_agreements(const AreaRaster& source_raster, const AreaRaster& dest_raster,
                                                         const MapEdges& edges, const Similarity2& T_dest_source,
                                                         double wall_inlier_distance_m) {
  auto shared_walls = [&](const std::vector<Eigen::Vector2d>& walls, const AreaRaster& other, const Similarity2& T,
                          const BoundaryLookup& other_edge) {
    std::vector<Eigen::Vector2d> near;
    for (const auto& q : walls) {
      if (detail::near_labelled(other, T * q)) near.push_back(q);
    }
    return boundary_inlier_fraction(near, other_edge, T, wall_inlier_distance_m);
  };
  return {shared_walls(edges.source_walls, dest_raster, T_dest_source, edges.dest_lookup),
          shared_walls(edges.dest_walls, source_raster, T_dest_source.inverse(), edges.source_lookup)};
}

/// The measures of `MatchEvidence` for T_dest_source, from both maps' edges (world metres) and
/// area rasters of one cell size.
inline MatchEvidence measure_evidence(const AreaGraph& source, const AreaGraph& dest, const AreaRaster& source_raster,
                                      const AreaRaster& dest_raster, const MapEdges& edges,
                                      const Similarity2& T_dest_source, double wall_inlier_distance_m,
                                      double passage_distance_m, double iou_weight) {
  MatchEvidence e;
  const Similarity2 T_source_dest = T_dest_source.inverse();
  e.wall_agreement = boundary_inlier_fraction(edges.source_points, edges.dest_lookup, T_dest_source, wall_inlier_distance_m);

  const auto [forward, reverse] = overlap_wall_agreements(source_raster, dest_raster, edges, T_dest_source, wall_inlier_distance_m);
  e.forward_wall_agreement = forward;
  e.reverse_wall_agreement = reverse;
  e.occupied_wall_agreement = detail::occupied_wall_agreement(edges.source_occupied, edges.dest_occupied, T_dest_source);

  // Cell overlaps per area pair, from the source cells, area by area: an area meets a few of the
  // other map's, so the pairs are listed per area (destination ids ascending), not held as an
  // areas_source × areas_dest table.
  const std::size_t ns = source.areas.size();
  std::vector<std::vector<std::pair<int, std::size_t>>> overlap(ns);  // per source area: (j, cells)
  std::size_t hits = 0;
  const Eigen::Affine2d to_cell = dest_raster.cell_from_world * T_dest_source.affine();
  std::vector<int> landed;
  for (std::size_t i = 0; i < ns; ++i) {
    landed.clear();
    for (int k : source_raster.area_cells[i]) {
      const int j = dest_raster.label_at_cell(to_cell * source_raster.centre(static_cast<std::size_t>(k)));
      if (j >= 0) landed.push_back(j);
    }
    hits += landed.size();
    overlap[i] = detail::counted(landed);
  }
  const double scale2 = T_dest_source.scale * T_dest_source.scale;  // source cells → destination cells
  const double source_cells = static_cast<double>(source_raster.labelled_count()) * scale2;
  const double dest_cells = static_cast<double>(dest_raster.labelled_count());
  const double common = static_cast<double>(hits) * scale2;
  e.overlap_m2 = common * dest_raster.cell_area();
  e.free_iou = source_cells + dest_cells - common > 0.0 ? common / (source_cells + dest_cells - common) : 0.0;
  e.source_on_dest = source_cells > 0.0 ? common / source_cells : 0.0;
  e.dest_on_source = dest_cells > 0.0 ? std::min(1.0, common / dest_cells) : 0.0;
  e.agreement = (1.0 - iou_weight) * std::max(e.forward_wall_agreement, e.reverse_wall_agreement) + iou_weight * e.free_iou;

  double consistent = 0.0;
  for (std::size_t i = 0; i < ns; ++i) {
    const double a = static_cast<double>(source_raster.area_cells[i].size()) * scale2;
    for (const auto& [j, cells] : overlap[i]) {
      const double o = static_cast<double>(cells) * scale2;
      const double b = static_cast<double>(dest_raster.area_cells[static_cast<std::size_t>(j)].size());
      if (o >= 0.5 * (a + b - o)) consistent += o;
    }
  }
  e.room_agreement = common > 0.0 ? consistent / common : 0.0;

  // Passages of the common part with a counterpart in the other map (the other map's passages
  // by x, so each looks only at those within reach along x).
  std::size_t considered = 0, matched = 0;
  const double d2 = passage_distance_m * passage_distance_m;
  const double reach = passage_distance_m * (1.0 + 1e-9);  // rounding must not narrow the window
  auto count = [&](const AreaGraph& from, const AreaGraph& to, const AreaRaster& to_raster, const Similarity2& T) {
    std::vector<Eigen::Vector2d> by_x;
    by_x.reserve(to.passages.size());
    for (const Passage& r : to.passages) by_x.push_back(r.position);
    std::sort(by_x.begin(), by_x.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() < b.x(); });
    for (const Passage& p : from.passages) {
      const Eigen::Vector2d q = T * p.position;
      if (!detail::near_labelled(to_raster, q)) continue;
      ++considered;
      auto it = std::lower_bound(by_x.begin(), by_x.end(), q.x() - reach,
                                 [](const Eigen::Vector2d& r, double x) { return r.x() < x; });
      for (; it != by_x.end() && it->x() <= q.x() + reach; ++it) {
        if ((*it - q).squaredNorm() <= d2) {
          ++matched;
          break;
        }
      }
    }
  };
  count(source, dest, dest_raster, T_dest_source);
  count(dest, source, source_raster, T_source_dest);
  e.passage_agreement = considered > 0 ? static_cast<double>(matched) / static_cast<double>(considered)
                                       : std::numeric_limits<double>::quiet_NaN();
  return e;
}

}  // namespace areamatch
