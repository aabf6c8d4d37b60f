#pragma once
/// \file match/answer.hpp
/// The stages around the selection that the matcher composes (matcher.hpp): the hypotheses of
/// every mutual area pair, and what describes the selected answer — its transform and score,
/// margins over the rivals, room correspondences, evidence, turn margin and p_correct.

#include "../area_graph.hpp"
#include "../detail/parallel.hpp"
#include "../transform.hpp"
#include "decision/decision.hpp"
#include "map_data.hpp"
#include "params.hpp"
#include "proposal/costs.hpp"
#include "proposal/hypotheses.hpp"
#include "result.hpp"
#include "verification/correspondence.hpp"
#include "verification/evidence.hpp"
#include "verification/margins.hpp"
#include "verification/selection.hpp"

#include <cstddef>
#include <vector>

namespace areamatch {
namespace detail {

/// What the hypotheses read of the two maps.
template <class Descriptors>
HypothesisInputs hypothesis_inputs(const AreaGraph& source, const AreaGraph& dest, const MapData<Descriptors>& source_data,
                                   const MapData<Descriptors>& dest_data) {
  return HypothesisInputs{&source, &dest, &source_data.coarse, &dest_data.coarse, source_data.wall_direction,
                          dest_data.wall_direction};
}

/// The hypotheses of every mutual pair on each side of the mirror, from the segments `features`
/// matches per pair. One job per (side, pair), each into its own list, joined in job order: the
/// same list for any thread count.
template <class Features, class Descriptors>
std::vector<Hypothesis> pair_hypotheses(const Features& features, const MatcherParams& params, const HypothesisInputs& maps,
                                        const std::vector<AreaPair>& pairs, const MapData<Descriptors>& source_data,
                                        const MapData<Descriptors>& dest_data, unsigned threads, MatchStatistics& statistics) {
  const std::vector<bool> sides = mirror_sides(params);
  std::vector<std::vector<Hypothesis>> per_job(sides.size() * pairs.size());
  std::vector<std::size_t> overlay_failures(per_job.size(), 0);
  for_each_index(per_job.size(), threads, [&](std::size_t job) {
    const AreaPair& pair = pairs[job % pairs.size()];
    const auto segments = features.segments(source_data.descriptors, dest_data.descriptors,
                                            static_cast<std::size_t>(pair.source), static_cast<std::size_t>(pair.dest));
    add_pair_hypotheses(maps, pair, segments, sides[job / pairs.size()], params.hypotheses, per_job[job],
                        &overlay_failures[job]);
  });
  std::vector<Hypothesis> hypotheses;
  for (auto& list : per_job) hypotheses.insert(hypotheses.end(), list.begin(), list.end());
  for (std::size_t failures : overlay_failures) statistics.overlay_failures += failures;
  statistics.hypotheses = hypotheses.size();
  return hypotheses;
}

/// The selection's answer in `result`: its transform and score, its margins over the rivals,
/// the room correspondences, the evidence, the turn margin and p_correct.
template <class Descriptors>
void describe_answer(const MatcherParams& params, const AreaGraph& source, const AreaGraph& dest,
                     const MapData<Descriptors>& source_data, const MapData<Descriptors>& dest_data, const MapEdges& edges,
                     const Selected& selected, MatchResult& result) {
  const ScoredTransform& best = selected.finalists.front();
  const AreaRaster& source_fine = source_data.fine();
  const AreaRaster& dest_fine = dest_data.fine();
  result.T_dest_source = best.T;
  result.pixel_transform = to_pixel_transform(best.T, source.grid, dest.grid);
  result.score = best.score;
  measure_margins(source_fine, dest_fine, selected, params, result);
  result.matched_areas = area_correspondences(area_wall_points(source, source_data.free_edge, params.correspondences.local.point_spacing_m),
                                              source, dest, source_fine, dest_fine, edges.dest_lookup, best.T,
                                              params.correspondences, params.threads);
  result.evidence = measure_evidence(source, dest, source_fine, dest_fine, edges, best.T, params.wall_inlier_distance_m,
                                     params.passage_distance_m, params.agreement_iou_weight);
  if (selected.refined) measure_turn_margin(source_fine, dest_fine, edges, dest_data.wall_direction, params, result);
  result.ambiguous = result.margin < params.ambiguity_margin;
  result.p_correct = p_correct(decision_features(result), params.decision);
}

}  // namespace detail
}  // namespace areamatch
