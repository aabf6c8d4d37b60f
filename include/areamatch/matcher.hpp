#pragma once
/// \file matcher.hpp
/// `Matcher<Segmenter, Features, Weights, Clusterer, Selection>`: two occupancy grids → the
/// transform between them, through the stages of `match/`, grouped by what they do:
///
///   inputs.hpp        what is checked of the maps given (each graph from its grid, the area limit)
///   map_data.hpp      what each map gives alone (descriptors, rasters, edges, lookups)
///   raster.hpp        area-covered free space on coarse cells, for fast overlaps
///   proposal/         candidate transforms from area pairs
///     features.hpp    per-area descriptors and costs (paper_features.hpp: area size, passage
///                     distances, hull diameter)
///     costs.hpp       weighted cost matrix, mutual k-nearest-neighbour area pairs
///     hypotheses.hpp  a transform per pair and segment match, filtered by the pair's overlap
///     clusterer.hpp   angular (paper) or pose (default) clustering
///   verification/     the answer checked on the whole maps
///     selection.hpp   the answer among the clusters: whole-map verification (default) or the paper's
///     edges.hpp       the edges of free space and of the areas, as cells and thinned points
///     boundary_lookup.hpp  nearest boundary point per cell (and per facing direction), normals
///     refine.hpp      trimmed ICP on the free-space boundaries
///     evidence.hpp    how much the maps agree under the answer (occupied_walls.hpp: walls against walls)
///     margins.hpp     how far the answer stands out from its rivals and its own turns
///     correspondence.hpp  which room is which, each with its own local transform
///   decision/         whether to accept it
///     decision.hpp    p_correct, the calibrated probability that the answer is right
///     acceptance.hpp  the rule that sets `ok`
///   scale/            the source's scale unknown (`estimate_scale`): scale.hpp, scale_search.hpp
///   answer.hpp        the hypotheses of all pairs; what describes the selected answer
///   result.hpp        MatchResult
///   params.hpp        MatcherParams, every tunable shared by the stages, and the paper's preset
///   schedule.hpp      which work runs on which thread, and its timing
///
/// Two configurations ship. `Matcher<>` with `MatcherParams{}` is our default, chosen by
/// measurement on real maps (docs/algorithm.md): k = 10, four turns per segment match, both
/// segment sources, wall-direction hypotheses, whole-map verification of every cluster, ICP
/// refinement. `PaperMatcher` is the paper as written: k = 3, one rotation per pair, OP ≥ 0.5 by
/// polygon intersection, 3° angular clustering, the largest cluster's member with the highest Σ OP.
///
/// Each policy is a public member, so it can be tuned after construction:
/// \code
/// areamatch::Matcher<> matcher;                              // default policies and parameters
/// matcher.segmenter.params.with_door_width(1.0);
/// matcher.params.allow_reflection = true;
/// areamatch::MatchResult result = matcher.match(source_grid, dest_grid);
/// \endcode

#include "area_graph.hpp"
#include "detail/format.hpp"
#include "detail/parallel.hpp"
#include "detail/timing.hpp"
#include "error.hpp"
#include "grid.hpp"
#include "image.hpp"
#include "match/answer.hpp"
#include "match/decision/acceptance.hpp"
#include "match/decision/decision.hpp"
#include "match/inputs.hpp"
#include "match/map_data.hpp"
#include "match/params.hpp"
#include "match/proposal/clusterer.hpp"
#include "match/proposal/costs.hpp"
#include "match/proposal/features.hpp"
#include "match/proposal/hypotheses.hpp"
#include "match/raster.hpp"
#include "match/result.hpp"
#include "match/scale/scale.hpp"
#include "match/scale/scale_search.hpp"
#include "match/schedule.hpp"
#include "match/verification/correspondence.hpp"
#include "match/verification/evidence.hpp"
#include "match/verification/margins.hpp"
#include "match/verification/selection.hpp"
#include "parameters.hpp"
#include "progress.hpp"
#include "segment/voronoi_segmenter.hpp"
#include "segmenter.hpp"
#include "transform.hpp"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <optional>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace areamatch {

