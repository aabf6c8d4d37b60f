#pragma once
/// \file warp/fit.hpp
/// Fits a non-rigid warp (warp/field.hpp) that lays a source map's walls onto a destination's,
/// starting from a rigid answer (a `MatchResult::T_dest_source`).
///
/// A bent SLAM map or hand-held scan is not one rigid piece: after the best rigid fit, rooms far
/// from the map's middle are 0.3–1 m off. The warp moves every part of the source a little, as
/// a thin plate would bend: it minimises
///
///   Σ over source wall points  w · ((n · r)² + along_wall_weight · |r|²)      (walls onto walls)
///   + κ · ∫ |∂²d/∂x²|² + 2 |∂²d/∂x∂y|² + |∂²d/∂y²|² dA                        (smooth bending)
///   + rest_weight · ∫ |d − d₀|² dA                                            (rest where nothing is seen)
///
/// over the control grid's displacements d (d₀: where they start, none unless `WarpStart` says), where r is the warped source point less the
/// destination wall point paired with it, n that wall's normal (point-to-line: walls slide along
/// each other), w the wall length per point, κ from `WarpParams::bend_length_m`. The bending
/// term does not resist a rigid or affine motion, only bends. For fixed pairs the energy is
/// quadratic: a sparse linear system (Eigen's SimplicialLDLT on a coarse control grid for the
/// early gates, conjugate gradients with an incomplete Cholesky preconditioner on the fine grid
/// for the last, started from the coarse warp: `WarpParams::coarse_spacing_m`). Pairs are found again after each
/// solve (a wall point with the nearest destination wall that faces the same way, within a gate
/// that shrinks stage by stage, the farthest share dropped as furniture and streaks), as ICP does.
/// Deterministic: one thread, fixed summation order.

#include "../detail/format.hpp"
#include "../error.hpp"
#include "../grid.hpp"
#include "../match/raster.hpp"
#include "../match/verification/refine.hpp"
#include "field.hpp"
#include "params.hpp"
#include "system.hpp"

#include <Eigen/Core>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace areamatch {

/// Where a warp starts (both optional): `displacement` (source world → destination metres) gives
/// the nodes' first displacements — e.g. each part of a map moved by its own rigid fit, so that
/// walls farther off than the first gate are paired all the same; `piece` labels the source's
/// rigid pieces (assess/pieces.hpp), and the warp does not resist bending between two of them.
struct WarpStart {
  std::function<Eigen::Vector2d(const Eigen::Vector2d&)> displacement;
  std::function<int(const Eigen::Vector2d&)> piece;
};

/// A fitted warp and how well it lays the walls, before and after.
struct WarpResult {
  WarpField field;
  std::size_t source_wall_points = 0;  ///< wall points of the source that could be paired
  std::size_t paired_points = 0;       ///< pairs of the last solve (within the last gate, kept)
  /// Over the source wall points whose destination wall (facing the same way) lies within
  /// `WarpParams::report_within_m` under the rigid transform: the median and 95th percentile of
  /// that distance under the rigid transform and under the warp, metres.
  double rigid_median_m = std::numeric_limits<double>::quiet_NaN();
  double rigid_p95_m = std::numeric_limits<double>::quiet_NaN();
  double warped_median_m = std::numeric_limits<double>::quiet_NaN();
  double warped_p95_m = std::numeric_limits<double>::quiet_NaN();
  /// The displacement at the source's wall points (how far the warp moves them beyond the rigid
  /// transform): median and maximum, metres.
  double median_displacement_m = 0.0;
  double max_displacement_m = 0.0;
};

