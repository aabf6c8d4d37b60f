#pragma once
/// \file simulate/integrate.hpp
/// A simulated SLAM map's beams into an occupancy grid (simulate.hpp): log-odds on a grid around
/// every beam, each cell it crosses seen free, its end seen occupied when it hit, then
/// thresholded into free, occupied and unknown.

#include "../error.hpp"
#include "../grid.hpp"
#include "params.hpp"
#include "world.hpp"

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

namespace areamatch::detail {

/// The map of `beams` (map frame). Throws `limit_error` when it would exceed `params.max_cells`.
inline OccupancyGrid integrate_beams(const std::vector<Beam>& beams, const LidarSlamParams& params) {
  Eigen::Vector2d lo = beams.empty() ? Eigen::Vector2d::Zero() : beams.front().from, hi = lo;
  for (const Beam& b : beams) {
    lo = lo.cwiseMin(b.from).cwiseMin(b.to);
    hi = hi.cwiseMax(b.from).cwiseMax(b.to);
  }
  const double res = params.resolution_m, margin = 2.0 * res;
  const double cols = std::ceil((hi.x() - lo.x() + 2.0 * margin) / res), rows = std::ceil((hi.y() - lo.y() + 2.0 * margin) / res);
  if (!(cols * rows <= static_cast<double>(params.max_cells))) {
    throw limit_error("simulate: the map would have " + std::to_string(static_cast<long long>(cols * rows)) +
                      " cells, more than LidarSlamParams::max_cells (" + std::to_string(params.max_cells) + ")");
  }
  OccupancyGrid grid(static_cast<int>(cols), static_cast<int>(rows), res,
                     Pose2{lo.x() - margin, lo.y() - margin, 0.0}, CellState::unknown);
  std::vector<float> log_odds(grid.cells().size(), 0.0f);
  std::vector<std::uint8_t> seen(grid.cells().size(), 0);
  const Eigen::Affine2d to_pixel = grid.pixel_from_world();
  for (const Beam& b : beams) {
    const Eigen::Vector2d a = to_pixel * b.from, e = to_pixel * b.to;
    int x = static_cast<int>(std::floor(a.x() + 0.5)), y = static_cast<int>(std::floor(a.y() + 0.5));
    const int x1 = static_cast<int>(std::floor(e.x() + 0.5)), y1 = static_cast<int>(std::floor(e.y() + 0.5));
    const int dx = std::abs(x1 - x), dy = -std::abs(y1 - y), sx = x < x1 ? 1 : -1, sy = y < y1 ? 1 : -1;
    int error = dx + dy;
    while (x != x1 || y != y1) {  // Bresenham: every cell before the end is seen free
      if (grid.contains(x, y)) {
        const std::size_t i = grid.index(x, y);
        log_odds[i] += static_cast<float>(params.miss_log_odds);
        seen[i] = 1;
      }
      const int twice = 2 * error;
      if (twice >= dy) error += dy, x += sx;
      if (twice <= dx) error += dx, y += sy;
    }
    if (b.hit && grid.contains(x1, y1)) {
      const std::size_t i = grid.index(x1, y1);
      log_odds[i] += static_cast<float>(params.hit_log_odds);
      seen[i] = 1;
    }
  }
  const CellState unknown = params.binary ? CellState::occupied : CellState::unknown;
  for (std::size_t i = 0; i < log_odds.size(); ++i) {
    grid.cells()[i] = !seen[i]                                  ? unknown
                      : log_odds[i] >= params.occupied_log_odds ? CellState::occupied
                      : log_odds[i] <= params.free_log_odds     ? CellState::free
                                                                : unknown;
  }
  return grid;
}

}  // namespace areamatch::detail