namespace detail {

/// A FeatureSet's size and per-area descriptors; for any other type none, so that a Matcher
/// given something else reports its one static_assert, not a cascade of follow-on errors.
template <class Features>
struct feature_set_traits {
  static constexpr std::size_t size = 0;
  using descriptors = std::tuple<>;
};
template <class... F>
struct feature_set_traits<FeatureSet<F...>> {
  static constexpr std::size_t size = sizeof...(F);
  using descriptors =
      std::decay_t<decltype(std::declval<const FeatureSet<F...>&>().describe(std::declval<const AreaGraph&>()))>;
};

}  // namespace detail

template <class Segmenter = VoronoiSegmenter, class Features = PaperFeatures, class Weights = PaperWeights,
          class Clusterer = PoseClusterer, class Selection = WholeMapSelection>
class Matcher {
  static_assert(is_segmenter_v<Segmenter>,
                "areamatch::Matcher: the Segmenter policy needs `areamatch::AreaGraph segment(const "
                "areamatch::OccupancyGrid&) const` (see segmenter.hpp)");
  static_assert(is_feature_set<Features>::value,
                "areamatch::Matcher: the Features policy must be an areamatch::FeatureSet<F1, F2, ...> of feature "
                "policies (see match/proposal/features.hpp)");
  static_assert(!is_feature_set<Features>::value || is_weights_v<Weights, detail::feature_set_traits<Features>::size>,
                "areamatch::Matcher: the Weights policy needs a member `std::array<double, N> values` with one "
                "weight per feature of the FeatureSet, in its order (see match/proposal/costs.hpp)");
  static_assert(is_clusterer_v<Clusterer>,
                "areamatch::Matcher: the Clusterer policy needs `std::vector<areamatch::Cluster> cluster(const "
                "std::vector<areamatch::Hypothesis>&) const` (see match/proposal/clusterer.hpp)");
  static_assert(is_selection_v<Selection>,
                "areamatch::Matcher: the Selection policy needs `areamatch::Selected select(const "
                "areamatch::SelectionInputs&, areamatch::MatchStatistics&) const` (see match/verification/selection.hpp)");

 public:
  Segmenter segmenter;
  Features features;
  Weights weights;
  Clusterer clusterer;
  Selection selection;
  MatcherParams params;
  /// Called at the start of each stage of a match ("segment", "prepare", "select", "check";
  /// "scale" per candidate scale of a scale search), on the calling thread; empty: no reports.
  /// It never changes a result; one that throws stops the match (progress.hpp).
  ProgressCallback progress;

  Matcher() = default;
  explicit Matcher(MatcherParams p) : params(std::move(p)) {}
  Matcher(MatcherParams p, Segmenter s, Features f = {}, Weights w = {}, Clusterer c = {}, Selection sel = {})
      : segmenter(std::move(s)), features(std::move(f)), weights(std::move(w)), clusterer(std::move(c)),
        selection(std::move(sel)), params(std::move(p)) {}

  /// The Features policy's per-area descriptors.
  using Descriptors = typename detail::feature_set_traits<Features>::descriptors;

 private:
  using MapData = detail::MapData<Descriptors>;
  using MapView = detail::MapView<Descriptors>;

 public:
  /// A map made ready for matching (`prepare`): its grid, its Area Graph and what matching builds
  /// from one map alone (the features' descriptors, coarse and fine rasters, wall direction,
  /// free-space edges and their lookup), built once and reused by any number of `match` calls:
  /// a floor plan prepared once localises any number of robot maps, and merging N maps needs N
  /// preparations, not N². Matching prepared maps gives the same result, bit for bit, as
  /// matching their grids and graphs. Tied to the parameters that shape that data (cell sizes,
  /// edge spacing, lookups, wall directions): a matcher that differs there refuses it.
  class PreparedMap {
   public:
    const OccupancyGrid& grid() const { return grid_; }
    const AreaGraph& graph() const { return graph_; }

