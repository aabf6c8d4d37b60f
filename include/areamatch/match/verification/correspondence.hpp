#pragma once
/// \file match/verification/correspondence.hpp
/// Room-to-room correspondences with a transform per room. The global transform is one rigid
/// motion; a SLAM map is bent (drift), so a room far from the map's middle can sit half a metre
/// off its drawn counterpart. Each source area gets its own transform — trimmed ICP of the
/// area's walls onto the destination's, started from the global transform, with short gates so
/// it cannot jump to a neighbouring room — and its counterpart is the destination area most of
/// it lands on under that transform. This is what transfers room labels from a layout to a robot
/// map (`areamatch match --labels`).

#include "../../area_graph.hpp"
#include "../../detail/parallel.hpp"
#include "../../error.hpp"
#include "../../grid.hpp"
#include "../../transform.hpp"
#include "../raster.hpp"
#include "../result.hpp"
#include "refine.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

namespace areamatch {

struct CorrespondenceParams {
  /// The local ICP: short gates (metres), so that a room moves to its own walls and not to the
  /// next room's (the global ICP starts at 2 m); more steps per gate on fewer points, as a room
  /// has few walls.
  RefineParams local = local_refinement();
  /// Areas with fewer wall points than this keep the global transform (too little to fit).
  std::size_t min_wall_points = 30;
  /// Pairs overlapping less than this (area of the overlap / the smaller area) are not reported.
  double min_overlap = 0.5;
  /// Wall points within this distance count as on the other map's wall (to judge local vs global).
  double wall_inlier_distance_m = 0.3;
  /// A local transform may differ from the global one by at most this rotation, and move the
  /// area's centroid by at most this distance: drift bends a map by centimetres to decimetres
  /// per room; more means ICP slid a small or featureless area somewhere else.
  double max_rotation_rad = 5.0 * pi / 180.0;
  double max_shift_m = 1.0;

  static RefineParams local_refinement() {
    RefineParams r;
    r.gates_m = {1.0, 0.6, 0.3};
    r.iterations_per_gate = 6;
    r.keep_fraction = 0.8;
    r.point_spacing_m = 0.1;
    r.max_points = 600;
    r.lookup_cell_m = 0.1;
    return r;
  }

