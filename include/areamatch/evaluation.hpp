#pragma once
/// \file evaluation.hpp
/// Judging a match against ground truth exactly as the reference scorer
/// (`shared/tools/score.py`) does: the rotation error between the two pixel transforms, and the
/// mean displacement (destination metres) of the source map's free-space edge pixels.

#include "grid.hpp"
#include "transform.hpp"

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <vector>

namespace areamatch {

/// The thresholds that make a match correct (`correct_if` of a pairs manifest).
struct CorrectnessThresholds {
  double max_rotation_error_deg = 3.0;
  double max_mean_displacement_m = 1.0;
};

struct MatchError {
  double rotation_error_deg = 0.0;   ///< 180 when one transform is mirrored and the other not
  double mean_displacement_m = 0.0;  ///< in destination metres
  double scale_error = 0.0;          ///< |estimated scale / true scale − 1| of the pixel transforms
  bool correct(const CorrectnessThresholds& t) const {
    return rotation_error_deg <= t.max_rotation_error_deg && mean_displacement_m <= t.max_mean_displacement_m;
  }
};

/// Source free cells with a non-free 8-neighbour (the grid's border counts as free, as in an
/// OpenCV erosion), in row-major order, evenly thinned to at most `max_points` — the reference
/// scorer's point set (it takes 20000).
inline std::vector<Eigen::Vector2d> free_edge_pixels(const OccupancyGrid& grid, std::size_t max_points = 20000) {
  std::vector<Eigen::Vector2d> points;
  for (int row = 0; row < grid.height(); ++row) {
    for (int col = 0; col < grid.width(); ++col) {
      if (!grid.is_free(col, row)) continue;
      bool edge = false;
      for (int dr = -1; dr <= 1 && !edge; ++dr)
        for (int dc = -1; dc <= 1 && !edge; ++dc)
          edge = grid.contains(col + dc, row + dr) && !grid.is_free(col + dc, row + dr);
      if (edge) points.emplace_back(col, row);
    }
  }
  if (points.size() > max_points) {
    // numpy's linspace(0, n − 1, max_points).astype(int)
    std::vector<Eigen::Vector2d> thinned;
    thinned.reserve(max_points);
    const double step = static_cast<double>(points.size() - 1) / static_cast<double>(max_points - 1);
    for (std::size_t i = 0; i < max_points; ++i) thinned.push_back(points[static_cast<std::size_t>(i * step)]);
    points.swap(thinned);
  }
  return points;
}

/// Rotation (degrees) and reflection of a pixel transform's linear part, as score.py reads it.
inline std::pair<double, bool> pixel_rotation(const PixelTransform& t) {
  Eigen::Matrix2d a = t.leftCols<2>();
  const bool reflected = a.determinant() < 0.0;
  if (reflected) a.col(1) = -a.col(1);
  return {std::atan2(a(1, 0), a(0, 0)) * 180.0 / pi, reflected};
}

/// The error of `estimate` against `truth` (both source pixel → destination pixel) over the
/// given source pixels, in metres of a destination map with `dest_resolution`.
inline MatchError match_error(const PixelTransform& estimate, const PixelTransform& truth,
                              const std::vector<Eigen::Vector2d>& source_pixels, double dest_resolution) {
  MatchError e;
  const auto [estimate_angle, estimate_reflected] = pixel_rotation(estimate);
  const auto [truth_angle, truth_reflected] = pixel_rotation(truth);
  if (estimate_reflected != truth_reflected) {
    e.rotation_error_deg = 180.0;
  } else {
    double d = std::fmod(estimate_angle - truth_angle + 180.0, 360.0);
    if (d < 0.0) d += 360.0;
    e.rotation_error_deg = std::abs(d - 180.0);
  }
  double sum = 0.0;
  for (const auto& p : source_pixels) {
    sum += (estimate.leftCols<2>() * p + estimate.col(2) - truth.leftCols<2>() * p - truth.col(2)).norm();
  }
  e.mean_displacement_m = source_pixels.empty() ? 0.0 : sum / static_cast<double>(source_pixels.size()) * dest_resolution;
  const double truth_scale = std::sqrt(std::abs(truth.leftCols<2>().determinant()));
  const double estimate_scale = std::sqrt(std::abs(estimate.leftCols<2>().determinant()));
  e.scale_error = truth_scale > 0.0 ? std::abs(estimate_scale / truth_scale - 1.0) : 0.0;
  return e;
}

}  // namespace areamatch
