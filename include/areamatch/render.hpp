#pragma once
/// \file render.hpp
/// Raster pictures of maps and of one map laid over another. File formats (PNG, SVG) are in the
/// `areamatch::io` target: see io/svg.hpp and io/png.hpp.

#include "area_graph.hpp"
#include "detail/tiny_font.hpp"
#include "grid.hpp"
#include "image.hpp"
#include "match/result.hpp"
#include "match/verification/occupied_walls.hpp"
#include "merge/fuse.hpp"
#include "segment/skeleton.hpp"
#include "transform.hpp"
#include "warp/field.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

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

/// Whether a cell has a free 8-neighbour: the occupied cells worth drawing (walls, not the
/// solid outside of a map).
inline bool touches_free(const OccupancyGrid& grid, int col, int row) {
  for (int dr = -1; dr <= 1; ++dr)
    for (int dc = -1; dc <= 1; ++dc)
      if (grid.contains(col + dc, row + dr) && grid.is_free(col + dc, row + dr)) return true;
  return false;
}

namespace detail {

/// Which pixels of a picture of `dest` show one of `source`'s walls (occupied cells next to free
/// space): `source_pixel(col, row)` is the source pixel under destination pixel (col, row). Each
/// destination pixel looks up the source cell under it, so the walls have no holes whatever the
/// scale. Row-major, 1 where a wall is.
template <class SourcePixel>
std::vector<std::uint8_t> walls_under(const OccupancyGrid& dest, const OccupancyGrid& source, const SourcePixel& source_pixel) {
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(dest.width()) * static_cast<std::size_t>(dest.height()), 0);
  for (int row = 0; row < dest.height(); ++row) {
    for (int col = 0; col < dest.width(); ++col) {
      const Eigen::Vector2d p = source_pixel(col, row);
      const int sc = static_cast<int>(std::floor(p.x() + 0.5)), sr = static_cast<int>(std::floor(p.y() + 0.5));
      if (source.contains(sc, sr) && source.at(sc, sr) == CellState::occupied && touches_free(source, sc, sr)) {
        mask[dest.index(col, row)] = 1;
      }
    }
  }
  return mask;
}

/// `source`'s walls on a picture of `dest` after `T_dest_source` (world frames), as `walls_under`.
inline std::vector<std::uint8_t> source_walls(const OccupancyGrid& dest, const OccupancyGrid& source, const Similarity2& T_dest_source) {
  const Eigen::Affine2d source_from_dest =
      source.pixel_from_world() * T_dest_source.affine().inverse() * dest.world_from_pixel();
  return walls_under(dest, source, [&](int col, int row) { return Eigen::Vector2d(source_from_dest * Eigen::Vector2d(col, row)); });
}

/// `source`'s walls on a picture of `dest` through a warp (source world → dest world), read as a
/// merge reads a warped map (`FuseParams::warp_lattice_m`).
inline std::vector<std::uint8_t> source_walls(const OccupancyGrid& dest, const OccupancyGrid& source, const WarpField& warp) {
  const FuseParams reading;
  const WarpedPixels pixels(source, warp, dest, warped_outline(known_corners(source), warp, reading.warp_lattice_m),
                            reading.warp_lattice_m);
  return walls_under(dest, source, [&](int col, int row) { return pixels.at(col, row); });
}

/// Paints the pixels of `mask` (row-major over `image`) in `color`.
inline void paint(RgbImage& image, const std::vector<std::uint8_t>& mask, const Rgb& color) {
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (mask[i]) {
      image.set(static_cast<int>(i % static_cast<std::size_t>(image.width)), static_cast<int>(i / static_cast<std::size_t>(image.width)),
                color[0], color[1], color[2]);
    }
  }
}

}  // namespace detail

/// Draws `source`'s walls (occupied cells next to free space) onto a picture of `dest` after
/// `T_dest_source` (world frames).
inline void draw_source_walls(RgbImage& image, const OccupancyGrid& dest, const OccupancyGrid& source,
                              const Similarity2& T_dest_source, const Rgb& color) {
  detail::paint(image, detail::source_walls(dest, source, T_dest_source), color);
}

