#pragma once
/// \file merge/double_walls.hpp
/// How much of a map's wall is doubled: a wall drawn twice a little apart, as when two maps that
/// bend differently are fused, or a SLAM map closed a loop imperfectly.
///
/// A **wall cell** is an occupied cell with a free 4-neighbour; its direction is the principal
/// axis of the occupied cells within `window_m` (a cell where they spread no way in particular,
/// a corner or a speck, has none and is never doubled). It is **doubled** when, looking from it
/// across the wall (either way along the normal), past its own wall's thickness, a run of free
/// cells `min_gap_m`–`max_gap_m` long ends at an occupied cell of a wall running the same way
/// (within `max_angle`): a parallel wall across a sliver of free space thinner than any room or
/// corridor. An unknown cell ends the look without a double.

#include "../error.hpp"
#include "../grid.hpp"
#include "../transform.hpp"

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace areamatch {

/// Parameters of `count_double_walls`, metres and radians.
struct DoubleWallParams {
  /// The sliver of free space between the two walls: from two cells' width at 0.05 m (one free
  /// cell between two walls is rasterisation, not a gap) to below the narrowest passage a person
  /// uses (0.4 m).
  double min_gap_m = 0.1;
  double max_gap_m = 0.4;
  /// The two walls must run the same way within this angle.
  double max_angle = pi / 6.0;
  /// A wall cell's direction comes from the occupied cells within this radius: a few cells, so
  /// that a wall bends with the map but a single cell's jag does not turn it.
  double window_m = 0.2;
  /// A wall is at most this thick: the look across it gives up inside an occupied run longer than this.
  double max_wall_thickness_m = 0.5;

  void validate() const {
    detail::require_positive(min_gap_m, "DoubleWallParams::min_gap_m");
    detail::require_positive(max_gap_m, "DoubleWallParams::max_gap_m");
    detail::require_positive(window_m, "DoubleWallParams::window_m");
    detail::require_positive(max_wall_thickness_m, "DoubleWallParams::max_wall_thickness_m");
    if (!(min_gap_m <= max_gap_m)) throw parameter_error("DoubleWallParams: min_gap_m must not exceed max_gap_m");
    if (!(max_angle > 0.0 && max_angle <= pi / 2.0)) throw parameter_error("DoubleWallParams::max_angle must be in (0, pi/2]");
  }
};

/// The count of `count_double_walls`.
struct DoubleWalls {
  std::size_t wall_cells = 0;     ///< occupied cells with a free 4-neighbour
  std::size_t doubled_cells = 0;  ///< of those, the doubled ones (file comment)
  std::vector<std::size_t> doubled;  ///< the doubled cells' indices (`OccupancyGrid::index`), in scan order
  /// doubled_cells / wall_cells (0 without walls).
  double share() const { return wall_cells ? static_cast<double>(doubled_cells) / static_cast<double>(wall_cells) : 0.0; }
};

namespace detail {

inline bool is_wall_cell(const OccupancyGrid& grid, int col, int row) {
  if (grid.at(col, row) != CellState::occupied) return false;
  constexpr int dc[4] = {1, -1, 0, 0}, dr[4] = {0, 0, 1, -1};
  for (int k = 0; k < 4; ++k) {
    if (grid.contains(col + dc[k], row + dr[k]) && grid.at(col + dc[k], row + dr[k]) == CellState::free) return true;
  }
  return false;
}

/// The unit direction (pixel axes) along which the occupied cells within `radius` cells of
/// (col, row) spread most; zero when they spread about as much every way (the larger spread
/// under twice the smaller).
inline Eigen::Vector2d wall_direction_in_pixels(const OccupancyGrid& grid, int col, int row, int radius) {
  Eigen::Matrix2d spread = Eigen::Matrix2d::Zero();
  for (int dr = -radius; dr <= radius; ++dr) {
    for (int dc = -radius; dc <= radius; ++dc) {
      if (dc * dc + dr * dr > radius * radius || !grid.contains(col + dc, row + dr)) continue;
      if (grid.at(col + dc, row + dr) != CellState::occupied) continue;
      const Eigen::Vector2d d(dc, dr);
      spread += d * d.transpose();
    }
  }
  // The eigenvector of the larger eigenvalue of the symmetric 2x2 matrix, in closed form.
  const double a = spread(0, 0), b = spread(0, 1), c = spread(1, 1);
  const double half_difference = 0.5 * (a - c), root = std::sqrt(half_difference * half_difference + b * b);
  const double larger = 0.5 * (a + c) + root, smaller = 0.5 * (a + c) - root;
  if (!(larger > 0.0) || larger < 2.0 * smaller) return Eigen::Vector2d::Zero();
  const double angle = 0.5 * std::atan2(2.0 * b, a - c);
  return {std::cos(angle), std::sin(angle)};
}

}  // namespace detail

/// Counts `grid`'s wall cells and the doubled ones (file comment). Throws `parameter_error` for
/// bad parameters.
inline DoubleWalls count_double_walls(const OccupancyGrid& grid, const DoubleWallParams& params = {}) {
  params.validate();
  DoubleWalls out;
  const double cell = grid.resolution();
  const int radius = std::max(1, static_cast<int>(std::lround(params.window_m / cell)));
  const double parallel = std::cos(params.max_angle);
  // Whether the look from (col, row) along `step` (a unit pixel vector) crosses the cell's own wall
  // and then min_gap..max_gap of free space to a wall running along `along`.
  auto doubled_towards = [&](int col, int row, const Eigen::Vector2d& step, const Eigen::Vector2d& along) {
    double first_free = -1.0;  // where the free run began, cells along the look
    int last_col = col, last_row = row;
    for (double t = 0.5;; t += 0.5) {
      const Eigen::Vector2d p = Eigen::Vector2d(col, row) + t * step;
      const int c = static_cast<int>(std::floor(p.x() + 0.5)), r = static_cast<int>(std::floor(p.y() + 0.5));
      if (c == last_col && r == last_row) continue;
      last_col = c, last_row = r;
      if (!grid.contains(c, r)) return false;
      const CellState state = grid.at(c, r);
      if (state == CellState::unknown) return false;
      if (state == CellState::free) {
        if (first_free < 0.0) first_free = t;
        if ((t - first_free) * cell > params.max_gap_m + cell) return false;
        continue;
      }
      if (first_free < 0.0) {  // still inside the cell's own wall
        if (t * cell > params.max_wall_thickness_m) return false;
        continue;
      }
      const double gap = (t - first_free) * cell;  // the free cells between the two walls
      if (gap < params.min_gap_m - 1e-9 || gap > params.max_gap_m + 1e-9) return false;
      return std::abs(detail::wall_direction_in_pixels(grid, c, r, radius).dot(along)) >= parallel;
    }
  };
  for (int row = 0; row < grid.height(); ++row) {
    for (int col = 0; col < grid.width(); ++col) {
      if (!detail::is_wall_cell(grid, col, row)) continue;
      ++out.wall_cells;
      const Eigen::Vector2d along = detail::wall_direction_in_pixels(grid, col, row, radius);
      if (along.isZero()) continue;
      const Eigen::Vector2d normal(-along.y(), along.x());
      if (doubled_towards(col, row, normal, along) || doubled_towards(col, row, -normal, along)) {
        ++out.doubled_cells;
        out.doubled.push_back(grid.index(col, row));
      }
    }
  }
  return out;
}

}  // namespace areamatch
