#pragma once
/// \file synthetic/line_drawing.hpp
/// A generated layout redrawn with thin walls, as hand-held datasets give floor plans, and the
/// chamfer distance it (and the robot maps' seen walls) measure with.

#include "../error.hpp"
#include "../grid.hpp"
#include "building_params.hpp"

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

namespace areamatch {

namespace detail {

/// Per cell of `grid`, the distance in metres to the nearest seed cell (a two-pass 3-4 chamfer
/// transform: within 8 % of Euclidean), +infinity without seeds.
inline std::vector<double> chamfer_distance(const OccupancyGrid& grid, const std::vector<bool>& seed) {
  const int w = grid.width(), h = grid.height();
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::vector<double> d(seed.size(), inf);
  for (std::size_t i = 0; i < seed.size(); ++i) if (seed[i]) d[i] = 0.0;
  auto relax = [&](int c, int r, int dc, int dr, double step) {
    const int nc = c + dc, nr = r + dr;
    if (nc < 0 || nr < 0 || nc >= w || nr >= h) return;
    double& here = d[static_cast<std::size_t>(r) * w + c];
    here = std::min(here, d[static_cast<std::size_t>(nr) * w + nc] + step);
  };
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      relax(c, r, -1, 0, 3.0), relax(c, r, -1, -1, 4.0), relax(c, r, 0, -1, 3.0), relax(c, r, 1, -1, 4.0);
    }
  for (int r = h - 1; r >= 0; --r)
    for (int c = w - 1; c >= 0; --c) {
      relax(c, r, 1, 0, 3.0), relax(c, r, 1, 1, 4.0), relax(c, r, 0, 1, 3.0), relax(c, r, -1, 1, 4.0);
    }
  for (double& v : d) v *= grid.resolution() / 3.0;
  return d;
}

}  // namespace detail

/// The layout drawn as a floor plan is: every wall as a line `line_width_m` wide along its
/// middle, the rest of the wall free on a room's side and unknown outside (hand-held datasets give
/// layouts as line drawings). Same frame and cells as `building.layout`.
inline OccupancyGrid layout_line_drawing(const SyntheticBuilding& building, double line_width_m) {
  detail::require_positive(line_width_m, "layout_line_drawing: line_width_m");
  const OccupancyGrid& layout = building.layout;
  std::vector<bool> free_seed(layout.cells().size()), unknown_seed(layout.cells().size());
  for (std::size_t i = 0; i < free_seed.size(); ++i) {
    free_seed[i] = layout.cells()[i] == CellState::free;
    unknown_seed[i] = layout.cells()[i] == CellState::unknown;
  }
  const std::vector<double> to_free = detail::chamfer_distance(layout, free_seed);
  const std::vector<double> to_unknown = detail::chamfer_distance(layout, unknown_seed);
  // A wall cell's centre lies half a cell further from the nearest other cell's centre than from
  // the wall's surface.
  const double keep = 0.5 * (building.params.wall_thickness_m - line_width_m) + 0.5 * layout.resolution();
  OccupancyGrid out = layout;
  for (int r = 0; r < layout.height(); ++r) {
    for (int c = 0; c < layout.width(); ++c) {
      const std::size_t i = layout.index(c, r);
      if (layout.cells()[i] != CellState::occupied || std::min(to_free[i], to_unknown[i]) >= keep - 1e-9) continue;
      out.set(c, r, to_free[i] <= to_unknown[i] ? CellState::free : CellState::unknown);
    }
  }
  return out;
}

}  // namespace areamatch
