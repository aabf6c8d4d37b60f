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
#include <utility>
#include <vector>

namespace areamatch {

/// Where a warp starts (both optional): `displacement` (a source point and the piece whose warp
/// asks, 0 for a map in one piece → destination metres) gives the nodes' first displacements —
/// e.g. each part of a map moved by its own rigid fit, so that walls farther off than the first
/// gate are paired all the same; `pieces` labels the source's rigid pieces (assess/pieces.hpp):
/// each piece then gets its own warp, fitted on its own walls, and the whole jumps at a cut.
struct WarpStart {
  std::function<Eigen::Vector2d(const Eigen::Vector2d&, int)> displacement;
  PieceLabels pieces;
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

namespace detail {

/// A field fitted on `points` (with their free `sides`) over their extent: the early gates on the
/// coarse grid, then the last on the fine grid from there (a bilinear field is itself on the
/// finer grid, so the fine warp starts exactly where the coarse one ended); the rest term still
/// pulls towards the start (`start_at`), not the coarse warp. Returns the field and the pairs of
/// its last solve.
inline std::pair<WarpField, std::size_t> fit_field(const OccupancyGrid& source, const std::vector<Eigen::Vector2d>& points,
                                                   const std::vector<Eigen::Vector2d>& sides, const BoundaryLookup& lookup,
                                                   const Similarity2& T_dest_source, const WarpParams& params,
                                                   const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& start_at) {
  const std::array<Eigen::Vector2d, 2> extent = control_extent(source, points, params);
  const Eigen::Vector2d lo = extent[0], hi = extent[1];
  // A control grid of `spacing` over [lo, hi], its nodes displaced where the start says.
  auto start_field = [&](double spacing) {
    WarpField field(T_dest_source, lo, spacing, static_cast<int>(std::ceil((hi.x() - lo.x()) / spacing)) + 1,
                    static_cast<int>(std::ceil((hi.y() - lo.y()) / spacing)) + 1);
    if (start_at) {
      for (int j = 0; j < field.rows(); ++j) {
        for (int i = 0; i < field.columns(); ++i) field.node_displacement(field.node(i, j)) = start_at(field.node_position(i, j));
      }
    }
    return field;
  };
  WarpField field = start_field(params.control_spacing_m);
  if (points.empty() || lookup.empty()) return {field, 0};

  // The gates [first, last) on `f`; returns the pairs of its last solve.
  constexpr std::size_t min_pairs = 10;
  auto run_gates = [&](WarpField& f, WarpSystem& system, std::size_t first, std::size_t last, bool from_near_start) {
    std::size_t paired = 0;
    for (std::size_t g = first; g < last; ++g) {
      for (int iteration = 0; iteration < params.iterations_per_gate; ++iteration) {
        const auto pairs = warp_pairs(f, points, sides, lookup, params.gates_m[g], params.keep_fraction);
        if (pairs.size() < min_pairs) break;
        if (!system.solve(f, pairs, points, lookup, params, from_near_start)) break;
        paired = pairs.size();
      }
    }
    return paired;
  };
  const std::size_t gates = params.gates_m.size();
  if (params.coarse_spacing_m > params.control_spacing_m && gates > 1) {
    WarpField coarse = start_field(params.coarse_spacing_m);
    {
      WarpSystem coarse_system(coarse, params);
      run_gates(coarse, coarse_system, 0, gates - 1, false);
    }
    WarpSystem system(field, params);
    for (int j = 0; j < field.rows(); ++j) {
      for (int i = 0; i < field.columns(); ++i) {
        field.node_displacement(field.node(i, j)) = coarse.displacement(field.node_position(i, j));
      }
    }
    const std::size_t paired = run_gates(field, system, gates - 1, gates, true);
    return {field, paired};
  }
  WarpSystem system(field, params);
  const std::size_t paired = run_gates(field, system, 0, gates, false);
  return {field, paired};
}

/// Where a broken map's pieces meet, their labels decided again by the pieces' warps: on cells of
/// `WarpParams::piece_label_cell_m`, each cell holding source wall points within
/// `piece_boundary_m` of another piece's cells goes to the piece (of those within that reach)
/// whose warp lays its points nearest the destination's walls facing their way (each distance
/// capped at the last gate); ties and cells without walls keep their label. A piece's labels came
/// from rigid fits of whole tiles; its warp follows the walls to within centimetres, so it tells
/// which side of a cut a wall lies on more finely.
inline PieceLabels relabel_pieces(const PieceLabels& labels, const std::vector<WarpField>& fields,
                                  const std::vector<Eigen::Vector2d>& points, const std::vector<Eigen::Vector2d>& sides,
                                  const BoundaryLookup& lookup, const WarpParams& params) {
  PieceLabels out;
  out.origin = labels.origin;
  out.cell_m = params.piece_label_cell_m;
  out.columns = std::max(1, static_cast<int>(std::ceil(labels.columns * labels.cell_m / out.cell_m)));
  out.rows = std::max(1, static_cast<int>(std::ceil(labels.rows * labels.cell_m / out.cell_m)));
  const auto columns = static_cast<std::size_t>(out.columns);
  out.labels.resize(columns * static_cast<std::size_t>(out.rows));
  for (int r = 0; r < out.rows; ++r) {
    for (int c = 0; c < out.columns; ++c) {
      out.labels[static_cast<std::size_t>(r) * columns + static_cast<std::size_t>(c)] =
          labels.at(out.origin + out.cell_m * Eigen::Vector2d(c + 0.5, r + 0.5));
    }
  }
  // The wall points of each cell, in the points' order.
  std::vector<std::vector<std::size_t>> in_cell(out.labels.size());
  for (std::size_t i = 0; i < points.size(); ++i) in_cell[out.cell_of(points[i])].push_back(i);
  const int reach = static_cast<int>(std::ceil(params.piece_boundary_m / out.cell_m));
  const double cap = params.gates_m.back();
  const std::vector<int> before = out.labels;
  const Eigen::Matrix2d turn = fields.front().rigid().linear() / fields.front().rigid().scale;
  std::vector<int> candidates;
  for (int r = 0; r < out.rows; ++r) {
    for (int c = 0; c < out.columns; ++c) {
      const std::size_t cell = static_cast<std::size_t>(r) * columns + static_cast<std::size_t>(c);
      if (in_cell[cell].empty()) continue;
      candidates.assign(1, before[cell]);
      for (int rr = std::max(0, r - reach); rr <= std::min(out.rows - 1, r + reach); ++rr) {
        for (int cc = std::max(0, c - reach); cc <= std::min(out.columns - 1, c + reach); ++cc) {
          const int other = before[static_cast<std::size_t>(rr) * columns + static_cast<std::size_t>(cc)];
          if (std::find(candidates.begin(), candidates.end(), other) == candidates.end()) candidates.push_back(other);
        }
      }
      if (candidates.size() == 1) continue;
      double best = std::numeric_limits<double>::infinity();
      for (const int k : candidates) {
        const WarpField& field = fields[static_cast<std::size_t>(k)];
        double cost = 0.0;
        for (const std::size_t i : in_cell[cell]) {
          const Eigen::Vector2d y = field.apply(points[i]);
          const Eigen::Vector2d* q = lookup.nearest_facing(y, turn * sides[i]);
          const double d = q ? std::min((*q - y).norm(), cap) : cap;
          cost += d * d;
        }
        if (cost < best) best = cost, out.labels[cell] = k;  // the current label first: ties keep it
      }
    }
  }
  return out;
}

}  // namespace detail

/// `fit_warp` (below) onto the destination's walls as `detail::wall_lookup(dest, params)` made
/// them, for a caller that has that lookup already (`assess_match` finds the pieces on it).
inline WarpResult fit_warp(const OccupancyGrid& source, const BoundaryLookup& lookup, const Similarity2& T_dest_source,
                           const WarpParams& params = {}, const WarpStart& start = {}) {
  params.validate();
  if (source.empty()) throw parameter_error("fit_warp: the source map must have cells");
  const GridInfo g = GridInfo::of(source);
  const std::vector<Eigen::Vector2d> points = detail::boundary_points(g, detail::wall_edge_cells(source), params.point_spacing_m);
  const std::vector<Eigen::Vector2d> sides = detail::free_sides(source, points, params.free_side_radius_m);

  WarpResult out;
  out.source_wall_points = points.size();
  auto start_of = [&](int piece) -> std::function<Eigen::Vector2d(const Eigen::Vector2d&)> {
    if (!start.displacement) return {};
    return [&start, piece](const Eigen::Vector2d& x) { return start.displacement(x, piece); };
  };
  const int piece_count = start.pieces.count();
  if (piece_count <= 1) {
    auto [field, paired] = detail::fit_field(source, points, sides, lookup, T_dest_source, params, start_of(0));
    out.field = std::move(field);
    out.paired_points = paired;
  } else {
    // One warp per piece on its own walls; the whole's own grid stays the rigid transform. Fitted
    // twice: on the pieces' labels as given, then on those labels decided again by the warps
    // where pieces meet.
    auto fit_pieces = [&](const PieceLabels& labels) {
      std::vector<std::vector<Eigen::Vector2d>> piece_points(static_cast<std::size_t>(piece_count)), piece_sides(piece_points.size());
      for (std::size_t i = 0; i < points.size(); ++i) {
        const auto k = static_cast<std::size_t>(labels.at(points[i]));
        piece_points[k].push_back(points[i]);
        piece_sides[k].push_back(sides[i]);
      }
      std::vector<WarpField> fields;
      out.paired_points = 0;
      for (int k = 0; k < piece_count; ++k) {
        const auto u = static_cast<std::size_t>(k);
        auto [field, paired] = detail::fit_field(source, piece_points[u], piece_sides[u], lookup, T_dest_source, params, start_of(k));
        fields.push_back(std::move(field));
        out.paired_points += paired;
      }
      return fields;
    };
    std::vector<WarpField> fields = fit_pieces(start.pieces);
    PieceLabels labels = start.pieces;
    if (!points.empty() && !lookup.empty()) {
      labels = detail::relabel_pieces(start.pieces, fields, points, sides, lookup, params);
      fields = fit_pieces(labels);
    }
    out.field = WarpField(T_dest_source);
    out.field.set_pieces(std::move(labels), std::move(fields));
  }
  if (!points.empty() && !lookup.empty()) detail::report_wall_fit(points, sides, lookup, T_dest_source, params, out);
  return out;
}

/// The warp from `source` to `dest` that starts from `T_dest_source` (a match's answer) and bends
/// the source's walls onto the destination's (file comment). Throws `parameter_error` for bad
/// parameters or an empty map; a source without walls near the destination's gives the rigid
/// transform alone (`WarpResult::paired_points` 0).
///
/// `start` may say where the displacements start and where the source is broken (see WarpStart):
/// a broken map's pieces are each warped on their own walls, and a point moves with its piece's
/// warp (`WarpField::set_pieces`), so that no control cell astride a cut blurs it.
inline WarpResult fit_warp(const OccupancyGrid& source, const OccupancyGrid& dest, const Similarity2& T_dest_source,
                           const WarpParams& params = {}, const WarpStart& start = {}) {
  params.validate();
  if (source.empty() || dest.empty()) throw parameter_error("fit_warp: both maps must have cells");
  return fit_warp(source, detail::wall_lookup(dest, params), T_dest_source, params, start);
}

}  // namespace areamatch
