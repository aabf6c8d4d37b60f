#pragma once
/// \file merge/picture.hpp
/// The picture of a merge (`areamatch merge --png`): the merged map with each placed map's walls in
/// its own colour, and a legend.

#include "../detail/tiny_font.hpp"
#include "../grid.hpp"
#include "../image.hpp"
#include "../match/verification/occupied_walls.hpp"
#include "../render.hpp"
#include "params.hpp"
#include "result.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace areamatch {

namespace detail {

/// Paints the set cells of `mask` (a raster the size of `image`) in `color`.
inline void paint(RgbImage& image, const BitRaster& mask, const Rgb& color) {
  for (int r = 0; r < mask.height; ++r)
    for (int c = 0; c < mask.width; ++c)
      if (mask.test(c, r)) image.set(c, r, color[0], color[1], color[2]);
}

/// A colour mixed towards white: `share` of `color`, the rest white.
inline Rgb paled(const Rgb& color, double share) {
  Rgb out{};
  for (int k = 0; k < 3; ++k) out[static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(std::lround(255.0 - share * (255.0 - color[static_cast<std::size_t>(k)])));
  return out;
}

/// One entry of a picture's legend: a swatch in `color` and its `label`.
struct LegendEntry {
  Rgb color;
  std::string label;
};

/// `picture` above a white strip holding `title` and the entries in as many columns as fit.
inline RgbImage with_legend(const RgbImage& picture, const std::string& title, const std::vector<LegendEntry>& entries) {
  const int scale = std::max(2, picture.width / 500);
  const int line = 8 * scale, swatch = 6 * scale;
  int label_width = 0;
  for (const auto& e : entries) label_width = std::max(label_width, tiny_text_width(e.label, scale));
  const int column = swatch + 2 * scale + label_width + 4 * scale;
  const int width = std::max(picture.width, std::max(tiny_text_width(title, scale), column) + 4 * scale);
  const int columns = std::max(1, (width - 2 * scale) / column);
  const int rows = (static_cast<int>(entries.size()) + columns - 1) / columns;
  RgbImage out(width, picture.height + (rows + 1) * line + 2 * scale, 255, 255, 255);
  blit(out, picture, 0, 0);
  const int x0 = 2 * scale, y0 = picture.height + scale;
  draw_tiny_text(out, x0, y0 + scale, title, scale, 0, 0, 0);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const int x = x0 + static_cast<int>(k) % columns * column, y = y0 + (static_cast<int>(k) / columns + 1) * line;
    const Rgb& c = entries[k].color;
    for (int dy = 0; dy < swatch; ++dy)
      for (int dx = 0; dx < swatch; ++dx) out.set(x + dx, y + dy, c[0], c[1], c[2]);
    draw_tiny_text(out, x + swatch + 2 * scale, y + scale / 2, entries[k].label, scale, 0, 0, 0);
  }
  return out;
}

}  // namespace detail

/// The picture `areamatch merge --png` writes: the merged map (black walls) with each placed map's
/// walls over it in its own colour (`map_color` of its index), thickened to be seen at the
/// picture's size; where the merged map is free (a wall the other maps outvoted: a scan's
/// artefact, or a wall out of place) a map's walls are drawn pale, under the others. A legend
/// below names each map's colour (`names`, in the order given to `merge_maps`; "map i" when
/// missing) and says which maps were not placed.
inline RgbImage render_merge(const MergeResult& result, const std::vector<const OccupancyGrid*>& maps,
                             const std::vector<std::string>& names = {}, const MapColors& colors = {}) {
  const OccupancyGrid& merged = result.merged;
  RgbImage image = render_grid(merged, colors);
  const int radius = std::max(1, std::max(merged.width(), merged.height()) / 1200);
  std::vector<detail::BitRaster> kept(maps.size());
  std::vector<detail::LegendEntry> legend;
  for (std::size_t m = 0; m < maps.size(); ++m) {
    const std::string name = merge_map_name(names, m);
    const bool placed = m < result.maps.size() && result.maps[m].placed;
    legend.push_back({placed ? map_color(static_cast<int>(m)) : colors.unknown, placed ? name : name + " (not placed)"});
    if (!placed) continue;
    const std::vector<std::uint8_t> walls = result.maps[m].warp ? detail::source_walls(merged, *maps[m], result.maps[m].warp->field)
                                                                : detail::source_walls(merged, *maps[m], result.maps[m].T_reference_map);
    detail::BitRaster outvoted(merged.width(), merged.height());
    kept[m] = detail::BitRaster(merged.width(), merged.height());
    for (int row = 0; row < merged.height(); ++row) {
      for (int col = 0; col < merged.width(); ++col) {
        if (walls[merged.index(col, row)]) (merged.is_free(col, row) ? outvoted : kept[m]).set(col, row);
      }
    }
    detail::paint(image, detail::dilated(outvoted, radius - 1), detail::paled(map_color(static_cast<int>(m)), 0.35));
  }
  for (std::size_t m = 0; m < maps.size(); ++m) {
    if (!kept[m].words.empty()) detail::paint(image, detail::dilated(kept[m], radius), map_color(static_cast<int>(m)));
  }
  return detail::with_legend(image, "WALLS OF EACH MAP IN ITS COLOUR, PALE WHERE THE MERGED MAP IS FREE", legend);
}

}  // namespace areamatch
