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
#include "../match/refine.hpp"
#include "field.hpp"
#include "params.hpp"

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

/// The bending and rest terms of the energy over `field`'s nodes (2 unknowns a node: x, y). With
/// `node_piece` (one label per node), a bending stencil whose nodes carry different labels is left
/// out: the field bends freely where a map is broken.
///
/// The terms couple a node with the 13 nodes within two steps along a row or column or one
/// diagonally, and x with x, y with y only; they are summed per node and offset, then written
/// column by column in row order (no triplets to sort: a large grid's matrix is built in a few
/// milliseconds).
inline Eigen::SparseMatrix<double> smoothness_matrix(const WarpField& field, const WarpParams& params,
                                                     const std::vector<int>& node_piece = {}) {
  // The offsets (row step, column step) in the order of their node indices.
  static constexpr int kOffsets = 13;
  static constexpr int kRowStep[kOffsets] = {-2, -1, -1, -1, 0, 0, 0, 0, 0, 1, 1, 1, 2};
  static constexpr int kColumnStep[kOffsets] = {0, -1, 0, 1, -2, -1, 0, 1, 2, -1, 0, 1, 0};
  auto offset_index = [](int dj, int di) {
    for (int o = 0; o < kOffsets; ++o) {
      if (kRowStep[o] == dj && kColumnStep[o] == di) return o;
    }
    return -1;  // not reached: every stencil spans offsets of the list
  };
  const int nx = field.columns(), ny = field.rows();
  std::vector<std::array<double, kOffsets>> sums(field.node_count());
  for (auto& s : sums) s.fill(0.0);
  const double h = field.spacing(), h2 = h * h;
  const double bend = params.bending_weight() * h2 / (h2 * h2);  // κ · area per node · (1/h²)²
  // One stencil: its nodes as (column, row) and their coefficients.
  auto add = [&](const int (*nodes)[2], const double* coefficients, int count, double weight) {
    for (int a = 1; a < count && !node_piece.empty(); ++a) {
      if (node_piece[field.node(nodes[a][0], nodes[a][1])] != node_piece[field.node(nodes[0][0], nodes[0][1])]) return;
    }
    for (int a = 0; a < count; ++a) {
      auto& row = sums[field.node(nodes[a][0], nodes[a][1])];
      for (int b = 0; b < count; ++b) {
        row[static_cast<std::size_t>(offset_index(nodes[b][1] - nodes[a][1], nodes[b][0] - nodes[a][0]))] +=
            weight * coefficients[a] * coefficients[b];
      }
    }
  };
  const double second[3] = {1.0, -2.0, 1.0}, mixed[4] = {1.0, -1.0, -1.0, 1.0}, one[1] = {1.0};
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int self[1][2] = {{i, j}};
      add(self, one, 1, params.rest_weight * h2);
      if (i > 0 && i + 1 < nx) {
        const int nodes[3][2] = {{i - 1, j}, {i, j}, {i + 1, j}};
        add(nodes, second, 3, bend);
      }
      if (j > 0 && j + 1 < ny) {
        const int nodes[3][2] = {{i, j - 1}, {i, j}, {i, j + 1}};
        add(nodes, second, 3, bend);
      }
      if (i + 1 < nx && j + 1 < ny) {
        const int nodes[4][2] = {{i, j}, {i + 1, j}, {i, j + 1}, {i + 1, j + 1}};
        add(nodes, mixed, 4, 2.0 * bend);
      }
    }
  }
  const Eigen::Index unknowns = static_cast<Eigen::Index>(2 * field.node_count());
  Eigen::SparseMatrix<double> S(unknowns, unknowns);
  S.reserve(Eigen::VectorXi::Constant(unknowns, kOffsets));
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const auto& row = sums[field.node(i, j)];
      for (int c = 0; c < 2; ++c) {
        const Eigen::Index column = static_cast<Eigen::Index>(2 * field.node(i, j) + static_cast<std::size_t>(c));
        for (int o = 0; o < kOffsets; ++o) {
          const int ii = i + kColumnStep[o], jj = j + kRowStep[o];
          if (ii < 0 || ii >= nx || jj < 0 || jj >= ny || row[static_cast<std::size_t>(o)] == 0.0) continue;
          S.insert(static_cast<Eigen::Index>(2 * field.node(ii, jj) + static_cast<std::size_t>(c)), column) = row[static_cast<std::size_t>(o)];
        }
      }
    }
  }
  S.makeCompressed();
  return S;
}

