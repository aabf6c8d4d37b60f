#pragma once
/// \file match/refine.hpp
/// Trimmed ICP on the boundaries of the two maps' area-covered free space: turns a coarse
/// per-area transform into an accurate global one (docs/algorithm.md). The
/// matching gate shrinks from `gates_m.front()` to `gates_m.back()`; at each step only the
/// `keep_fraction` closest correspondences count, so laser streaks, furniture and rooms one map
/// lacks do not pull the result. Each step minimises the distances to the destination's walls
/// along their normals (point-to-line), so the walls across a corridor pin a map sliding along
/// it; point-to-point steps, which pull every point towards its nearest boundary point, stop
/// short there. With `RefineParams::same_side_only` (merging's refinement) a point is paired
/// with the nearest wall that faces free space the same way: the two faces of a wall between a
/// room one map entered and one only the other did look opposite ways, a wall's thickness apart,
/// and would pull the map across it.

#include "../area_graph.hpp"
#include "../error.hpp"
#include "../grid.hpp"
#include "raster.hpp"
#include "../transform.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

namespace areamatch {

struct RefineParams {
  std::vector<double> gates_m{2.0, 1.2, 0.7, 0.4};  ///< correspondence gates, one stage each
  int iterations_per_gate = 4;
  double keep_fraction = 0.8;       ///< share of the gated correspondences kept (closest first)
  double point_spacing_m = 0.1;     ///< source boundary points are thinned to about this spacing
  int max_points = 2000;            ///< and to at most this many
  double lookup_cell_m = 0.1;       ///< cell of the destination's nearest-boundary-point lookup
  /// Also fit the scale (a similarity instead of a rigid motion); each iteration may change it by
  /// at most `max_scale_step` (factor), so a bad early match cannot collapse the map. The scale is
  /// fitted by point-to-point steps (point-to-line ones fitting it too lost lab_b_rot123 in
  /// `areamatch eval --estimate-scale`: docs/matching.md).
  bool estimate_scale = false;
  double max_scale_step = 1.1;
  /// Minimise distances along the destination's wall normals (point-to-line) rather than to the
  /// nearest boundary points; needs a lookup built with normals (`BoundaryLookup`'s
  /// `normal_radius_m`), else point-to-point.
  bool point_to_line = true;
  /// The destination's wall normals come from its boundary points within this radius (the
  /// matcher builds its destination lookup with `MatcherParams::refinement`'s).
  double normal_radius_m = 0.2;
  /// Pair a source edge point with the nearest destination edge point that faces the same way
  /// (`BoundaryLookup::nearest_facing`, when both maps' free sides are known: `free_sides`),
  /// not merely the nearest. Across a wall the two faces look opposite ways; without this, the
  /// face of a room only one map entered is pulled onto the other face of its wall, a wall's
  /// thickness away (0.11–0.13 m off on partial robot maps). Off in the matcher (measured there,
  /// not adopted: docs/matching.md); merging refines its accepted matches with it (`MergeParams`).
  bool same_side_only = false;
  /// An edge point's free side: the direction to the free cells within this radius, less the
  /// direction to the others (at least the point's 8 neighbours).
  double free_side_radius_m = 0.1;
  /// A gate's iterations stop early once a step turns by less than `converged_rad` and moves by
  /// less than `converged_m` (and, fitting the scale, changes it by a factor within
  /// `converged_scale` of 1): far below what the evidence can tell apart, so more steps change
  /// nothing a user could see.
  double converged_rad = 1e-5;
  double converged_m = 1e-4;
  double converged_scale = 1e-6;

