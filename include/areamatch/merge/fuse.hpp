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
#include "../warp/field.hpp"

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
  /// A warped map (`fuse_warped_maps`) is read through its warp's exact inverse at cells this far
  /// apart and bilinearly between them: a warp bends over metres (`WarpParams::bend_length_m`),
  /// so between points a quarter metre apart it is as good as straight (off by millimetres),
  /// and the inverse is found once per 25 cells at 0.05 m instead of once per cell.
  double warp_lattice_m = 0.25;

  void validate() const {
    detail::require_non_negative(resolution, "FuseParams::resolution");
    detail::require_positive(warp_lattice_m, "FuseParams::warp_lattice_m");
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

namespace detail {

/// Fuses maps already laid into the merged frame (file comment): `outline[i]` are points of the
/// merged world around map i's known cells (the merged grid covers them all; a map is read only
/// inside their box), and `lay(merged)` gives, for the merged grid once it is laid out, the
/// function `(i, col, row)` → map i's pixel under merged cell (col, row). The rigid and the
/// warped merge differ only in these two.
template <class Lay>
OccupancyGrid fuse_laid(const std::vector<const OccupancyGrid*>& maps, const std::vector<std::vector<Eigen::Vector2d>>& outline,
                        const Lay& lay, const FuseParams& params) {
  params.validate();
  if (maps.empty() || maps.size() != outline.size()) throw parameter_error("fuse_maps: needs at least one map and one pose per map");
  if (maps.size() > std::numeric_limits<std::uint16_t>::max()) throw limit_error("fuse_maps: more than 65535 maps");
  double resolution = params.resolution;
  Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d high = -low;
  for (std::size_t i = 0; i < maps.size(); ++i) {
    if (maps[i] == nullptr || maps[i]->empty()) throw parameter_error("fuse_maps: map " + std::to_string(i) + " is empty");
    if (params.resolution == 0.0) resolution = i == 0 ? maps[i]->resolution() : std::min(resolution, maps[i]->resolution());
    for (const auto& p : outline[i]) {
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

  const auto map_pixel = lay(static_cast<const OccupancyGrid&>(merged));
  std::vector<std::uint16_t> occupied(merged.cells().size(), 0), free(merged.cells().size(), 0);
  for (std::size_t i = 0; i < maps.size(); ++i) {
    const OccupancyGrid& map = *maps[i];
    // The merged pixels the map can cover.
    Eigen::Vector2d pixel_low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), pixel_high = -pixel_low;
    for (const auto& p : outline[i]) {
      const Eigen::Vector2d q = merged.world_to_pixel(p);
      pixel_low = pixel_low.cwiseMin(q);
      pixel_high = pixel_high.cwiseMax(q);
    }
    const int col0 = std::max(0, static_cast<int>(std::floor(pixel_low.x())));
    const int col1 = std::min(merged.width() - 1, static_cast<int>(std::ceil(pixel_high.x())));
    const int row0 = std::max(0, static_cast<int>(std::floor(pixel_low.y())));
    const int row1 = std::min(merged.height() - 1, static_cast<int>(std::ceil(pixel_high.y())));
    for (int row = row0; row <= row1; ++row) {
      for (int col = col0; col <= col1; ++col) {
        const Eigen::Vector2d p = map_pixel(i, col, row);
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

/// The corners of the part of `grid` a fusion reads (its known cells', or with a negative
/// margin its whole image's), in its world frame.
inline std::array<Eigen::Vector2d, 4> fused_corners(const OccupancyGrid& grid, const FuseParams& params) {
  return params.margin_m < 0.0 ? grid_corners(grid) : known_corners(grid);
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
  std::vector<std::vector<Eigen::Vector2d>> outline(maps.size());
  for (std::size_t i = 0; i < maps.size(); ++i) {
    if (maps[i] == nullptr || maps[i]->empty()) throw parameter_error("fuse_maps: map " + std::to_string(i) + " is empty");
    for (const auto& corner : detail::fused_corners(*maps[i], params)) outline[i].push_back(T_reference_map[i] * corner);
  }
  auto lay = [&](const OccupancyGrid& merged) {
    std::vector<Eigen::Affine2d> map_from_merged(maps.size());  // merged pixel → map pixel
    for (std::size_t m = 0; m < maps.size(); ++m) {
      map_from_merged[m] = maps[m]->pixel_from_world() * T_reference_map[m].affine().inverse() * merged.world_from_pixel();
    }
    return [map_from_merged](std::size_t i, int col, int row) { return Eigen::Vector2d(map_from_merged[i] * Eigen::Vector2d(col, row)); };
  };
  return detail::fuse_laid(maps, outline, lay, params);
}

namespace detail {

/// The border of the box `corners`, a point every `spacing_m`, through `warp`: a warp's image of
/// a box is bounded by the image of its border.
inline std::vector<Eigen::Vector2d> warped_outline(const std::array<Eigen::Vector2d, 4>& corners, const WarpField& warp, double spacing_m) {
  std::vector<Eigen::Vector2d> outline;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const Eigen::Vector2d a = corners[k], b = corners[(k + 1) % corners.size()];
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / spacing_m)));
    for (int s = 0; s < steps; ++s) outline.push_back(warp.apply(a + (b - a) * (static_cast<double>(s) / steps)));
  }
  return outline;
}

/// A map's pixels under a merged grid's cells through a warp (map world → merged world): the
/// warp's exact inverse at lattice cells every `step`, bilinear between (`FuseParams::warp_lattice_m`);
/// a rigid warp is read exactly, as an affine map.
class WarpedPixels {
 public:
  WarpedPixels(const OccupancyGrid& map, const WarpField& warp, const OccupancyGrid& merged, const std::vector<Eigen::Vector2d>& outline,
               double lattice_m)
      : rigid_(warp.is_rigid()),
        affine_(map.pixel_from_world() * warp.rigid().affine().inverse() * merged.world_from_pixel()) {
    if (rigid_) return;
    Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), high = -low;
    for (const auto& p : outline) {
      const Eigen::Vector2d q = merged.world_to_pixel(p);
      low = low.cwiseMin(q);
      high = high.cwiseMax(q);
    }
    step_ = std::max(1, static_cast<int>(std::lround(lattice_m / merged.resolution())));
    col0_ = static_cast<int>(std::floor(low.x())) - step_;
    row0_ = static_cast<int>(std::floor(low.y())) - step_;
    columns_ = static_cast<int>(std::ceil((high.x() - col0_) / step_)) + 2;
    rows_ = static_cast<int>(std::ceil((high.y() - row0_) / step_)) + 2;
    const Eigen::Affine2d map_pixel = map.pixel_from_world(), merged_world = merged.world_from_pixel();
    const double tolerance = 0.01 * merged.resolution();
    lattice_.reserve(static_cast<std::size_t>(columns_) * static_cast<std::size_t>(rows_));
    for (int j = 0; j < rows_; ++j) {
      for (int i = 0; i < columns_; ++i) {
        const Eigen::Vector2d cell(col0_ + i * step_, row0_ + j * step_);
        lattice_.push_back(map_pixel * warp.inverse(merged_world * cell, tolerance));
      }
    }
  }

  /// The map pixel under merged cell (col, row) (inside the outline's box; beyond it, the
  /// nearest lattice border's).
  Eigen::Vector2d at(int col, int row) const {
    if (rigid_) return affine_ * Eigen::Vector2d(col, row);
    const double u = std::clamp(static_cast<double>(col - col0_) / step_, 0.0, columns_ - 1.000001);
    const double v = std::clamp(static_cast<double>(row - row0_) / step_, 0.0, rows_ - 1.000001);
    const int i = static_cast<int>(u), j = static_cast<int>(v);
    const double tu = u - i, tv = v - j;
    const std::size_t k = static_cast<std::size_t>(j) * static_cast<std::size_t>(columns_) + static_cast<std::size_t>(i);
    const std::size_t below = k + static_cast<std::size_t>(columns_);
    return (1 - tv) * ((1 - tu) * lattice_[k] + tu * lattice_[k + 1]) + tv * ((1 - tu) * lattice_[below] + tu * lattice_[below + 1]);
  }

 private:
  bool rigid_ = true;
  Eigen::Affine2d affine_;
  int step_ = 1, col0_ = 0, row0_ = 0, columns_ = 0, rows_ = 0;
  std::vector<Eigen::Vector2d> lattice_;
};

}  // namespace detail

/// Lays `maps[i]` into one grid through `warps[i]` (map world → the merged grid's world frame,
/// e.g. fitted by `fit_warp`) and fuses them as `fuse_maps` does. Each merged cell reads the map
/// cell the warp brings under it (the warp's inverse: see `FuseParams::warp_lattice_m`).
inline OccupancyGrid fuse_warped_maps(const std::vector<const OccupancyGrid*>& maps, const std::vector<WarpField>& warps,
                                      const FuseParams& params = {}) {
  params.validate();
  if (maps.empty() || maps.size() != warps.size()) throw parameter_error("fuse_warped_maps: needs at least one map and one warp per map");
  std::vector<std::vector<Eigen::Vector2d>> outline(maps.size());
  for (std::size_t i = 0; i < maps.size(); ++i) {
    if (maps[i] == nullptr || maps[i]->empty()) throw parameter_error("fuse_warped_maps: map " + std::to_string(i) + " is empty");
    outline[i] = detail::warped_outline(detail::fused_corners(*maps[i], params), warps[i], params.warp_lattice_m);
  }
  auto lay = [&](const OccupancyGrid& merged) {
    std::vector<detail::WarpedPixels> pixels;
    for (std::size_t m = 0; m < maps.size(); ++m) pixels.emplace_back(*maps[m], warps[m], merged, outline[m], params.warp_lattice_m);
    return [pixels = std::move(pixels)](std::size_t i, int col, int row) { return pixels[i].at(col, row); };
  };
  return detail::fuse_laid(maps, outline, lay, params);
}

}  // namespace areamatch
