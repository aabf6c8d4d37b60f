#pragma once
/// \file match/result.hpp
/// What a match returns. "No acceptable match" is a result (`ok == false` with a reason and the
/// scores), not an exception; exceptions are for bad input.

#include "../area_graph.hpp"
#include "../transform.hpp"

#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace areamatch {

/// Agreement of the two maps under the result's transform, higher is better: the shares and
/// agreements in [0, 1] (NaN where a field says so), `overlap_m2` in square metres, and
/// `turn_margin` a difference of two agreements, in [−1, 1].
struct MatchEvidence {
  /// Share of the source's free-space edge within `wall_inlier_distance_m` of the destination's
  /// (the whole-map score with the default weights).
  double wall_agreement = 0.0;
  /// Share of the destination's walls near the source's free space that lie on the source's
  /// free-space edge: only where the source has been (a partial map is not penalised for what it
  /// did not see), and walls only (free space ending at unknown cells is a frontier, not a wall).
  double reverse_wall_agreement = 0.0;
  /// The same for the source's walls near the destination's free space.
  double forward_wall_agreement = 0.0;
  /// IoU of the two maps' area-covered free space.
  double free_iou = 0.0;
  /// The area-covered free space the two maps share under the result, destination m².
  double overlap_m2 = 0.0;
  /// Share of the source's area-covered free space landing on the destination's, and back.
  double source_on_dest = 0.0;
  double dest_on_source = 0.0;
  /// Share of the passages in the common part (both maps' free space) that have a counterpart in
  /// the other map within `passage_distance_m`; NaN when the common part holds no passage.
  double passage_agreement = 0.0;
  /// Share of the common free space that lies in area pairs overlapping with IoU ≥ 0.5: whether
  /// the two segmentations cut the common part into the same rooms.
  double room_agreement = 0.0;
  /// The number the decision uses (`DecisionParams::min_agreement`): (1 − w) · max(forward,
  /// reverse wall agreement) + w · free_iou, w = `MatcherParams::agreement_iou_weight`. Where
  /// both maps have been, one map's walls must all be walls of the other (the plainer map's: a
  /// layout's walls are in a SLAM map, not the SLAM map's furniture in the layout); and the more
  /// free space is shared, the surer that is.
  double agreement = 0.0;
  /// How far the answer stands out from its own quarter turns about the common part's centre
  /// (and, with reflection allowed, its mirror images), each refined by ICP as the answer was:
  /// the answer's better overlap-restricted wall agreement minus the best alternative's. In a
  /// building of repeated rooms a wrong answer is often the right one turned; two different
  /// buildings agree about as badly in every turn. NaN when not measured.
  double turn_margin = std::numeric_limits<double>::quiet_NaN();
  /// Walls against walls: of each map's occupied cells (their surfaces, one per
  /// `MatcherParams::occupied_point_spacing_m` square) that land within
  /// `occupied_wall_context_m` of the other map's, the share within `occupied_wall_distance_m`;
  /// the higher of the two directions (a SLAM map's furniture has nothing to land on in a floor
  /// plan; the plan's walls all land on the SLAM map's). Unlike the measures above it sees walls away from both
  /// maps' free space — the walls of rooms a robot saw but never entered — where two alike
  /// buildings that agree in their shared part still differ. NaN when neither map's walls come
  /// near the other's.
  double occupied_wall_agreement = std::numeric_limits<double>::quiet_NaN();
};

/// A source area, the destination area it corresponds to, and the area's own transform
/// (see match/verification/correspondence.hpp).
struct MatchedAreaPair {
  int source = -1;
  int dest = -1;
  double overlap = 0.0;  ///< area(T(source) ∩ dest) / min(size_source, size_dest), under T_dest_source
  double iou = 0.0;      ///< area(T(source) ∩ dest) / area(T(source) ∪ dest)
  /// The area's local transform: the result's, refined on this area's walls alone (equal to the
  /// result's when that did not lay them better or the area has too few wall points).
  Similarity2 T_dest_source;
  /// Share of the area's wall points on the destination's walls under its local transform; NaN
  /// when the area has too few wall points to judge.
  double wall_agreement = std::numeric_limits<double>::quiet_NaN();
};

