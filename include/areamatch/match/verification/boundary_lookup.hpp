#pragma once
/// \file match/verification/boundary_lookup.hpp
/// The destination side of ICP and of the wall evidence: boundary points with, per cell of a square
/// lookup grid, the nearest one (optionally per facing direction), and their normals.

#include "../../error.hpp"
#include "../../transform.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace areamatch {

/// The destination side of ICP: boundary points and, per cell of a square lookup grid, the index
/// of the (approximately) nearest one — a two-pass nearest-seed propagation, exact to a fraction
/// of a cell, which is all a shrinking-gate ICP needs — and optionally each point's normal.
class BoundaryLookup {
 public:
  BoundaryLookup() = default;
  /// A lookup over `points` on cells of `cell_m`, reaching `margin_m` beyond their bounding box;
  /// with `normal_radius_m` > 0, each point's normal from its neighbours within that radius.
  BoundaryLookup(std::vector<Eigen::Vector2d> points, double cell_m, double margin_m, double normal_radius_m = 0.0)
      : cell_m_(cell_m), reach_m_(margin_m), points_(std::move(points)) {
    if (points_.empty()) return;
    Eigen::Vector2d lo = points_.front(), hi = points_.front();
    for (const auto& p : points_) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    origin_ = lo - Eigen::Vector2d::Constant(margin_m);
    width_ = static_cast<int>(std::ceil((hi.x() - lo.x() + 2.0 * margin_m) / cell_m)) + 1;
    height_ = static_cast<int>(std::ceil((hi.y() - lo.y() + 2.0 * margin_m) / cell_m)) + 1;
    nearest_ = nearest_of([](std::size_t) { return true; });
    if (normal_radius_m > 0.0) compute_normals(normal_radius_m, lo, hi);
  }

  bool empty() const { return points_.empty(); }
  /// How far beyond its points it answers: `nearest` finds every point within this distance.
  double reach_m() const { return reach_m_; }
  const std::vector<Eigen::Vector2d>& points() const { return points_; }
  bool has_normals() const { return !normals_.empty(); }
  /// The unit normal at a point returned by `nearest` (lookups built with normals only); its
  /// sign is arbitrary.
  const Eigen::Vector2d& normal_at(const Eigen::Vector2d* point) const {
    return normals_[static_cast<std::size_t>(point - points_.data())];
  }
  /// Gives each point its free side (`free_sides`, one per point, in order) and builds the
  /// lookups of `nearest_facing`: one per quarter of the circle (sides within 67.5° of +x, +y,
  /// −x, −y; a point without a side in all four).
  void set_sides(std::vector<Eigen::Vector2d> sides) {
    if (sides.size() != points_.size()) throw parameter_error("BoundaryLookup::set_sides: one side per point");
    sides_ = std::move(sides);
    const double within = std::cos(0.375 * pi);  // 67.5°: quarters overlap near their edges
    for (int q = 0; q < 4; ++q) {
      const Eigen::Vector2d centre = quarter_centre(q);
      facing_[static_cast<std::size_t>(q)] = nearest_of([&](std::size_t i) {
        return sides_[i].isZero() || sides_[i].dot(centre) >= within;
      });
    }
  }
  bool has_sides() const { return !sides_.empty(); }
  /// The free side of a point returned by `nearest` (lookups given sides only).
  const Eigen::Vector2d& side_at(const Eigen::Vector2d* point) const {
    return sides_[static_cast<std::size_t>(point - points_.data())];
  }
  /// The boundary point nearest to p among those whose free side faces the way `side` does
  /// (within 112.5°: the quarter of the circle `side` falls in, widened; never the opposite
  /// face of a wall), or nullptr. A zero `side` or a lookup without sides: `nearest(p)`.
  const Eigen::Vector2d* nearest_facing(const Eigen::Vector2d& p, const Eigen::Vector2d& side) const {
    if (sides_.empty() || side.isZero()) return nearest(p);
    const int q = std::abs(side.x()) >= std::abs(side.y()) ? (side.x() > 0.0 ? 0 : 2) : (side.y() > 0.0 ? 1 : 3);
    return nearest_in(facing_[static_cast<std::size_t>(q)], p);
  }

  /// The boundary point nearest to p, or nullptr when p is outside the lookup grid.
  const Eigen::Vector2d* nearest(const Eigen::Vector2d& p) const { return nearest_in(nearest_, p); }