  void validate() const {
    if (gates_m.empty()) throw parameter_error("RefineParams::gates_m must not be empty");
    for (double g : gates_m) detail::require_positive(g, "RefineParams::gates_m");
    if (iterations_per_gate < 1) throw parameter_error("RefineParams::iterations_per_gate must be >= 1");
    if (!(keep_fraction > 0.0 && keep_fraction <= 1.0)) throw parameter_error("RefineParams::keep_fraction must be in (0, 1]");
    detail::require_positive(point_spacing_m, "RefineParams::point_spacing_m");
    if (max_points < 3) throw parameter_error("RefineParams::max_points must be >= 3");
    detail::require_positive(lookup_cell_m, "RefineParams::lookup_cell_m");
    detail::require_positive(normal_radius_m, "RefineParams::normal_radius_m");
    detail::require_positive(free_side_radius_m, "RefineParams::free_side_radius_m");
    detail::require_non_negative(converged_rad, "RefineParams::converged_rad");
    detail::require_non_negative(converged_m, "RefineParams::converged_m");
    detail::require_non_negative(converged_scale, "RefineParams::converged_scale");
    if (!(max_scale_step >= 1.0 && std::isfinite(max_scale_step))) {
      throw parameter_error("RefineParams::max_scale_step must be a finite factor >= 1");
    }
  }
};

namespace detail {

/// The cells within `bounds` on the edge of a region (a cell inside with a 4-neighbour outside
/// or off the grid), as row-major indices in scan order. `inside(index)` tells whether a cell
/// is in the region; it is asked once per cell of `bounds` and the ring around it (the
/// neighbours of border cells count whether or not they lie in `bounds`), then the edge test
/// reads a mask with a false border instead of checking the grid's bounds four times a cell.
template <class Inside>
std::vector<std::size_t> edge_cells(const GridInfo& g, const PixelBounds& bounds, Inside inside) {
  std::vector<std::size_t> out;
  if (bounds.empty()) return out;
  const int x0 = bounds.col0 - 1, y0 = bounds.row0 - 1;
  const int mask_w = bounds.col1 - bounds.col0 + 2, mask_h = bounds.row1 - bounds.row0 + 2;
  const auto width = static_cast<std::size_t>(g.width);
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(mask_w) * static_cast<std::size_t>(mask_h), 0);
  for (int my = 0; my < mask_h; ++my) {
    const int y = y0 + my;
    if (y < 0 || y >= g.height) continue;
    std::uint8_t* row = mask.data() + static_cast<std::size_t>(my) * static_cast<std::size_t>(mask_w);
    const std::size_t grid_row = static_cast<std::size_t>(y) * width;
    const int mx_end = std::min(mask_w, g.width - x0);
    for (int mx = std::max(0, -x0); mx < mx_end; ++mx) row[mx] = inside(grid_row + static_cast<std::size_t>(x0 + mx)) ? 1 : 0;
  }
  for (int my = 1; my + 1 < mask_h; ++my) {
    const std::uint8_t* row = mask.data() + static_cast<std::size_t>(my) * static_cast<std::size_t>(mask_w);
    const std::uint8_t* above = row - mask_w;
    const std::uint8_t* below = row + mask_w;
    const std::size_t grid_row = static_cast<std::size_t>(y0 + my) * width;
    for (int mx = 1; mx + 1 < mask_w; ++mx) {
      if (mx + 8 < mask_w) {  // most cells are outside the region: skip eight at a time
        std::uint64_t eight;
        std::memcpy(&eight, row + mx, sizeof eight);
        if (!eight) {
          mx += 7;
          continue;
        }
      }
      if (!row[mx] || (row[mx - 1] & row[mx + 1] & above[mx] & below[mx])) continue;
      out.push_back(grid_row + static_cast<std::size_t>(x0 + mx));
    }
  }
  return out;
}

/// Visits the edge cells `cells` (from `edge_cells`: in scan order, so the first and last are in
/// the top and bottom rows), at most one per `spacing_m` square: `take(index, world)` gets the
/// cell's row-major index and world position and returns whether it took it (the square is then
/// used up).
template <class Take>
void for_each_edge_cell(const GridInfo& g, const std::vector<std::size_t>& cells, double spacing_m, Take take) {
  if (cells.empty()) return;
  const int step = std::max(1, static_cast<int>(std::lround(spacing_m / g.resolution)));
  const auto width = static_cast<std::size_t>(g.width);
  // The squares are the grid's (row and column divided by `step`); only those the cells span get a flag.
  int bin_x0 = std::numeric_limits<int>::max(), bin_x1 = 0;
  for (const std::size_t i : cells) {
    bin_x0 = std::min(bin_x0, static_cast<int>(i % width) / step);
    bin_x1 = std::max(bin_x1, static_cast<int>(i % width) / step);
  }
  const int bin_y0 = static_cast<int>(cells.front() / width) / step, bin_y1 = static_cast<int>(cells.back() / width) / step;
  const auto bins_x = static_cast<std::size_t>(bin_x1 - bin_x0 + 1);
  std::vector<std::uint8_t> taken(bins_x * static_cast<std::size_t>(bin_y1 - bin_y0 + 1), 0);
  const Eigen::Affine2d world = g.world_from_pixel();
  for (const std::size_t i : cells) {
    const int x = static_cast<int>(i % width), y = static_cast<int>(i / width);
    auto& bin = taken[static_cast<std::size_t>(y / step - bin_y0) * bins_x + static_cast<std::size_t>(x / step - bin_x0)];
    if (bin) continue;
    if (take(i, Eigen::Vector2d(world * Eigen::Vector2d(x, y)))) bin = 1;
  }
}

/// World positions of edge cells (from `edge_cells`) at most one per `spacing_m` square, then
/// thinned evenly to at most `max_points`.
inline std::vector<Eigen::Vector2d> boundary_points(const GridInfo& g, const std::vector<std::size_t>& cells, double spacing_m,
                                                    std::size_t max_points = std::numeric_limits<std::size_t>::max()) {
  std::vector<Eigen::Vector2d> points;
  for_each_edge_cell(g, cells, spacing_m, [&](std::size_t, const Eigen::Vector2d& p) {
    points.push_back(p);
    return true;
  });
  if (points.size() > max_points) {
    std::vector<Eigen::Vector2d> thinned;
    thinned.reserve(max_points);
    for (std::size_t i = 0; i < max_points; ++i) thinned.push_back(points[i * points.size() / max_points]);
    points.swap(thinned);
  }
  return points;
}

/// The edge cells of a map's free space (what the reference scorer's boundary is made of)
/// within the extent of its areas: free streaks far outside the building do not count.
inline std::vector<std::size_t> free_edge_cells(const OccupancyGrid& grid, const AreaGraph& graph) {
  const auto& cells = grid.cells();
  return edge_cells(graph.grid, label_bounds(graph), [&](std::size_t i) { return cells[i] == CellState::free; });
}

/// Edge points of a map's free space within the extent of its areas (`free_edge_cells`).
inline std::vector<Eigen::Vector2d> free_boundary_points(const OccupancyGrid& grid, const AreaGraph& graph, double spacing_m,
                                                         std::size_t max_points = std::numeric_limits<std::size_t>::max()) {
  return boundary_points(graph.grid, free_edge_cells(grid, graph), spacing_m, max_points);
}

/// Each free-space edge point's free side (`RefineParams::free_side_radius_m`): the unit
/// direction, in world coordinates, of the free cells within `radius_m` (at least one cell) less
/// that of the others, off-grid cells counting as not free; zero where they balance.
inline std::vector<Eigen::Vector2d> free_sides(const OccupancyGrid& grid, const std::vector<Eigen::Vector2d>& points,
                                               double radius_m) {
  const int reach = std::max(1, static_cast<int>(std::lround(radius_m / grid.resolution())));
  const Eigen::Affine2d world_from_pixel = grid.world_from_pixel();
  const Eigen::Affine2d pixel_from_world = world_from_pixel.inverse();
  std::vector<Eigen::Vector2d> sides;
  sides.reserve(points.size());
  for (const auto& p : points) {
    const Eigen::Vector2d pixel = pixel_from_world * p;
    const int col = static_cast<int>(std::floor(pixel.x() + 0.5)), row = static_cast<int>(std::floor(pixel.y() + 0.5));
    int sx = 0, sy = 0;
    for (int dy = -reach; dy <= reach; ++dy) {
      for (int dx = -reach; dx <= reach; ++dx) {
        const int sign = grid.contains(col + dx, row + dy) && grid.is_free(col + dx, row + dy) ? 1 : -1;
        sx += sign * dx;
        sy += sign * dy;
      }
    }
    const Eigen::Vector2d side = world_from_pixel.linear() * Eigen::Vector2d(sx, sy);
    const double norm = side.norm();
    sides.push_back(norm > 0.0 ? Eigen::Vector2d(side / norm) : Eigen::Vector2d::Zero());
  }
  return sides;
}

/// Edge points of the area-covered free space.
inline std::vector<Eigen::Vector2d> area_boundary_points(const AreaGraph& graph, double spacing_m,
                                                         std::size_t max_points = std::numeric_limits<std::size_t>::max()) {
  const auto cells = edge_cells(graph.grid, label_bounds(graph), [&](std::size_t i) { return graph.labels[i] >= 0; });
  return boundary_points(graph.grid, cells, spacing_m, max_points);
}

}  // namespace detail

