#pragma once
/// \file match/verification/margins.hpp
/// How far the answer stands out from its rivals: the selection's other finalists
/// (`MatchResult::margin_different`, `margin_mirrored`, `margin`) and its own quarter turns
/// and mirror images (`MatchEvidence::turn_margin`).

#include "../../detail/thinning.hpp"
#include "../../transform.hpp"
#include "../params.hpp"
#include "../raster.hpp"
#include "../result.hpp"
#include "evidence.hpp"
#include "refine.hpp"
#include "selection.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace areamatch::detail {

/// Margins of the answer (the first finalist) over the best clearly different finalist and the
/// best mirrored one, by the finalists' own scores when the selection's are comparable, else by
/// free-space IoU; `margin` is the smallest of the answer's score and the two margins.
inline void measure_margins(const AreaRaster& source_fine, const AreaRaster& dest_fine, const Selected& selected,
                            const MatcherParams& params, MatchResult& result) {
  const std::vector<ScoredTransform>& finalists = selected.finalists;
  const Similarity2& best = finalists.front().T;
  auto score_of = [&](const ScoredTransform& f) {
    return selected.comparable_scores ? f.score : free_space_iou(source_fine, dest_fine, f.T);
  };
  const double best_score = score_of(finalists.front());
  double rival_different = -1.0, rival_mirrored = -1.0;
  const Eigen::Vector2d centroid = centroid_of(source_fine);
  for (std::size_t i = 1; i < finalists.size(); ++i) {
    const Similarity2& T = finalists[i].T;
    const double score = score_of(finalists[i]);
    if (T.reflected != best.reflected) rival_mirrored = std::max(rival_mirrored, score);
    else if (different(best, T, centroid, params)) rival_different = std::max(rival_different, score);
  }
  if (rival_different >= 0.0) result.margin_different = best_score - rival_different;
  if (params.allow_reflection && rival_mirrored >= 0.0) result.margin_mirrored = best_score - rival_mirrored;
  double margin = best_score;
  if (!std::isnan(result.margin_different)) margin = std::min(margin, result.margin_different);
  if (!std::isnan(result.margin_mirrored)) margin = std::min(margin, result.margin_mirrored);
  result.margin = margin;
}

/// `MatchEvidence::turn_margin`: the answer against its own quarter turns about the centre of
/// the common part (and its mirror images about an axis along the destination's walls through
/// that centre, when reflection is allowed), each refined by the finalists' ICP on the
/// free-space edges (on fewer points) and scored by the overlap-restricted wall agreements.
inline void measure_turn_margin(const AreaRaster& source_fine, const AreaRaster& dest_fine, const MapEdges& edges,
                                double wall_direction, const MatcherParams& params, MatchResult& result) {
  const Similarity2& T = result.T_dest_source;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  std::size_t common = 0;
  const Eigen::Affine2d to_cell = dest_fine.cell_from_world * T.affine();
  for (std::size_t k = 0; k < source_fine.labelled_count(); ++k) {
    const Eigen::Vector2d c = source_fine.centre(k);
    if (dest_fine.label_at_cell(to_cell * c) < 0) continue;
    centre += T * c;
    ++common;
  }
  if (common == 0) return;
  centre /= static_cast<double>(common);
  auto about_centre = [&](const Eigen::Matrix2d& m) {
    Eigen::Affine2d a = Eigen::Affine2d::Identity();
    a.linear() = m;
    a.translation() = centre - m * centre;
    return Similarity2::from_affine(a);
  };
  auto turn = [](double angle) { return Eigen::Rotation2Dd(angle).toRotationMatrix(); };
  std::vector<Similarity2> alternatives;
  for (int k = 1; k < 4; ++k) alternatives.push_back(about_centre(turn(k * 0.5 * pi)) * T);
  if (params.allow_reflection) {
    Eigen::Matrix2d flip;
    flip << 1.0, 0.0, 0.0, -1.0;
    const Eigen::Matrix2d mirror = turn(wall_direction) * flip * turn(-wall_direction);
    for (int k = 0; k < 4; ++k) alternatives.push_back(about_centre(turn(k * 0.5 * pi) * mirror) * T);
  }
  const RefineParams refinement = finalist_refinement(params);
  // A rival needs only to be placed well enough to be scored: its ICP runs on fewer points.
  const std::vector<Eigen::Vector2d> points = evenly_thinned(edges.source_points, params.turn_check_points);
  const std::vector<Eigen::Vector2d> sides = evenly_thinned(edges.source_sides, params.turn_check_points);
  std::vector<double> walls(alternatives.size());
  for_each_index(alternatives.size(), params.threads, [&](std::size_t i) {
    const Similarity2 refined = refine_icp(points, edges.dest_lookup, alternatives[i], refinement, &sides);
    const auto [forward, reverse] = overlap_wall_agreements(source_fine, dest_fine, edges, refined, params.wall_inlier_distance_m);
    walls[i] = std::max(forward, reverse);
  });
  const double answer = std::max(result.evidence.forward_wall_agreement, result.evidence.reverse_wall_agreement);
  result.evidence.turn_margin = answer - *std::max_element(walls.begin(), walls.end());
}

}  // namespace areamatch::detail
