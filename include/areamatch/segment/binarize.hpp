#pragma once
/// \file segment/binarize.hpp
/// Stage 1 of segmentation: occupancy grid → free-space mask, with speckles removed.

#include "../error.hpp"
#include "../grid.hpp"

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace areamatch {

/// Parameters of `binarize`. Areas in m².
struct BinarizeParams {
  /// Unknown cells count as obstacles (default): they must not produce skeleton or areas.
  bool unknown_is_free = false;
  /// Obstacle blobs (8-connected) up to this area are erased: chair legs, laser noise, dust.
  double max_speckle_area_m2 = 0.05;
  /// Free blobs (4-connected) smaller than this are dropped: isolated pixels outside the building.
  double min_free_area_m2 = 0.25;

  void validate() const {
    if (!(std::isfinite(max_speckle_area_m2) && max_speckle_area_m2 >= 0.0)) {
      throw parameter_error("BinarizeParams::max_speckle_area_m2 must be >= 0, got " + std::to_string(max_speckle_area_m2));
    }
    if (!(std::isfinite(min_free_area_m2) && min_free_area_m2 >= 0.0)) {
      throw parameter_error("BinarizeParams::min_free_area_m2 must be >= 0, got " + std::to_string(min_free_area_m2));
    }
  }
};

/// A binary free-space mask in image order (row 0 on top), 1 = free.
struct FreeSpace {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> free;

  bool is_free(int col, int row) const {
    return col >= 0 && row >= 0 && col < width && row < height && free[static_cast<std::size_t>(row) * width + col];
  }
  std::size_t count() const {
    std::size_t n = 0;
    for (auto f : free) n += f;
    return n;
  }
};

namespace detail {

/// Flood-fills every connected component of cells with `mask[i] == value` and calls
/// `on_component(cells)` with its cell indices; `eight` chooses 8- over 4-connectivity.
template <class OnComponent>
void for_each_component(const std::vector<std::uint8_t>& mask, int width, int height, std::uint8_t value, bool eight,
                        OnComponent&& on_component) {
  std::vector<std::uint8_t> seen(mask.size(), 0);
  std::vector<std::size_t> cells;
  for (std::size_t start = 0; start < mask.size(); ++start) {
    if (mask[start] != value || seen[start]) continue;
    cells.clear();
    cells.push_back(start);
    seen[start] = 1;
    for (std::size_t head = 0; head < cells.size(); ++head) {
      const int c = static_cast<int>(cells[head] % width), r = static_cast<int>(cells[head] / width);
      for (int dr = -1; dr <= 1; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          if ((dr == 0 && dc == 0) || (!eight && dr != 0 && dc != 0)) continue;
          const int nc = c + dc, nr = r + dr;
          if (nc < 0 || nr < 0 || nc >= width || nr >= height) continue;
          const std::size_t j = static_cast<std::size_t>(nr) * width + nc;
          if (mask[j] == value && !seen[j]) {
            seen[j] = 1;
            cells.push_back(j);
          }
        }
      }
    }
    on_component(cells);
  }
}

}  // namespace detail

/// Free cells of `grid` (unknown per `params`), without obstacle speckles and free crumbs.
inline FreeSpace binarize(const OccupancyGrid& grid, const BinarizeParams& params = {}) {
  params.validate();
  FreeSpace space;
  space.width = grid.width();
  space.height = grid.height();
  space.free.resize(grid.cells().size());
  for (std::size_t i = 0; i < space.free.size(); ++i) {
    const CellState s = grid.cells()[i];
    space.free[i] = s == CellState::free || (params.unknown_is_free && s == CellState::unknown);
  }
  const double cell_area = grid.resolution() * grid.resolution();
  const auto max_speckle = static_cast<std::size_t>(std::floor(params.max_speckle_area_m2 / cell_area));
  if (max_speckle > 0) {
    auto copy = space.free;
    detail::for_each_component(copy, space.width, space.height, 0, true, [&](const std::vector<std::size_t>& cells) {
      if (cells.size() <= max_speckle) for (std::size_t i : cells) space.free[i] = 1;
    });
  }
  const auto min_free = static_cast<std::size_t>(std::ceil(params.min_free_area_m2 / cell_area));
  if (min_free > 1) {
    auto copy = space.free;
    detail::for_each_component(copy, space.width, space.height, 1, false, [&](const std::vector<std::size_t>& cells) {
      if (cells.size() < min_free) for (std::size_t i : cells) space.free[i] = 0;
    });
  }
  return space;
}

}  // namespace areamatch
