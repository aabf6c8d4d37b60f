#pragma once
/// \file io/svg.hpp
/// SVG pictures: the destination map as an embedded PNG and the source map's walls as a vector
/// path placed with the exact pixel transform, so the picture stays sharp at any zoom.

#include "../detail/file.hpp"
#include "../detail/format.hpp"
#include "../grid.hpp"
#include "../render.hpp"
#include "../transform.hpp"
#include "../area_graph.hpp"
#include "../segment/skeleton.hpp"
#include "png.hpp"

#include <string>
#include <vector>

namespace areamatch {
namespace detail {

inline std::string base64(const std::vector<unsigned char>& bytes) {
  static const char table[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const unsigned v = (bytes[i] << 16) | ((i + 1 < bytes.size() ? bytes[i + 1] : 0) << 8) |
                       (i + 2 < bytes.size() ? bytes[i + 2] : 0);
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? table[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? table[v & 63] : '=';
  }
  return out;
}

inline std::string svg_color(const Rgb& c) {
  return "rgb(" + std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) + ")";
}

/// The occupied cells of `grid` as one SVG path in pixel units (pixel (c, r) covers
/// [c − 0.5, c + 0.5] × [r − 0.5, r + 0.5]), one rectangle per horizontal run.
inline std::string occupied_path(const OccupancyGrid& grid) {
  std::string d;
  for (int row = 0; row < grid.height(); ++row) {
    int col = 0;
    while (col < grid.width()) {
      if (grid.at(col, row) != CellState::occupied) {
        ++col;
        continue;
      }
      const int start = col;
      while (col < grid.width() && grid.at(col, row) == CellState::occupied) ++col;
      d += "M" + std::to_string(start) + "-.5 " + std::to_string(row) + "-.5h" + std::to_string(col - start) + "v1h-" +
           std::to_string(col - start) + "z";
    }
  }
  return d;
}

}  // namespace detail

/// An SVG of a picture of `dest` (one pixel per cell, e.g. `render_grid(dest)`) with `source`'s
/// occupied cells laid over it as vectors by `T_dest_source`.
inline std::string overlay_svg(const RgbImage& dest_picture, const OccupancyGrid& dest, const OccupancyGrid& source,
                               const Similarity2& T_dest_source, const MapColors& colors = {}) {
  using detail::format_double;
  const PixelTransform m = to_pixel_transform(T_dest_source, source, dest);
  const std::string png = detail::base64(encode_png(dest_picture));
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"-0.5 -0.5 " + std::to_string(dest.width()) +
                    " " + std::to_string(dest.height()) + "\" width=\"" + std::to_string(dest.width()) +
                    "\" height=\"" + std::to_string(dest.height()) + "\">\n";
  svg += "<image x=\"-0.5\" y=\"-0.5\" width=\"" + std::to_string(dest.width()) + "\" height=\"" +
         std::to_string(dest.height()) + "\" style=\"image-rendering:pixelated\" href=\"data:image/png;base64," + png +
         "\"/>\n";
  svg += "<g transform=\"matrix(" + format_double(m(0, 0)) + " " + format_double(m(1, 0)) + " " +
         format_double(m(0, 1)) + " " + format_double(m(1, 1)) + " " + format_double(m(0, 2)) + " " +
         format_double(m(1, 2)) + ")\">\n";
  svg += "<path fill=\"" + detail::svg_color(colors.overlay) + "\" fill-opacity=\"0.8\" d=\"" +
         detail::occupied_path(source) + "\"/>\n</g>\n</svg>\n";
  return svg;
}

/// An SVG of `dest` with `source`'s occupied cells laid over it by `T_dest_source`.
inline std::string overlay_svg(const OccupancyGrid& dest, const OccupancyGrid& source,
                               const Similarity2& T_dest_source, const MapColors& colors = {}) {
  return overlay_svg(render_grid(dest, colors), dest, source, T_dest_source, colors);
}

/// An SVG of a segmentation: the coloured areas as an embedded PNG (one pixel per cell), each
/// passage as a line across its opening with a circle whose diameter is its width, and the
/// skeleton as polylines when given.
inline std::string area_graph_svg(const OccupancyGrid& grid, const AreaGraph& graph, const Skeleton* skeleton = nullptr,
                                  const MapColors& colors = {}) {
  using detail::format_double;
  AreaGraph without_passages = graph;
  without_passages.passages.clear();
  const std::string png = detail::base64(encode_png(render_area_graph(grid, without_passages, colors)));
  const std::string w = std::to_string(grid.width()), h = std::to_string(grid.height());
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"-0.5 -0.5 " + w + " " + h + "\" width=\"" + w +
                    "\" height=\"" + h + "\">\n<image x=\"-0.5\" y=\"-0.5\" width=\"" + w + "\" height=\"" + h +
                    "\" style=\"image-rendering:pixelated\" href=\"data:image/png;base64," + png + "\"/>\n";
  auto pixel = [&](const Eigen::Vector2d& world) {
    const Eigen::Vector2d p = grid.world_to_pixel(world);
    return format_double(std::round(p.x() * 100) / 100) + "," + format_double(std::round(p.y() * 100) / 100);
  };
  if (skeleton) {
    svg += "<g fill=\"none\" stroke=\"rgb(90,90,90)\" stroke-width=\"1\">\n";
    for (const auto& branch : skeleton->branches) {
      if (branch.removed) continue;
      svg += "<polyline points=\"";
      for (const auto& sample : skeleton->samples_of(branch)) {
        const Eigen::Vector2d p = sample.position + skeleton->lattice_offset - Eigen::Vector2d(0.5, 0.5);
        svg += format_double(std::round(p.x() * 100) / 100) + "," + format_double(std::round(p.y() * 100) / 100) + " ";
      }
      svg += "\"/>\n";
    }
    svg += "</g>\n";
  }
  svg += "<g stroke=\"rgb(20,20,160)\" stroke-width=\"2\" fill=\"rgb(20,20,160)\" fill-opacity=\"0.35\">\n";
  for (const auto& p : graph.passages) {
    const Eigen::Vector2d c = grid.world_to_pixel(p.position);
    const std::string a = pixel(to_vector(p.line.first)), b = pixel(to_vector(p.line.second));
    svg += "<path d=\"M" + a + " L" + b + "\"/><circle cx=\"" + format_double(std::round(c.x() * 100) / 100) +
           "\" cy=\"" + format_double(std::round(c.y() * 100) / 100) + "\" r=\"" +
           format_double(std::round(50.0 * p.width_m / grid.resolution()) / 100) + "\"><title>passage " +
           std::to_string(p.id) + ": areas " + std::to_string(p.area_a) + "-" + std::to_string(p.area_b) + ", " +
           detail::format_fixed(p.width_m, 2) + " m</title></circle>\n";
  }
  return svg + "</g>\n</svg>\n";
}

inline void write_text_file(const std::string& path, const std::string& text) { detail::write_file_text(path, text); }

}  // namespace areamatch