/// One source wall point paired with a destination wall point.
struct WarpPair {
  double distance2;
  std::size_t point;
  const Eigen::Vector2d* to;
};

/// Pairs each source point (warped by `field`) with the nearest destination wall facing its way
/// within `gate`; the closest `keep_fraction` of them, in the points' order.
inline std::vector<WarpPair> warp_pairs(const WarpField& field, const std::vector<Eigen::Vector2d>& points,
                                        const std::vector<Eigen::Vector2d>& sides, const BoundaryLookup& dest, double gate,
                                        double keep_fraction) {
  std::vector<WarpPair> pairs;
  const Eigen::Matrix2d turn = field.rigid().linear() / field.rigid().scale;  // sides are directions
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d y = field.apply(points[i]);
    const Eigen::Vector2d* q = dest.nearest_facing(y, turn * sides[i]);
    if (!q) continue;
    const double d2 = (*q - y).squaredNorm();
    if (d2 <= gate * gate) pairs.push_back({d2, i, q});
  }
  const std::size_t keep = static_cast<std::size_t>(std::ceil(keep_fraction * static_cast<double>(pairs.size())));
  if (keep < pairs.size()) {
    // The first `keep` by (distance, point) are those before the one at `keep` in that order:
    // find it, then filter in place (the points' order stays, no sort).
    auto before = [](const WarpPair& a, const WarpPair& b) {
      return a.distance2 < b.distance2 || (a.distance2 == b.distance2 && a.point < b.point);
    };
    std::vector<WarpPair> ranked(pairs);
    std::nth_element(ranked.begin(), ranked.begin() + static_cast<std::ptrdiff_t>(keep), ranked.end(), before);
    const WarpPair first_dropped = ranked[keep];
    pairs.erase(std::remove_if(pairs.begin(), pairs.end(), [&](const WarpPair& p) { return !before(p, first_dropped); }), pairs.end());
  }
  return pairs;
}

/// The warp's linear system across the solves of one fit: the smoothness part (the same for
/// every solve) and the last factorization. The first solve factorizes its system (sparse LDLT);
/// the solves after it differ in their pairs only (fewer, nearer, as the gates shrink), so they
/// are solved by conjugate gradients preconditioned with that factorization, from the current
/// displacements — a few triangular solves instead of a factorization each (a factorization costs
/// as much as a warp's other work). Deterministic: one thread, fixed order.
class WarpSystem {
 public:
  /// The rest term pulls each node towards its displacement in `field` now (where the warp
  /// starts), not towards none: a piece that the start turned away from the rigid transform stays
  /// turned where no wall holds it (room middles), rather than bending back.
  WarpSystem(const WarpField& field, const WarpParams& params, const std::vector<int>& node_piece = {})
      : unknowns_(static_cast<Eigen::Index>(2 * field.node_count())), rest_pull_(unknowns_) {
    smoothness_ = smoothness_matrix(field, params, node_piece);
    const double rest = params.rest_weight * field.spacing() * field.spacing();
    for (std::size_t k = 0; k < field.node_count(); ++k) {
      rest_pull_.segment<2>(static_cast<Eigen::Index>(2 * k)) = rest * field.node_displacement(k);
    }
  }

