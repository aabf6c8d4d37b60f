#pragma once
/// \file parameter_table.hpp
/// The table of settings that parameters.hpp reads: each field of `VoronoiSegmenter::Params`,
/// `MatcherParams`, the shipped clusterers' and `WholeMapSelection::Params` with its dotted name
/// and one line on what it does, in struct order. A field added to those structs is added here
/// too; `test_parameters` checks that docs/parameters.md lists exactly these names, and that each
/// name reaches its own field and no other.

#include "match/params.hpp"
#include "match/proposal/clusterer.hpp"
#include "match/verification/selection.hpp"
#include "segment/voronoi_segmenter.hpp"

#include <string>
#include <type_traits>
#include <utility>

namespace areamatch {

using VoronoiSegmenterParams = VoronoiSegmenter::Params;

/// What the table says of one setting.
struct ParameterInfo {
  std::string name;     ///< dotted field path: `k`, `decision.min_agreement`, `rooms.door_width_m`
  std::string meaning;  ///< one line; the docs say why its default
  /// The setting shapes what `Matcher::prepare` builds from a map (cells, edges, lookups, wall
  /// directions): a map prepared under one value is refused by a matcher with another.
  bool shapes_map_data = false;
};

/// Calls `f(info, field)` for every setting of the segmenter; `P` is `VoronoiSegmenterParams`,
/// const or not.
template <class P, class F>
void for_each_segmenter_parameter(P& p, F&& f) {
  f(ParameterInfo{"binarize.unknown_is_free", "unknown cells count as free space (else as obstacles)"}, p.binarize.unknown_is_free);
  f(ParameterInfo{"binarize.max_speckle_area_m2", "obstacle blobs up to this area are erased"}, p.binarize.max_speckle_area_m2);
  f(ParameterInfo{"binarize.max_speckle_size_m", "obstacle blobs fitting in a square this wide are erased (0: off)"},
    p.binarize.max_speckle_size_m);
  f(ParameterInfo{"binarize.min_free_area_m2", "free blobs smaller than this are dropped"}, p.binarize.min_free_area_m2);
  f(ParameterInfo{"boundary.simplify_tolerance_m", "Douglas-Peucker tolerance of the wall outline"}, p.boundary.simplify_tolerance_m);
  f(ParameterInfo{"boundary.min_traced_width_m", "free space no wider than this is left out of the Voronoi input (0: off)"},
    p.boundary.min_traced_width_m);
  f(ParameterInfo{"boundary.max_segments", "most boundary segments of a map (limit_error beyond)"}, p.boundary.max_segments);
  f(ParameterInfo{"skeleton.min_clearance_m", "skeleton closer than this to a wall is dropped"}, p.skeleton.min_clearance_m);
  f(ParameterInfo{"skeleton.sample_step_m", "spacing of clearance samples along skeleton edges"}, p.skeleton.sample_step_m);
  f(ParameterInfo{"skeleton.spur_length_m", "dead ends shorter than this are pruned"}, p.skeleton.spur_length_m);
  f(ParameterInfo{"skeleton.fast_circle_events", "the faster Voronoi circle events (else Boost's stock builder)"},
    p.skeleton.fast_circle_events);
  f(ParameterInfo{"rooms.door_width_m", "the widest opening that still separates two areas"}, p.rooms.door_width_m);
  f(ParameterInfo{"rooms.room_margin_m", "a wide part is a room only if its clearance exceeds the door threshold by this"},
    p.rooms.room_margin_m);
  f(ParameterInfo{"rooms.narrow_corridor_length_m", "narrow parts longer than this (or branching) become areas"},
    p.rooms.narrow_corridor_length_m);
  f(ParameterInfo{"rooms.door_search_m", "how far into a narrow part the passage to a room is looked for"}, p.rooms.door_search_m);
  f(ParameterInfo{"rooms.split_at_junctions", "split corridors where three or more meet (the paper)"}, p.rooms.split_at_junctions);
  f(ParameterInfo{"rooms.junction_arm_length_m", "least arm length for a junction split"}, p.rooms.junction_arm_length_m);
  f(ParameterInfo{"rooms.junction_arm_clearances", "an arm is also at least this many junction clearances long"},
    p.rooms.junction_arm_clearances);
  f(ParameterInfo{"rooms.junction_arm_elongation", "and this many times its own width"}, p.rooms.junction_arm_elongation);
  f(ParameterInfo{"areas.min_area_m2", "smaller areas merge into a neighbour"}, p.areas.min_area_m2);
  f(ParameterInfo{"areas.fringe_m", "how far labelling reaches beyond the skeleton's space"}, p.areas.fringe_m);
  f(ParameterInfo{"areas.corridor_elongation", "hull diameter / widest disc above which an area is a corridor"},
    p.areas.corridor_elongation);
}

/// `for_each_matcher_parameter`'s rows of one `RefineParams` under `prefix`.
template <class R, class F>
void for_each_refine_parameter(const std::string& prefix, R& r, bool shapes_map_data, F&& f) {
  auto info = [&](const char* name, const char* meaning, bool shapes = false) {
    return ParameterInfo{prefix + name, meaning, shapes && shapes_map_data};
  };
  f(info("gates_m", "correspondence gates, one ICP stage each", true), r.gates_m);
  f(info("iterations_per_gate", "ICP iterations per gate"), r.iterations_per_gate);
  f(info("keep_fraction", "share of the gated correspondences kept, closest first"), r.keep_fraction);
  f(info("point_spacing_m", "source edge points thinned to about this spacing", true), r.point_spacing_m);
  f(info("max_points", "and to at most this many", true), r.max_points);
  f(info("lookup_cell_m", "cell of the nearest-edge lookup", true), r.lookup_cell_m);
  f(info("estimate_scale", "ICP fits the scale too"), r.estimate_scale);
  f(info("max_scale_step", "most scale change per iteration (factor)"), r.max_scale_step);
  f(info("point_to_line", "distances along the destination's wall normals", true), r.point_to_line);
  f(info("normal_radius_m", "edge points each normal is fitted to", true), r.normal_radius_m);
  f(info("same_side_only", "pair only edge points facing the same way", true), r.same_side_only);
  f(info("free_side_radius_m", "an edge point's free side: free cells within this radius", true), r.free_side_radius_m);
  f(info("converged_rad", "a gate stops once a step turns less than this"), r.converged_rad);
  f(info("converged_m", "and moves less than this"), r.converged_m);
  f(info("converged_scale", "and scales less than this"), r.converged_scale);
}

/// Calls `f(info, field)` for every setting of the matcher; `P` is `MatcherParams`, const or not.
/// Left out: `threads`, which says how to run, not what to compute (the result is the same for
/// any count). The decision model's `bias` and `weights` are in (`areamatch calibrate` fits them).
template <class P, class F>
void for_each_matcher_parameter(P& p, F&& f) {
  auto info = [](const char* name, const char* meaning, bool shapes = false) { return ParameterInfo{name, meaning, shapes}; };
  f(info("k", "mutual nearest neighbours per area"), p.k);
  f(info("hypotheses.extra_turns", "turns added to each segment rotation (rad)"), p.hypotheses.extra_turns);
  f(info("hypotheses.all_segment_sources", "every feature with segments gives rotations"), p.hypotheses.all_segment_sources);
  f(info("hypotheses.wall_directions", "also the rotations aligning the maps' dominant wall directions", true),
    p.hypotheses.wall_directions);
  f(info("hypotheses.wall_direction.bins", "wall-direction histogram bins across 90 degrees", true), p.hypotheses.wall_direction.bins);
  f(info("hypotheses.wall_direction.peak_window_bins", "a bin's length summed over this many bins each side", true),
    p.hypotheses.wall_direction.peak_window_bins);
  f(info("hypotheses.wall_direction.mean_window_bins", "the mean over edges within this many bins of the peak", true),
    p.hypotheses.wall_direction.mean_window_bins);
  f(info("hypotheses.min_area_overlap", "keep a hypothesis only if its own pair overlaps this much"), p.hypotheses.min_area_overlap);
  f(info("hypotheses.exact_overlap", "overlap by polygon intersection (else on rasters)"), p.hypotheses.exact_overlap);
  f(info("allow_reflection", "also try the source's mirror image"), p.allow_reflection);
  f(info("estimate_scale", "the source's resolution is unknown: estimate the scale"), p.estimate_scale);
  f(info("scale.min_scale", "least scale of the source's true resolution to its given one"), p.scale.min_scale);
  f(info("scale.max_scale", "greatest such scale"), p.scale.max_scale);
  f(info("scale.candidates_per_doubling", "candidate scales per factor 2"), p.scale.candidates_per_doubling);
  f(info("scale.sweep_range", "scales within this share of each finalist are swept"), p.scale.sweep_range);
  f(info("scale.sweep_step", "in steps of this share"), p.scale.sweep_step);
  f(info("scale.sweep_gates_m", "ICP gates of each sweep step", true), p.scale.sweep_gates_m);
  f(info("scale.finalists", "best candidate scales swept and run again"), p.scale.finalists);
  f(info("coarse_cell_m", "raster cell for scoring candidates", true), p.coarse_cell_m);
  f(info("fine_cell_m", "raster cell for the finalists' free-space IoU", true), p.fine_cell_m);
  f(info("refine", "ICP refinement"), p.refine);
  for_each_refine_parameter("refinement.", p.refinement, true, f);
  f(info("wall_inlier_distance_m", "edge points this near the other map's edge count in the score", true), p.wall_inlier_distance_m);
  f(info("occupied_point_spacing_m", "occupied cells thinned to one per square this wide", true), p.occupied_point_spacing_m);
  f(info("occupied_wall_distance_m", "walls against walls: agree within this", true), p.occupied_wall_distance_m);
  f(info("occupied_wall_context_m", "walls against walls: count within this", true), p.occupied_wall_context_m);
  f(info("passage_distance_m", "passages this close count as the same (evidence)"), p.passage_distance_m);
  f(info("turn_check_points", "source edge points the answer's turns and mirrors are refined on"), p.turn_check_points);
  f(info("different_rotation_rad", "rivals turned less than this are the same answer"), p.different_rotation_rad);
  f(info("different_translation_m", "rivals moved less than this are the same answer"), p.different_translation_m);
  f(info("decision.min_score", "reject below this score"), p.decision.min_score);
  f(info("decision.min_agreement", "reject below this agreement unless the model is sure"), p.decision.min_agreement);
  f(info("decision.gate_max_lower_walls", "the agreement accepts alone only where the lower wall agreement is at most this"),
    p.decision.gate_max_lower_walls);
  f(info("decision.gate_min_overlap_m2", "and on at least this much shared free space"), p.decision.gate_min_overlap_m2);
  f(info("decision.gate_both_ways_min_occupied", "where the walls agree both ways, the gate needs the occupied walls to agree this much"),
    p.decision.gate_both_ways_min_occupied);
  f(info("decision.gate_both_ways_min_margin", "... and this margin to the best rival"), p.decision.gate_both_ways_min_margin);
  f(info("decision.min_margin", "reject below this margin to the best rival"), p.decision.min_margin);
  f(info("decision.bias", "the p_correct model's bias (areamatch calibrate fits it)"), p.decision.bias);
  f(info("decision.weights", "its weights, in DecisionFeatures::names order"), p.decision.weights);
  f(info("decision.accept_p_correct", "accept at p_correct at least this"), p.decision.accept_p_correct);
  f(info("decision.min_p_correct", "reject below this p_correct whatever the agreement"), p.decision.min_p_correct);
  f(info("decision.different_places_p", "a refusal below this p_correct says 'different places'"), p.decision.different_places_p);
  f(info("agreement_iou_weight", "agreement = (1 - w) better wall agreement + w free-space IoU"), p.agreement_iou_weight);
  f(info("ambiguity_margin", "flag ambiguous below this margin"), p.ambiguity_margin);
  for_each_refine_parameter("correspondences.local.", p.correspondences.local, false, f);
  f(info("correspondences.min_wall_points", "areas with fewer wall points keep the global transform"),
    p.correspondences.min_wall_points);
  f(info("correspondences.min_overlap", "area pairs overlapping this much are listed"), p.correspondences.min_overlap);
  f(info("correspondences.wall_inlier_distance_m", "a room's wall points this near count"), p.correspondences.wall_inlier_distance_m);
  f(info("correspondences.max_rotation_rad", "a room's own transform turned further is not taken"),
    p.correspondences.max_rotation_rad);
  f(info("correspondences.max_shift_m", "nor one moved further"), p.correspondences.max_shift_m);
  f(info("max_areas", "most areas of a map (limit_error beyond)"), p.max_areas);
}

/// Calls `f(info, field)` for every setting of `WholeMapSelection` (under `selection.`).
template <class P, class F>
void for_each_selection_parameter(P& p, F&& f) {
  auto info = [](const char* name, const char* meaning) { return ParameterInfo{name, meaning, false}; };
  f(info("selection.members_per_cluster", "best members of each cluster that get verified"), p.members_per_cluster);
  f(info("selection.sparse_samples", "source wall points of the cheap first ranking"), p.sparse_samples);
  f(info("selection.verify_candidates", "candidates ranked again on all source wall points"), p.verify_candidates);
  f(info("selection.candidate_wall_distance_m", "before ICP, walls this near the other map's edge count"),
    p.candidate_wall_distance_m);
  f(info("selection.refine_candidates", "candidates refined by ICP and scored as finalists"), p.refine_candidates);
  f(info("selection.refine_on_free_edges", "ICP on the free-space edges (else the area outlines)"), p.refine_on_free_edges);
  f(info("selection.wall_score_weight", "finalist score = (1 - w) free-space IoU + w edge share"), p.wall_score_weight);
}

/// Calls `f(info, field)` for the settings of the shipped clusterers (under `clusterer.`).
template <class P, class F>
void for_each_clusterer_parameter(P& p, F&& f) {
  if constexpr (std::is_same_v<std::remove_const_t<P>, PoseClusterer::Params>) {
    f(ParameterInfo{"clusterer.rotation_rad", "hypotheses turned less than this apart join a cluster"}, p.rotation_rad);
    f(ParameterInfo{"clusterer.translation_m", "and moved less than this apart"}, p.translation_m);
  } else {
    f(ParameterInfo{"clusterer.threshold_rad", "hypotheses turned less than this apart join a cluster"}, p.threshold_rad);
    f(ParameterInfo{"clusterer.max_reassignments", "guards the reassignment loop"}, p.max_reassignments);
  }
}

namespace detail {
template <class Policy, class Params>
inline constexpr bool policy_params_are = std::is_same_v<std::decay_t<decltype(std::declval<Policy&>().params)>, Params>;
template <class Policy, class = void>
struct has_params : std::false_type {};
template <class Policy>
struct has_params<Policy, std::void_t<decltype(std::declval<Policy&>().params)>> : std::true_type {};
template <class Policy, class Params>
constexpr bool policy_has_params() {
  if constexpr (has_params<Policy>::value) return policy_params_are<Policy, Params>;
  else return false;
}
}  // namespace detail

/// Calls `f(info, field)` for every setting of `matcher` (any `Matcher<...>`, const or not): its
/// segmenter's when it is `VoronoiSegmenter`, `MatcherParams`, then its clusterer's and
/// selection's when they are the shipped ones. Policies of your own keep their settings to
/// themselves.
template <class M, class F>
void for_each_parameter(M& matcher, F&& f) {
  using Matcher = std::remove_const_t<M>;
  if constexpr (detail::policy_has_params<decltype(Matcher::segmenter), VoronoiSegmenterParams>()) {
    for_each_segmenter_parameter(matcher.segmenter.params, f);
  }
  for_each_matcher_parameter(matcher.params, f);
  if constexpr (detail::policy_has_params<decltype(Matcher::clusterer), PoseClusterer::Params>() ||
                detail::policy_has_params<decltype(Matcher::clusterer), AngularClusterer::Params>()) {
    for_each_clusterer_parameter(matcher.clusterer.params, f);
  }
  if constexpr (detail::policy_has_params<decltype(Matcher::selection), WholeMapSelection::Params>()) {
    for_each_selection_parameter(matcher.selection.params, f);
  }
}

}  // namespace areamatch
