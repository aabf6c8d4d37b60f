#pragma once
/// \file grid.hpp
/// `OccupancyGrid`: a 2D map of free / occupied / unknown cells with a metric frame.
///
/// Frames (the ROS map_server convention, see docs/conventions.md):
/// - **Image pixels** (col, row): row 0 is the *top* image row, rows grow downwards. A pixel's
///   centre sits at integer coordinates, so pixel (0, 0) covers [-0.5, 0.5]² and the image
///   spans [-0.5, width - 0.5] × [-0.5, height - 0.5].
/// - **World** (x, y) in metres, y up. `origin` is the world pose (x, y, yaw) of the lower-left
///   corner of the lower-left pixel, as in a map_server YAML. The centre of pixel (col, row) is
///
///       world = origin.xy + Rot(origin.yaw) · [ (col + 0.5)·res,  (height − row − 0.5)·res ]
///
///   so the image and the world frame are mirror images of each other (rows go down, y goes up).
/// - **Cell index** (storage order): `row · width + col`, image rows top to bottom.
///   A ROS `nav_msgs/OccupancyGrid` stores rows bottom to top: see `ros_data_index`.

#include "detail/blocks.hpp"
#include "detail/format.hpp"
#include "error.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace areamatch {

/// What a cell is known to be.
enum class CellState : std::uint8_t { free = 0, occupied = 1, unknown = 2 };

/// A pose in the plane: metres and radians.
struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;
  friend bool operator==(const Pose2& a, const Pose2& b) {
    return a.x == b.x && a.y == b.y && a.yaw == b.yaw;
  }
};

namespace detail {
/// Continuous pixel coordinates (col, row; pixel centres at integers, rows downwards) → world
/// metres, for a grid of `height` rows with the ROS origin convention (see the file comment).
inline Eigen::Affine2d world_from_pixel(int height, double resolution, const Pose2& origin) {
  const Eigen::Rotation2Dd rotation(origin.yaw);
  Eigen::Affine2d transform = Eigen::Affine2d::Identity();
  transform.linear() = rotation.toRotationMatrix() * Eigen::Vector2d(resolution, -resolution).asDiagonal();
  transform.translation() = Eigen::Vector2d(origin.x, origin.y) +
                            rotation * Eigen::Vector2d(0.5 * resolution, (height - 0.5) * resolution);
  return transform;
}
}  // namespace detail

/// Number of cells in each state.
struct CellCounts {
  std::size_t free = 0;
  std::size_t occupied = 0;
  std::size_t unknown = 0;
  std::size_t total() const { return free + occupied + unknown; }
};

/// The finest resolution areamatch takes, metres per cell. The segmenter's clearances span at
/// most 249 cells (0.25 m: 125 cells at 2 mm), and a finer map of a building would not fit in
/// memory: a resolution below this is a typo (1e-9 for 0.05), not a map.
inline constexpr double min_resolution_m = 0.002;

/// Throws `parameter_error` unless `resolution` is a finite number of metres per cell of at
/// least `min_resolution_m`.
inline void check_resolution(double resolution, const std::string& what = "resolution") {
  if (!(std::isfinite(resolution) && resolution > 0.0)) {
    throw parameter_error(what + " must be a positive finite number of metres per cell, got " +
                          std::to_string(resolution));
  }
  if (resolution < min_resolution_m) {
    throw parameter_error(what + " " + detail::format_double(resolution) + " m per cell is finer than areamatch::min_resolution_m (" +
                          detail::format_double(min_resolution_m) + " m); is it right?");
  }
}

/// The widest map areamatch takes, metres, either way: a floor, a building, a campus's few buildings.
/// A map wider than this is a resolution typo (1e300 for 0.05) more often than a map, and the
/// lookups sized in metres could not be allocated for it.
inline constexpr double max_map_extent_m = 2000.0;

/// Throws `parameter_error` when a width × height grid of `resolution` would be wider than
/// `max_map_extent_m` either way.
inline void check_extent(int width, int height, double resolution, const std::string& what = "map") {
  const double extent = std::max(width, height) * resolution;
  if (!(extent <= max_map_extent_m)) {
    char across[32];
    std::snprintf(across, sizeof across, "%.3g", extent);
    throw parameter_error(what + ": " + std::to_string(std::max(width, height)) + " cells of " + detail::format_double(resolution) +
                          " m make it " + across + " m across, more than areamatch::max_map_extent_m (" +
                          detail::format_fixed(max_map_extent_m, 0) + " m); is the resolution (metres per cell) right?");
  }
}

