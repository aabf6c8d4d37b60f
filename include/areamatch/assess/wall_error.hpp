#pragma once
/// \file assess/wall_error.hpp
/// Wall error both ways (accuracy and completeness of a map against a reference): the distance
/// of each of the map's wall points to the reference's nearest wall, and of each reference wall
/// point near the map's explored space to the map's nearest wall — under the rigid answer and
/// under the warp. Distances are capped (`AssessParams::wall_distance_cap_m`): beyond the cap a
/// wall is not displaced but missing from the other map, and the share at the cap says how much.

#include "../grid.hpp"
#include "../match/verification/refine.hpp"
#include "../segment/morphology.hpp"
#include "../warp/field.hpp"
#include "../warp/fit.hpp"
#include "params.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace areamatch {

/// Distances of one map's wall points to the other's walls, metres.
struct WallErrorStats {
  std::size_t points = 0;  ///< wall points measured
  double mean_m = std::numeric_limits<double>::quiet_NaN();    ///< of the capped distances
  double median_m = std::numeric_limits<double>::quiet_NaN();
  double p95_m = std::numeric_limits<double>::quiet_NaN();
  double within_tolerance = std::numeric_limits<double>::quiet_NaN();  ///< share within `wall_tolerance_m`
  double at_cap = std::numeric_limits<double>::quiet_NaN();            ///< share at or beyond `wall_distance_cap_m`
};

/// Wall error both ways under one placement of the map.
struct WallErrors {
  /// The map's walls to the reference's (accuracy: is what the map draws there?).
  WallErrorStats map_to_reference;
  /// The reference's walls near the map's explored space to the map's (completeness: is what is
  /// there drawn?).
  WallErrorStats reference_to_map;
};

namespace detail {

/// Summary of capped distances; `distances` is reordered.
inline WallErrorStats wall_error_stats(std::vector<double>& distances, double tolerance_m, double cap_m) {
  WallErrorStats out;
  out.points = distances.size();
  if (distances.empty()) return out;
  double sum = 0.0;
  std::size_t within = 0, capped = 0;
  for (double& d : distances) {
    d = std::min(d, cap_m);
    sum += d;
    within += d <= tolerance_m;
    capped += d >= cap_m;
  }
  const double n = static_cast<double>(distances.size());
  out.mean_m = sum / n;
  const auto q = median_and_p95(distances);
  out.median_m = q[0];
  out.p95_m = q[1];
  out.within_tolerance = static_cast<double>(within) / n;
  out.at_cap = static_cast<double>(capped) / n;
  return out;
}

/// A map's wall points (`wall_edge_cells`, about `spacing_m` apart), world metres.
inline std::vector<Eigen::Vector2d> wall_points(const OccupancyGrid& grid, double spacing_m) {
  return boundary_points(GridInfo::of(grid), wall_edge_cells(grid), spacing_m, std::numeric_limits<std::size_t>::max());
}

/// Per cell of `grid`: whether a free cell lies within `reach_m` (a disc).
inline std::vector<std::uint8_t> near_free_mask(const OccupancyGrid& grid, double reach_m) {
  std::vector<std::uint8_t> not_free(grid.cells().size());
  for (std::size_t i = 0; i < not_free.size(); ++i) not_free[i] = grid.cells()[i] != CellState::free;
  if (reach_m <= 0.0) {
    for (auto& v : not_free) v = !v;
    return not_free;
  }
  std::vector<std::uint8_t> far = erode_mask(not_free, grid.width(), grid.height(), reach_m / grid.resolution());
  for (auto& v : far) v = !v;
  return far;
}

/// Distance from each point (placed by `place`) to the nearest point of `lookup`, or `cap_m` when
/// there is none in reach.
template <class Place>
std::vector<double> nearest_distances(const std::vector<Eigen::Vector2d>& points, Place&& place, const BoundaryLookup& lookup,
                                      double cap_m) {
  std::vector<double> out;
  out.reserve(points.size());
  for (const Eigen::Vector2d& p : points) {
    const Eigen::Vector2d y = place(p);
    const Eigen::Vector2d* q = lookup.empty() ? nullptr : lookup.nearest(y);
    out.push_back(q ? (*q - y).norm() : cap_m);
  }
  return out;
}

}  // namespace detail

/// The walls of both maps, ready to be compared under any placement: each map's wall points
/// about `wall_spacing_m` apart (those measured) and a lookup of all its wall cells (those
/// measured to: thinning the targets would add up to half a spacing to every distance).
struct WallSets {
  std::vector<Eigen::Vector2d> map_points;        ///< map world
  std::vector<Eigen::Vector2d> reference_points;  ///< reference world
  BoundaryLookup map_lookup;                      ///< every map wall cell
  BoundaryLookup reference_lookup;                ///< every reference wall cell
  std::vector<std::uint8_t> map_near_free;        ///< per map cell: within `explored_reach_m` of its free space

  WallSets(const OccupancyGrid& map, const OccupancyGrid& reference, const AssessParams& params)
      : map_points(detail::wall_points(map, params.wall_spacing_m)),
        reference_points(detail::wall_points(reference, params.wall_spacing_m)),
        map_lookup(detail::wall_points(map, map.resolution()), params.wall_lookup_cell_m, params.wall_distance_cap_m),
        reference_lookup(detail::wall_points(reference, reference.resolution()), params.wall_lookup_cell_m,
                         params.wall_distance_cap_m),
        map_near_free(detail::near_free_mask(map, params.explored_reach_m)) {}
};

/// Wall error both ways with the map placed by `to_reference` (map world → reference world) and
/// brought back by `to_map` (its inverse): a rigid transform or a warp. `scale` is the
/// placement's scale (reference metres per map metre): every distance is in reference metres.
template <class ToReference, class ToMap>
WallErrors wall_errors(const OccupancyGrid& map, const WallSets& walls, ToReference&& to_reference, ToMap&& to_map,
                       double scale, const AssessParams& params) {
  WallErrors out;
  std::vector<double> forward = detail::nearest_distances(walls.map_points, to_reference, walls.reference_lookup,
                                                          params.wall_distance_cap_m);
  out.map_to_reference = detail::wall_error_stats(forward, params.wall_tolerance_m, params.wall_distance_cap_m);
  std::vector<Eigen::Vector2d> explored;  // reference walls where the map has been, in the map's frame
  for (const Eigen::Vector2d& q : walls.reference_points) {
    const Eigen::Vector2d p = to_map(q);
    const Eigen::Vector2i cell = map.world_to_cell(p);
    if (map.contains(cell.x(), cell.y()) && walls.map_near_free[map.index(cell.x(), cell.y())]) explored.push_back(p);
  }
  std::vector<double> back = detail::nearest_distances(explored, [](const Eigen::Vector2d& p) { return p; }, walls.map_lookup,
                                                       params.wall_distance_cap_m / scale);
  for (double& d : back) d *= scale;
  out.reference_to_map = detail::wall_error_stats(back, params.wall_tolerance_m, params.wall_distance_cap_m);
  return out;
}

}  // namespace areamatch
