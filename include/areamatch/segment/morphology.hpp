#pragma once
/// \file segment/morphology.hpp
/// Erosion and opening of free space by a disc: the area stage grows regions from the free space
/// eroded by the skeleton's clearance (`build_areas`, which takes the erosion a row at a time from
/// the free space's runs, `erode_rows`), and the segmenter opens free space (a byte mask, one byte
/// per cell) before tracing when `BoundaryParams::min_traced_width_m` is set.
/// Distances in cells: the caller converts from metres at the grid's resolution.

#include "../detail/blocks.hpp"
#include "../detail/run_components.hpp"
#include "binarize.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace areamatch {

namespace detail {

// The erosion's byte kernels, each over `count` cells of distinct rows, called through
// `in_blocks` (detail/blocks.hpp: vectorised at -O2 too).

/// Vertical distance to a non-free cell from the row above's, capped (over a run of free cells).
inline void grow_from_above(std::uint8_t* __restrict row, const std::uint8_t* __restrict above, int count,
                            std::uint8_t cap) {
  for (int k = 0; k < count; ++k) row[k] = above[k] < cap ? static_cast<std::uint8_t>(above[k] + 1) : cap;
}

/// The same from the row below, kept where smaller.
inline void grow_from_below(std::uint8_t* __restrict row, const std::uint8_t* __restrict below, int count,
                            std::uint8_t cap) {
  for (int k = 0; k < count; ++k) {
    const std::uint8_t grown = below[k] < cap ? static_cast<std::uint8_t>(below[k] + 1) : cap;
    row[k] = std::min(row[k], grown);
  }
}

inline void at_least(std::uint8_t* __restrict out, const std::uint8_t* __restrict row, int count, std::uint8_t n) {
  for (int k = 0; k < count; ++k) out[k] = row[k] >= n;
}

/// out &= (left ≥ n) and (right ≥ n); left and right may overlap (both are only read).
inline void and_both_at_least(std::uint8_t* __restrict out, const std::uint8_t* __restrict left,
                              const std::uint8_t* __restrict right, int count, std::uint8_t n) {
  for (int k = 0; k < count; ++k) out[k] &= static_cast<std::uint8_t>((left[k] >= n) & (right[k] >= n));
}

/// Rows of vertical distances the erosion computes at once (`erode_rows`): a band and its margins
/// instead of a full-size buffer.
inline constexpr int erosion_band_rows = 256;

/// The erosion of a mask (`W` x `H`, given by its runs of cells `inside`) by a disc of `distance`
/// cells (centre to centre; beyond the mask's edge counts as outside), row by row: calls
/// `on_row(r, core)` for r = 0, 1, ..., H − 1, where `core` points to that row's W bytes (1: no
/// cell outside the mask closer than `distance`), valid during the call. Works on byte column
/// distances capped at the disc's reach, so a row's depends only on the rows within reach: they
/// are found a band of rows at a time, and the working memory is a band, not the mask's size.
template <class OnRow>
void erode_rows(const RowRuns& inside, int W, int H, double distance, OnRow&& on_row) {
  if (W <= 0 || H <= 0) return;
  const double threshold = distance * distance;
  const int reach = static_cast<int>(std::ceil(distance));
  if (reach >= 250) throw parameter_error("erosion radius too large for the grid's resolution");
  const auto cap = static_cast<std::uint8_t>(reach + 1);  // cap² ≥ threshold: "far enough"
  const auto w = static_cast<std::size_t>(W);
  // Each row's mask cells lie in [first[r], last[r]); outside it the column distances and the
  // core stay 0, so every pass skips it — on a rotated or L-shaped building, most of the box.
  std::vector<int> first(static_cast<std::size_t>(H), W), last(static_cast<std::size_t>(H), W);
  for (int r = 0; r < H; ++r) {
    const auto runs = inside.row(r);
    if (runs.empty()) continue;
    first[r] = runs.begin()->begin;
    last[r] = (runs.end() - 1)->end;
  }
  // Core iff for every column offset dx within reach: vertical(c + dx) ≥ need[|dx|], the
  // smallest vertical distance that keeps that column's nearest obstacle far enough. need[0] ≥ 1
  // keeps the core inside the mask (cells outside have vertical distance 0).
  std::vector<std::uint8_t> need(static_cast<std::size_t>(reach) + 1);
  for (int dx = 0; dx <= reach; ++dx) {
    const double rest = threshold - static_cast<double>(dx) * dx;
    need[dx] = static_cast<std::uint8_t>(rest <= 0.0 ? 0 : std::min<int>(cap, static_cast<int>(std::ceil(std::sqrt(rest) - 1e-9))));
  }
  need[0] = std::max<std::uint8_t>(need[0], 1);
  // Vertical distance to the nearest non-free cell in the same column (beyond the first and last
  // rows counts as outside), capped, for the band's rows and `cap` rows either side. A pass
  // started inside the mask assumes "far" above (or below) its first row: wrong only by how far
  // the true obstacle lies beyond it, which the cap hides from every row `cap` rows in.
  const int margin = cap;
  std::vector<std::uint8_t> vertical(static_cast<std::size_t>(erosion_band_rows + 2 * margin) * w, 0);
  std::vector<std::uint8_t> out(w, 0);
  for (int band = 0; band < H; band += erosion_band_rows) {
    const int band_end = std::min(H, band + erosion_band_rows);
    const int top = std::max(0, band - margin), bottom = std::min(H, band_end + margin);
    auto vrow = [&](int r) { return vertical.data() + static_cast<std::size_t>(r - top) * w; };
    {
      std::uint8_t* row = vrow(top);
      std::fill(row, row + w, std::uint8_t{0});
      const std::uint8_t start = top == 0 ? 1 : cap;
      for (const CellRun& run : inside.row(top)) std::fill(row + run.begin, row + run.end, start);
    }
    for (int r = top + 1; r < bottom; ++r) {
      const std::uint8_t* above = vrow(r - 1);
      std::uint8_t* row = vrow(r);
      std::fill(row, row + w, std::uint8_t{0});
      for (const CellRun& run : inside.row(r)) {
        in_blocks(run.begin, run.end, [&](int c, int count) { grow_from_above(row + c, above + c, count, cap); });
      }
    }
    if (bottom == H) {
      std::uint8_t* last_row = vrow(H - 1);
      for (int c = first[H - 1]; c < last[H - 1]; ++c) last_row[c] = std::min<std::uint8_t>(last_row[c], 1);
    }
    for (int r = bottom - 2; r >= top; --r) {
      const std::uint8_t* below = vrow(r + 1);
      std::uint8_t* row = vrow(r);
      in_blocks(first[r], last[r], [&](int c, int count) { grow_from_below(row + c, below + c, count, cap); });
    }
    for (int r = band; r < band_end; ++r) {
      const int lo = first[r], hi = last[r];
      std::fill(out.begin(), out.end(), std::uint8_t{0});
      if (lo < hi) {
        const std::uint8_t* row = vrow(r);
        std::uint8_t* o = out.data();
        in_blocks(lo, hi, [&](int c, int count) { at_least(o + c, row + c, count, need[0]); });
        for (int dx = 1; dx <= reach; ++dx) {
          const std::uint8_t n = need[dx];
          if (n > 0) {  // beyond the mask counts as obstacle: cells that close to its edge fail
            for (int c = lo; c < std::min(dx, hi); ++c) o[c] = 0;
            for (int c = std::max(W - dx, lo); c < hi; ++c) o[c] = 0;
          }
          in_blocks(std::max(dx, lo), std::min(W - dx, hi),
                    [&](int c, int count) { and_both_at_least(o + c, row + c - dx, row + c + dx, count, n); });
        }
      }
      on_row(r, static_cast<const std::uint8_t*>(out.data()));
    }
  }
}

/// The runs of a byte mask's cells that are not 0.
inline RowRuns nonzero_runs(const std::vector<std::uint8_t>& mask, int W, int H) {
  return row_runs_of(mask.data(), W, H, std::uint8_t{0}, false);
}

/// `erode_rows` of a byte mask (not 0: inside) into a full mask.
inline std::vector<std::uint8_t> erode_mask(const std::vector<std::uint8_t>& mask, int W, int H, double distance) {
  const std::size_t N = static_cast<std::size_t>(W) * static_cast<std::size_t>(H);
  std::vector<std::uint8_t> core(N, 0);
  erode_rows(nonzero_runs(mask, W, H), W, H, distance, [&](int r, const std::uint8_t* row) {
    std::copy(row, row + W, core.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(r) * static_cast<std::size_t>(W)));
  });
  return core;
}

