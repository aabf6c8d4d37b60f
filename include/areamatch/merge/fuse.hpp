#pragma once
/// \file merge/fuse.hpp
/// One occupancy grid from several maps laid in one frame, cell by cell.
///
/// Each cell of the merged grid asks every map what lies under its centre (nearest cell after
/// the map's pose) and counts the maps that saw it occupied and free. The rule:
///
///   occupied  when some map saw a wall there and occupied ≥ `wall_share` · (occupied + free):
///             by default a wall seen by half the maps that saw the cell at all stays a wall, so a
///             wall seen by one of two maps is kept (a door closed in one scan, a thin layout wall
///             the other map saw a cell beside) and one map's speckle is outvoted by several
///   free      when some map saw it free and it is not occupied
///   unknown   when no map saw it.

#include "../error.hpp"
#include "../grid.hpp"
#include "../image.hpp"
#include "../transform.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace areamatch {

/// Parameters of `fuse_maps`.
struct FuseParams {
  /// Metres per cell of the merged grid; 0: the finest of the maps'.
  double resolution = 0.0;
  /// A cell is occupied when at least this share of the maps that saw it saw it occupied (see the
  /// file comment); in (0, 1].
  double wall_share = 0.5;
  /// Unknown border kept around the cells some map saw (the maps' unknown margins are cut away:
  /// hand-held scans are mostly margin); negative: keep the maps' whole extent.
  double margin_m = 1.0;

  void validate() const {
    detail::require_non_negative(resolution, "FuseParams::resolution");
    if (!std::isfinite(margin_m)) throw parameter_error("FuseParams::margin_m must be finite");
    if (!(wall_share > 0.0 && wall_share <= 1.0)) {
      throw parameter_error("FuseParams::wall_share must be in (0, 1], got " + std::to_string(wall_share));
    }
  }
};

/// The corners of a grid's image in its world frame.
inline std::array<Eigen::Vector2d, 4> grid_corners(const OccupancyGrid& grid) {
  const double w = grid.width() - 0.5, h = grid.height() - 0.5;
  return {grid.pixel_to_world({-0.5, -0.5}), grid.pixel_to_world({w, -0.5}), grid.pixel_to_world({w, h}),
          grid.pixel_to_world({-0.5, h})};
}

namespace detail {

/// The pixel box of `grid`'s known (free or occupied) cells, inclusive; empty (col1 < 0) when
/// none is known.
struct CellBox {
  int col0 = 0, col1 = -1, row0 = 0, row1 = -1;
  bool empty() const { return col1 < col0; }
};

inline CellBox known_box(const OccupancyGrid& grid) {
  CellBox box{grid.width(), -1, grid.height(), -1};
  for (int row = 0; row < grid.height(); ++row) {
    for (int col = 0; col < grid.width(); ++col) {
      if (grid.at(col, row) == CellState::unknown) continue;
      box.col0 = std::min(box.col0, col), box.col1 = std::max(box.col1, col);
      box.row0 = std::min(box.row0, row), box.row1 = std::max(box.row1, row);
    }
  }
  return box;
}

/// The world corners of the box of `grid`'s known (free or occupied) cells; the whole image's
/// when none is known. Cells outside it vote for nothing, so fusion reads only inside it (a
/// hand-held scan is mostly unknown margin).
inline std::array<Eigen::Vector2d, 4> known_corners(const OccupancyGrid& grid) {
  const CellBox box = known_box(grid);
  if (box.empty()) return grid_corners(grid);
  const double c0 = box.col0 - 0.5, c1 = box.col1 + 0.5, r0 = box.row0 - 0.5, r1 = box.row1 + 0.5;
  return {grid.pixel_to_world({c0, r0}), grid.pixel_to_world({c1, r0}), grid.pixel_to_world({c1, r1}),
          grid.pixel_to_world({c0, r1})};
}

/// `grid` cut to the bounding box of its known cells plus `margin_m` (unchanged when all unknown).
inline OccupancyGrid crop_to_known(const OccupancyGrid& grid, double margin_m) {
  const CellBox box = known_box(grid);
  if (box.empty()) return grid;
  const int margin = static_cast<int>(std::ceil(margin_m / grid.resolution()));
  const int col0 = std::max(0, box.col0 - margin), row0 = std::max(0, box.row0 - margin);
  const int col1 = std::min(grid.width() - 1, box.col1 + margin), row1 = std::min(grid.height() - 1, box.row1 + margin);
  // The new lower-left corner: the old one moved by the columns cut on the left and the rows cut
  // at the bottom (rows count from the top).
  const Pose2 origin{grid.origin().x + col0 * grid.resolution(),
                     grid.origin().y + (grid.height() - 1 - row1) * grid.resolution(), 0.0};
  OccupancyGrid out(col1 - col0 + 1, row1 - row0 + 1, grid.resolution(), origin);
  for (int row = row0; row <= row1; ++row) {
    for (int col = col0; col <= col1; ++col) out.set(col - col0, row - row0, grid.at(col, row));
  }
  return out;
}

}  // namespace detail

