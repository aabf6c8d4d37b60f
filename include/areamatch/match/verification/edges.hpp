#pragma once
/// \file match/verification/edges.hpp
/// The edges of a map's free space or of its areas, as raster cells and as thinned world points, and
/// each free-space edge point's free side: what refinement (`refine.hpp`), the evidence and the
/// selection lay onto each other.

#include "../../area_graph.hpp"
#include "../../grid.hpp"
#include "../raster.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

namespace areamatch {

namespace detail {

/// The cells within `bounds` on the edge of a region (a cell inside with a 4-neighbour outside
/// or off the grid), as row-major indices in scan order. `fill_row(first, last, out)` writes 1
/// for the cells [first, last) (row-major indices, within one row) that are in the region and 0
/// for the others; it is asked for each row of `bounds` and the ring around it (the neighbours
/// of border cells count whether or not they lie in `bounds`), once each and in order. The edge
/// test reads three rows of a mask with a false border instead of checking the grid's bounds
/// four times a cell; only those three rows are held.
template <class FillRow>
std::vector<std::size_t> edge_cells_by_rows(const GridInfo& g, const PixelBounds& bounds, FillRow fill_row) {
  std::vector<std::size_t> out;
  if (bounds.empty()) return out;
  const int x0 = bounds.col0 - 1, y0 = bounds.row0 - 1;
  const int mask_w = bounds.col1 - bounds.col0 + 2, mask_h = bounds.row1 - bounds.row0 + 2;
  const auto width = static_cast<std::size_t>(g.width);
  const auto row_bytes = static_cast<std::size_t>(mask_w);
  std::vector<std::uint8_t> rows(3 * row_bytes, 0);
  auto mask_row = [&](int my) { return rows.data() + static_cast<std::size_t>(my % 3) * row_bytes; };
  auto fill = [&](int my) {
    std::uint8_t* row = mask_row(my);
    std::fill(row, row + row_bytes, std::uint8_t{0});
    const int y = y0 + my;
    if (y < 0 || y >= g.height) return;
    const std::size_t grid_row = static_cast<std::size_t>(y) * width;
    const int mx_begin = std::max(0, -x0), mx_end = std::min(mask_w, g.width - x0);
    if (mx_begin < mx_end) {
      fill_row(grid_row + static_cast<std::size_t>(x0 + mx_begin), grid_row + static_cast<std::size_t>(x0 + mx_end), row + mx_begin);
    }
  };
  fill(0);
  if (mask_h > 1) fill(1);
  for (int my = 1; my + 1 < mask_h; ++my) {
    fill(my + 1);
    const std::uint8_t* row = mask_row(my);
    const std::uint8_t* above = mask_row(my - 1);
    const std::uint8_t* below = mask_row(my + 1);
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
  out.shrink_to_fit();  // kept with the match data: without the growth's slack (up to half)
  return out;
}

/// `edge_cells_by_rows` with `inside(index)` asked once per cell.
template <class Inside>
std::vector<std::size_t> edge_cells(const GridInfo& g, const PixelBounds& bounds, Inside inside) {
  return edge_cells_by_rows(g, bounds, [&](std::size_t first, std::size_t last, std::uint8_t* out) {
    for (std::size_t i = first; i < last; ++i) *out++ = inside(i) ? 1 : 0;
  });
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
  // Counted first, so the points are held once at their exact size: on a large floor, growing
  // them by doubling allocated (and the system zeroed) twice their size again.
  std::size_t count = 0;
  for_each_edge_cell(g, cells, spacing_m, [&](std::size_t, const Eigen::Vector2d&) {
    ++count;
    return true;
  });
  std::vector<Eigen::Vector2d> points;
  points.reserve(count);
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
  const auto cells = edge_cells_by_rows(graph.grid, label_bounds(graph), [&](std::size_t first, std::size_t last, std::uint8_t* out) {
    graph.labels.for_each_run(first, last, [&](std::size_t begin, std::size_t end, int label) {
      std::fill(out + (begin - first), out + (end - first), label >= 0 ? 1 : 0);
    });
  });
  return boundary_points(graph.grid, cells, spacing_m, max_points);
}

}  // namespace detail

}  // namespace areamatch