/// Draws `source`'s walls onto a picture of `dest` through a warp (source world → dest world),
/// read as a merge reads a warped map (`FuseParams::warp_lattice_m`).
inline void draw_source_walls(RgbImage& image, const OccupancyGrid& dest, const OccupancyGrid& source, const WarpField& warp,
                              const Rgb& color) {
  detail::paint(image, detail::source_walls(dest, source, warp), color);
}

/// The destination map with the source map's walls drawn over it after `T_dest_source`.
inline RgbImage render_overlay(const OccupancyGrid& dest, const OccupancyGrid& source,
                               const Similarity2& T_dest_source, const MapColors& colors = {}) {
  RgbImage image = render_grid(dest, colors);
  draw_source_walls(image, dest, source, T_dest_source, colors.overlay);
  return image;
}

namespace detail {
/// The RGB of a hue (degrees), saturation and value (both in [0, 1]).
inline Rgb hsv_color(double hue_deg, double s, double v) {
  const double hue = std::fmod(hue_deg, 360.0) / 60.0;
  const double c = v * s, x = c * (1.0 - std::abs(std::fmod(hue, 2.0) - 1.0)), m = v - c;
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(hue)) {
    case 0: r = c, g = x; break;
    case 1: r = x, g = c; break;
    case 2: g = c, b = x; break;
    case 3: g = x, b = c; break;
    case 4: r = x, b = c; break;
    default: r = c, b = x; break;
  }
  auto byte = [m](double value) { return static_cast<std::uint8_t>(std::lround((value + m) * 255.0)); };
  return {byte(r), byte(g), byte(b)};
}
}  // namespace detail

/// A distinct, light colour for area `id` (golden-angle hues, so neighbours in id differ).
inline Rgb area_color(int id) { return detail::hsv_color(id * 137.50776405, 0.55, 0.95); }

/// A strong colour for map `index` of a merge, to read as a line on white: golden-angle hues,
/// every other map darker, so that many maps still differ.
inline Rgb map_color(int index) { return detail::hsv_color(index * 137.50776405, 0.9, index % 2 ? 0.6 : 0.9); }

/// Draws a line of world points onto a picture of `grid` (nearest pixels).
inline void draw_world_line(RgbImage& image, const OccupancyGrid& grid, const Eigen::Vector2d& a,
                            const Eigen::Vector2d& b, const Rgb& color) {
  const Eigen::Vector2d pa = grid.world_to_pixel(a), pb = grid.world_to_pixel(b);
  const int steps = std::max(1, static_cast<int>(std::ceil((pb - pa).norm() * 2.0)));
  for (int i = 0; i <= steps; ++i) {
    const Eigen::Vector2d p = pa + (pb - pa) * (static_cast<double>(i) / steps);
    const int c = static_cast<int>(std::floor(p.x() + 0.5)), r = static_cast<int>(std::floor(p.y() + 0.5));
    if (c >= 0 && r >= 0 && c < image.width && r < image.height) image.set(c, r, color[0], color[1], color[2]);
  }
}

/// A filled disc of `radius` pixels around a world point.
inline void draw_world_dot(RgbImage& image, const OccupancyGrid& grid, const Eigen::Vector2d& centre, double radius,
                           const Rgb& color) {
  const Eigen::Vector2d p = grid.world_to_pixel(centre);
  const int r0 = static_cast<int>(std::ceil(radius));
  for (int dr = -r0; dr <= r0; ++dr)
    for (int dc = -r0; dc <= r0; ++dc) {
      if (dc * dc + dr * dr > radius * radius) continue;
      const int c = static_cast<int>(std::floor(p.x() + 0.5)) + dc, r = static_cast<int>(std::floor(p.y() + 0.5)) + dr;
      if (c >= 0 && r >= 0 && c < image.width && r < image.height) image.set(c, r, color[0], color[1], color[2]);
    }
}