   private:
    friend class Matcher;
    OccupancyGrid grid_;
    AreaGraph graph_;
    MapData data_;
    MatcherParams params_;  ///< those it was prepared with (`map_data_setting_differing`)
  };

  /// A prepared map's free-space edge points with their free sides and a lookup with normals and
  /// sides reaching `reach_m`, from the edge it already holds: what merging's same-side
  /// refinement (`MergeParams::refine_same_side`) needs of each map. Empty for a map without areas.
  detail::FacingEdges facing_edges(const PreparedMap& m, double reach_m) const {
    check_prepared(m, "merged");
    detail::FacingEdges e;
    if (m.graph_.areas.empty()) return e;
    const RefineParams& r = params.refinement;
    e.points = m.data_.edge_points;
    e.sides = m.data_.edge_sides.empty() ? detail::free_sides(m.grid_, e.points, r.free_side_radius_m) : m.data_.edge_sides;
    e.lookup = detail::edge_lookup(m.grid_, m.graph_.grid, m.data_.free_edge, r, reach_m, true, true);
    return e;
  }

  /// Segments `grid` with `segmenter` and prepares it for matching (with `params.threads` ≥ 2,
  /// what needs only the cells is built beside the segmentation: the same map either way).
  PreparedMap prepare(const OccupancyGrid& grid) const {
    params.validate();
    std::optional<detail::GridOnlyData> from_grid;
    AreaGraph graph = detail::segment_beside_grid_data(grid, params, segment_fn(), from_grid);
    return prepare_with(grid, std::move(graph), from_grid ? &*from_grid : nullptr);
  }

  /// Prepares a map already segmented (by anything, e.g. with its own door width); the graph
  /// must come from the grid.
  PreparedMap prepare(const OccupancyGrid& grid, AreaGraph graph) const { return prepare_with(grid, std::move(graph), nullptr); }

  /// Matches two prepared maps. Not with `params.estimate_scale` (the source is re-segmented at
  /// each candidate scale: match its grid onto the prepared destination instead).
  MatchResult match(const PreparedMap& source, const PreparedMap& dest) const {
    if (params.estimate_scale) {
      throw parameter_error("Matcher::match: estimate_scale re-segments the source at each candidate scale; pass the "
                            "source grid (match(source_grid, prepared_dest)), not a prepared source");
    }
    check_prepared(source, "source");
    check_prepared(dest, "destination");
    return match_graphs(view(source), view(dest));
  }

  /// Segments `source` with `segmenter` and matches it onto a prepared map (estimating the
  /// source's scale too with `params.estimate_scale`): a robot map against a prepared floor plan.
  MatchResult match(const OccupancyGrid& source, const PreparedMap& dest) const {
    check_prepared(dest, "destination");
    const auto start = std::chrono::steady_clock::now();
    if (params.estimate_scale) {
      MatchResult result = estimate_scale_onto(source, view(dest));
      result.timings.total_s = detail::seconds_since(start);
      return result;
    }
    std::optional<detail::GridOnlyData> from_grid;
    detail::report(progress, "segment");
    const AreaGraph source_graph = detail::segment_beside_grid_data(source, params, segment_fn(), from_grid);
    const double segment_source_s = detail::seconds_since(start);
    MatchResult result = match_graphs(MapView{&source, &source_graph, nullptr}, view(dest), from_grid ? &*from_grid : nullptr);
    result.timings.segment_source_s = segment_source_s;
    result.timings.total_s = detail::seconds_since(start);
    return result;
  }

