#pragma once
/// \file match/params.hpp
/// `MatcherParams`: every tunable of the matching pipeline (`Matcher`, matcher.hpp), with the
/// paper's values as a preset (`MatcherParams::paper()`). Lengths in metres, angles in radians.
/// Why each default is what it is, with the measurements: docs/parameters.md and docs/matching.md.

#include "../error.hpp"
#include "correspondence.hpp"
#include "decision.hpp"
#include "hypotheses.hpp"
#include "refine.hpp"
#include "scale.hpp"

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
  /// given one, and estimate it (match/scale.hpp). Needs the grids (the source is segmented at
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

  // Whole-map verification (`WholeMapSelection`, match/selection.hpp).
  double coarse_cell_m = 0.25;          ///< raster cell for scoring all candidates (and raster OP)
  double fine_cell_m = 0.25;            ///< raster cell for the finalists' IoU (0.1 measured no better)
  std::size_t members_per_cluster = 1;  ///< best members of each cluster that get verified
  std::size_t sparse_samples = 300;     ///< source wall points of the first, cheap ranking pass
  std::size_t verify_candidates = 48;   ///< candidates ranked again on all source wall points
  /// Before ICP, candidates are ranked by the share of the source's walls within this distance of
  /// the destination's free-space edge. Loose, because an unrefined hypothesis is anchored at one
  /// pair's segment midpoints and can be off by a few decimetres. Walls, not free-space IoU: a
  /// partial map lies inside the other's free space under many wrong transforms (IoU saturates),
  /// so IoU let the right rotation fall out before ICP on hand-held scans (docs/matching.md).
  double candidate_wall_distance_m = 0.5;
  std::size_t refine_candidates = 8;    ///< candidates refined and scored on the fine raster
  bool refine = true;
  RefineParams refinement;
  bool refine_on_free_edges = true;     ///< ICP on the maps' free-space edges (else the areas' edges)
  /// The finalists' score: (1 − w) · free-space IoU + w · share of the source's free-space edge
  /// within `wall_inlier_distance_m` of the destination's. IoU alone lets a map that extends past
  /// the other slide along a corridor; edges pin room dividers.
  double wall_score_weight = 1.0;
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
  /// centroid) count as the same answer when the confidence margin is computed.
  double different_rotation_rad = 3.0 * pi / 180.0;
  double different_translation_m = 1.0;
  /// Below this whole-map score (see `MatchResult::score`) the best transform is rejected (ok = false).
  double min_score = 0.25;
  /// The calibrated probability that the answer is right (match/decision.hpp), reported as
  /// `MatchResult::p_correct`. An answer whose agreement is below `min_agreement` is still
  /// accepted when p_correct ≥ `decision.accept_p_correct`; below `decision.min_p_correct` it is
  /// rejected (off by default).
  DecisionParams decision;
  /// Below this `MatchEvidence::agreement` the result is rejected unless the model is sure
  /// (`decision.accept_p_correct`); the refusal says "different places" or "not sure"
  /// (`decision.different_places_p`).
  /// Calibrated on the real pairs of shared/pairs.json, all 596 pairs of maps of different
  /// buildings in shared/maps and three synthetic sets (docs/evaluation.md): every true pair
  /// scored 0.840 or more; 2 of 2876 pairs of different buildings scored above 0.835 (at most 0.845).
  /// Alone it rejects right answers of unseen buildings and hand-held scans (agreement 0.77-0.83):
  /// `decision.accept_p_correct` lets the calibrated model accept those. Above 1 the gate never
  /// accepts and the model alone decides (the CLI takes [0, 1]: 1 is that, but for a perfect agreement).
  double min_agreement = 0.835;
  /// The agreement gate (`min_agreement`) accepts an answer the model is not sure of only where
  /// the lower of the two wall agreements (`MatchEvidence::forward_wall_agreement` and
  /// `reverse_wall_agreement`, the decision's `walls_worst`) is at most this. The gate is for a
  /// map whose walls the other cannot explain — a SLAM map's furniture and laser streaks against
  /// a floor plan — where the model underrates right answers (lab_b's p_correct 0.09–0.14 cross-
  /// validated, lower walls 0.42–0.43); where the walls agree both ways the model judges alone
  /// (two alike buildings' partial maps agreed at 0.84 with lower walls 0.71–0.92). 0.7 is what
  /// `areamatch calibrate --choose-rule` chooses from data, in all 141 folds of its nested
  /// cross-validation (docs/evaluation.md). Above 1: the gate applies whatever the walls.
  double gate_max_lower_walls = 0.7;
  /// The agreement gate also needs at least this much shared free space (`MatchEvidence::
  /// overlap_m2`, destination m²): agreeing walls prove little on one room. A hand-held scan of a
  /// single office (F5_02, 43 m² shared) agreed at 0.874 with an apartment's scan, lower walls
  /// 0.31; every right answer the gate lets through on the real maps shares 231 m² or more.
  /// 100 m² (a few rooms) is what `areamatch calibrate --choose-rule` chooses from its grid
  /// (0, 25, 50, 100) on all rows and in every fold of the nested cross-validation
  /// (docs/evaluation.md). 0: the gate whatever the overlap.
  double gate_min_overlap_m2 = 100.0;
  /// The weight of the free-space IoU in `MatchEvidence::agreement` (the rest is the better of
  /// the two wall agreements). A map confirmed on little of the other's free space is less certain.
  double agreement_iou_weight = 0.2;
  /// Below this margin to a different or mirrored rival the result is rejected (ok = false).
  double min_confidence = 0.0;
  /// Below this margin the result is flagged `ambiguous` (still ok): on real maps correct answers
  /// have come with margins as small as 0.002 (a SLAM map longer than its layout slides along
  /// the corridor), so rejecting them is the caller's call.
  double ambiguity_margin = 0.02;
  /// Room correspondences and per-room transforms (`MatchResult::matched_areas`).
  CorrespondenceParams correspondences;
  /// Most areas accepted per map; beyond, `match` throws `limit_error`. The feature costs grow
  /// with areas_source × areas_dest: a pair of 1550-area maps takes 3.6 s to match on the CI
  /// machine, so the limit keeps a pair under about 15 s.
  std::size_t max_areas = 3000;

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
    p.min_score = 0.0;          // the paper has no rejection rule:
    p.min_agreement = 0.0;
    p.gate_max_lower_walls = 2.0;
    p.gate_min_overlap_m2 = 0.0;
    p.decision.min_p_correct = 0.0;
    p.decision.accept_p_correct = 1.0;
    p.min_confidence = -1.0;    // it always answers
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
    detail::require_positive(candidate_wall_distance_m, "MatcherParams::candidate_wall_distance_m");
    detail::require_positive(occupied_point_spacing_m, "MatcherParams::occupied_point_spacing_m");
    detail::require_positive(occupied_wall_distance_m, "MatcherParams::occupied_wall_distance_m");
    if (!(occupied_wall_context_m >= occupied_wall_distance_m && std::isfinite(occupied_wall_context_m))) {
      throw parameter_error("MatcherParams::occupied_wall_context_m must be finite and at least occupied_wall_distance_m");
    }
    if (members_per_cluster < 1 || sparse_samples < 1 || verify_candidates < 1 || refine_candidates < 1 ||
        turn_check_points < 1) {
      throw parameter_error("MatcherParams: members_per_cluster, sparse_samples, verify_candidates, "
                            "refine_candidates and turn_check_points must be >= 1");
    }
    refinement.validate();
    detail::require_positive(different_rotation_rad, "MatcherParams::different_rotation_rad");
    detail::require_positive(different_translation_m, "MatcherParams::different_translation_m");
    detail::require_non_negative(min_score, "MatcherParams::min_score");
    detail::require_non_negative(min_agreement, "MatcherParams::min_agreement");
    detail::require_non_negative(gate_max_lower_walls, "MatcherParams::gate_max_lower_walls");
    detail::require_non_negative(gate_min_overlap_m2, "MatcherParams::gate_min_overlap_m2");
    decision.validate();
    if (!(agreement_iou_weight >= 0.0 && agreement_iou_weight <= 1.0)) {
      throw parameter_error("MatcherParams::agreement_iou_weight must be in [0, 1]");
    }
    if (!std::isfinite(min_confidence)) throw parameter_error("MatcherParams::min_confidence must be finite");
    correspondences.validate();
    detail::require_non_negative(ambiguity_margin, "MatcherParams::ambiguity_margin");
  }
};

}  // namespace areamatch