  /// How many of `points`, moved by T, have their `nearest` boundary point within `distance_m`.
  /// With `enough` > 0 it may stop once fewer than `enough` can be reached, returning the count
  /// so far (then below `enough`); a count of `enough` or more is always exact.
  std::size_t count_within(const std::vector<Eigen::Vector2d>& points, const Similarity2& T, double distance_m,
                           std::size_t enough = 0) const {
    std::size_t count = 0;
    const double d2 = distance_m * distance_m;
    const Eigen::Matrix2d linear = T.linear();
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector2d q = linear * points[i] + T.translation;  // T * p
      const Eigen::Vector2d* nearest_point = nearest(q);
      count += nearest_point && (*nearest_point - q).squaredNorm() <= d2;
      if (i % 16 == 15 && count + (points.size() - i - 1) < enough) break;
    }
    return count;
  }

 private:
  const Eigen::Vector2d* nearest_in(const std::vector<int>& cells, const Eigen::Vector2d& p) const {
    const double fx = (p.x() - origin_.x()) / cell_m_, fy = (p.y() - origin_.y()) / cell_m_;
    if (!(fx >= 0.0 && fy >= 0.0 && fx < width_ && fy < height_)) return nullptr;
    const int slot = cells[index(static_cast<int>(fx), static_cast<int>(fy))];
    return slot < 0 ? nullptr : &points_[static_cast<std::size_t>(slot)];
  }
  static Eigen::Vector2d quarter_centre(int q) {
    return q == 0 ? Eigen::Vector2d(1.0, 0.0) : q == 1 ? Eigen::Vector2d(0.0, 1.0) : q == 2 ? Eigen::Vector2d(-1.0, 0.0) : Eigen::Vector2d(0.0, -1.0);
  }
  /// Per cell, the index of the (approximately) nearest of the points `take(i)` accepts: each
  /// seeds its own cell, then `propagate`.
  template <class Take>
  std::vector<int> nearest_of(Take take) const {
    std::vector<int> cells(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_), -1);
    for (std::size_t i = 0; i < points_.size(); ++i) {
      if (!take(i)) continue;
      const auto [x, y] = cell_of(points_[i]);
      auto& slot = cells[index(x, y)];
      if (slot < 0 || distance2(points_[i], x, y) < distance2(points_[static_cast<std::size_t>(slot)], x, y)) {
        slot = static_cast<int>(i);
      }
    }
    propagate(cells);
    return cells;
  }
  std::pair<int, int> cell_of(const Eigen::Vector2d& p) const {
    return {std::clamp(static_cast<int>((p.x() - origin_.x()) / cell_m_), 0, width_ - 1),
            std::clamp(static_cast<int>((p.y() - origin_.y()) / cell_m_), 0, height_ - 1)};
  }
  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x);
  }
  double centre_x(int x) const { return origin_.x() + cell_m_ * (x + 0.5); }
  double centre_y(int y) const { return origin_.y() + cell_m_ * (y + 0.5); }
  static double squared_distance(const Eigen::Vector2d& p, double cx, double cy) {
    const double dx = p.x() - cx, dy = p.y() - cy;
    return dx * dx + dy * dy;
  }
  double distance2(const Eigen::Vector2d& p, int x, int y) const { return squared_distance(p, centre_x(x), centre_y(y)); }
  /// A cell (centre cx, cy) holding `slot` at squared distance `best` takes `candidate` if it is
  /// nearer; a neighbour holding the same point (most do) costs no distance.
  void consider(int& slot, double& best, int candidate, double cx, double cy) const {
    if (candidate < 0 || candidate == slot) return;
    const double d = squared_distance(points_[static_cast<std::size_t>(candidate)], cx, cy);
    if (slot < 0 || d < best) slot = candidate, best = d;
  }
  /// Two raster passes, down then up; in each, a cell looks at its neighbours already visited
  /// (left, above-left, above, above-right going down), then a sweep the other way along the row.
  void propagate(std::vector<int>& cells) const {
    const int W = width_, H = height_;
    std::vector<double> centres_x(static_cast<std::size_t>(W)), row_best(static_cast<std::size_t>(W));
    for (int x = 0; x < W; ++x) centres_x[static_cast<std::size_t>(x)] = centre_x(x);
    auto row = [&](int y) { return cells.data() + index(0, y); };
    for (int y = 0; y < H; ++y) sweep_row<1>(row(y), y > 0 ? row(y - 1) : nullptr, centre_y(y), centres_x, row_best);
    for (int y = H - 1; y >= 0; --y) sweep_row<-1>(row(y), y + 1 < H ? row(y + 1) : nullptr, centre_y(y), centres_x, row_best);
  }

  /// One row of a pass (`Step` 1 going down, −1 going up); `other` is the row visited before this
  /// one (above going down, below going up), or null. A cell's squared distance to its point,
  /// found in the first sweep, is kept in `row_best` for the second.
  template <int Step>
  void sweep_row(int* cells, const int* other, double cy, const std::vector<double>& centres_x, std::vector<double>& row_best) const {
    const int W = width_;
    const int first = Step > 0 ? 0 : W - 1, last = Step > 0 ? W - 1 : 0;
    auto visit = [&](int x, bool has_back, bool has_ahead) {
      int& slot = cells[x];
      const double cx = centres_x[static_cast<std::size_t>(x)];
      double best = slot < 0 ? 0.0 : squared_distance(points_[static_cast<std::size_t>(slot)], cx, cy);
      if (has_back) consider(slot, best, cells[x - Step], cx, cy);
      if (other) {
        consider(slot, best, other[x], cx, cy);
        if (has_back) consider(slot, best, other[x - Step], cx, cy);
        if (has_ahead) consider(slot, best, other[x + Step], cx, cy);
      }
      row_best[static_cast<std::size_t>(x)] = best;
    };
    visit(first, false, first != last);
    if (first != last) {
      for (int x = first + Step; x != last; x += Step) visit(x, true, true);  // the ends peeled off: no bounds tests
      visit(last, true, false);
    }
    for (int x = last - Step; x != first - Step; x -= Step) {
      consider(cells[x], row_best[static_cast<std::size_t>(x)], cells[x + Step], centres_x[static_cast<std::size_t>(x)], cy);
    }
  }

  /// Per point, the direction of least spread of the points within `radius` (2×2 covariance):
  /// across the wall. Neighbours are found in buckets of side `radius` over the points' box
  /// [lo, hi] (counting sort), so each point looks at 3 × 3 buckets.
  void compute_normals(double radius, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
    const int bx = static_cast<int>((hi.x() - lo.x()) / radius) + 1, by = static_cast<int>((hi.y() - lo.y()) / radius) + 1;
    auto bucket_of = [&](const Eigen::Vector2d& p) {
      return std::pair<int, int>{std::min(bx - 1, static_cast<int>((p.x() - lo.x()) / radius)),
                                 std::min(by - 1, static_cast<int>((p.y() - lo.y()) / radius))};
    };
    // The points sorted by bucket (counting sort, stable), in 32-bit indices: on a large floor
    // these arrays were a third of the lookup's memory at 64 bits.
    if (points_.size() >= std::numeric_limits<std::uint32_t>::max()) throw limit_error("BoundaryLookup: too many points");
    auto bucket_index = [&](const Eigen::Vector2d& p) {
      const auto [x, y] = bucket_of(p);
      return static_cast<std::size_t>(y) * static_cast<std::size_t>(bx) + static_cast<std::size_t>(x);
    };
    std::vector<std::uint32_t> start(static_cast<std::size_t>(bx) * static_cast<std::size_t>(by) + 1, 0), order(points_.size());
    for (const Eigen::Vector2d& p : points_) ++start[bucket_index(p) + 1];
    for (std::size_t b = 0; b + 1 < start.size(); ++b) start[b + 1] += start[b];
    {
      std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
      for (std::size_t i = 0; i < points_.size(); ++i) order[next[bucket_index(points_[i])]++] = static_cast<std::uint32_t>(i);
    }
    const double radius2 = radius * radius;
    normals_.assign(points_.size(), Eigen::Vector2d(1.0, 0.0));
    for (std::size_t i = 0; i < points_.size(); ++i) {
      const auto [x, y] = bucket_of(points_[i]);
      double n = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, syy = 0.0;
      for (int ny = std::max(0, y - 1); ny <= std::min(by - 1, y + 1); ++ny) {
        const std::size_t row = static_cast<std::size_t>(ny) * static_cast<std::size_t>(bx);
        // The three buckets of a row are consecutive in `order`.
        const std::size_t first = start[row + static_cast<std::size_t>(std::max(0, x - 1))];
        const std::size_t last = start[row + static_cast<std::size_t>(std::min(bx - 1, x + 1)) + 1];
        for (std::size_t k = first; k < last; ++k) {
          const Eigen::Vector2d d = points_[order[k]] - points_[i];
          if (d.squaredNorm() > radius2) continue;
          n += 1.0;
          sx += d.x();
          sy += d.y();
          sxx += d.x() * d.x();
          sxy += d.x() * d.y();
          syy += d.y() * d.y();
        }
      }
      if (n < 2.0) continue;  // a lone point: any direction is as good
      const double cxx = sxx - sx * sx / n, cxy = sxy - sx * sy / n, cyy = syy - sy * sy / n;
      const double along = 0.5 * std::atan2(2.0 * cxy, cxx - cyy);  // direction of most spread
      normals_[i] = Eigen::Vector2d(-std::sin(along), std::cos(along));
    }
  }

  double cell_m_ = 0.1;
  double reach_m_ = 0.0;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  int width_ = 0;
  int height_ = 0;
  std::vector<Eigen::Vector2d> points_;
  std::vector<int> nearest_;
  std::vector<Eigen::Vector2d> normals_;  ///< per point; empty when built without normals
  std::vector<Eigen::Vector2d> sides_;    ///< per point; empty unless `set_sides`
  std::array<std::vector<int>, 4> facing_;  ///< `nearest_` over the points facing each quarter
};

/// Share of `source_points` that land within `distance_m` of a destination boundary point under
/// T_dest_source: how well the walls agree.
inline double boundary_inlier_fraction(const std::vector<Eigen::Vector2d>& source_points, const BoundaryLookup& dest,
                                       const Similarity2& T_dest_source, double distance_m) {
  if (source_points.empty() || dest.empty()) return 0.0;
  return static_cast<double>(dest.count_within(source_points, T_dest_source, distance_m)) /
         static_cast<double>(source_points.size());
}

}  // namespace areamatch