  /// Segments both grids with `segmenter` and matches them (estimating the source's scale too
  /// with `params.estimate_scale`).
  MatchResult match(const OccupancyGrid& source, const OccupancyGrid& dest) const {
    const auto start = std::chrono::steady_clock::now();
    if (params.estimate_scale) {
      params.validate();
      const AreaGraph dest_graph = segmenter.segment(dest);
      const double segment_dest_s = detail::seconds_since(start);
      MatchResult result = match_estimating_scale(source, dest, dest_graph);
      result.timings.segment_dest_s = segment_dest_s;
      result.timings.total_s = detail::seconds_since(start);
      return result;
    }
    // The two maps are segmented on two threads with `params.threads` ≥ 2 (same graphs either way).
    detail::report(progress, "segment");
    AreaGraph graphs[2];
    double segment_s[2] = {0.0, 0.0};
    MatchResult result = match_side_by_side(source, graphs[0], dest, graphs[1], [&](std::size_t i) {
      const auto map_start = std::chrono::steady_clock::now();
      graphs[i] = segmenter.segment(i == 0 ? source : dest);
      segment_s[i] = detail::seconds_since(map_start);
    });
    result.timings.segment_source_s = segment_s[0];
    result.timings.segment_dest_s = segment_s[1];
    result.timings.total_s = detail::seconds_since(start);
    return result;
  }

  /// Matches two maps that `make_map(i)` makes — it fills `source` and `source_graph` for i = 0,
  /// `dest` and `dest_graph` for i = 1 (loads and segments them, say) — side by side with
  /// `params.threads` ≥ 2: the map made first has its match data built while the other is still
  /// being made, and the other's is then built on both threads. The same result as making both and
  /// calling `match(source, source_graph, dest, dest_graph)`; errors: map 0's first, then map 1's,
  /// then the match's. `timings.match_s`: from when both maps are made to the end.
  template <class MakeMap>
  MatchResult match_side_by_side(const OccupancyGrid& source, const AreaGraph& source_graph, const OccupancyGrid& dest,
                                 const AreaGraph& dest_graph, const MakeMap& make_map) const {
    // Invalid parameters are reported by the match below, after the maps' own errors.
    const bool build_early = detail::resolved_threads(params.threads) >= 2 && !params.estimate_scale && [&] {
      try {
        params.validate();
        return true;
      } catch (const parameter_error&) {
        return false;
      }
    }();
    const auto early = detail::make_two_maps<MapData>(params, build_early, make_map, [&](std::size_t i) -> std::optional<MapData> {
      const OccupancyGrid& grid = i == 0 ? source : dest;
      const AreaGraph& graph = i == 0 ? source_graph : dest_graph;
      if (!detail::graph_fits(grid, graph) || graph.areas.empty() || graph.areas.size() > params.max_areas) return std::nullopt;
      return detail::build_map_data(grid, graph, features, params, i == 1);  // normals: the destination's, for ICP
    });
    detail::check_segmented(params, source, source_graph, dest, dest_graph);
    MatchResult result = match_graphs(MapView{&source, &source_graph, early.of(0)}, MapView{&dest, &dest_graph, early.of(1)});
    result.timings.prepare_s += early.seconds;
    result.timings.match_s = detail::seconds_since(early.both_made);
    return result;
  }

  /// Matches two maps already segmented (by anything, e.g. with a door width per map). Each graph
  /// must come from its grid. Not with `params.estimate_scale` (see `match_estimating_scale`).
  MatchResult match(const OccupancyGrid& source, const AreaGraph& source_graph, const OccupancyGrid& dest,
                    const AreaGraph& dest_graph) const {
    detail::check_segmented(params, source, source_graph, dest, dest_graph);
    return match_graphs(MapView{&source, &source_graph, nullptr}, MapView{&dest, &dest_graph, nullptr});
  }

