#pragma once
/// \file match/map_data.hpp
/// What matching builds from one map alone, the same whichever side the map is on: the
/// features' descriptors, coarse and fine rasters, the wall direction, the free-space edge and
/// its lookup. Built once per map by `Matcher::prepare` (or per match), never per pair.

#include "../area_graph.hpp"
#include "../detail/parallel.hpp"
#include "../grid.hpp"
#include "params.hpp"
#include "proposal/hypotheses.hpp"
#include "raster.hpp"
#include "verification/evidence.hpp"
#include "verification/occupied_walls.hpp"
#include "verification/refine.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <optional>
#include <type_traits>
#include <vector>

namespace areamatch::detail {

template <class Descriptors>
struct MapData {
  Descriptors descriptors;                   ///< the Features policy's, per area
  AreaRaster coarse;                         ///< area-covered free space on coarse cells
  std::optional<AreaRaster> fine_own;        ///< on fine cells, when they differ from the coarse ones
  double wall_direction = 0.0;               ///< for wall-direction hypotheses
  std::vector<Eigen::Vector2d> edge_points;  ///< sparse free-space edge: what moves (ICP, scores)
  std::vector<Eigen::Vector2d> edge_sides;   ///< each edge point's free side (`free_sides`; empty unless used)
  std::vector<Eigen::Vector2d> walls;        ///< edge_points without frontiers
  std::vector<std::size_t> free_edge;        ///< the free-space edge cells (`detail::free_edge_cells`)
  BoundaryLookup lookup;                     ///< dense free-space edge: what is landed on
  OccupiedWalls occupied;                    ///< the occupied cells, for walls against walls
  const AreaRaster& fine() const { return fine_own ? *fine_own : coarse; }
};

/// One map as matching reads it; `data` null: not built yet (or the map has no areas).
template <class Descriptors>
struct MapView {
  const OccupancyGrid* grid;
  const AreaGraph* graph;
  const MapData<Descriptors>* data;
};

/// The lookups reach this far beyond the edges: every distance the matcher's own stages ask them
/// about (the refinement's and the scale sweep's gates, `wall_inlier_distance_m`). A selection
/// asks within it (`BoundaryLookup::reach_m`).
inline double lookup_margin(const MatcherParams& params) {
  const auto& gates = params.refinement.gates_m;
  const auto& sweep_gates = params.scale.sweep_gates_m;
  return std::max({*std::max_element(gates.begin(), gates.end()), *std::max_element(sweep_gates.begin(), sweep_gates.end()),
                   params.wall_inlier_distance_m});
}

/// The dense lookup over a map's free-space edge cells (points every half lookup cell) reaching
/// `margin_m`: with normals for point-to-line ICP onto it when `normals`, and with each point's
/// free side (`same_side_only` ICP onto it) when `sides`.
inline BoundaryLookup edge_lookup(const OccupancyGrid& grid, const GridInfo& g, const std::vector<std::size_t>& free_edge,
                                  const RefineParams& r, double margin_m, bool normals, bool sides) {
  BoundaryLookup lookup(boundary_points(g, free_edge, 0.5 * r.lookup_cell_m), r.lookup_cell_m, margin_m,
                        normals && r.point_to_line ? r.normal_radius_m : 0.0);
  if (sides) lookup.set_sides(free_sides(grid, lookup.points(), r.free_side_radius_m));
  return lookup;
}

/// A map's free-space edge points with the side each faces, and a lookup with normals and sides
/// to land on: what `same_side_only` ICP reads (merging's refinement builds it from prepared maps).
struct FacingEdges {
  std::vector<Eigen::Vector2d> points;
  std::vector<Eigen::Vector2d> sides;
  BoundaryLookup lookup;
};

/// What of a map's data its grid alone gives, before its Area Graph exists: the free-space edge
/// cells of the whole grid and the occupied walls. A matcher with threads to spare builds it
/// beside the segmentation and hands it to `build_map_data`, which then need not find them again.
struct GridOnlyData {
  GridInfo grid;                       ///< the frame it was built in
  std::vector<std::size_t> free_edge;  ///< `edge_cells` of the free space over every cell
  OccupiedWalls occupied;
};

inline OccupiedWalls map_occupied_walls(const OccupancyGrid& grid, const GridInfo& info, const MatcherParams& params) {
  return occupied_walls(grid, info, params.occupied_point_spacing_m, params.refinement.lookup_cell_m,
                        params.occupied_wall_distance_m, params.occupied_wall_context_m);
}

inline GridOnlyData grid_only_data(const OccupancyGrid& grid, const MatcherParams& params) {
  GridOnlyData out;
  out.grid = GridInfo::of(grid);
  const auto& cells = grid.cells();
  out.free_edge = edge_cells(out.grid, PixelBounds{0, 0, grid.width(), grid.height()},
                             [&](std::size_t i) { return cells[i] == CellState::free; });
  out.occupied = map_occupied_walls(grid, out.grid, params);
  return out;
}

/// The part of `d` that reads the areas: descriptors, rasters, wall direction.
template <class Descriptors, class Features>
void build_area_data(MapData<Descriptors>& d, const AreaGraph& graph, const Features& features, const MatcherParams& params) {
  d.descriptors = features.describe(graph);
  d.coarse = make_area_raster(graph, params.coarse_cell_m);
  if (params.fine_cell_m != params.coarse_cell_m) d.fine_own = make_area_raster(graph, params.fine_cell_m);
  if (params.hypotheses.wall_directions) d.wall_direction = dominant_wall_direction(graph, params.hypotheses.wall_direction);
}

/// The part of `d` that reads the cells: the free-space edge, its points and lookup, the occupied
/// walls; from `from_grid` (`grid_only_data`) where it was built in the graph's frame.
template <class Descriptors>
void build_edge_data(MapData<Descriptors>& d, const OccupancyGrid& grid, const AreaGraph& graph, const MatcherParams& params,
                     bool normals, const GridOnlyData* from_grid) {
  const RefineParams& r = params.refinement;
  const GridInfo& g = graph.grid;
  if (from_grid && from_grid->grid == g) {
    // `edge_cells` within the areas' extent are the whole grid's edge cells inside it (a cell's
    // neighbours count wherever they lie), in the same scan order.
    d.free_edge = cells_within(from_grid->free_edge, label_bounds(graph), g.width);
    d.occupied = from_grid->occupied;
  } else {
    d.free_edge = free_edge_cells(grid, graph);  // found once: thinned for the points, the lookup, the rooms' walls
    d.occupied = map_occupied_walls(grid, g, params);
  }
  d.edge_points = boundary_points(g, d.free_edge, r.point_spacing_m, static_cast<std::size_t>(r.max_points));
  d.walls = without_frontiers(grid, d.edge_points);
  // With same_side_only: which way each wall faces, so that ICP does not pair a wall's two faces.
  d.lookup = edge_lookup(grid, g, d.free_edge, r, lookup_margin(params), normals, normals && r.same_side_only);
  if (r.same_side_only) d.edge_sides = free_sides(grid, d.edge_points, r.free_side_radius_m);
}

/// Everything matching builds from one map alone; the areas' part and the cells' part on two
/// threads with `threads` ≥ 2 (the same data either way).
template <class Features>
auto build_map_data(const OccupancyGrid& grid, const AreaGraph& graph, const Features& features,
                    const MatcherParams& params, bool normals, unsigned threads = 1,
                    const GridOnlyData* from_grid = nullptr) {
  MapData<std::decay_t<decltype(features.describe(graph))>> d;
  for_each_index(2, threads, [&](std::size_t part) {
    if (part == 0) build_area_data(d, graph, features, params);
    else build_edge_data(d, grid, graph, params, normals, from_grid);
  });
  return d;
}

/// The free-space edges of both maps, each as sparse points (what moves) and a dense lookup
/// (what is landed on), so that scores and evidence can look both ways.
template <class Descriptors>
MapEdges map_edges(const MapData<Descriptors>& source, const MapData<Descriptors>& dest) {
  return MapEdges{source.edge_points, source.edge_sides, source.walls, dest.walls, source.lookup, dest.lookup,
                  source.occupied, dest.occupied};
}

}  // namespace areamatch::detail