/// Draws the kept skeleton branches (lattice coordinates) onto a picture of the same grid.
inline void draw_skeleton(RgbImage& image, const Skeleton& skeleton, const Rgb& color = {90, 90, 90}) {
  for (const auto& branch : skeleton.branches) {
    if (branch.removed) continue;
    for (const auto& s : skeleton.samples_of(branch)) {
      const Eigen::Vector2d p = s.position + skeleton.lattice_offset;
      const int c = static_cast<int>(std::floor(p.x())), r = static_cast<int>(std::floor(p.y()));
      if (c >= 0 && r >= 0 && c < image.width && r < image.height) image.set(c, r, color[0], color[1], color[2]);
    }
  }
}

/// Tints the cells of the listed areas, each in the colour of its partner `colour_of[label]`
/// (no tint where that is −1).
inline void tint_areas(RgbImage& image, const AreaGraph& graph, const std::vector<int>& colour_of) {
  const auto width = static_cast<std::size_t>(image.width);
  graph.labels.for_each_run([&](std::size_t first, std::size_t last, int label) {
    if (label < 0 || colour_of[static_cast<std::size_t>(label)] < 0) return;
    const Rgb c = area_color(colour_of[static_cast<std::size_t>(label)]);
    for (std::size_t i = first; i < last; ++i) image.set(static_cast<int>(i % width), static_cast<int>(i / width), c[0], c[1], c[2]);
  });
}

/// The map with every area in its own colour, passages as lines across their openings with a dot
/// whose size shows the width, and the skeleton when given. Free cells in no area stay white.
inline RgbImage render_area_graph(const OccupancyGrid& grid, const AreaGraph& graph, const MapColors& colors = {},
                                  const Skeleton* skeleton = nullptr) {
  RgbImage image = render_grid(grid, colors);
  std::vector<int> all(graph.areas.size());
  std::iota(all.begin(), all.end(), 0);
  tint_areas(image, graph, all);
  if (skeleton) draw_skeleton(image, *skeleton);
  const Rgb passage_color{20, 20, 160};
  for (const auto& p : graph.passages) {
    draw_world_line(image, grid, to_vector(p.line.first), to_vector(p.line.second), passage_color);
    draw_world_dot(image, grid, p.position, std::max(1.5, 0.25 * p.width_m / grid.resolution()), passage_color);
  }
  return image;
}

/// A match at a glance: the destination map with its matched areas tinted and the source map's
/// walls laid over it by the result's transform (in `colors.overlay`); the matched source areas
/// are tinted in the same colour as their partners in the destination.
inline RgbImage render_match_overlay(const OccupancyGrid& source, const OccupancyGrid& dest,
                                     const AreaGraph& dest_graph, const MatchResult& result,
                                     const MapColors& colors = {}) {
  std::vector<int> dest_colour(dest_graph.areas.size(), -1);
  for (const auto& m : result.matched_areas) dest_colour[static_cast<std::size_t>(m.dest)] = m.dest;
  RgbImage image = render_grid(dest, colors);
  tint_areas(image, dest_graph, dest_colour);
  draw_source_walls(image, dest, source, result.T_dest_source, colors.overlay);
  return image;
}

/// The source map with its matched areas tinted in their partners' colours.
inline RgbImage render_match_source(const OccupancyGrid& source, const AreaGraph& source_graph,
                                    const MatchResult& result, const MapColors& colors = {}) {
  std::vector<int> source_colour(source_graph.areas.size(), -1);
  for (const auto& m : result.matched_areas) source_colour[static_cast<std::size_t>(m.source)] = m.dest;
  RgbImage image = render_grid(source, colors);
  tint_areas(image, source_graph, source_colour);
  return image;
}

namespace detail {
/// Copies `in` into `out` with its top-left corner at (x0, y0); `in` must fit.
inline void blit(RgbImage& out, const RgbImage& in, int x0, int y0) {
  for (int r = 0; r < in.height; ++r)
    for (int c = 0; c < in.width; ++c) {
      const std::uint8_t* p = &in.rgb[(static_cast<std::size_t>(r) * in.width + c) * 3];
      out.set(x0 + c, y0 + r, p[0], p[1], p[2]);
    }
}
}  // namespace detail