  /// The source's scale unknown (match/scale/scale.hpp): the source is segmented with `segmenter` and
  /// matched at each candidate scale; the best candidate's ICP-refined scale is run once more.
  /// The result maps the source's frame as given; `source_graph`, when given, receives the
  /// source's graph at the estimated scale (its cells are the source grid's cells, its metres
  /// the estimated ones). `timings.segment_source_s` sums every segmentation of the source.
  MatchResult match_estimating_scale(const OccupancyGrid& source, const OccupancyGrid& dest, const AreaGraph& dest_graph,
                                     AreaGraph* source_graph = nullptr) const {
    params.validate();
    detail::check_graph(dest, dest_graph, "destination");
    const auto start = std::chrono::steady_clock::now();
    // The destination's data once for every candidate scale.
    std::optional<MapData> dest_data;
    if (!dest_graph.areas.empty()) dest_data = detail::build_map_data(dest, dest_graph, features, params, true);
    const double prepare_dest_s = detail::seconds_since(start);
    MatchResult result = estimate_scale_onto(source, MapView{&dest, &dest_graph, dest_data ? &*dest_data : nullptr},
                                             source_graph);
    result.timings.prepare_s += prepare_dest_s;
    result.timings.match_s += prepare_dest_s;
    result.timings.total_s += prepare_dest_s;
    return result;
  }

 private:
  static MapView view(const PreparedMap& m) { return MapView{&m.grid_, &m.graph_, &m.data_}; }

  PreparedMap prepare_with(const OccupancyGrid& grid, AreaGraph graph, const detail::GridOnlyData* from_grid) const {
    params.validate();
    detail::check_graph(grid, graph, "prepared");
    PreparedMap m;
    m.grid_ = grid;
    m.graph_ = std::move(graph);
    m.params_ = params;
    if (!m.graph_.areas.empty()) m.data_ = detail::build_map_data(m.grid_, m.graph_, features, params, true, params.threads, from_grid);
    return m;
  }

  /// The segmenter as a function of the grid, for the schedules.
  auto segment_fn() const {
    return [this](const OccupancyGrid& grid) { return segmenter.segment(grid); };
  }

  void check_prepared(const PreparedMap& m, const char* which) const {
    params.validate();
    const std::string differing = map_data_setting_differing(m.params_, params);
    if (!differing.empty()) {
      throw parameter_error(std::string("Matcher::match: the ") + which + " map was prepared by a matcher with another " +
                            differing + ", which shapes a prepared map's data; prepare it with this matcher");
    }
  }

  /// `match_estimating_scale` onto a destination whose data is built (`dest.data` null: it has
  /// no areas), with the ICP fitting the scale.
  MatchResult estimate_scale_onto(const OccupancyGrid& source, const MapView& dest, AreaGraph* source_graph = nullptr) const {
    Matcher at_scale = *this;
    at_scale.params.estimate_scale = true;
    at_scale.params.validate();
    at_scale.progress = nullptr;  // one report per candidate scale, not its stages
    std::size_t tried = 0;
    return detail::estimate_scale(source, dest, at_scale.params, segmenter, features,
                                  [&](const MapView& scaled) {
                                    detail::report(progress, "scale", tried++);
                                    return at_scale.match_graphs(scaled, dest);
                                  },
                                  source_graph);
  }

