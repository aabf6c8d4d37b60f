#pragma once
/// \file warp/resample.hpp
/// A source map drawn in a destination's frame through a warp: each destination cell takes the
/// state of the source cell the warp brings there (nearest cell; unknown where the source has
/// none, or where no source point goes: a gap between a broken map's pieces), so the two maps can
/// be laid over each other cell for cell.

#include "../area_graph.hpp"
#include "../grid.hpp"
#include "field.hpp"

#include <Eigen/Core>

#include <cmath>
#include <optional>

namespace areamatch {

/// `source` resampled into the frame `frame` (size, resolution and origin, e.g.
/// `GridInfo::of(dest)`) through `warp` (source world → destination world).
inline OccupancyGrid resample_through(const OccupancyGrid& source, const WarpField& warp, const GridInfo& frame) {
  OccupancyGrid out(frame.width, frame.height, frame.resolution, frame.origin, CellState::unknown);
  const Eigen::Affine2d dest_world = frame.world_from_pixel();
  const Eigen::Affine2d source_pixel = source.pixel_from_world();
  for (int row = 0; row < frame.height; ++row) {
    for (int col = 0; col < frame.width; ++col) {
      const std::optional<Eigen::Vector2d> from = warp.preimage(dest_world * Eigen::Vector2d(col, row));
      if (!from) continue;
      const Eigen::Vector2d p = source_pixel * *from;
      const int x = static_cast<int>(std::lround(p.x())), y = static_cast<int>(std::lround(p.y()));
      if (source.contains(x, y)) out.set(col, row, source.at(x, y));
    }
  }
  return out;
}

}  // namespace areamatch
