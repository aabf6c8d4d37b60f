#pragma once
/// \file warp/field.hpp
/// A smooth deformation from a source map's world frame to a destination's: a rigid (similarity)
/// transform plus a displacement interpolated bilinearly over a regular control grid laid on the
/// source. Fitted by `fit_warp` (warp/fit.hpp); applied to points here, forwards and backwards.

#include "../transform.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace areamatch {

class WarpField {
 public:
  WarpField() = default;
  /// A field of `columns` × `rows` nodes `spacing_m` apart from `origin` (source world), every
  /// displacement zero: the rigid transform alone.
  WarpField(const Similarity2& rigid, const Eigen::Vector2d& origin, double spacing_m, int columns, int rows)
      : rigid_(rigid), rigid_linear_(rigid.linear()), rigid_back_(rigid.affine().inverse()), origin_(origin), spacing_(spacing_m), columns_(std::max(columns, 2)), rows_(std::max(rows, 2)),
        displacement_(static_cast<std::size_t>(columns_) * static_cast<std::size_t>(rows_), Eigen::Vector2d::Zero()) {}

  /// The rigid transform alone (no displacement anywhere).
  explicit WarpField(const Similarity2& rigid) : WarpField(rigid, Eigen::Vector2d::Zero(), 1.0, 2, 2) {}

  /// The rigid part: source world → destination world.
  const Similarity2& rigid() const { return rigid_; }
  const Eigen::Vector2d& origin() const { return origin_; }
  double spacing() const { return spacing_; }
  int columns() const { return columns_; }
  int rows() const { return rows_; }
  std::size_t node_count() const { return displacement_.size(); }
  std::size_t node(int column, int row) const {
    return static_cast<std::size_t>(row) * static_cast<std::size_t>(columns_) + static_cast<std::size_t>(column);
  }
  /// A node's displacement, destination metres, added after the rigid transform.
  const Eigen::Vector2d& node_displacement(std::size_t i) const { return displacement_[i]; }
  Eigen::Vector2d& node_displacement(std::size_t i) { return displacement_[i]; }
  /// A node's position in the source world.
  Eigen::Vector2d node_position(int column, int row) const {
    return origin_ + spacing_ * Eigen::Vector2d(column, row);
  }

  /// The four nodes around a source point and their bilinear weights (beyond the grid: its
  /// nearest border, so the displacement continues flat).
  struct Stencil {
    std::array<std::size_t, 4> nodes{};
    std::array<double, 4> weights{};
  };
  Stencil stencil(const Eigen::Vector2d& source_world) const {
    const Eigen::Vector2d u = (source_world - origin_) / spacing_;
    const double x = std::clamp(u.x(), 0.0, static_cast<double>(columns_ - 1));
    const double y = std::clamp(u.y(), 0.0, static_cast<double>(rows_ - 1));
    const int i = std::min(static_cast<int>(x), columns_ - 2), j = std::min(static_cast<int>(y), rows_ - 2);
    const double tx = x - i, ty = y - j;
    Stencil s;
    s.nodes = {node(i, j), node(i + 1, j), node(i, j + 1), node(i + 1, j + 1)};
    s.weights = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
    return s;
  }

  /// The displacement at a source point (destination metres).
  Eigen::Vector2d displacement(const Eigen::Vector2d& source_world) const {
    const Stencil s = stencil(source_world);
    Eigen::Vector2d d = Eigen::Vector2d::Zero();
    for (std::size_t k = 0; k < 4; ++k) d += s.weights[k] * displacement_[s.nodes[k]];
    return d;
  }

  /// Whether no node is displaced: the field is its rigid part alone.
  bool is_rigid() const {
    return std::all_of(displacement_.begin(), displacement_.end(), [](const Eigen::Vector2d& d) { return d.isZero(0.0); });
  }

  /// The rigid part alone at a source point (its matrix kept: no sine and cosine per point).
  Eigen::Vector2d apply_rigid(const Eigen::Vector2d& source_world) const {
    return rigid_linear_ * source_world + rigid_.translation;
  }

  /// Source world → destination world.
  Eigen::Vector2d apply(const Eigen::Vector2d& source_world) const { return apply_rigid(source_world) + displacement(source_world); }

  /// Destination world → source world: the point the warp takes to `dest_world`, by fixed-point
  /// iteration x ← T⁻¹(y − d(x)) (which converges while the displacement bends less than the
  /// rigid part, as any warp `fit_warp` makes does); within `tolerance_m` of exact.
  Eigen::Vector2d inverse(const Eigen::Vector2d& dest_world, double tolerance_m = 1e-6) const {
    const Eigen::Affine2d& back = rigid_back_;
    Eigen::Vector2d x = back * dest_world;
    for (int iteration = 0; iteration < 50; ++iteration) {
      const Eigen::Vector2d next = back * (dest_world - displacement(x));
      const double moved = (next - x).norm();
      x = next;
      if (moved < tolerance_m) break;
    }
    return x;
  }

 private:
  Similarity2 rigid_;
  Eigen::Matrix2d rigid_linear_ = Eigen::Matrix2d::Identity();
  Eigen::Affine2d rigid_back_ = Eigen::Affine2d::Identity();  // the rigid part's inverse, for `inverse`
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  double spacing_ = 1.0;
  int columns_ = 2, rows_ = 2;
  std::vector<Eigen::Vector2d> displacement_ = std::vector<Eigen::Vector2d>(4, Eigen::Vector2d::Zero());
};

}  // namespace areamatch
