#pragma once
/// \file match/params.hpp
/// `MatcherParams`: every tunable of the matching pipeline (`Matcher`, matcher.hpp), with the
/// paper's values as a preset (`MatcherParams::paper()`). Lengths in metres, angles in radians.
/// Why each default is what it is, with the measurements: docs/parameters.md and docs/matching.md.

#include "../error.hpp"
#include "decision/decision.hpp"
#include "proposal/hypotheses.hpp"
#include "scale/scale.hpp"
#include "verification/correspondence.hpp"
#include "verification/refine.hpp"

#include <cmath>
#include <cstddef>

namespace areamatch {

struct MatcherParams {
  /// Mutual k-nearest neighbours. The paper's 3 kept ~15 % of the true pairs on SLAM-to-layout
  /// maps (docs/algorithm.md); 10 keeps ~42 %, and the verification stage rejects the rest.
  std::size_t k = 10;
  HypothesisParams hypotheses;
  /// Also try the mirror image of the source (image rows run down, map y up: mirrored pairs are
  /// common). Both sides are judged by the same score.
  bool allow_reflection = false;
  /// Treat the source's resolution as unknown, within [scale.min_scale, scale.max_scale] × the
  /// given one, and estimate it (match/scale/scale.hpp). Needs the grids (the source is segmented at
  /// each candidate scale) and `refine` (the ICP fits the scale); about 10× the time of a match.
  bool estimate_scale = false;
  ScaleParams scale;
  /// Threads of one match: the two maps segmented and their rasters, edges and lookups built side
  /// by side, then the hypotheses of the area pairs, the candidates' scores, the finalists' ICP
  /// and the rooms' correspondences spread over them. A grid matched onto a prepared map (and
  /// `prepare(grid)`) builds what needs only its cells beside its segmentation, and its edge
  /// lookup beside the pairs, hypotheses and clusters. The result is the same, bit for bit, for
  /// any count (0: one per hardware thread); with more than one, the policies' const member
  /// functions are called from several threads at once (the built-in ones are pure).
  unsigned threads = 1;

  // Shared by the stages after the clusters (the selection's own settings are its policy's:
  // `WholeMapSelection::Params`, match/verification/selection.hpp).
  double coarse_cell_m = 0.25;          ///< raster cell for scoring all candidates (and raster OP)
  double fine_cell_m = 0.25;            ///< raster cell for the finalists' IoU (0.1 measured no better)
  bool refine = true;
  RefineParams refinement;
  /// A free-space edge point within this distance of the other map's edge is on it: in the
  /// finalists' score and the evidence's wall agreements.
  double wall_inlier_distance_m = 0.3;
  /// Walls against walls (`MatchEvidence::occupied_wall_agreement`): each map's occupied cells
  /// are thinned to one per `occupied_point_spacing_m` square; those landing within
  /// `occupied_wall_context_m` of the other map's occupied cells count, and agree when within
  /// `occupied_wall_distance_m`. 0.25 m: a wall drawn one or two cells thick in either map, like
  /// `wall_inlier_distance_m`; 1.5 m: a room's width apart is another wall, not this one misplaced.
  double occupied_point_spacing_m = 0.15;
  double occupied_wall_distance_m = 0.25;
  double occupied_wall_context_m = 1.5;
  /// Passages of the two maps this close under the result count as the same (evidence only).
  double passage_distance_m = 1.0;
  /// The answer's quarter turns and mirror images are refined on at most about this many of the
  /// source's edge points (`MatchEvidence::turn_margin`; the answer itself used them all).
  std::size_t turn_check_points = 500;

