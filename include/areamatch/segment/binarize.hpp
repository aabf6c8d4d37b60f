#pragma once
/// \file segment/binarize.hpp
/// Stage 1 of segmentation: occupancy grid → free-space mask, with speckles removed.

#include "../detail/blocks.hpp"
#include "../detail/run_components.hpp"
#include "../error.hpp"
#include "../grid.hpp"

#include <algorithm>
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
  /// Obstacle blobs whose bounding box is at most this long on each side are erased too, whatever
  /// their area: chairs, bins, pillars. They are not walls, and the narrow gaps they leave next to
  /// walls read as doors. 0 (the default) turns this off. At 0.5 m, on shared/maps: furnished
  /// maps segment like their layouts (office_g furnished 83 → 26 areas, its layout has 24;
  /// office_i 61 → 27 of 27) and 25–45 % faster, furnished→layout consistency 0.973 → 0.976,
  /// layouts and SLAM maps unchanged in score — but matching lost two pairs (office_e furnished
  /// took its mirror image, which scores within 0.001 of the right answer in that near-symmetric
  /// building either way; lab_b slid 1.2 m along its corridor). Hence off; see docs/segmentation.md.
  double max_speckle_size_m = 0.0;
  /// Free blobs (4-connected) smaller than this are dropped: isolated pixels outside the building.
  double min_free_area_m2 = 0.25;

  void validate() const {
    detail::require_non_negative(max_speckle_area_m2, "BinarizeParams::max_speckle_area_m2");
    detail::require_non_negative(max_speckle_size_m, "BinarizeParams::max_speckle_size_m");
    detail::require_non_negative(min_free_area_m2, "BinarizeParams::min_free_area_m2");
  }
};

/// A binary free-space mask (1 = free) over the bounding box of the free cells plus a border of
/// one obstacle cell all round, so that no free cell touches the edge of the mask. Cell (c, r)
/// of the mask is cell (c + offset_col, r + offset_row) of the source grid; the border may lie
/// one cell outside the grid.
struct FreeSpace {
  int width = 0;
  int height = 0;
  int offset_col = 0;
  int offset_row = 0;
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

/// Whether a cell counts as free space (unknown ones only with `unknown_is_free`).
inline bool counts_as_free(CellState s, bool unknown_is_free) {
  return s == CellState::free || (unknown_is_free && s == CellState::unknown);
}

/// out = 1 where the cell counts as free; see detail/blocks.hpp.
inline void free_flags(std::uint8_t* __restrict out, const CellState* __restrict in, int count, bool unknown_is_free) {
  for (int k = 0; k < count; ++k) out[k] = counts_as_free(in[k], unknown_is_free);
}

}  // namespace detail

/// Free cells of `grid` (unknown per `params`), without obstacle speckles and free crumbs,
/// cropped to where the free space is.
inline FreeSpace binarize(const OccupancyGrid& grid, const BinarizeParams& params = {}) {
  params.validate();
  auto is_free = [&](CellState s) { return detail::counts_as_free(s, params.unknown_is_free); };
  // Bounding box of the free cells: each row is searched from both ends only as far as its
  // first and last free cell.
  int min_c = grid.width(), max_c = -1, min_r = grid.height(), max_r = -1;
  for (int r = 0; r < grid.height(); ++r) {
    const CellState* row = &grid.cells()[grid.index(0, r)];
    // Free is 0, or anything but 1 (occupied) when unknown counts as free.
    static_assert(sizeof(CellState) == 1 && static_cast<int>(CellState::free) == 0 && static_cast<int>(CellState::occupied) == 1);
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(row);
    const int first = params.unknown_is_free ? detail::find_byte_not_equal(bytes, 0, grid.width(), 1)
                                             : detail::find_byte_equal(bytes, 0, grid.width(), 0);
    if (first == grid.width()) continue;
    int last = grid.width() - 1;
    while (!is_free(row[last])) --last;
    min_c = std::min(min_c, first), max_c = std::max(max_c, last);
    min_r = std::min(min_r, r), max_r = r;
  }
  FreeSpace space;
  if (max_c < 0) return space;  // no free cell at all
  space.offset_col = min_c - 1;
  space.offset_row = min_r - 1;
  space.width = max_c - min_c + 3;
  space.height = max_r - min_r + 3;
  space.free.assign(static_cast<std::size_t>(space.width) * space.height, 0);
  for (int r = 1; r + 1 < space.height; ++r) {
    const CellState* from = &grid.cells()[grid.index(min_c, r + space.offset_row)];
    std::uint8_t* to = &space.free[static_cast<std::size_t>(r) * space.width + 1];
    detail::in_blocks(0, space.width - 2, [&](int c, int count) {
      detail::free_flags(to + c, from + c, count, params.unknown_is_free);
    });
  }

  const double cell_area = grid.resolution() * grid.resolution();
  auto size_of = [](const detail::RunSpan& runs) {
    std::size_t n = 0;
    for (const auto& run : runs) n += static_cast<std::size_t>(run.end - run.begin);
    return n;
  };
  auto fill = [&](const detail::RunSpan& runs, std::uint8_t value) {
    for (const auto& run : runs)
      std::fill(space.free.begin() + static_cast<std::ptrdiff_t>(run.row) * space.width + run.begin,
                space.free.begin() + static_cast<std::ptrdiff_t>(run.row) * space.width + run.end, value);
  };
  const auto max_speckle = static_cast<std::size_t>(std::floor(params.max_speckle_area_m2 / cell_area));
  // In cells, rounded to a micro-cell so that a size of exactly k cells is not lost to noise.
  const double max_speckle_cells = std::floor(params.max_speckle_size_m / grid.resolution() * 1e6 + 0.5) / 1e6;
  auto fits_speckle_box = [&](const detail::RunSpan& runs) {
    int first_col = space.width, end_col = 0, first_row = space.height, end_row = 0;
    for (const auto& run : runs) {
      first_col = std::min(first_col, run.begin), end_col = std::max(end_col, run.end);
      first_row = std::min(first_row, run.row), end_row = std::max(end_row, run.row + 1);
    }
    return std::max(end_col - first_col, end_row - first_row) <= max_speckle_cells;
  };
  // (The components are found before any is filled, so the mask is changed in place.)
  if (max_speckle > 0 || max_speckle_cells >= 1.0) {
    detail::for_each_run_component(space.free, space.width, space.height, 0, true, [&](const detail::RunSpan& runs) {
      const bool touches_border = std::any_of(runs.begin(), runs.end(), [&](const detail::CellRun& run) {
        return run.row == 0 || run.row == space.height - 1 || run.begin == 0 || run.end == space.width;
      });
      if (!touches_border && (size_of(runs) <= max_speckle || fits_speckle_box(runs))) fill(runs, 1);
    });
  }
  const auto min_free = static_cast<std::size_t>(std::ceil(params.min_free_area_m2 / cell_area));
  if (min_free > 1) {
    detail::for_each_run_component(space.free, space.width, space.height, 1, false, [&](const detail::RunSpan& runs) {
      if (size_of(runs) < min_free) fill(runs, 0);
    });
  }
  return space;
}

}  // namespace areamatch
