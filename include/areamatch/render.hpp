#pragma once
/// \file render.hpp
/// Raster pictures of maps and of one map laid over another. File formats (PNG, SVG) are in the
/// `areamatch::io` target: see io/svg.hpp and io/png.hpp.

#include "grid.hpp"
#include "image.hpp"
#include "transform.hpp"

#include <array>
#include <cstdint>

namespace areamatch {

using Rgb = std::array<std::uint8_t, 3>;

/// Colours of map pictures.
struct MapColors {
  Rgb free{255, 255, 255};
  Rgb occupied{40, 40, 40};
  Rgb unknown{200, 200, 200};
  Rgb overlay{220, 30, 30};  ///< the source map's occupied cells laid over the destination
};

/// One pixel per cell: free, occupied, unknown in their colours.
inline RgbImage render_grid(const OccupancyGrid& grid, const MapColors& colors = {}) {
  RgbImage image(grid.width(), grid.height());
  for (int row = 0; row < grid.height(); ++row) {
    for (int col = 0; col < grid.width(); ++col) {
      const CellState s = grid.at(col, row);
      const Rgb& c = s == CellState::free ? colors.free : s == CellState::occupied ? colors.occupied : colors.unknown;
      image.set(col, row, c[0], c[1], c[2]);
    }
  }
  return image;
}

/// The destination map with the source map's occupied cells drawn over it after `T_dest_source`
/// (world frames). Each destination pixel looks up the source cell under it, so the overlay has
/// no holes whatever the scale.
inline RgbImage render_overlay(const OccupancyGrid& dest, const OccupancyGrid& source,
                               const Similarity2& T_dest_source, const MapColors& colors = {}) {
  RgbImage image = render_grid(dest, colors);
  const Eigen::Affine2d source_from_dest =
      source.pixel_from_world() * T_dest_source.affine().inverse() * dest.world_from_pixel();
  for (int row = 0; row < dest.height(); ++row) {
    for (int col = 0; col < dest.width(); ++col) {
      const Eigen::Vector2d p = source_from_dest * Eigen::Vector2d(col, row);
      const int sc = static_cast<int>(std::floor(p.x() + 0.5)), sr = static_cast<int>(std::floor(p.y() + 0.5));
      if (source.contains(sc, sr) && source.at(sc, sr) == CellState::occupied) {
        image.set(col, row, colors.overlay[0], colors.overlay[1], colors.overlay[2]);
      }
    }
  }
  return image;
}

/// Two pictures side by side with a gap (white), top-aligned.
inline RgbImage side_by_side(const RgbImage& left, const RgbImage& right, int gap = 10) {
  RgbImage out(left.width + gap + right.width, std::max(left.height, right.height));
  auto blit = [&out](const RgbImage& in, int x0) {
    for (int r = 0; r < in.height; ++r)
      for (int c = 0; c < in.width; ++c) {
        const std::uint8_t* p = &in.rgb[(static_cast<std::size_t>(r) * in.width + c) * 3];
        out.set(x0 + c, r, p[0], p[1], p[2]);
      }
  };
  blit(left, 0);
  blit(right, left.width + gap);
  return out;
}

}  // namespace areamatch