/// Two pictures side by side, top-aligned, with a white gap between them; the shorter one is
/// padded with `background` (the maps' unknown colour, so the padding reads as "no map here").
inline RgbImage side_by_side(const RgbImage& left, const RgbImage& right, const Rgb& background = MapColors{}.unknown,
                             int gap = 10) {
  RgbImage out(left.width + gap + right.width, std::max(left.height, right.height), background[0], background[1],
               background[2]);
  for (int r = 0; r < out.height; ++r)
    for (int c = left.width; c < left.width + gap; ++c) out.set(c, r, 255, 255, 255);
  detail::blit(out, left, 0, 0);
  detail::blit(out, right, left.width + gap, 0);
  return out;
}

/// `picture` below a red band that reads "REJECTED: " and the first words of `reason` (up to its
/// first parenthesis, cut at a word to fit the width): the overlay of a rejected match shows a
/// transform nobody should use, and must not be mistaken for an answer.
inline RgbImage with_rejection_banner(const RgbImage& picture, const std::string& reason) {
  const int scale = std::max(2, picture.width / 400);
  const std::size_t fits = static_cast<std::size_t>(std::max(1, (picture.width - 4 * scale) / (4 * scale)));
  std::string text = "REJECTED: " + reason.substr(0, reason.find(" ("));
  if (text.size() > fits) {
    const std::size_t cut = text.rfind(' ', fits > 3 ? fits - 3 : 0);
    text = text.substr(0, cut == std::string::npos || cut < 9 ? fits : cut) + "...";
    if (text.size() > fits) text.resize(fits);
  }
  const int band = 9 * scale;
  RgbImage out(picture.width, picture.height + band, 190, 30, 30);
  detail::blit(out, picture, 0, band);
  detail::draw_tiny_text(out, 2 * scale, 2 * scale, text, scale, 255, 255, 255);
  return out;
}

/// The picture `areamatch match --png` and `areamatch eval` write: the source with matched areas
/// tinted, beside the destination with the source's walls laid over it; a rejected match under
/// a red band saying so (`with_rejection_banner`).
inline RgbImage render_match(const OccupancyGrid& source, const AreaGraph& source_graph, const OccupancyGrid& dest,
                             const AreaGraph& dest_graph, const MatchResult& result, const MapColors& colors = {}) {
  RgbImage picture = side_by_side(render_match_source(source, source_graph, result, colors),
                                  render_match_overlay(source, dest, dest_graph, result, colors), colors.unknown);
  return result.ok ? picture : with_rejection_banner(picture, result.reason);
}

/// `image` shrunk by an integer `factor` (≥ 1). Each block becomes its mean colour, unless it
/// holds a strongly coloured pixel (an overlay line one pixel thin), which then wins, so that
/// thin coloured lines survive the shrinking instead of fading into the background.
inline RgbImage downscaled(const RgbImage& image, int factor) {
  if (factor <= 1) return image;
  RgbImage out((image.width + factor - 1) / factor, (image.height + factor - 1) / factor);
  for (int r = 0; r < out.height; ++r) {
    for (int c = 0; c < out.width; ++c) {
      int sum[3] = {0, 0, 0}, count = 0, best_chroma = -1;
      const std::uint8_t* best = nullptr;
      for (int y = r * factor; y < std::min(image.height, (r + 1) * factor); ++y) {
        for (int x = c * factor; x < std::min(image.width, (c + 1) * factor); ++x) {
          const std::uint8_t* p = &image.rgb[(static_cast<std::size_t>(y) * image.width + x) * 3];
          for (int k = 0; k < 3; ++k) sum[k] += p[k];
          ++count;
          const int chroma = std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]});
          if (chroma > best_chroma) best_chroma = chroma, best = p;
        }
      }
      constexpr int strong_chroma = 150;
      if (best_chroma >= strong_chroma) out.set(c, r, best[0], best[1], best[2]);
      else out.set(c, r, static_cast<std::uint8_t>(sum[0] / count), static_cast<std::uint8_t>(sum[1] / count),
                   static_cast<std::uint8_t>(sum[2] / count));
    }
  }
  return out;
}

}  // namespace areamatch