  void validate() const {
    local.validate();
    if (min_wall_points < 3) throw parameter_error("CorrespondenceParams::min_wall_points must be >= 3");
    detail::require_non_negative(min_overlap, "CorrespondenceParams::min_overlap");
    detail::require_positive(wall_inlier_distance_m, "CorrespondenceParams::wall_inlier_distance_m");
    detail::require_non_negative(max_rotation_rad, "CorrespondenceParams::max_rotation_rad");
    detail::require_non_negative(max_shift_m, "CorrespondenceParams::max_shift_m");
  }
};

namespace detail {

/// Per area: the free-space edge points (walls, furniture) of its cells, about `spacing_m` apart,
/// from the free-space edge cells `free_edge` (`edge_cells`, in scan order; those outside the
/// areas' extent are passed over). The cuts at passages are not edges of the free space, so they
/// are not included.
inline std::vector<std::vector<Eigen::Vector2d>> area_wall_points(const AreaGraph& graph, const std::vector<std::size_t>& free_edge,
                                                                  double spacing_m) {
  std::vector<std::vector<Eigen::Vector2d>> out(graph.areas.size());
  const std::vector<std::size_t> within = detail::cells_within(free_edge, label_bounds(graph, 0), graph.grid.width);
  detail::for_each_edge_cell(graph.grid, within, spacing_m, [&](std::size_t i, const Eigen::Vector2d& p) {
    const int label = graph.labels[i];
    if (label < 0) return false;  // free but in no area: not this function's, leave the square
    out[static_cast<std::size_t>(label)].push_back(p);
    return true;
  });
  return out;
}

/// `area_correspondences` with the source's per-area wall points given (`area_wall_points`);
/// the areas on `threads` threads (each into its own slot: the same list for any count).
inline std::vector<MatchedAreaPair> area_correspondences(const std::vector<std::vector<Eigen::Vector2d>>& walls,
                                                         const AreaGraph& source, const AreaGraph& dest,
                                                         const AreaRaster& source_raster, const AreaRaster& dest_raster,
                                                         const BoundaryLookup& dest_edge, const Similarity2& T_dest_source,
                                                         const CorrespondenceParams& params, unsigned threads = 1) {
  params.validate();
  const double scale2 = T_dest_source.scale * T_dest_source.scale;
  std::vector<std::optional<MatchedAreaPair>> per_area(source.areas.size());
  for_each_index(source.areas.size(), threads, [&](std::size_t i) {
    // The area's own transform, kept only when it lays the area's walls better.
    Similarity2 T = T_dest_source;
    double on_walls = std::numeric_limits<double>::quiet_NaN();
    if (walls[i].size() >= params.min_wall_points) {
      on_walls = boundary_inlier_fraction(walls[i], dest_edge, T, params.wall_inlier_distance_m);
      const Similarity2 local = refine_icp(walls[i], dest_edge, T, params.local);
      const double local_on_walls = boundary_inlier_fraction(walls[i], dest_edge, local, params.wall_inlier_distance_m);
      const Eigen::Vector2d centroid = source.areas[i].centroid;
      const bool close = std::abs(wrap_angle(local.rotation - T.rotation)) <= params.max_rotation_rad &&
                         (local * centroid - T * centroid).norm() <= params.max_shift_m;
      if (close && local_on_walls > on_walls) {
        T = local;
        on_walls = local_on_walls;
      }
    }
    std::vector<int> landed;  // the destination areas of its cells (a few, not all of them)
    const Eigen::Affine2d to_cell = dest_raster.cell_from_world * T.affine();
    for (int index : source_raster.area_cells[i]) {
      const int label = dest_raster.label_at_cell(to_cell * source_raster.centre(static_cast<std::size_t>(index)));
      if (label >= 0) landed.push_back(label);
    }
    const auto counts = counted(landed);
    const auto it = std::max_element(counts.begin(), counts.end(),  // the lowest id on ties
                                     [](const auto& a, const auto& b) { return a.second < b.second; });
    if (it == counts.end()) return;
    const std::size_t j = static_cast<std::size_t>(it->first);
    const double common_m2 = static_cast<double>(it->second) * source_raster.cell_area() * scale2;
    const double smaller = std::min(source.areas[i].size_m2 * scale2, dest.areas[j].size_m2);
    const double overlap = smaller > 0.0 ? std::min(1.0, common_m2 / smaller) : 0.0;
    if (overlap < params.min_overlap) return;
    const double a = static_cast<double>(source_raster.area_cells[i].size()) * source_raster.cell_area() * scale2;
    const double b = static_cast<double>(dest_raster.area_cells[j].size()) * dest_raster.cell_area();
    MatchedAreaPair pair;
    pair.source = static_cast<int>(i);
    pair.dest = static_cast<int>(j);
    pair.overlap = overlap;
    pair.iou = a + b - common_m2 > 0.0 ? std::min(1.0, common_m2 / (a + b - common_m2)) : 0.0;
    pair.T_dest_source = T;
    pair.wall_agreement = on_walls;
    per_area[i] = pair;
  });
  std::vector<MatchedAreaPair> out;
  for (const auto& pair : per_area) {
    if (pair) out.push_back(*pair);
  }
  return out;
}

}  // namespace detail

/// For every source area: its local transform and the destination area it corresponds to under
/// it (reported when they overlap by at least `params.min_overlap`), in source-area order.
/// `dest_edge` looks up the destination's free-space edge; the rasters share one cell size.
inline std::vector<MatchedAreaPair> area_correspondences(const OccupancyGrid& source_grid, const AreaGraph& source,
                                                         const AreaGraph& dest, const AreaRaster& source_raster,
                                                         const AreaRaster& dest_raster, const BoundaryLookup& dest_edge,
                                                         const Similarity2& T_dest_source,
                                                         const CorrespondenceParams& params) {
  params.validate();
  return detail::area_correspondences(
      detail::area_wall_points(source, detail::free_edge_cells(source_grid, source), params.local.point_spacing_m), source,
      dest, source_raster, dest_raster, dest_edge, T_dest_source, params);
}

/// A label image the size of the source map (as `areamatch segment --labels`): each cell of a
/// source area that has a counterpart holds that destination area's id + 1; every other cell 0.
inline std::vector<int> correspondence_labels(const AreaGraph& source, const std::vector<MatchedAreaPair>& pairs) {
  std::vector<int> dest_of(source.areas.size(), -1);
  for (const auto& p : pairs) dest_of[static_cast<std::size_t>(p.source)] = p.dest;
  std::vector<int> out(source.labels.size(), 0);
  source.labels.for_each_run([&](std::size_t first, std::size_t last, int label) {
    if (label >= 0 && dest_of[static_cast<std::size_t>(label)] >= 0) {
      std::fill(out.begin() + static_cast<std::ptrdiff_t>(first), out.begin() + static_cast<std::ptrdiff_t>(last),
                dest_of[static_cast<std::size_t>(label)] + 1);
    }
  });
  return out;
}

}  // namespace areamatch