/// The destination side of ICP: boundary points and, per cell of a square lookup grid, the index
/// of the (approximately) nearest one — a two-pass nearest-seed propagation, exact to a fraction
/// of a cell, which is all a shrinking-gate ICP needs — and optionally each point's normal.
class BoundaryLookup {
 public:
  BoundaryLookup() = default;
  /// A lookup over `points` on cells of `cell_m`, reaching `margin_m` beyond their bounding box;
  /// with `normal_radius_m` > 0, each point's normal from its neighbours within that radius.
  BoundaryLookup(std::vector<Eigen::Vector2d> points, double cell_m, double margin_m, double normal_radius_m = 0.0)
      : cell_m_(cell_m), points_(std::move(points)) {
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
    std::vector<std::size_t> start(static_cast<std::size_t>(bx) * static_cast<std::size_t>(by) + 1, 0), order(points_.size());
    std::vector<std::size_t> bucket(points_.size());
    for (std::size_t i = 0; i < points_.size(); ++i) {
      const auto [x, y] = bucket_of(points_[i]);
      bucket[i] = static_cast<std::size_t>(y) * static_cast<std::size_t>(bx) + static_cast<std::size_t>(x);
      ++start[bucket[i] + 1];
    }
    for (std::size_t b = 0; b + 1 < start.size(); ++b) start[b + 1] += start[b];
    std::vector<std::size_t> next(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < points_.size(); ++i) order[next[bucket[i]]++] = i;
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

/// Trimmed ICP from `initial`: the rigid transform (reflection and scale kept; the scale fitted
/// too with `params.estimate_scale`) that best lays `source_points` onto the destination
/// boundary. Point-to-line steps with `params.point_to_line` and a lookup with normals (rigid
/// only), else point-to-point. With `source_sides` (the points' free sides, `free_sides`; empty:
/// none) and a lookup with sides, `params.same_side_only` pairs each point with the nearest wall
/// facing the same way. Returns `initial` when too few points match.
inline Similarity2 refine_icp(const std::vector<Eigen::Vector2d>& source_points, const BoundaryLookup& dest,
                              const Similarity2& initial, const RefineParams& params,
                              const std::vector<Eigen::Vector2d>* source_sides = nullptr) {
  Similarity2 T = initial;
  if (dest.empty() || source_points.size() < 3) return T;
  const bool same_side = params.same_side_only && source_sides && !source_sides->empty() && dest.has_sides();
  if (same_side && source_sides->size() != source_points.size()) {
    throw parameter_error("refine_icp: one free side per source point");
  }
  // Small, because trimming moves every match: the destination point by address (its normal,
  // for point-to-line, looked up from it when summing).
  struct Match {
    double distance2;
    Eigen::Vector2d from;  // F·scale·x, the source point before rotation
    const Eigen::Vector2d* to;
  };
  const bool point_to_line = params.point_to_line && dest.has_normals() && !params.estimate_scale;
  std::vector<Match> matches;
  matches.reserve(source_points.size());
  Similarity2 shape{0.0, Eigen::Vector2d::Zero(), initial.scale, initial.reflected};
  for (double gate : params.gates_m) {
    for (int iteration = 0; iteration < params.iterations_per_gate; ++iteration) {
      matches.clear();
      const Eigen::Matrix2d rotation = Eigen::Rotation2Dd(T.rotation).toRotationMatrix();
      const Eigen::Matrix2d side_turn = rotation * shape.linear();  // scale does not change a side's direction
      for (std::size_t i = 0; i < source_points.size(); ++i) {
        const Eigen::Vector2d from = shape * source_points[i];
        const Eigen::Vector2d y = rotation * from + T.translation;
        const Eigen::Vector2d* d = same_side ? dest.nearest_facing(y, side_turn * (*source_sides)[i]) : dest.nearest(y);
        if (!d) continue;
        const double d2 = (*d - y).squaredNorm();
        if (d2 <= gate * gate) matches.push_back({d2, from, d});
      }
      if (matches.size() < 3) return T;
      const std::size_t keep = std::max<std::size_t>(3, static_cast<std::size_t>(params.keep_fraction * matches.size()));
      if (keep < matches.size()) {
        std::nth_element(matches.begin(), matches.begin() + static_cast<std::ptrdiff_t>(keep), matches.end(),
                         [](const Match& a, const Match& b) { return a.distance2 < b.distance2; });
        matches.resize(keep);
      }
      if (point_to_line) {
        // Linearised about the matched points' centre c: a small turn a about c and a shift t
        // move y to y + a·perp(y − c) + t; minimise Σ ((that − to)·normal)² (3×3 normal equations).
        Eigen::Vector2d c = Eigen::Vector2d::Zero();
        for (const auto& m : matches) c += rotation * m.from;
        c = c / static_cast<double>(matches.size()) + T.translation;
        // The sums in scalars, the symmetric A's six entries once each: accumulating a 3×3
        // temporary per match stalled on its stack round trip (a fifth of ICP's time). Same sums.
        double a00 = 0.0, a01 = 0.0, a02 = 0.0, a11 = 0.0, a12 = 0.0, a22 = 0.0, b0 = 0.0, b1 = 0.0, b2 = 0.0;
        for (const auto& m : matches) {
          const Eigen::Vector2d y = rotation * m.from + T.translation, q = y - c;
          const Eigen::Vector2d& normal = dest.normal_at(m.to);
          const double j0 = q.x() * normal.y() - q.y() * normal.x(), j1 = normal.x(), j2 = normal.y();
          const double residual = (y - *m.to).dot(normal);
          a00 += j0 * j0;
          a01 += j0 * j1;
          a02 += j0 * j2;
          a11 += j1 * j1;
          a12 += j1 * j2;
          a22 += j2 * j2;
          b0 -= j0 * residual;
          b1 -= j1 * residual;
          b2 -= j2 * residual;
        }
        Eigen::Matrix3d A;
        A << a00, a01, a02, a01, a11, a12, a02, a12, a22;
        const Eigen::Vector3d b(b0, b1, b2);
        // A tiny ridge keeps a direction no wall constrains (a straight corridor's length) where it is.
        const Eigen::Vector3d step = (A + (1e-9 * A.trace() + 1e-12) * Eigen::Matrix3d::Identity()).ldlt().solve(b);
        const Eigen::Rotation2Dd turn(step(0));
        T.rotation = wrap_angle(T.rotation + step(0));
        T.translation = turn * (T.translation - c) + c + step.tail<2>();
        if (std::abs(step(0)) < params.converged_rad && step.tail<2>().norm() < params.converged_m) break;
        continue;
      }
      // 2D Procrustes: the rotation that best turns the centred source points onto the targets.
      Eigen::Vector2d mean_from = Eigen::Vector2d::Zero(), mean_to = Eigen::Vector2d::Zero();
      for (const auto& m : matches) {
        mean_from += m.from;
        mean_to += *m.to;
      }
      mean_from /= static_cast<double>(matches.size());
      mean_to /= static_cast<double>(matches.size());
      double dot = 0.0, cross = 0.0;
      for (const auto& m : matches) {
        const Eigen::Vector2d a = m.from - mean_from, b = *m.to - mean_to;
        dot += a.dot(b);
        cross += a.x() * b.y() - a.y() * b.x();
      }
      const double angle = std::atan2(cross, dot);
      const Eigen::Rotation2Dd turn(angle);
      // With scale: the factor k minimising Σ |b − k·R·a|² is Σ b·(R·a) / Σ |a|².
      double k = 1.0;
      if (params.estimate_scale) {
        double along = 0.0, norm2 = 0.0;
        for (const auto& m : matches) {
          const Eigen::Vector2d a = m.from - mean_from;
          along += (*m.to - mean_to).dot(turn * a);
          norm2 += a.squaredNorm();
        }
        if (norm2 > 0.0 && along > 0.0) k = std::clamp(along / norm2, 1.0 / params.max_scale_step, params.max_scale_step);
        shape.scale *= k;
      }
      const Similarity2 previous = T;
      T.rotation = wrap_angle(angle);
      T.scale = shape.scale;
      T.translation = mean_to - turn * (k * mean_from);
      if (std::abs(wrap_angle(T.rotation - previous.rotation)) < params.converged_rad &&
          (T.translation - previous.translation).norm() < params.converged_m && std::abs(k - 1.0) < params.converged_scale) {
        break;
      }
    }
  }
  return T;
}

}  // namespace areamatch
