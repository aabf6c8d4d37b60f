#pragma once
/// \file match/scale/scale_search.hpp
/// The unknown-scale search (`MatcherParams::estimate_scale`, match/scale/scale.hpp): the source
/// segmented and matched at every candidate scale, the best `scale.finalists` candidates' scales
/// swept by rigid ICP, the whole pipeline re-run at each swept scale, and the re-run the maps
/// agree with most kept.

#include "../../area_graph.hpp"
#include "../../detail/format.hpp"
#include "../../detail/timing.hpp"
#include "../../grid.hpp"
#include "../../transform.hpp"
#include "../map_data.hpp"
#include "../params.hpp"
#include "../result.hpp"
#include "../verification/evidence.hpp"
#include "../verification/refine.hpp"
#include "../verification/selection.hpp"
#include "scale.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace areamatch::detail {

/// The factor (≈ T.scale) in [1 − sweep_range, 1 + sweep_range] × T.scale whose rigidly
/// refined transform the maps agree with most, for the source at candidate scale `scale`
/// (`graph`: its segmentation at that scale).
template <class Features, class Descriptors>
double sweep_scale(const OccupancyGrid& source, const AreaGraph& graph, const MapView<Descriptors>& dest, double scale,
                   const Similarity2& T, const Features& features, const MatcherParams& p) {
  if (graph.areas.empty()) return T.scale;
  const OccupancyGrid scaled = rescaled_grid(source, scale);
  const MapData<Descriptors> source_data = build_map_data(scaled, graph, features, p, false);
  const MapEdges edges = map_edges(source_data, *dest.data);
  const AreaGraph& dest_graph = *dest.graph;
  const AreaRaster& source_raster = source_data.fine();
  const AreaRaster& dest_raster = dest.data->fine();
  const Eigen::Vector2d centre = centroid_of(source_raster);
  RefineParams rigid = p.refinement;
  rigid.estimate_scale = false;
  rigid.gates_m = p.scale.sweep_gates_m;
  double best_factor = 1.0, best = -1.0;
  const int steps = static_cast<int>(std::floor(p.scale.sweep_range / p.scale.sweep_step + 1e-9));
  for (int k = -steps; k <= steps; ++k) {
    const double factor = 1.0 + k * p.scale.sweep_step;
    const Similarity2 moved = refine_icp(edges.source_points, edges.dest_lookup, scaled_about(T, factor, centre), rigid,
                                         &edges.source_sides);
    const double agreement = measure_evidence(graph, dest_graph, source_raster, dest_raster, edges, moved,
                                              p.wall_inlier_distance_m, p.passage_distance_m, p.agreement_iou_weight)
                                 .agreement;
    if (agreement > best) {
      best = agreement;
      best_factor = factor;
    }
  }
  return T.scale * best_factor;
}

/// The source's scale unknown: `source` matched onto `dest` (its data built; null when it has no
/// areas) with `p.estimate_scale` set. `match_at(view)` runs the matcher's pipeline on a source
/// view onto `dest`; `segmenter` and `features` are the matcher's policies. The result maps the
/// source's frame as given; `source_graph`, when given, receives the source's graph at the
/// estimated scale. `timings.segment_source_s` sums every segmentation of the source.
template <class Segmenter, class Features, class Descriptors, class MatchAt>
MatchResult estimate_scale(const OccupancyGrid& source, const MapView<Descriptors>& dest, const MatcherParams& p,
                           const Segmenter& segmenter, const Features& features, const MatchAt& match_at,
                           AreaGraph* source_graph) {
  const AreaGraph& dest_graph = *dest.graph;
  const auto start = std::chrono::steady_clock::now();
  double segment_s = 0.0;
  auto run_at = [&](double scale, AreaGraph& graph) {
    const OccupancyGrid scaled = rescaled_grid(source, scale);
    const auto segment_start = std::chrono::steady_clock::now();
    graph = segmenter.segment(scaled);
    segment_s += seconds_since(segment_start);
    return match_at(MapView<Descriptors>{&scaled, &graph, nullptr});
  };
  // The best `scale.finalists` candidates by agreement, best first (ties: the smaller scale).
  struct Candidate {
    double scale, agreement;
    Similarity2 T;
    AreaGraph graph;  // the source segmented at this scale
  };
  std::vector<Candidate> finalists;
  std::size_t tried = 0;
  for (double scale : scale_candidates(p.scale)) {
    AreaGraph graph;
    const MatchResult r = run_at(scale, graph);
    ++tried;
    if (r.statistics.hypotheses == 0) continue;
    auto at = std::find_if(finalists.begin(), finalists.end(),
                           [&](const Candidate& c) { return r.evidence.agreement > c.agreement; });
    if (static_cast<std::size_t>(at - finalists.begin()) >= p.scale.finalists) continue;
    finalists.insert(at, Candidate{scale, r.evidence.agreement, r.T_dest_source, std::move(graph)});
    if (finalists.size() > p.scale.finalists) finalists.pop_back();
  }
  MatchResult result;
  AreaGraph graph;
  if (finalists.empty()) {
    result = run_at(1.0, graph);
    result.ok = false;
    result.rejection = Rejection::no_answer;
    result.reason = "the scale could not be estimated: no candidate scale in [" + format_double(p.scale.min_scale) +
                    ", " + format_double(p.scale.max_scale) + "] gave a transform hypothesis" +
                    (result.reason.empty() ? "" : " (" + result.reason + ")");
  } else {
    // Each finalist's scale is swept and the whole pipeline re-run there; the re-run the maps
    // agree with most wins (the first on ties).
    bool have = false;
    for (const Candidate& c : finalists) {
      double scale = c.scale * c.T.scale;
      if (p.scale.sweep_range > 0.0) scale = c.scale * sweep_scale(source, c.graph, dest, c.scale, c.T, features, p);
      const double estimate = std::clamp(scale, p.scale.min_scale, p.scale.max_scale);
      AreaGraph final_graph;
      MatchResult r = run_at(estimate, final_graph);
      ++tried;
      if (have && !(r.evidence.agreement > result.evidence.agreement)) continue;
      r.T_dest_source = from_scaled_source(r.T_dest_source, estimate);
      for (auto& pair : r.matched_areas) pair.T_dest_source = from_scaled_source(pair.T_dest_source, estimate);
      r.scale_estimated = true;
      if (!r.ok) r.reason = "at the estimated scale " + format_fixed(r.T_dest_source.scale, 4) + ": " + r.reason;
      result = std::move(r);
      graph = std::move(final_graph);
      have = true;
    }
  }
  const GridInfo given{source.width(), source.height(), source.resolution(), source.origin()};
  result.pixel_transform = to_pixel_transform(result.T_dest_source, given, dest_graph.grid);
  result.statistics.scales_tried = tried + (finalists.empty() ? 1 : 0);
  result.timings.segment_source_s = segment_s;
  result.timings.total_s = seconds_since(start);
  result.timings.match_s = result.timings.total_s - segment_s;
  if (source_graph) *source_graph = std::move(graph);
  return result;
}

}  // namespace areamatch::detail