  /// Solves for the displacements that lay `pairs` best under the smoothness terms and writes
  /// them into `field`: by conjugate gradients preconditioned with the last factorization, or by
  /// factorizing this system (the first solve, or when that did not converge). Returns false when
  /// it could not be solved (the field is kept).
  ///
  /// `from_near_start`: the field already holds a near solution (the coarse level's warp), so
  /// conjugate gradients with an incomplete Cholesky preconditioner (no factorization) finish it;
  /// stopped after `kNearStartSteps` steps, the solve is kept even if not to 1e-4 (the next
  /// pairing round goes on from it).
  bool solve(WarpField& field, const std::vector<WarpPair>& pairs, const std::vector<Eigen::Vector2d>& points,
             const BoundaryLookup& dest, const WarpParams& params, bool from_near_start = false) {
    Eigen::VectorXd b;
    const Eigen::SparseMatrix<double> A = smoothness_ + data_terms(field, pairs, points, dest, params, b);
    b += rest_pull_;
    Eigen::VectorXd x(unknowns_);
    for (std::size_t k = 0; k < field.node_count(); ++k) x.segment<2>(static_cast<Eigen::Index>(2 * k)) = field.node_displacement(k);
    if (from_near_start) {
      // One incomplete factor for all the fine solves: their systems differ in their pairs only.
      // In the grid's own node order: a fill-reducing (AMD) order cost more to find than it saved
      // (office_g's fine gates 207 -> 137 ms in grid order, 35-40 CG steps).
      if (!incomplete_ready_) {
        incomplete_.compute(A);
        if (incomplete_.info() != Eigen::Success) return false;
        incomplete_ready_ = true;
      }
      if (conjugate_gradients(A, b, x, [&](const Eigen::VectorXd& r) { return Eigen::VectorXd(incomplete_.solve(r)); }, kNearStartSteps) < 0) {
        return false;
      }
    } else if (!(factored_ && within(conjugate_gradients(A, b, x, [&](const Eigen::VectorXd& r) { return Eigen::VectorXd(factor_.solve(r)); },
                                                         kFactoredSteps),
                                     kFactoredSteps))) {
      factor_.compute(A);
      factored_ = factor_.info() == Eigen::Success;
      if (!factored_) return false;
      x = factor_.solve(b);
      if (factor_.info() != Eigen::Success) return false;
    }
    if (!x.allFinite()) return false;
    for (std::size_t k = 0; k < field.node_count(); ++k) field.node_displacement(k) = x.segment<2>(static_cast<Eigen::Index>(2 * k));
    return true;
  }

 private:
  /// The pairs' point-to-line (and a little point-to-point) terms, summed per control cell (its
  /// four nodes, eight unknowns) before they enter the sparse matrix: one 8×8 block a cell
  /// instead of one a pair. Fills the right-hand side `b`.
  Eigen::SparseMatrix<double> data_terms(const WarpField& field, const std::vector<WarpPair>& pairs,
                                         const std::vector<Eigen::Vector2d>& points, const BoundaryLookup& dest,
                                         const WarpParams& params, Eigen::VectorXd& b) const {
    const std::size_t columns = static_cast<std::size_t>(field.columns());
    const std::size_t cells = (columns - 1) * static_cast<std::size_t>(field.rows() - 1);
    // Blocks only for the cells that hold pairs (a few hundred of a large grid's many thousand).
    std::vector<std::int32_t> block_of(cells, -1);
    std::vector<std::array<double, 64>> blocks;
    b = Eigen::VectorXd::Zero(unknowns_);
    const double w = params.point_spacing_m;
    for (const WarpPair& pair : pairs) {
      const Eigen::Vector2d& p = points[pair.point];
      const WarpField::Stencil s = field.stencil(p);
      const std::size_t cell = s.nodes[0] - s.nodes[0] / columns;  // i + j·(columns − 1)
      if (block_of[cell] < 0) {
        block_of[cell] = static_cast<std::int32_t>(blocks.size());
        blocks.emplace_back().fill(0.0);
      }
      auto& block = blocks[static_cast<std::size_t>(block_of[cell])];
      const Eigen::Vector2d r0 = field.apply_rigid(p) - *pair.to;
      const Eigen::Vector2d& normal = dest.normal_at(pair.to);
      // Rows of the residuals in the cell's eight unknowns (node k, component c at 2k + c).
      auto add_row = [&](const Eigen::Vector2d& direction, double residual, double weight) {
        std::array<double, 8> j{};
        for (std::size_t k = 0; k < 4; ++k) {
          j[2 * k] = s.weights[k] * direction.x();
          j[2 * k + 1] = s.weights[k] * direction.y();
        }
        for (std::size_t a = 0; a < 8; ++a) {
          if (j[a] == 0.0) continue;
          for (std::size_t c = 0; c < 8; ++c) block[a * 8 + c] += weight * j[a] * j[c];
          b(static_cast<Eigen::Index>(2 * s.nodes[a / 2] + a % 2)) -= weight * j[a] * residual;
        }
      };
      add_row(normal, normal.dot(r0), w);
      if (params.along_wall_weight > 0.0) {
        add_row(Eigen::Vector2d::UnitX(), r0.x(), w * params.along_wall_weight);
        add_row(Eigen::Vector2d::UnitY(), r0.y(), w * params.along_wall_weight);
      }
    }
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(64 * blocks.size());
    for (std::size_t cell = 0; cell < cells; ++cell) {
      if (block_of[cell] < 0) continue;
      const auto& block = blocks[static_cast<std::size_t>(block_of[cell])];
      const std::size_t i = cell % (columns - 1), j = cell / (columns - 1);
      const std::array<std::size_t, 4> nodes = {j * columns + i, j * columns + i + 1, (j + 1) * columns + i,
                                                (j + 1) * columns + i + 1};
      for (std::size_t a = 0; a < 8; ++a) {
        for (std::size_t c = 0; c < 8; ++c) {
          const double v = block[a * 8 + c];
          if (v != 0.0) {
            triplets.emplace_back(static_cast<int>(2 * nodes[a / 2] + a % 2), static_cast<int>(2 * nodes[c / 2] + c % 2), v);
          }
        }
      }
    }
    Eigen::SparseMatrix<double> D(unknowns_, unknowns_);
    D.setFromTriplets(triplets.begin(), triplets.end());
    return D;
  }

