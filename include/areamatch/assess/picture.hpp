#pragma once
/// \file assess/picture.hpp
/// The picture of an assessment (`areamatch assess --png`): the reference map in grey with the
/// map's walls laid on it by the rigid answer, each wall coloured by how far the warp has to move
/// it (green in place, yellow, orange, red at `error_scale_m` and beyond; grey-blue where no
/// reference wall is near), the broken pieces' areas outlined in their own colours, and a legend
/// below.

#include "../detail/format.hpp"
#include "../detail/tiny_font.hpp"
#include "../render.hpp"
#include "../warp/fit.hpp"
#include "report.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace areamatch {

/// The colour of a local error of `error_m` on a scale that saturates at `scale_m`.
inline Rgb error_color(double error_m, double scale_m) {
  const double t = std::clamp(error_m / scale_m, 0.0, 1.0);
  // green (0, 170, 0) → yellow (230, 200, 0) → red (220, 0, 0)
  auto mix = [](double a, double b, double u) { return static_cast<std::uint8_t>(std::lround(a + (b - a) * u)); };
  if (t < 0.5) return {mix(0, 230, 2 * t), mix(170, 200, 2 * t), 0};
  return {mix(230, 220, 2 * t - 1), mix(200, 0, 2 * t - 1), 0};
}

/// Outline colours of the broken pieces (the main piece is not outlined).
inline Rgb piece_color(std::size_t k) {
  static constexpr Rgb colors[] = {{30, 80, 255}, {200, 0, 200}, {0, 170, 200}, {120, 60, 200}};
  return colors[(k + 3) % 4];  // piece 1 first colour
}

/// Map walls with no reference wall within `counterpart_m` under the warp (furniture, laser
/// streaks, rooms the reference lacks): their displacement means nothing, so they are drawn in
/// this colour instead.
inline constexpr Rgb unmatched_color{150, 160, 190};

/// The assessment's picture (file comment). `error_scale_m`: the error drawn fully red.
inline RgbImage render_assessment(const OccupancyGrid& map, const AreaGraph& map_graph, const OccupancyGrid& reference,
                                  const MapAssessment& assessment, double error_scale_m = 0.5, double counterpart_m = 0.3,
                                  const MapColors& colors = {}) {
  RgbImage image = render_grid(reference, colors);
  if (assessment.ok) {
    const Similarity2& T = assessment.match.T_dest_source;
    const WarpField& field = assessment.warp.field;
    const GridInfo g = GridInfo::of(map);
    const Eigen::Affine2d world = g.world_from_pixel();
    const auto width = static_cast<std::size_t>(map.width());
    // The pieces' outlines first, a little thicker, so that the walls stay readable on top.
    const auto& pieces = assessment.brokenness;
    for (std::size_t k = 1; k < pieces.pieces.size(); ++k) {
      for (const int a : pieces.pieces[k].areas) {
        const auto& ring = map_graph.areas[static_cast<std::size_t>(a)].polygon.outer();
        for (std::size_t i = 0; i + 1 < ring.size(); ++i) {
          const Eigen::Vector2d p(ring[i].x(), ring[i].y()), q(ring[i + 1].x(), ring[i + 1].y());
          for (const Eigen::Vector2d& offset : {Eigen::Vector2d(0, 0), Eigen::Vector2d(reference.resolution(), 0),
                                                Eigen::Vector2d(0, reference.resolution())}) {
            draw_world_line(image, reference, T * p + offset, T * q + offset, piece_color(k));
          }
        }
      }
    }
    const BoundaryLookup reference_walls(detail::wall_points(reference, reference.resolution()), 2.0 * reference.resolution(),
                                         counterpart_m);
    for (const std::size_t i : detail::wall_edge_cells(map)) {
      const Eigen::Vector2d p = world * Eigen::Vector2d(static_cast<double>(i % width), static_cast<double>(i / width));
      const Eigen::Vector2i cell = reference.world_to_cell(T * p);
      if (!reference.contains(cell.x(), cell.y())) continue;
      const Eigen::Vector2d y = field.apply(p);
      const Eigen::Vector2d* q = reference_walls.empty() ? nullptr : reference_walls.nearest(y);
      const bool placed = q && (*q - y).norm() <= counterpart_m;
      const Rgb c = placed ? error_color(field.displacement(p).norm(), error_scale_m) : unmatched_color;
      image.set(cell.x(), cell.y(), c[0], c[1], c[2]);
    }
  }

  // The legend, in a strip below the map.
  const int scale = std::max(2, image.width / 500);
  const int line = 8 * scale, strip = 4 * line;
  RgbImage out(std::max(image.width, 140 * scale), image.height + strip, 255, 255, 255);
  for (int r = 0; r < image.height; ++r) {
    std::copy_n(&image.rgb[static_cast<std::size_t>(r) * image.width * 3], static_cast<std::size_t>(image.width) * 3,
                &out.rgb[static_cast<std::size_t>(r) * out.width * 3]);
  }
  const int x0 = 2 * scale, y0 = image.height + scale;
  const std::string title = assessment.ok ? "MAP WALLS BY LOCAL ERROR (M)" : "NOT PLACED: NO ACCEPTED MATCH";
  detail::draw_tiny_text(out, x0, y0, title, scale, 0, 0, 0);
  if (assessment.ok) {
    const int bar = 100 * scale, bar_y = y0 + line;
    for (int x = 0; x < bar; ++x) {
      const Rgb c = error_color(error_scale_m * x / (bar - 1), error_scale_m);
      for (int y = 0; y < 2 * scale; ++y) out.set(x0 + x, bar_y + y, c[0], c[1], c[2]);
    }
    for (int tick = 0; tick <= 2; ++tick) {
      const double v = error_scale_m * tick / 2.0;
      std::string label = detail::format_double(v);
      if (tick == 2) label = ">" + label;
      const int x = x0 + tick * (bar - 1) / 2 - (tick == 0 ? 0 : tick == 1 ? detail::tiny_text_width(label, scale) / 2
                                                                             : detail::tiny_text_width(label, scale));
      detail::draw_tiny_text(out, x, bar_y + 3 * scale, label, scale, 0, 0, 0);
    }
    int x = x0 + bar + 6 * scale;
    {
      const std::string label = "NO WALL THERE";
      for (int y = 0; y < 2 * scale; ++y)
        for (int dx = 0; dx < 4 * scale; ++dx)
          out.set(std::min(out.width - 1, x + dx), bar_y + y, unmatched_color[0], unmatched_color[1], unmatched_color[2]);
      detail::draw_tiny_text(out, x, bar_y + 3 * scale, label, scale, 90, 100, 130);
      x += detail::tiny_text_width(label, scale) + 3 * scale;
    }
    for (std::size_t k = 1; k < assessment.brokenness.pieces.size() && k <= 4; ++k) {
      const Rgb c = piece_color(k);
      const std::string label = "PIECE " + std::to_string(k + 1);
      for (int y = 0; y < 2 * scale; ++y)
        for (int dx = 0; dx < 4 * scale; ++dx) out.set(std::min(out.width - 1, x + dx), bar_y + y, c[0], c[1], c[2]);
      detail::draw_tiny_text(out, x, bar_y + 3 * scale, label, scale, c[0], c[1], c[2]);
      x += detail::tiny_text_width(label, scale) + 3 * scale;
    }
  }
  return out;
}

}  // namespace areamatch