/// A width × height grid of cells with resolution (m per cell) and origin (see the file comment).
class OccupancyGrid {
 public:
  OccupancyGrid() = default;

  /// A grid with every cell set to `fill`. Throws `parameter_error` for a non-positive size or
  /// resolution, or a non-finite origin.
  OccupancyGrid(int width, int height, double resolution, Pose2 origin = {},
                CellState fill = CellState::unknown)
      : width_(width), height_(height), resolution_(resolution), origin_(origin) {
    if (width <= 0 || height <= 0) {
      throw parameter_error("grid size must be positive, got " + std::to_string(width) + "x" +
                            std::to_string(height));
    }
    check_resolution(resolution);
    check_extent(width, height, resolution);
    if (!std::isfinite(origin.x) || !std::isfinite(origin.y) || !std::isfinite(origin.yaw)) {
      throw parameter_error("grid origin must be finite");
    }
    cells_.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), fill);
  }

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution() const { return resolution_; }
  const Pose2& origin() const { return origin_; }
  bool empty() const { return cells_.empty(); }

  void set_resolution(double resolution) {
    check_resolution(resolution);
    check_extent(width_, height_, resolution);
    resolution_ = resolution;
  }
  void set_origin(const Pose2& origin) { origin_ = origin; }

  bool contains(int col, int row) const {
    return col >= 0 && row >= 0 && col < width_ && row < height_;
  }
  /// Storage index of pixel (col, row): row-major, image rows top to bottom.
  std::size_t index(int col, int row) const {
    return static_cast<std::size_t>(row) * static_cast<std::size_t>(width_) +
           static_cast<std::size_t>(col);
  }
  /// Index of pixel (col, row) in a ROS `nav_msgs/OccupancyGrid::data` (rows bottom to top).
  std::size_t ros_data_index(int col, int row) const { return index(col, height_ - 1 - row); }

  CellState at(int col, int row) const { return cells_[index(col, row)]; }
  void set(int col, int row, CellState state) { cells_[index(col, row)] = state; }
  bool is_free(int col, int row) const { return at(col, row) == CellState::free; }

  const std::vector<CellState>& cells() const { return cells_; }
  std::vector<CellState>& cells() { return cells_; }

  CellCounts count() const {
    static_assert(sizeof(CellState) == 1);
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(cells_.data());
    CellCounts counts;
    counts.free = detail::count_byte_equal(bytes, cells_.size(), static_cast<std::uint8_t>(CellState::free));
    counts.occupied = detail::count_byte_equal(bytes, cells_.size(), static_cast<std::uint8_t>(CellState::occupied));
    counts.unknown = cells_.size() - counts.free - counts.occupied;
    return counts;
  }

  /// Affine map from continuous pixel coordinates (col, row) to world metres.
  Eigen::Affine2d world_from_pixel() const { return detail::world_from_pixel(height_, resolution_, origin_); }
  /// Affine map from world metres to continuous pixel coordinates (col, row).
  Eigen::Affine2d pixel_from_world() const { return world_from_pixel().inverse(); }

  Eigen::Vector2d pixel_to_world(const Eigen::Vector2d& pixel) const { return world_from_pixel() * pixel; }
  Eigen::Vector2d world_to_pixel(const Eigen::Vector2d& world) const { return pixel_from_world() * world; }
  /// World position of the centre of pixel (col, row).
  Eigen::Vector2d cell_center(int col, int row) const {
    return pixel_to_world(Eigen::Vector2d(col, row));
  }
  /// The pixel containing a world point, rounded to the nearest centre (may lie outside).
  Eigen::Vector2i world_to_cell(const Eigen::Vector2d& world) const {
    const Eigen::Vector2d p = world_to_pixel(world);
    return {static_cast<int>(std::floor(p.x() + 0.5)), static_cast<int>(std::floor(p.y() + 0.5))};
  }

  friend bool operator==(const OccupancyGrid& a, const OccupancyGrid& b) {
    return a.width_ == b.width_ && a.height_ == b.height_ && a.resolution_ == b.resolution_ &&
           a.origin_ == b.origin_ && a.cells_ == b.cells_;
  }
  friend bool operator!=(const OccupancyGrid& a, const OccupancyGrid& b) { return !(a == b); }

 private:
  int width_ = 0;
  int height_ = 0;
  double resolution_ = 0.05;
  Pose2 origin_{};
  std::vector<CellState> cells_;
};

}  // namespace areamatch