/// Wall-clock seconds per stage. The segment fields are zero when graphs were passed in.
struct MatchTimings {
  double segment_source_s = 0.0;
  double segment_dest_s = 0.0;
  /// What matching builds from each map alone (descriptors, rasters, wall direction, free-space
  /// edges and lookups); 0 for maps prepared beforehand (`Matcher::prepare`). On two threads
  /// part of it overlaps a segmentation (`Matcher::match_side_by_side`): then a sum of pieces
  double prepare_s = 0.0;
  double features_s = 0.0;     ///< cost matrix, mutual pairs
  double hypotheses_s = 0.0;   ///< hypotheses with their overlap
  double clustering_s = 0.0;
  double selection_s = 0.0;    ///< verification (or the paper's Σ OP) and refinement
  double match_s = 0.0;        ///< everything after segmentation (after both maps', when side by side)
  double total_s = 0.0;
};

/// Counts that explain a result.
struct MatchStatistics {
  std::size_t source_areas = 0;
  std::size_t dest_areas = 0;
  std::size_t mutual_pairs = 0;
  std::size_t hypotheses = 0;
  std::size_t clusters = 0;
  std::size_t verified = 0;    ///< candidates scored on the whole map
  std::size_t refined = 0;
  std::size_t scales_tried = 0;  ///< source scales matched (`estimate_scale`), else 0
  /// Exact area overlaps (`HypothesisParams::exact_overlap`, the paper's) that Boost.Geometry could
  /// not compute (a degenerate overlay); the raster overlap stood in for each.
  std::size_t overlay_failures = 0;
};

/// What a refusal says of the two maps (`MatchResult::rejection`): that they look like different
/// places, or that the best answer may be right but the evidence does not carry it. The two call
/// for different things: another map, or `--allow-reflection`, a door width, a known-same-building
/// override (`areamatch assess --same-building`).
enum class Rejection {
  none,              ///< accepted
  no_answer,         ///< nothing to judge: a map without areas, no hypothesis, no cluster survived
  different_places,  ///< the evidence is against: a low whole-map score, or the model all but sure the answer is wrong
  not_sure,          ///< too weak to accept: little agreement with a model not sure either way, or a close rival
};

/// "none", "no answer", "different places", "not sure": as `--json` writes it.
inline const char* to_string(Rejection r) {
  switch (r) {
    case Rejection::none: return "none";
    case Rejection::no_answer: return "no answer";
    case Rejection::different_places: return "different places";
    case Rejection::not_sure: return "not sure";
  }
  return "none";
}

struct MatchResult {
  bool ok = false;
  std::string reason;              ///< why not ok (empty when ok), saying what the `rejection` is
  Rejection rejection = Rejection::none;  ///< what the refusal says of the maps (`none` when ok)
  Similarity2 T_dest_source;       ///< source world → destination world (metres)
  PixelTransform pixel_transform = PixelTransform::Zero();  ///< source pixel → destination pixel
  /// Whole-map score of the result: (1 − w) · IoU of the two maps' area-covered free space + w ·
  /// share of the source's free-space edge on the destination's, w = `WholeMapSelection::Params::wall_score_weight` (1 by
  /// default: the edge share); the paper preset reports its Σ OP over the mutual pairs.
  double score = 0.0;
  /// Whether the source's scale was estimated (`MatcherParams::estimate_scale`); the estimate is
  /// `T_dest_source.scale` (the source's true resolution / its given one).
  bool scale_estimated = false;
  /// min(margin_different, margin_mirrored): how much better the result scores than the
  /// best clearly different transform and than the best transform on the other side of the
  /// mirror. Small means ambiguous (a near-symmetric building).
  double margin = 0.0;
  double margin_different = std::numeric_limits<double>::quiet_NaN();  ///< NaN when there is no rival
  double margin_mirrored = std::numeric_limits<double>::quiet_NaN();   ///< NaN without allow_reflection
  bool ambiguous = false;          ///< margin below `MatcherParams::ambiguity_margin`
  /// The calibrated probability that the transform is right (match/decision/decision.hpp); `ok` needs at
  /// least `DecisionParams::min_p_correct`.
  double p_correct = 0.0;
  /// How much the maps agree under the result, measured several ways (see match/verification/evidence.hpp).
  MatchEvidence evidence;
  std::vector<MatchedAreaPair> matched_areas;
  MatchStatistics statistics;
  MatchTimings timings;
};

/// The pixel transform (source image pixel → destination image pixel) of a world transform.
inline PixelTransform to_pixel_transform(const Similarity2& T_dest_source, const GridInfo& source,
                                         const GridInfo& dest) {
  const Eigen::Affine2d a = dest.world_from_pixel().inverse() * T_dest_source.affine() * source.world_from_pixel();
  return a.matrix().topRows<2>();
}

}  // namespace areamatch
