#pragma once
/// \file warp/field.hpp
/// A smooth deformation from a source map's world frame to a destination's: a rigid (similarity)
/// transform plus a displacement interpolated bilinearly over a regular control grid laid on the
/// source — or, for a map broken into rigid pieces (a failed loop closure), one such grid per
/// piece, each point displaced by its own piece's, so that the warp jumps at a cut instead of
/// smearing it over a control cell. Fitted by `fit_warp` (warp/fit.hpp); applied to points here,
/// forwards and backwards.

#include "../error.hpp"
#include "../transform.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

namespace areamatch {

/// Which piece of a broken map each part of its world belongs to: labels on a square raster
/// (source world; a point beyond it takes the nearest cell's). Empty: one piece.
struct PieceLabels {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  ///< the corner of cell (0, 0), lowest x and y
  double cell_m = 1.0;
  int columns = 0, rows = 0;
  std::vector<int> labels;  ///< row-major from `origin`, each in [0, count())

  bool empty() const { return labels.empty(); }
  int count() const { return labels.empty() ? 1 : *std::max_element(labels.begin(), labels.end()) + 1; }
  /// The cell a source point falls in (the nearest cell beyond the raster), row-major.
  std::size_t cell_of(const Eigen::Vector2d& source_world) const {
    const Eigen::Vector2d u = (source_world - origin) / cell_m;
    const int c = std::clamp(static_cast<int>(std::floor(u.x())), 0, columns - 1);
    const int r = std::clamp(static_cast<int>(std::floor(u.y())), 0, rows - 1);
    return static_cast<std::size_t>(r) * static_cast<std::size_t>(columns) + static_cast<std::size_t>(c);
  }
  /// The piece at a source point.
  int at(const Eigen::Vector2d& source_world) const { return labels.empty() ? 0 : labels[cell_of(source_world)]; }
};

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

  /// Makes this a broken map's warp: the displacement at a point is that of `fields[k]`, k its
  /// piece in `labels` (each field with this one's rigid part); this field's own nodes are then
  /// not read. Throws `parameter_error` unless `fields` holds a field for every label and the
  /// raster's size matches its labels.
  void set_pieces(PieceLabels labels, std::vector<WarpField> fields) {
    const bool sized = labels.columns > 0 && labels.rows > 0 && labels.cell_m > 0.0 &&
                       labels.labels.size() == static_cast<std::size_t>(labels.columns) * static_cast<std::size_t>(labels.rows);
    const bool labelled = std::all_of(labels.labels.begin(), labels.labels.end(),
                                      [&](int k) { return k >= 0 && static_cast<std::size_t>(k) < fields.size(); });
    if (!labels.empty() && !(sized && labelled)) {
      throw parameter_error("WarpField::set_pieces: the piece labels must fill their raster and each name one of the fields");
    }
    piece_labels_ = std::move(labels);
    piece_fields_ = std::move(fields);
  }
  /// The pieces' own fields (empty: one field, this one's nodes) and which points each displaces.
  const std::vector<WarpField>& piece_fields() const { return piece_fields_; }
  const PieceLabels& piece_labels() const { return piece_labels_; }

  /// The displacement at a source point (destination metres).
  Eigen::Vector2d displacement(const Eigen::Vector2d& source_world) const {
    if (!piece_fields_.empty()) {
      return piece_fields_[static_cast<std::size_t>(piece_labels_.at(source_world))].own_displacement(source_world);
    }
    return own_displacement(source_world);
  }

  /// The displacement interpolated from this field's own nodes (for a broken map's warp, not the
  /// pieces'): what a fit on this grid solves for.
  Eigen::Vector2d own_displacement(const Eigen::Vector2d& source_world) const {
    const Stencil s = stencil(source_world);
    Eigen::Vector2d d = Eigen::Vector2d::Zero();
    for (std::size_t k = 0; k < 4; ++k) d += s.weights[k] * displacement_[s.nodes[k]];
    return d;
  }

  /// Whether no node is displaced: the field is its rigid part alone.
  bool is_rigid() const {
    if (!piece_fields_.empty()) {
      return std::all_of(piece_fields_.begin(), piece_fields_.end(), [](const WarpField& f) { return f.is_rigid(); });
    }
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
  /// rigid part, as any warp `fit_warp` makes does); within `tolerance_m` of exact. In a gap
  /// between a broken map's pieces, which no source point reaches (`preimage` says none), the one
  /// of the pieces' own inverses that the warp takes nearest to `dest_world` (within the gap's
  /// width of it).
  Eigen::Vector2d inverse(const Eigen::Vector2d& dest_world, double tolerance_m = 1e-6) const {
    if (piece_fields_.empty()) return inverse_of_own(dest_world, tolerance_m);
    if (const auto x = preimage(dest_world, tolerance_m)) return *x;
    Eigen::Vector2d nearest = Eigen::Vector2d::Zero();
    double best = std::numeric_limits<double>::infinity();
    for (const WarpField& piece : piece_fields_) {
      const Eigen::Vector2d x = piece.inverse_of_own(dest_world, tolerance_m);
      const double off = (apply(x) - dest_world).norm();
      if (off < best) best = off, nearest = x;
    }
    return nearest;
  }

  /// The source point the warp takes to `dest_world` (as `inverse`), or none where no source
  /// point goes: a gap between a broken map's pieces. A broken map's warp is inverted piece by
  /// piece; where pieces overlap after the warp, the first piece whose own inverse lies in it.
  std::optional<Eigen::Vector2d> preimage(const Eigen::Vector2d& dest_world, double tolerance_m = 1e-6) const {
    if (piece_fields_.empty()) return inverse_of_own(dest_world, tolerance_m);
    for (std::size_t k = 0; k < piece_fields_.size(); ++k) {
      const Eigen::Vector2d x = piece_fields_[k].inverse_of_own(dest_world, tolerance_m);
      if (piece_labels_.at(x) == static_cast<int>(k)) return x;
    }
    return std::nullopt;
  }

 private:
  Similarity2 rigid_;
  Eigen::Matrix2d rigid_linear_ = Eigen::Matrix2d::Identity();
  Eigen::Affine2d rigid_back_ = Eigen::Affine2d::Identity();  // the rigid part's inverse, for `inverse`
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  double spacing_ = 1.0;
  int columns_ = 2, rows_ = 2;
  std::vector<Eigen::Vector2d> displacement_ = std::vector<Eigen::Vector2d>(4, Eigen::Vector2d::Zero());
  PieceLabels piece_labels_;
  std::vector<WarpField> piece_fields_;  // a broken map's: one per piece (vector of an incomplete type: C++17)

  // `inverse` through this field's own nodes.
  Eigen::Vector2d inverse_of_own(const Eigen::Vector2d& dest_world, double tolerance_m) const {
    const Eigen::Affine2d& back = rigid_back_;
    Eigen::Vector2d x = back * dest_world;
    for (int iteration = 0; iteration < 50; ++iteration) {
      const Eigen::Vector2d next = back * (dest_world - own_displacement(x));
      const double moved = (next - x).norm();
      x = next;
      if (moved < tolerance_m) break;
    }
    return x;
  }
};

}  // namespace areamatch