namespace detail {

/// A map's walls as edge cells: free cells with an occupied 4-neighbour (free space ending at
/// unknown cells is a frontier, not a wall), in scan order.
inline std::vector<std::size_t> wall_edge_cells(const OccupancyGrid& grid) {
  const GridInfo g = GridInfo::of(grid);
  const auto& cells = grid.cells();
  std::vector<std::size_t> edge =
      edge_cells(g, PixelBounds{0, 0, grid.width(), grid.height()}, [&](std::size_t i) { return cells[i] == CellState::free; });
  std::vector<std::size_t> walls;
  walls.reserve(edge.size());
  auto occupied = [&](int x, int y) { return grid.contains(x, y) && grid.at(x, y) == CellState::occupied; };
  for (const std::size_t i : edge) {
    const int x = static_cast<int>(i % static_cast<std::size_t>(grid.width()));
    const int y = static_cast<int>(i / static_cast<std::size_t>(grid.width()));
    if (occupied(x - 1, y) || occupied(x + 1, y) || occupied(x, y - 1) || occupied(x, y + 1)) walls.push_back(i);
  }
  return walls;
}

/// The destination's walls to land on: a lookup with normals and free sides.
inline BoundaryLookup wall_lookup(const OccupancyGrid& grid, const WarpParams& params) {
  const GridInfo g = GridInfo::of(grid);
  const double reach = *std::max_element(params.gates_m.begin(), params.gates_m.end());
  BoundaryLookup lookup(boundary_points(g, wall_edge_cells(grid), 0.5 * params.lookup_cell_m), params.lookup_cell_m, reach,
                        params.normal_radius_m);
  if (!lookup.empty()) lookup.set_sides(free_sides(grid, lookup.points(), params.free_side_radius_m));
  return lookup;
}


/// The median and 95th percentile of `values` (NaN when empty); reorders them.
inline std::array<double, 2> median_and_p95(std::vector<double>& values) {
  if (values.empty()) return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  std::sort(values.begin(), values.end());
  auto at = [&](double q) { return values[std::min(values.size() - 1, static_cast<std::size_t>(q * static_cast<double>(values.size())))]; };
  return {at(0.5), at(0.95)};
}

/// The corners of the control grid: the source's walls (or its whole extent when it has none)
/// and `WarpParams::margin_m` around them. Refuses a grid of more than 4 million nodes.
inline std::array<Eigen::Vector2d, 2> control_extent(const OccupancyGrid& source, const std::vector<Eigen::Vector2d>& points,
                                                     const WarpParams& params) {
  Eigen::Vector2d lo = source.cell_center(0, source.height() - 1), hi = source.cell_center(source.width() - 1, 0);
  if (!points.empty()) {
    lo = hi = points.front();
    for (const auto& p : points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  lo.array() -= params.margin_m;
  hi.array() += params.margin_m;
  const double h = params.control_spacing_m;
  const double columns = std::ceil((hi.x() - lo.x()) / h) + 1, rows = std::ceil((hi.y() - lo.y()) / h) + 1;
  if (columns * rows > 4.0e6) {
    throw parameter_error("fit_warp: the control grid would have more than 4 million nodes; raise WarpParams::control_spacing_m (now " +
                          detail::format_double(h) + " m)");
  }
  return {lo, hi};
}

/// How well the walls lie before and after the warp in `out.field`, on the points the rigid
/// transform brings within `WarpParams::report_within_m` of a wall facing the same way.
inline void report_wall_fit(const std::vector<Eigen::Vector2d>& points, const std::vector<Eigen::Vector2d>& sides,
                            const BoundaryLookup& lookup, const Similarity2& T_dest_source, const WarpParams& params,
                            WarpResult& out) {
  const double within = params.report_within_m;
  const Eigen::Matrix2d turn = T_dest_source.linear() / T_dest_source.scale;
  std::vector<double> rigid, warped, moved;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d y0 = T_dest_source * points[i];
    const Eigen::Vector2d* q0 = lookup.nearest_facing(y0, turn * sides[i]);
    if (!q0 || (*q0 - y0).norm() > within) continue;
    const Eigen::Vector2d d = out.field.displacement(points[i]);
    const Eigen::Vector2d* q1 = lookup.nearest_facing(y0 + d, turn * sides[i]);
    rigid.push_back((*q0 - y0).norm());
    warped.push_back(q1 ? (*q1 - (y0 + d)).norm() : within);
    moved.push_back(d.norm());
  }
  const auto r = detail::median_and_p95(rigid), wp = detail::median_and_p95(warped);
  out.rigid_median_m = r[0];
  out.rigid_p95_m = r[1];
  out.warped_median_m = wp[0];
  out.warped_p95_m = wp[1];
  if (!moved.empty()) {
    out.max_displacement_m = *std::max_element(moved.begin(), moved.end());
    out.median_displacement_m = detail::median_and_p95(moved)[0];
  }
}

}  // namespace detail

/// The warp from `source` to `dest` that starts from `T_dest_source` (a match's answer) and bends
/// the source's walls onto the destination's (file comment). Throws `parameter_error` for bad
/// parameters or an empty map; a source without walls near the destination's gives the rigid
/// transform alone (`WarpResult::paired_points` 0).
///
/// `start` may say where the displacements start and where the source is broken (see WarpStart).
inline WarpResult fit_warp(const OccupancyGrid& source, const OccupancyGrid& dest, const Similarity2& T_dest_source,
                           const WarpParams& params = {}, const WarpStart& start = {}) {
  params.validate();
  if (source.empty() || dest.empty()) throw parameter_error("fit_warp: both maps must have cells");
  const GridInfo g = GridInfo::of(source);
  const std::vector<Eigen::Vector2d> points = detail::boundary_points(g, detail::wall_edge_cells(source), params.point_spacing_m);
  const std::vector<Eigen::Vector2d> sides = detail::free_sides(source, points, params.free_side_radius_m);
  const BoundaryLookup lookup = detail::wall_lookup(dest, params);

  WarpResult out;
  out.source_wall_points = points.size();
  const std::array<Eigen::Vector2d, 2> extent = detail::control_extent(source, points, params);
  const Eigen::Vector2d lo = extent[0], hi = extent[1];
  const double h = params.control_spacing_m;
  // A control grid of `spacing` over [lo, hi], its nodes displaced where the start says, and
  // their pieces.
  auto start_field = [&](double spacing, std::vector<int>& node_piece) {
    WarpField field(T_dest_source, lo, spacing, static_cast<int>(std::ceil((hi.x() - lo.x()) / spacing)) + 1,
                    static_cast<int>(std::ceil((hi.y() - lo.y()) / spacing)) + 1);
    for (int j = 0; j < field.rows(); ++j) {
      for (int i = 0; i < field.columns(); ++i) {
        const Eigen::Vector2d x = field.node_position(i, j);
        if (start.displacement) field.node_displacement(field.node(i, j)) = start.displacement(x);
        if (start.piece) node_piece.push_back(start.piece(x));
      }
    }
    return field;
  };
  std::vector<int> node_piece;
  out.field = start_field(h, node_piece);
  if (points.empty() || lookup.empty()) return out;

  // The gates [first, last) on `field`; returns the pairs of its last solve.
  constexpr std::size_t min_pairs = 10;
  auto run_gates = [&](WarpField& field, detail::WarpSystem& system, std::size_t first, std::size_t last, bool from_near_start) {
    std::size_t paired = 0;
    for (std::size_t g = first; g < last; ++g) {
      for (int iteration = 0; iteration < params.iterations_per_gate; ++iteration) {
        const auto pairs = detail::warp_pairs(field, points, sides, lookup, params.gates_m[g], params.keep_fraction);
        if (pairs.size() < min_pairs) break;
        if (!system.solve(field, pairs, points, lookup, params, from_near_start)) break;
        paired = pairs.size();
      }
    }
    return paired;
  };
  const std::size_t gates = params.gates_m.size();
  // Two levels: the early gates on the coarse grid, then the last on the fine grid from there (a
  // bilinear field is itself on the finer grid, so the fine warp starts exactly where the coarse
  // one ended); the rest term still pulls towards the start, not the coarse warp. Not for a map
  // broken into pieces: a coarse cell astride a cut blurs it, and the last gate alone does not
  // undo that (generated broken maps: 3 of 60 fell over 0.15 m at the 95th percentile).
  if (params.coarse_spacing_m > h && gates > 1 && !start.piece) {
    std::vector<int> coarse_piece;
    WarpField coarse = start_field(params.coarse_spacing_m, coarse_piece);
    {
      detail::WarpSystem coarse_system(coarse, params, coarse_piece);
      run_gates(coarse, coarse_system, 0, gates - 1, false);
    }
    detail::WarpSystem system(out.field, params, node_piece);
    for (int j = 0; j < out.field.rows(); ++j) {
      for (int i = 0; i < out.field.columns(); ++i) {
        out.field.node_displacement(out.field.node(i, j)) = coarse.displacement(out.field.node_position(i, j));
      }
    }
    out.paired_points = run_gates(out.field, system, gates - 1, gates, true);
  } else {
    detail::WarpSystem system(out.field, params, node_piece);
    out.paired_points = run_gates(out.field, system, 0, gates, false);
  }

  detail::report_wall_fit(points, sides, lookup, T_dest_source, params, out);
  return out;
}

}  // namespace areamatch
