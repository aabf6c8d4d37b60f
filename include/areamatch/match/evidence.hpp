#pragma once
/// \file match/evidence.hpp
/// How much the two maps agree under one transform, measured several ways, so that "these maps
/// are not the same building" can be decided (`MatcherParams::min_agreement`).
///
/// The whole-map score (share of the source's free-space edge lying on the destination's) picks
/// the best transform well but does not say whether it is right: cluttered SLAM maps have edges
/// everywhere, and a corridor-with-rooms building lies well on another one (0.78 between two
/// different buildings of the dataset, 0.38 on a true SLAM-to-layout pair). The measures here
/// look both ways and at the building's structure, which chance agrees with much less.

#include "../area_graph.hpp"
#include "../transform.hpp"
#include "raster.hpp"
#include "refine.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace areamatch {

/// Agreement of the two maps under the result's transform; each in [0, 1], higher is better.
struct MatchEvidence {
  /// Share of the source's free-space edge within `wall_inlier_distance_m` of the destination's
  /// (the whole-map score with the default weights).
  double wall_agreement = 0.0;
  /// The same from the destination's side, counting only the destination's edge where the
  /// source has free space nearby (so a partial map is not penalised for what it did not see).
  double reverse_wall_agreement = 0.0;
  /// IoU of the two maps' area-covered free space.
  double free_iou = 0.0;
  /// Share of the source's area-covered free space landing on the destination's, and back.
  double source_on_dest = 0.0;
  double dest_on_source = 0.0;
  /// Share of the passages in the common part (both maps' free space) that have a counterpart in
  /// the other map within `passage_distance_m`; NaN when the common part holds no passage.
  double passage_agreement = 0.0;
  /// Share of the common free space that lies in area pairs overlapping with IoU ≥ 0.5: whether
  /// the two segmentations cut the common part into the same rooms.
  double room_agreement = 0.0;
  /// The number the decision uses (`MatcherParams::min_agreement`): (1 − w) ·
  /// reverse_wall_agreement + w · free_iou, w = `MatcherParams::agreement_iou_weight`. The
  /// destination's walls where the source has been must be the source's walls; and the more of
  /// the two maps' free space is shared, the surer that is.
  double agreement = 0.0;
};

namespace detail {

/// Whether a world point is in, or within one raster cell of, a labelled cell of `raster`.
inline bool near_labelled(const AreaRaster& raster, const Eigen::Vector2d& world) {
  const Eigen::Vector2d c = raster.cell_from_world * world;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      if (raster.label_at_cell(c + Eigen::Vector2d(dx, dy)) >= 0) return true;
    }
  }
  return false;
}

}  // namespace detail

/// The measures of `MatchEvidence` for T_dest_source. `source_edge` / `dest_edge` are the maps'
/// free-space edge points (world metres) and lookups over them; the rasters share one cell size.
inline MatchEvidence measure_evidence(const AreaGraph& source, const AreaGraph& dest, const AreaRaster& source_raster,
                                      const AreaRaster& dest_raster, const std::vector<Eigen::Vector2d>& source_edge,
                                      const BoundaryLookup& source_lookup, const std::vector<Eigen::Vector2d>& dest_edge,
                                      const BoundaryLookup& dest_lookup, const Similarity2& T_dest_source,
                                      double wall_inlier_distance_m, double passage_distance_m,
                                      double iou_weight) {
  MatchEvidence e;
  const Similarity2 T_source_dest = T_dest_source.inverse();
  e.wall_agreement = boundary_inlier_fraction(source_edge, dest_lookup, T_dest_source, wall_inlier_distance_m);

  // Destination edge where the source has free space: explained by the source's edge?
  std::vector<Eigen::Vector2d> shared_dest_edge;
  for (const auto& q : dest_edge) {
    if (detail::near_labelled(source_raster, T_source_dest * q)) shared_dest_edge.push_back(q);
  }
  e.reverse_wall_agreement =
      boundary_inlier_fraction(shared_dest_edge, source_lookup, T_source_dest, wall_inlier_distance_m);

  // Cell overlaps per area pair, from the source cells.
  const std::size_t ns = source.areas.size(), nd = dest.areas.size();
  std::vector<std::size_t> overlap(ns * nd, 0);
  std::size_t hits = 0;
  const Eigen::Affine2d to_cell = dest_raster.cell_from_world * T_dest_source.affine();
  for (std::size_t k = 0; k < source_raster.centres.size(); ++k) {
    const int j = dest_raster.label_at_cell(to_cell * source_raster.centres[k]);
    if (j < 0) continue;
    ++hits;
    ++overlap[static_cast<std::size_t>(source_raster.centre_labels[k]) * nd + static_cast<std::size_t>(j)];
  }
  const double scale2 = T_dest_source.scale * T_dest_source.scale;  // source cells → destination cells
  const double source_cells = static_cast<double>(source_raster.centres.size()) * scale2;
  const double dest_cells = static_cast<double>(dest_raster.centres.size());
  const double common = static_cast<double>(hits) * scale2;
  e.free_iou = source_cells + dest_cells - common > 0.0 ? common / (source_cells + dest_cells - common) : 0.0;
  e.source_on_dest = source_cells > 0.0 ? common / source_cells : 0.0;
  e.dest_on_source = dest_cells > 0.0 ? std::min(1.0, common / dest_cells) : 0.0;
  e.agreement = (1.0 - iou_weight) * e.reverse_wall_agreement + iou_weight * e.free_iou;

  double consistent = 0.0;
  for (std::size_t i = 0; i < ns; ++i) {
    const double a = static_cast<double>(source_raster.area_cells[i].size()) * scale2;
    for (std::size_t j = 0; j < nd; ++j) {
      const double o = static_cast<double>(overlap[i * nd + j]) * scale2;
      if (o <= 0.0) continue;
      const double b = static_cast<double>(dest_raster.area_cells[j].size());
      if (o >= 0.5 * (a + b - o)) consistent += o;
    }
  }
  e.room_agreement = common > 0.0 ? consistent / common : 0.0;

  // Passages of the common part with a counterpart in the other map.
  std::size_t considered = 0, matched = 0;
  const double d2 = passage_distance_m * passage_distance_m;
  auto count = [&](const AreaGraph& from, const AreaGraph& to, const AreaRaster& to_raster, const Similarity2& T) {
    for (const Passage& p : from.passages) {
      const Eigen::Vector2d q = T * p.position;
      if (!detail::near_labelled(to_raster, q)) continue;
      ++considered;
      for (const Passage& r : to.passages) {
        if ((r.position - q).squaredNorm() <= d2) {
          ++matched;
          break;
        }
      }
    }
  };
  count(source, dest, dest_raster, T_dest_source);
  count(dest, source, source_raster, T_source_dest);
  e.passage_agreement = considered > 0 ? static_cast<double>(matched) / static_cast<double>(considered)
                                       : std::numeric_limits<double>::quiet_NaN();
  return e;
}

}  // namespace areamatch