/// Lays `maps[i]` into one grid by `T_reference_map[i]` (map world → the merged grid's world
/// frame) and fuses them by the rule of the file comment. The merged grid's origin has yaw 0; it
/// covers the cells some map saw plus `margin_m` (or the maps' whole union). Throws `limit_error`
/// when that needs more than `max_grid_cells` cells at the resolution.
inline OccupancyGrid fuse_maps(const std::vector<const OccupancyGrid*>& maps, const std::vector<Similarity2>& T_reference_map,
                               const FuseParams& params = {}) {
  params.validate();
  if (maps.empty() || maps.size() != T_reference_map.size()) {
    throw parameter_error("fuse_maps: needs at least one map and one pose per map");
  }
  if (maps.size() > std::numeric_limits<std::uint16_t>::max()) throw limit_error("fuse_maps: more than 65535 maps");
  double resolution = params.resolution;
  Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d high = -low;
  std::vector<std::array<Eigen::Vector2d, 4>> corners;  // of each map's known cells, its world
  for (std::size_t i = 0; i < maps.size(); ++i) {
    if (maps[i] == nullptr || maps[i]->empty()) throw parameter_error("fuse_maps: map " + std::to_string(i) + " is empty");
    if (params.resolution == 0.0) resolution = i == 0 ? maps[i]->resolution() : std::min(resolution, maps[i]->resolution());
    corners.push_back(params.margin_m < 0.0 ? grid_corners(*maps[i]) : detail::known_corners(*maps[i]));
    for (const auto& corner : corners.back()) {
      const Eigen::Vector2d p = T_reference_map[i] * corner;
      low = low.cwiseMin(p);
      high = high.cwiseMax(p);
    }
  }
  if (params.margin_m > 0.0) {
    low.array() -= params.margin_m;
    high.array() += params.margin_m;
  }
  // (the 1e-6 cell keeps rounding from adding a column: 10 m / 0.1 m is 100 cells, not 101)
  const double width_cells = std::ceil((high.x() - low.x()) / resolution - 1e-6);
  const double height_cells = std::ceil((high.y() - low.y()) / resolution - 1e-6);
  if (!(width_cells * height_cells <= static_cast<double>(max_grid_cells))) {
    throw limit_error("the merged map would need " + std::to_string(static_cast<long long>(width_cells)) + " x " +
                      std::to_string(static_cast<long long>(height_cells)) + " cells at " + std::to_string(resolution) +
                      " m per cell: more than areamatch::max_grid_cells (" + std::to_string(max_grid_cells) +
                      "); choose a coarser resolution");
  }
  OccupancyGrid merged(std::max(1, static_cast<int>(width_cells)), std::max(1, static_cast<int>(height_cells)), resolution,
                       Pose2{low.x(), low.y(), 0.0});

  std::vector<std::uint16_t> occupied(merged.cells().size(), 0), free(merged.cells().size(), 0);
  for (std::size_t i = 0; i < maps.size(); ++i) {
    const OccupancyGrid& map = *maps[i];
    // Merged pixel → map pixel, and the merged pixels the map can cover.
    const Eigen::Affine2d map_from_merged = map.pixel_from_world() * T_reference_map[i].affine().inverse() * merged.world_from_pixel();
    Eigen::Vector2d pixel_low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), pixel_high = -pixel_low;
    for (const auto& corner : corners[i]) {
      const Eigen::Vector2d p = merged.world_to_pixel(T_reference_map[i] * corner);
      pixel_low = pixel_low.cwiseMin(p);
      pixel_high = pixel_high.cwiseMax(p);
    }
    const int col0 = std::max(0, static_cast<int>(std::floor(pixel_low.x())));
    const int col1 = std::min(merged.width() - 1, static_cast<int>(std::ceil(pixel_high.x())));
    const int row0 = std::max(0, static_cast<int>(std::floor(pixel_low.y())));
    const int row1 = std::min(merged.height() - 1, static_cast<int>(std::ceil(pixel_high.y())));
    for (int row = row0; row <= row1; ++row) {
      for (int col = col0; col <= col1; ++col) {
        const Eigen::Vector2d p = map_from_merged * Eigen::Vector2d(col, row);
        const int c = static_cast<int>(std::floor(p.x() + 0.5)), r = static_cast<int>(std::floor(p.y() + 0.5));
        if (!map.contains(c, r)) continue;
        const CellState s = map.at(c, r);
        const std::size_t k = merged.index(col, row);
        if (s == CellState::occupied) ++occupied[k];
        else if (s == CellState::free) ++free[k];
      }
    }
  }
  for (std::size_t k = 0; k < merged.cells().size(); ++k) {
    const double seen = static_cast<double>(occupied[k]) + free[k];
    if (occupied[k] > 0 && occupied[k] >= params.wall_share * seen) merged.cells()[k] = CellState::occupied;
    else if (free[k] > 0) merged.cells()[k] = CellState::free;
  }
  return params.margin_m < 0.0 ? merged : detail::crop_to_known(merged, params.margin_m);
}

}  // namespace areamatch
