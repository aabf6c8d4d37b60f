#pragma once
/// \file warp/system.hpp
/// The linear algebra of `fit_warp` (warp/fit.hpp): the bending and rest terms as a sparse matrix,
/// wall points paired with destination walls, and the system solved for fixed pairs (a direct
/// factorisation on coarse grids, preconditioned conjugate gradients on fine ones).

#include "../match/verification/refine.hpp"
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
#include <vector>

namespace areamatch {
namespace detail {

/// The bending and rest terms of the energy over `field`'s nodes (2 unknowns a node: x, y).
///
/// The terms couple a node with the 13 nodes within two steps along a row or column or one
/// diagonally, and x with x, y with y only; they are summed per node and offset, then written
/// column by column in row order (no triplets to sort: a large grid's matrix is built in a few
/// milliseconds).
inline Eigen::SparseMatrix<double> smoothness_matrix(const WarpField& field, const WarpParams& params) {
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
  WarpSystem(const WarpField& field, const WarpParams& params)
      : unknowns_(static_cast<Eigen::Index>(2 * field.node_count())), rest_pull_(unknowns_) {
    smoothness_ = smoothness_matrix(field, params);
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

}  // namespace detail
}  // namespace areamatch