inline std::vector<std::uint8_t> erode(const FreeSpace& space, double distance) {
  return erode_mask(space.free, space.width, space.height, distance);
}

}  // namespace detail

/// The opening of free space by a disc of `radius` cells: the cells some disc of that radius
/// lying wholly in free space covers. Same frame as `space`.
inline FreeSpace open_free_space(const FreeSpace& space, double radius) {
  FreeSpace opened = space;
  if (radius < 1.0) return opened;  // no cell is that close to another: nothing changes
  const int W = space.width;
  if (radius < std::sqrt(2.0)) {
    // The disc holds a cell and its four neighbours: erode and dilate by that cross directly,
    // far faster than the general erosion. Free cells never lie on the mask's border.
    // Three rows of the eroded mask at a time (rows r − 1, r, r + 1 for output row r).
    const std::uint8_t* f = space.free.data();
    std::uint8_t* out = opened.free.data();
    std::vector<std::uint8_t> rows(3 * static_cast<std::size_t>(W), 0);
    auto core_row = [&](int r) { return rows.data() + static_cast<std::size_t>((r + 3) % 3) * W; };
    auto erode_row = [&](int r, std::uint8_t* e) {
      std::fill(e, e + W, std::uint8_t{0});
      if (r <= 0 || r + 1 >= space.height) return;
      const std::uint8_t* x = f + static_cast<std::size_t>(r) * W;
      for (int c = 1; c + 1 < W; ++c) e[c] = x[c] & x[c - 1] & x[c + 1] & x[c - W] & x[c + W];
    };
    erode_row(0, core_row(0));
    erode_row(1, core_row(1));
    for (int r = 1; r + 1 < space.height; ++r) {
      erode_row(r + 1, core_row(r + 1));
      const std::uint8_t *up = core_row(r - 1), *mid = core_row(r), *down = core_row(r + 1);
      const std::uint8_t* x = f + static_cast<std::size_t>(r) * W;
      std::uint8_t* o = out + static_cast<std::size_t>(r) * W;
      for (int c = 1; c + 1 < W; ++c) o[c] = x[c] & (mid[c] | mid[c - 1] | mid[c + 1] | up[c] | down[c]);
    }
    return opened;
  }
  const auto core = detail::erode(space, radius);
  // Dilation of the core = complement of the erosion of its complement. The erosion counts
  // beyond the mask as outside, which here would mean "core": pad the complement so it does not.
  const int pad = static_cast<int>(std::ceil(radius));
  const int PW = W + 2 * pad, PH = space.height + 2 * pad;
  std::vector<std::uint8_t> outside_core(static_cast<std::size_t>(PW) * PH, 1);
  for (int r = 0; r < space.height; ++r)
    for (int c = 0; c < W; ++c)
      outside_core[static_cast<std::size_t>(r + pad) * PW + c + pad] = !core[static_cast<std::size_t>(r) * W + c];
  const auto far_from_core = detail::erode_mask(outside_core, PW, PH, radius);
  for (int r = 0; r < space.height; ++r)
    for (int c = 0; c < W; ++c) {
      const std::size_t i = static_cast<std::size_t>(r) * W + c;
      opened.free[i] = space.free[i] && !far_from_core[static_cast<std::size_t>(r + pad) * PW + c + pad];
    }
  return opened;
}

}  // namespace areamatch