  // Decision.
  /// Transforms closer than these (rotation, and displacement of the source's free-space
  /// centroid) count as the same answer when the margin (`MatchResult::margin`) is computed.
  double different_rotation_rad = 3.0 * pi / 180.0;
  double different_translation_m = 1.0;
  /// The accept/reject rule — its thresholds (`min_score`, `min_agreement`, the agreement gate's,
  /// `accept_p_correct`, `min_p_correct`, `min_margin`) and the calibrated model of
  /// `MatchResult::p_correct` — in one place (match/decision/decision.hpp; applied by match/decision/acceptance.hpp).
  DecisionParams decision;
  /// The weight of the free-space IoU in `MatchEvidence::agreement` (the rest is the better of
  /// the two wall agreements). A map confirmed on little of the other's free space is less certain.
  double agreement_iou_weight = 0.2;
  /// Below this margin the result is flagged `ambiguous` (still ok): on real maps correct answers
  /// have come with margins as small as 0.002 (a SLAM map longer than its layout slides along
  /// the corridor), so rejecting them is the caller's call.
  double ambiguity_margin = 0.02;
  /// Room correspondences and per-room transforms (`MatchResult::matched_areas`).
  CorrespondenceParams correspondences;
  /// Most areas accepted per map; beyond, `match` throws `limit_error`. A guard against a map
  /// shattered into pieces (noise read as walls), no longer against cost: the area pairs are
  /// found along the features' bound keys (match/proposal/costs.hpp) and the evidence lists only the pairs
  /// that meet, so matching grows with the areas, not with areas_source × areas_dest. A
  /// 400 × 300 m generated floor has about 5000 areas; `max_grid_cells` bounds a map long before
  /// this does (docs/performance.md).
  std::size_t max_areas = 20000;

  /// The paper as written (docs/algorithm.md): k = 3, one rotation per pair from the passage pair
  /// (or hull diameters), exact OP ≥ 0.5; no refinement, no rejection. With `PaperMatcher`'s
  /// AngularClusterer and LargestClusterSelection: the largest 3° cluster, its best member by Σ OP.
  static MatcherParams paper() {
    MatcherParams p;
    p.k = 3;
    p.hypotheses.extra_turns = {0.0};
    p.hypotheses.all_segment_sources = false;
    p.hypotheses.wall_directions = false;
    p.hypotheses.min_area_overlap = 0.5;
    p.hypotheses.exact_overlap = true;
    p.refine = false;
    p.decision.min_score = 0.0;          // the paper has no rejection rule:
    p.decision.min_agreement = 0.0;
    p.decision.gate_max_lower_walls = 2.0;
    p.decision.gate_min_overlap_m2 = 0.0;
    p.decision.min_p_correct = 0.0;
    p.decision.accept_p_correct = 1.0;
    p.decision.min_margin = -1.0;    // it always answers
    return p;
  }

  void validate() const {
    if (k < 1) throw parameter_error("MatcherParams::k must be >= 1");
    if (estimate_scale) {
      scale.validate();
      if (!refine) throw parameter_error("MatcherParams::estimate_scale needs refine (the scale is fitted by the ICP)");
    }
    hypotheses.validate();
    detail::require_positive(coarse_cell_m, "MatcherParams::coarse_cell_m");
    detail::require_positive(fine_cell_m, "MatcherParams::fine_cell_m");
    detail::require_positive(occupied_point_spacing_m, "MatcherParams::occupied_point_spacing_m");
    detail::require_positive(occupied_wall_distance_m, "MatcherParams::occupied_wall_distance_m");
    if (!(occupied_wall_context_m >= occupied_wall_distance_m && std::isfinite(occupied_wall_context_m))) {
      throw parameter_error("MatcherParams::occupied_wall_context_m must be finite and at least occupied_wall_distance_m");
    }
    if (turn_check_points < 1) throw parameter_error("MatcherParams::turn_check_points must be >= 1");
    refinement.validate();
    detail::require_positive(different_rotation_rad, "MatcherParams::different_rotation_rad");
    detail::require_positive(different_translation_m, "MatcherParams::different_translation_m");
    decision.validate();
    if (!(agreement_iou_weight >= 0.0 && agreement_iou_weight <= 1.0)) {
      throw parameter_error("MatcherParams::agreement_iou_weight must be in [0, 1]");
    }
    correspondences.validate();
    detail::require_non_negative(ambiguity_margin, "MatcherParams::ambiguity_margin");
  }
};

}  // namespace areamatch