  /// The pipeline: what each map gives alone, area pairs, hypotheses, clusters, the selection's
  /// answer, what describes it, and the decision.
  /// `source_grid_data`: the source's `detail::grid_only_data`, when built beside its segmentation.
  MatchResult match_graphs(const MapView& source_map, const MapView& dest_map,
                           const detail::GridOnlyData* source_grid_data = nullptr) const {
    const AreaGraph& source = *source_map.graph;
    const AreaGraph& dest = *dest_map.graph;
    params.validate();
    detail::check_area_limit(params, source, dest);
    const auto start = std::chrono::steady_clock::now();
    MatchResult result;
    result.statistics.source_areas = source.areas.size();
    result.statistics.dest_areas = dest.areas.size();
    auto finish = [&](detail::Refusal refusal) {
      result.ok = refusal.reason.empty();
      result.reason = std::move(refusal.reason);
      result.rejection = result.ok ? Rejection::none : refusal.kind;
      result.timings.match_s = detail::seconds_since(start);
      result.timings.total_s = result.timings.match_s;
      return result;
    };
    // A refusal before an answer exists says nothing of the maps but that there is none.
    auto no_answer = [&](std::string reason) { return finish({std::move(reason), Rejection::no_answer}); };
    if (source.areas.empty()) return no_answer("the source map has no areas: " + source.reason);
    if (dest.areas.empty()) return no_answer("the destination map has no areas: " + dest.reason);
    detail::report(progress, "prepare");

    // What each map gives alone: prepared beforehand (or while the other map was segmented), or
    // built now (match/schedule.hpp) — the destination's lookup with normals, for point-to-line
    // ICP onto it — then the costs and mutual pairs (the same on both sides of the mirror),
    // hypotheses and, when there are any, their clusters.
    std::optional<MapData> source_own, dest_own;
    std::vector<AreaPair> pairs;
    std::vector<Hypothesis> hypotheses;
    std::vector<Cluster> clusters;
    auto find_clusters = [&](const MapData& source_data, const MapData& dest_data, unsigned threads) {
      detail::timed(result.timings.features_s, [&] {
        pairs = mutual_nearest_pairs(features, source_data.descriptors, dest_data.descriptors, weights.values, params.k,
                                     threads);
      });
      result.statistics.mutual_pairs = pairs.size();
      hypotheses = detail::timed(result.timings.hypotheses_s, [&] {
        return detail::pair_hypotheses(features, params, detail::hypothesis_inputs(source, dest, source_data, dest_data), pairs,
                                       source_data, dest_data, threads, result.statistics);
      });
      if (hypotheses.empty()) return;
      clusters = detail::timed(result.timings.clustering_s, [&] { return clusterer.cluster(hypotheses); });
      result.statistics.clusters = clusters.size();
    };
    result.timings.prepare_s = detail::build_missing_data(source_map, dest_map, features, params, source_grid_data, source_own,
                                                          dest_own, find_clusters);
    const MapData& source_data = source_map.data ? *source_map.data : *source_own;
    const MapData& dest_data = dest_map.data ? *dest_map.data : *dest_own;
    const HypothesisInputs maps = detail::hypothesis_inputs(source, dest, source_data, dest_data);
    if (hypotheses.empty()) {
      return no_answer("no transform hypothesis: " + std::to_string(pairs.size()) +
                    " mutual area pairs, none overlapping by at least " +
                    detail::format_double(params.hypotheses.min_area_overlap) + " under its own transform");
    }

    detail::report(progress, "select");
    const MapEdges edges = detail::map_edges(source_data, dest_data);
    const Selected selected = detail::timed(result.timings.selection_s, [&] {
      return selection.select(SelectionInputs{params, maps, pairs, hypotheses, clusters, source_data.fine(), dest_data.fine(), edges},
                              result.statistics);
    });
    if (selected.finalists.empty()) return no_answer("no cluster survived the selection");
    // The proposals are not read again: let them go before the answer's checks build their own
    // (on a large floor they are tens of megabytes, and the checks are the match's peak).
    std::vector<AreaPair>().swap(pairs);
    std::vector<Hypothesis>().swap(hypotheses);
    std::vector<Cluster>().swap(clusters);

    detail::report(progress, "check");
    detail::describe_answer(params, source, dest, source_data, dest_data, edges, selected, result);
    return finish(detail::refusal(result, params.decision, selected.comparable_scores));
  }
};

/// The paper's matcher as written: its features, weights, angular clustering, largest-cluster
/// selection and `MatcherParams::paper()`.
class PaperMatcher
    : public Matcher<VoronoiSegmenter, PaperFeatures, PaperWeights, AngularClusterer, LargestClusterSelection> {
 public:
  PaperMatcher() : Matcher(MatcherParams::paper()) {}
  explicit PaperMatcher(MatcherParams p) : Matcher(std::move(p)) {}
};

}  // namespace areamatch