  static bool within(int steps, int max_steps) { return steps >= 0 && steps <= max_steps; }
  static constexpr int kFactoredSteps = 40;   ///< preconditioned by a factorization of a near system: converges fast, or refactor
  static constexpr int kNearStartSteps = 100;  ///< incomplete Cholesky from a near start: 20-40 steps measured (docs/warp.md)

  /// Conjugate gradients on A x = b from `x`, preconditioned by `precondition` (r ↦ M⁻¹ r). Returns
  /// the steps taken when the residual fell below 1e-4 of b's (displacements to well under a
  /// millimetre), `max_steps + 1` when it did not within them (`x` is then the last iterate), −1 on
  /// a breakdown.
  template <class Precondition>
  int conjugate_gradients(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                          const Precondition& precondition, int max_steps) const {
    const double goal = 1e-4 * b.norm();
    Eigen::VectorXd r = b - A.selfadjointView<Eigen::Lower>() * x;
    if (r.norm() <= goal) return 0;
    Eigen::VectorXd z = precondition(r);
    Eigen::VectorXd p = z;
    double rz = r.dot(z);
    for (int step = 0; step < max_steps; ++step) {
      const Eigen::VectorXd Ap = A.selfadjointView<Eigen::Lower>() * p;
      const double pAp = p.dot(Ap);
      if (!(pAp > 0.0)) return -1;
      const double alpha = rz / pAp;
      x += alpha * p;
      r -= alpha * Ap;
      if (r.norm() <= goal) return step + 1;
      z = precondition(r);
      const double rz_next = r.dot(z);
      p = z + (rz_next / rz) * p;
      rz = rz_next;
    }
    return max_steps + 1;
  }

  Eigen::Index unknowns_;
  Eigen::SparseMatrix<double> smoothness_;
  Eigen::VectorXd rest_pull_;  ///< the rest term's right-hand side: rest weight × starting displacement
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor_;
  bool factored_ = false;
  Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::NaturalOrdering<int>> incomplete_;
  bool incomplete_ready_ = false;
};

/// The median and 95th percentile of `values` (NaN when empty); reorders them.
inline std::array<double, 2> median_and_p95(std::vector<double>& values) {
  if (values.empty()) return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  std::sort(values.begin(), values.end());
  auto at = [&](double q) { return values[std::min(values.size() - 1, static_cast<std::size_t>(q * static_cast<double>(values.size())))]; };
  return {at(0.5), at(0.95)};
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
  // The control grid over the source's walls (or its whole extent when it has none).
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

  // How well the walls lie, before and after, on the points the rigid transform brings near a wall.
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
  return out;
}

}  // namespace areamatch
