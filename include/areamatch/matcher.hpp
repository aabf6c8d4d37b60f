#pragma once
/// \file matcher.hpp
/// `Matcher<Segmenter, Features, Weights, Clusterer>`: two occupancy grids → the transform
/// between them, through the stages of `match/`:
///
///   features.hpp    per-area descriptors and costs (area size, passage distances, hull diameter)
///   costs.hpp       weighted cost matrix, mutual k-nearest-neighbour area pairs
///   raster.hpp      area-covered free space on coarse cells, for fast overlaps
///   hypotheses.hpp  a transform per pair and segment match, filtered by the pair's overlap
///   clusterer.hpp   angular (paper) or pose (default) clustering
///   refine.hpp      trimmed ICP on the free-space boundaries
///   result.hpp      MatchResult
///   params.hpp      MatcherParams, every tunable, and the paper's preset
///
/// Two configurations ship. `MatcherParams{}` is our default, chosen by measurement on real maps
/// (docs/algorithm.md): k = 10, four turns per segment match, both segment sources, wall-direction
/// hypotheses, whole-map verification of every cluster, ICP refinement. `PaperMatcher` is the
/// paper as written: k = 3, one rotation per pair, OP ≥ 0.5 by polygon intersection, 3° angular
/// clustering, the largest cluster's member with the highest Σ OP.
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
#include "match/clusterer.hpp"
#include "match/correspondence.hpp"
#include "match/costs.hpp"
#include "match/decision.hpp"
#include "match/evidence.hpp"
#include "match/features.hpp"
#include "match/hypotheses.hpp"
#include "match/params.hpp"
#include "match/raster.hpp"
#include "match/refine.hpp"
#include "match/result.hpp"
#include "match/scale.hpp"
#include "segment/voronoi_segmenter.hpp"
#include "segmenter.hpp"
#include "transform.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <optional>
#include <string>
#include <utility>
#include <tuple>
#include <vector>

namespace areamatch {

namespace detail {

/// Every k-th of `points`, k = max(1, size / about): about `about` of them (at most 2·about − 1),
/// evenly spread, in order.
inline std::vector<Eigen::Vector2d> evenly_thinned(const std::vector<Eigen::Vector2d>& points, std::size_t about) {
  const std::size_t stride = std::max<std::size_t>(1, points.size() / about);
  std::vector<Eigen::Vector2d> out;
  out.reserve(points.size() / stride + 1);
  for (std::size_t i = 0; i < points.size(); i += stride) out.push_back(points[i]);
  return out;
}

/// A transform with its whole-map score.
struct ScoredTransform {
  Similarity2 T;
  double score = 0.0;
};

/// What matching builds from one map alone, the same whichever side the map is on
/// (`Matcher::prepare`).
template <class Descriptors>
struct MapData {
  Descriptors descriptors;                   ///< the Features policy's, per area
  AreaRaster coarse;                         ///< area-covered free space on coarse cells
  std::optional<AreaRaster> fine_own;        ///< on fine cells, when they differ from the coarse ones
  double wall_direction = 0.0;               ///< for wall-direction hypotheses
  std::vector<Eigen::Vector2d> edge_points;  ///< sparse free-space edge: what moves (ICP, scores)
  std::vector<Eigen::Vector2d> walls;        ///< edge_points without frontiers
  std::vector<std::size_t> free_edge;        ///< the free-space edge cells (`detail::free_edge_cells`)
  BoundaryLookup lookup;                     ///< dense free-space edge: what is landed on
  const AreaRaster& fine() const { return fine_own ? *fine_own : coarse; }
};

/// The parameters that shape `MapData`: a prepared map serves the matchers that agree on them.
struct MapDataKey {
  double coarse_cell_m = 0.0, fine_cell_m = 0.0, point_spacing_m = 0.0, lookup_cell_m = 0.0, margin_m = 0.0,
         normal_radius_m = 0.0;
  int max_points = 0;
  bool wall_directions = false;
  WallDirectionParams wall_direction;
  bool operator==(const MapDataKey& o) const {
    return coarse_cell_m == o.coarse_cell_m && fine_cell_m == o.fine_cell_m && point_spacing_m == o.point_spacing_m &&
           lookup_cell_m == o.lookup_cell_m && margin_m == o.margin_m && normal_radius_m == o.normal_radius_m &&
           max_points == o.max_points && wall_directions == o.wall_directions && wall_direction == o.wall_direction;
  }
};

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
          class Clusterer = PoseClusterer>
class Matcher {
  static_assert(is_segmenter_v<Segmenter>,
                "areamatch::Matcher: the Segmenter policy needs `areamatch::AreaGraph segment(const "
                "areamatch::OccupancyGrid&) const` (see segmenter.hpp)");
  static_assert(is_feature_set<Features>::value,
                "areamatch::Matcher: the Features policy must be an areamatch::FeatureSet<F1, F2, ...> of feature "
                "policies (see match/features.hpp)");
  static_assert(!is_feature_set<Features>::value || is_weights_v<Weights, detail::feature_set_traits<Features>::size>,
                "areamatch::Matcher: the Weights policy needs a member `std::array<double, N> values` with one "
                "weight per feature of the FeatureSet, in its order (see match/costs.hpp)");
  static_assert(is_clusterer_v<Clusterer>,
                "areamatch::Matcher: the Clusterer policy needs `std::vector<areamatch::Cluster> cluster(const "
                "std::vector<areamatch::Hypothesis>&) const` (see match/clusterer.hpp)");

 public:
  Segmenter segmenter;
  Features features;
  Weights weights;
  Clusterer clusterer;
  MatcherParams params;

  Matcher() = default;
  explicit Matcher(MatcherParams p) : params(std::move(p)) {}
  Matcher(MatcherParams p, Segmenter s, Features f = {}, Weights w = {}, Clusterer c = {})
      : segmenter(std::move(s)), features(std::move(f)), weights(std::move(w)), clusterer(std::move(c)),
        params(std::move(p)) {}

  /// The Features policy's per-area descriptors.
  using Descriptors = typename detail::feature_set_traits<Features>::descriptors;

 private:
  /// One map as matching reads it; `data` null: built for this match.
  struct MapView {
    const OccupancyGrid* grid;
    const AreaGraph* graph;
    const detail::MapData<Descriptors>* data;
  };

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
    detail::MapData<Descriptors> data_;
    detail::MapDataKey key_;
  };

  /// Segments `grid` with `segmenter` and prepares it for matching.
  PreparedMap prepare(const OccupancyGrid& grid) const { return prepare(grid, segmenter.segment(grid)); }

  /// Prepares a map already segmented (by anything, e.g. with its own door width); the graph
  /// must come from the grid.
  PreparedMap prepare(const OccupancyGrid& grid, AreaGraph graph) const {
    params.validate();
    check_graph(grid, graph, "prepared");
    PreparedMap m;
    m.grid_ = grid;
    m.graph_ = std::move(graph);
    m.key_ = data_key(true);
    if (!m.graph_.areas.empty()) m.data_ = map_data(m.grid_, m.graph_, true);
    return m;
  }

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
    const AreaGraph source_graph = segmenter.segment(source);
    const double segment_source_s = detail::seconds_since(start);
    MatchResult result = match_graphs(MapView{&source, &source_graph, nullptr}, view(dest));
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
    AreaGraph graphs[2];
    double segment_s[2] = {0.0, 0.0};
    detail::for_each_index(2, params.threads, [&](std::size_t i) {
      const auto map_start = std::chrono::steady_clock::now();
      graphs[i] = segmenter.segment(i == 0 ? source : dest);
      segment_s[i] = detail::seconds_since(map_start);
    });
    const AreaGraph& source_graph = graphs[0];
    const AreaGraph& dest_graph = graphs[1];
    const double segment_source_s = segment_s[0], segment_dest_s = segment_s[1];
    MatchResult result = match(source, source_graph, dest, dest_graph);
    result.timings.segment_source_s = segment_source_s;
    result.timings.segment_dest_s = segment_dest_s;
    result.timings.total_s = detail::seconds_since(start);
    return result;
  }

  /// Matches two maps already segmented (by anything, e.g. with a door width per map). Each graph
  /// must come from its grid. Not with `params.estimate_scale` (see `match_estimating_scale`).
  MatchResult match(const OccupancyGrid& source, const AreaGraph& source_graph, const OccupancyGrid& dest,
                    const AreaGraph& dest_graph) const {
    if (params.estimate_scale) {
      throw parameter_error("Matcher::match: estimate_scale re-segments the source at each candidate scale; pass the "
                            "source grid (match(source, dest) or match_estimating_scale), not its graph");
    }
    check_graph(source, source_graph, "source");
    check_graph(dest, dest_graph, "destination");
    return match_graphs(MapView{&source, &source_graph, nullptr}, MapView{&dest, &dest_graph, nullptr});
  }

 private:
  /// The factor (≈ T.scale) in [1 − sweep_range, 1 + sweep_range] × T.scale whose rigidly
  /// refined transform the maps agree with most, for the source at candidate scale `scale`
  /// (`graph`: its segmentation at that scale).
  double sweep_scale(const OccupancyGrid& source, const AreaGraph& graph, const MapView& dest, double scale,
                     const Similarity2& T, const MatcherParams& p) const {
    if (graph.areas.empty()) return T.scale;
    const OccupancyGrid scaled = rescaled_grid(source, scale);
    const detail::MapData<Descriptors> source_data = map_data(scaled, graph, false);
    const detail::MapEdges edges = map_edges(source_data, *dest.data);
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
      const Similarity2 moved = refine_icp(edges.source_points, edges.dest_lookup, scaled_about(T, factor, centre), rigid);
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

  static MapView view(const PreparedMap& m) { return MapView{&m.grid_, &m.graph_, &m.data_}; }

  /// The lookups reach this far beyond the edges: every distance they are asked about.
  double lookup_margin() const {
    const auto& gates = params.refinement.gates_m;
    const auto& sweep_gates = params.scale.sweep_gates_m;
    return std::max({*std::max_element(gates.begin(), gates.end()), *std::max_element(sweep_gates.begin(), sweep_gates.end()),
                     params.wall_inlier_distance_m, params.candidate_wall_distance_m});
  }

  /// The key of the data this matcher builds; `normals`: the lookup carries normals (needed by
  /// the destination's for point-to-line ICP, not by the source's).
  detail::MapDataKey data_key(bool normals) const {
    const RefineParams& r = params.refinement;
    return {params.coarse_cell_m, params.fine_cell_m, r.point_spacing_m, r.lookup_cell_m, lookup_margin(),
            normals && r.point_to_line ? r.normal_radius_m : 0.0, r.max_points, params.hypotheses.wall_directions,
            params.hypotheses.wall_direction};
  }

  void check_prepared(const PreparedMap& m, const char* which) const {
    params.validate();
    if (!(m.key_ == data_key(true))) {
      throw parameter_error(std::string("Matcher::match: the ") + which + " map was prepared by a matcher with other "
                            "cell sizes, edge spacing, lookups or wall directions; prepare it with this matcher");
    }
  }

  /// What matching builds from one map alone.
  detail::MapData<Descriptors> map_data(const OccupancyGrid& grid, const AreaGraph& graph, bool normals) const {
    const RefineParams& r = params.refinement;
    detail::MapData<Descriptors> d;
    d.descriptors = features.describe(graph);
    d.coarse = make_area_raster(graph, params.coarse_cell_m);
    if (params.fine_cell_m != params.coarse_cell_m) d.fine_own = make_area_raster(graph, params.fine_cell_m);
    if (params.hypotheses.wall_directions) d.wall_direction = dominant_wall_direction(graph, params.hypotheses.wall_direction);
    d.free_edge = detail::free_edge_cells(grid, graph);  // found once: thinned for the points, the lookup, the rooms' walls
    d.edge_points = detail::boundary_points(graph.grid, d.free_edge, r.point_spacing_m, static_cast<std::size_t>(r.max_points));
    d.walls = detail::without_frontiers(grid, d.edge_points);
    d.lookup = BoundaryLookup(detail::boundary_points(graph.grid, d.free_edge, 0.5 * r.lookup_cell_m), r.lookup_cell_m,
                              lookup_margin(), normals && r.point_to_line ? r.normal_radius_m : 0.0);
    return d;
  }

 public:
  /// The source's scale unknown (match/scale.hpp): the source is segmented with `segmenter` and
  /// matched at each candidate scale; the best candidate's ICP-refined scale is run once more.
  /// The result maps the source's frame as given; `source_graph`, when given, receives the
  /// source's graph at the estimated scale (its cells are the source grid's cells, its metres
  /// the estimated ones). `timings.segment_source_s` sums every segmentation of the source.
  MatchResult match_estimating_scale(const OccupancyGrid& source, const OccupancyGrid& dest, const AreaGraph& dest_graph,
                                     AreaGraph* source_graph = nullptr) const {
    params.validate();
    check_graph(dest, dest_graph, "destination");
    const auto start = std::chrono::steady_clock::now();
    // The destination's data once for every candidate scale.
    std::optional<detail::MapData<Descriptors>> dest_data;
    if (!dest_graph.areas.empty()) dest_data = map_data(dest, dest_graph, true);
    const double prepare_dest_s = detail::seconds_since(start);
    MatchResult result = estimate_scale_onto(source, MapView{&dest, &dest_graph, dest_data ? &*dest_data : nullptr},
                                             source_graph);
    result.timings.prepare_s += prepare_dest_s;
    result.timings.match_s += prepare_dest_s;
    result.timings.total_s += prepare_dest_s;
    return result;
  }

 private:
  /// `match_estimating_scale` onto a destination whose data is built (`dest.data` null: it has
  /// no areas).
  MatchResult estimate_scale_onto(const OccupancyGrid& source, const MapView& dest, AreaGraph* source_graph = nullptr) const {
    MatcherParams p = params;
    p.estimate_scale = true;
    p.validate();
    const AreaGraph& dest_graph = *dest.graph;
    const auto start = std::chrono::steady_clock::now();
    double segment_s = 0.0;
    Matcher at_scale = *this;  // matches with the ICP fitting the scale
    at_scale.params = p;
    auto run_at = [&](double scale, AreaGraph& graph) {
      const OccupancyGrid scaled = rescaled_grid(source, scale);
      const auto segment_start = std::chrono::steady_clock::now();
      graph = segmenter.segment(scaled);
      segment_s += detail::seconds_since(segment_start);
      return at_scale.match_graphs(MapView{&scaled, &graph, nullptr}, dest);
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
      result.reason = "the scale could not be estimated: no candidate scale in [" + detail::format_double(p.scale.min_scale) +
                      ", " + detail::format_double(p.scale.max_scale) + "] gave a transform hypothesis" +
                      (result.reason.empty() ? "" : " (" + result.reason + ")");
    } else {
      // Each finalist's scale is swept and the whole pipeline re-run there; the re-run the maps
      // agree with most wins (the first on ties).
      bool have = false;
      for (const Candidate& c : finalists) {
        double scale = c.scale * c.T.scale;
        if (p.scale.sweep_range > 0.0) scale = c.scale * sweep_scale(source, c.graph, dest, c.scale, c.T, p);
        const double estimate = std::clamp(scale, p.scale.min_scale, p.scale.max_scale);
        AreaGraph final_graph;
        MatchResult r = run_at(estimate, final_graph);
        ++tried;
        if (have && !(r.evidence.agreement > result.evidence.agreement)) continue;
        r.T_dest_source = from_scaled_source(r.T_dest_source, estimate);
        for (auto& pair : r.matched_areas) pair.T_dest_source = from_scaled_source(pair.T_dest_source, estimate);
        r.scale_estimated = true;
        if (!r.ok) r.reason = "at the estimated scale " + detail::format_fixed(r.T_dest_source.scale, 4) + ": " + r.reason;
        result = std::move(r);
        graph = std::move(final_graph);
        have = true;
      }
    }
    const GridInfo given{source.width(), source.height(), source.resolution(), source.origin()};
    result.pixel_transform = to_pixel_transform(result.T_dest_source, given, dest_graph.grid);
    result.statistics.scales_tried = tried + (finalists.empty() ? 1 : 0);
    result.timings.segment_source_s = segment_s;
    result.timings.total_s = detail::seconds_since(start);
    result.timings.match_s = result.timings.total_s - segment_s;
    if (source_graph) *source_graph = std::move(graph);
    return result;
  }

 private:

  static void check_graph(const OccupancyGrid& grid, const AreaGraph& graph, const char* which) {
    if (graph.grid.width != grid.width() || graph.grid.height != grid.height() ||
        graph.labels.size() != grid.cells().size()) {
      throw parameter_error(std::string("Matcher::match: the ") + which + " Area Graph was not made from the " + which +
                            " grid (sizes differ)");
    }
  }

  MatchResult match_graphs(const MapView& source_map, const MapView& dest_map) const {
    const AreaGraph& source = *source_map.graph;
    const AreaGraph& dest = *dest_map.graph;
    params.validate();
    for (const auto& [graph, which] : {std::pair{&source, "source"}, std::pair{&dest, "destination"}}) {
      if (graph->areas.size() > params.max_areas) {
        throw limit_error(std::string("the ") + which + " map has " + std::to_string(graph->areas.size()) +
                          " areas, more than MatcherParams::max_areas (" + std::to_string(params.max_areas) +
                          "); raise it (matching time grows with areas_source x areas_dest) or match parts of the map");
      }
    }
    const auto start = std::chrono::steady_clock::now();
    MatchResult result;
    result.statistics.source_areas = source.areas.size();
    result.statistics.dest_areas = dest.areas.size();
    auto finish = [&](std::string reason) {
      result.ok = reason.empty();
      result.reason = std::move(reason);
      result.timings.match_s = detail::seconds_since(start);
      result.timings.total_s = result.timings.match_s;
      return result;
    };
    if (source.areas.empty()) return finish("the source map has no areas: " + source.reason);
    if (dest.areas.empty()) return finish("the destination map has no areas: " + dest.reason);

    // What each map gives alone: prepared beforehand, or built now (the destination's lookup
    // with normals, for point-to-line ICP onto it).
    auto stage = std::chrono::steady_clock::now();
    std::optional<detail::MapData<Descriptors>> source_own, dest_own;
    detail::for_each_index(2, params.threads, [&](std::size_t i) {
      if (i == 0 && !source_map.data) source_own = map_data(*source_map.grid, source, false);
      if (i == 1 && !dest_map.data) dest_own = map_data(*dest_map.grid, dest, true);
    });
    const detail::MapData<Descriptors>& source_data = source_map.data ? *source_map.data : *source_own;
    const detail::MapData<Descriptors>& dest_data = dest_map.data ? *dest_map.data : *dest_own;
    if (source_own || dest_own) result.timings.prepare_s = detail::seconds_since(stage);

    // Costs and mutual pairs. They do not change under reflection: computed once.
    stage = std::chrono::steady_clock::now();
    const auto& source_descriptors = source_data.descriptors;
    const auto& dest_descriptors = dest_data.descriptors;
    const Eigen::MatrixXd cost = weighted_cost(features.costs(source_descriptors, dest_descriptors), weights.values);
    const std::vector<AreaPair> pairs = mutual_nearest_pairs(cost, params.k);
    result.statistics.mutual_pairs = pairs.size();
    result.timings.features_s = detail::seconds_since(stage);

    // Hypotheses on each side of the mirror.
    stage = std::chrono::steady_clock::now();
    const AreaRaster& source_raster = source_data.coarse;
    const AreaRaster& dest_raster = dest_data.coarse;
    HypothesisInputs inputs{&source, &dest, &source_raster, &dest_raster, source_data.wall_direction,
                            dest_data.wall_direction};
    // One job per (side, pair), each into its own list, joined in job order: the same list for
    // any thread count.
    const std::vector<bool> side_list = sides();
    std::vector<std::vector<Hypothesis>> per_job(side_list.size() * pairs.size());
    std::vector<std::size_t> overlay_failures(per_job.size(), 0);
    detail::for_each_index(per_job.size(), params.threads, [&](std::size_t job) {
      const AreaPair& pair = pairs[job % pairs.size()];
      const auto segments = features.segments(source_descriptors, dest_descriptors, static_cast<std::size_t>(pair.source),
                                              static_cast<std::size_t>(pair.dest));
      add_pair_hypotheses(inputs, pair, segments, side_list[job / pairs.size()], params.hypotheses, per_job[job],
                          &overlay_failures[job]);
    });
    std::vector<Hypothesis> hypotheses;
    for (auto& list : per_job) hypotheses.insert(hypotheses.end(), list.begin(), list.end());
    for (std::size_t failures : overlay_failures) result.statistics.overlay_failures += failures;
    result.statistics.hypotheses = hypotheses.size();
    result.timings.hypotheses_s = detail::seconds_since(stage);
    if (hypotheses.empty()) {
      return finish("no transform hypothesis: " + std::to_string(pairs.size()) +
                    " mutual area pairs, none overlapping by at least " +
                    detail::format_double(params.hypotheses.min_area_overlap) + " under its own transform");
    }

    stage = std::chrono::steady_clock::now();
    const std::vector<Cluster> clusters = clusterer.cluster(hypotheses);
    result.statistics.clusters = clusters.size();
    result.timings.clustering_s = detail::seconds_since(stage);

    stage = std::chrono::steady_clock::now();
    // The finalists' rasters (the coarse ones again when the cell sizes agree).
    const AreaRaster& source_fine = source_data.fine();
    const AreaRaster& dest_fine = dest_data.fine();
    const detail::MapEdges edges = map_edges(source_data, dest_data);
    std::vector<detail::ScoredTransform> finalists;  // best first
    if (params.selection == Selection::largest_cluster) {
      finalists = select_largest_cluster(inputs, pairs, hypotheses, clusters, result);
    } else {
      finalists = select_whole_map(source_map, dest_map, edges, source_raster, source_fine, dest_fine,
                                   hypotheses, clusters, result);
    }
    result.timings.selection_s = detail::seconds_since(stage);
    if (finalists.empty()) return finish("no cluster survived the selection");

    const detail::ScoredTransform& best = finalists.front();
    result.T_dest_source = best.T;
    result.pixel_transform = to_pixel_transform(best.T, source.grid, dest.grid);
    result.score = best.score;
    compute_margins(source_fine, dest_fine, finalists, result);
    result.matched_areas = detail::area_correspondences(
        detail::area_wall_points(source, source_data.free_edge, params.correspondences.local.point_spacing_m), source, dest,
        source_fine, dest_fine, edges.dest_lookup, best.T, params.correspondences);
    result.evidence = measure_evidence(source, dest, source_fine, dest_fine, edges, best.T, params.wall_inlier_distance_m,
                                       params.passage_distance_m, params.agreement_iou_weight);
    if (params.selection == Selection::whole_map && params.refine) {
      measure_turn_margins(source_fine, dest_fine, edges, dest_data.wall_direction, result);
    }
    result.ambiguous = result.confidence < params.ambiguity_margin;
    result.p_correct = p_correct(decision_features(result), params.decision);

    if (params.selection == Selection::whole_map && result.score < params.min_score) {
      return finish("best whole-map score " + detail::format_fixed(result.score, 3) + " is below min_score " +
                    detail::format_double(params.min_score) + ": the maps do not match");
    }
    const bool model_sure = result.p_correct >= params.decision.accept_p_correct;
    if (result.evidence.agreement < params.min_agreement && !model_sure) {
      return finish("the maps agree too little under the best transform to be the same building: agreement " +
                    detail::format_fixed(result.evidence.agreement, 3) + " < min_agreement " +
                    detail::format_double(params.min_agreement) + " (the destination's walls near the source's " +
                    "free space explained: " + detail::format_fixed(result.evidence.reverse_wall_agreement, 3) +
                    ", the source's near the destination's: " + detail::format_fixed(result.evidence.forward_wall_agreement, 3) +
                    ", free-space IoU " + detail::format_fixed(result.evidence.free_iou, 3) + "; p_correct " +
                    detail::format_fixed(result.p_correct, 3) + " < accept_p_correct " +
                    detail::format_double(params.decision.accept_p_correct) + ")");
    }
    if (result.p_correct < params.decision.min_p_correct) {
      return finish("the answer is too likely wrong: p_correct " + detail::format_fixed(result.p_correct, 3) +
                    " < min_p_correct " + detail::format_double(params.decision.min_p_correct) + " (wall agreement " +
                    detail::format_fixed(result.evidence.forward_wall_agreement, 3) + " / " +
                    detail::format_fixed(result.evidence.reverse_wall_agreement, 3) + ", rooms " +
                    detail::format_fixed(result.evidence.room_agreement, 3) + ", margin " +
                    detail::format_fixed(result.confidence, 3) + ", overlap " +
                    detail::format_fixed(result.evidence.overlap_m2, 1) + " m²)");
    }
    if (result.confidence < params.min_confidence) {
      return finish("ambiguous: a different transform scores within " + detail::format_fixed(result.confidence, 3) +
                    " of the best (min_confidence " + detail::format_double(params.min_confidence) + ")");
    }
    return finish("");
  }

  std::vector<bool> sides() const {
    return params.allow_reflection ? std::vector<bool>{false, true} : std::vector<bool>{false};
  }

  /// The paper: on each side of the mirror, the largest cluster's member with the highest
  /// Σ OP over all mutual pairs; the sides compare by that Σ OP. Also returns the first member of
  /// every other cluster (scored by Σ OP too) so the margins can be computed.
  std::vector<detail::ScoredTransform> select_largest_cluster(const HypothesisInputs& inputs,
                                                              const std::vector<AreaPair>& pairs,
                                                              const std::vector<Hypothesis>& hypotheses,
                                                              const std::vector<Cluster>& clusters,
                                                              MatchResult& result) const {
    auto total_overlap = [&](const Similarity2& T) {
      double sum = 0.0;
      for (const AreaPair& pair : pairs) {
        sum += pair_overlap(inputs, pair, params.hypotheses.exact_overlap, T, &result.statistics.overlay_failures);
      }
      return sum;
    };
    std::vector<detail::ScoredTransform> chosen;   // the best of each side's largest cluster
    std::vector<detail::ScoredTransform> others;   // first members of the other clusters
    for (bool side : sides()) {
      bool first = true;
      for (const Cluster& cluster : clusters) {
        if (hypotheses[static_cast<std::size_t>(cluster.members.front())].T_dest_source.reflected != side) continue;
        if (first) {
          first = false;
          detail::ScoredTransform best{{}, -1.0};
          for (int m : cluster.members) {
            const Similarity2& T = hypotheses[static_cast<std::size_t>(m)].T_dest_source;
            const double s = total_overlap(T);
            ++result.statistics.verified;
            if (s > best.score) best = {T, s};
          }
          chosen.push_back(best);
        } else {
          const Similarity2& T = hypotheses[static_cast<std::size_t>(cluster.members.front())].T_dest_source;
          others.push_back({T, -1.0});  // scored by IoU in compute_margins only
        }
      }
    }
    std::stable_sort(chosen.begin(), chosen.end(),
                     [](const auto& a, const auto& b) { return a.score > b.score; });
    chosen.insert(chosen.end(), others.begin(), others.end());
    return chosen;
  }

  /// Ours: the best members of every cluster, ranked by how much of the source's walls land near
  /// the destination's (sparse, then all wall points); the best few refined by ICP and scored.
  /// The answer is the best of those, whatever cluster it came from.
  std::vector<detail::ScoredTransform> select_whole_map(const MapView& source, const MapView& dest,
                                                        const detail::MapEdges& edges, const AreaRaster& source_raster,
                                                        const AreaRaster& source_fine, const AreaRaster& dest_fine,
                                                        const std::vector<Hypothesis>& hypotheses,
                                                        const std::vector<Cluster>& clusters,
                                                        MatchResult& result) const {
    std::vector<detail::ScoredTransform> candidates;
    for (const Cluster& cluster : clusters) {
      for (std::size_t m = 0; m < std::min(params.members_per_cluster, cluster.members.size()); ++m) {
        candidates.push_back({hypotheses[static_cast<std::size_t>(cluster.members[m])].T_dest_source, 0.0});
      }
    }
    auto by_score = [](const detail::ScoredTransform& a, const detail::ScoredTransform& b) { return a.score > b.score; };
    // Unrefined candidates are ranked by the share of the source's walls near the destination's
    // edge (frontiers left out: a partial map's frontier is not a wall of the other map), first
    // on a few hundred wall points, then on all of them.
    const std::vector<Eigen::Vector2d>& walls = edges.source_walls.empty() ? edges.source_points : edges.source_walls;
    const std::vector<Eigen::Vector2d> sparse_walls = detail::evenly_thinned(walls, params.sparse_samples);
    auto score_on = [&](const std::vector<Eigen::Vector2d>& points) {
      detail::for_each_index(candidates.size(), params.threads, [&](std::size_t i) {
        candidates[i].score = boundary_inlier_fraction(points, edges.dest_lookup, candidates[i].T, params.candidate_wall_distance_m);
      });
    };
    score_on(sparse_walls);
    std::stable_sort(candidates.begin(), candidates.end(), by_score);
    if (candidates.size() > params.verify_candidates) candidates.resize(params.verify_candidates);
    score_on(walls);
    result.statistics.verified = candidates.size();
    std::stable_sort(candidates.begin(), candidates.end(), by_score);

    // Finalists: the best few, plus the best on the other side of the mirror and the best clearly
    // different transform, so that the confidence margins compare refined with refined.
    std::vector<detail::ScoredTransform> finalists;
    const Eigen::Vector2d centroid = centroid_of(source_raster);
    auto add_finalist = [&](const detail::ScoredTransform& c) {
      for (const auto& f : finalists) {
        if (!different(f.T, c.T, centroid)) return;
      }
      finalists.push_back(c);
    };
    for (const auto& c : candidates) {
      if (finalists.size() >= params.refine_candidates) break;
      add_finalist(c);
    }
    for (const auto& c : candidates) {
      if (c.T.reflected != candidates.front().T.reflected) { add_finalist(c); break; }
    }

    stage_refine(source, dest, edges, source_fine, dest_fine, finalists, result);
    std::stable_sort(finalists.begin(), finalists.end(), by_score);
    return finalists;
  }

  /// Refines the finalists by ICP and scores them: a blend of the fine free-space IoU and the
  /// share of the source's free-space edge that lies on the destination's.
  void stage_refine(const MapView& source, const MapView& dest, const detail::MapEdges& edges,
                    const AreaRaster& source_fine, const AreaRaster& dest_fine,
                    std::vector<detail::ScoredTransform>& finalists, MatchResult& result) const {
    const std::vector<Eigen::Vector2d>& edge = edges.source_points;
    const BoundaryLookup& dest_edge = edges.dest_lookup;
    if (params.refine) {
      RefineParams refinement = params.refinement;
      refinement.estimate_scale = refinement.estimate_scale || params.estimate_scale;
      const std::vector<Eigen::Vector2d>* points = &edge;
      const BoundaryLookup* lookup = &dest_edge;
      std::vector<Eigen::Vector2d> area_points;
      BoundaryLookup area_lookup;
      if (!params.refine_on_free_edges) {
        area_points = detail::area_boundary_points(*source.graph, params.refinement.point_spacing_m,
                                                   static_cast<std::size_t>(params.refinement.max_points));
        area_lookup = BoundaryLookup(detail::area_boundary_points(*dest.graph, 0.5 * params.refinement.lookup_cell_m),
                                     params.refinement.lookup_cell_m, params.refinement.gates_m.front(),
                                     params.refinement.point_to_line ? params.refinement.normal_radius_m : 0.0);
        points = &area_points;
        lookup = &area_lookup;
      }
      detail::for_each_index(finalists.size(), params.threads, [&](std::size_t i) {
        finalists[i].T = refine_icp(*points, *lookup, finalists[i].T, refinement);
      });
      result.statistics.refined = finalists.size();
    }
    detail::for_each_index(finalists.size(), params.threads, [&](std::size_t i) {
      auto& f = finalists[i];
      const double iou = free_space_iou(source_fine, dest_fine, f.T);
      const double walls = boundary_inlier_fraction(edge, dest_edge, f.T, params.wall_inlier_distance_m);
      f.score = (1.0 - params.wall_score_weight) * iou + params.wall_score_weight * walls;
    });
  }

  /// The free-space edges of both maps, each as sparse points (what moves) and a dense lookup
  /// (what is landed on), so that scores and evidence can look both ways.
  static detail::MapEdges map_edges(const detail::MapData<Descriptors>& source, const detail::MapData<Descriptors>& dest) {
    return detail::MapEdges{source.edge_points, source.walls, dest.walls, source.lookup, dest.lookup};
  }

  /// Whether two transforms are clearly different answers: another side of the mirror, a
  /// rotation apart, or the source's free-space centroid lands apart.
  bool different(const Similarity2& a, const Similarity2& b, const Eigen::Vector2d& source_centroid) const {
    if (a.reflected != b.reflected) return true;
    if (std::abs(wrap_angle(a.rotation - b.rotation)) > params.different_rotation_rad) return true;
    return ((a * source_centroid) - (b * source_centroid)).norm() > params.different_translation_m;
  }

  static Eigen::Vector2d centroid_of(const AreaRaster& raster) {
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (const auto& c : raster.centres) centroid += c;
    return raster.centres.empty() ? centroid : Eigen::Vector2d(centroid / static_cast<double>(raster.centres.size()));
  }

  /// `MatchEvidence::turn_margin`: the answer against its own quarter turns about the centre of
  /// the common part (and its mirror images about an axis along the destination's walls through
  /// that centre, when reflection is allowed), each refined by the finalists' ICP on the
  /// free-space edges (on fewer points) and scored by the overlap-restricted wall agreements.
  void measure_turn_margins(const AreaRaster& source_fine, const AreaRaster& dest_fine, const detail::MapEdges& edges,
                            double wall_direction, MatchResult& result) const {
    const Similarity2& T = result.T_dest_source;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    std::size_t common = 0;
    const Eigen::Affine2d to_cell = dest_fine.cell_from_world * T.affine();
    for (const auto& c : source_fine.centres) {
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
    RefineParams refinement = params.refinement;
    refinement.estimate_scale = refinement.estimate_scale || params.estimate_scale;
    // A rival needs only to be placed well enough to be scored: its ICP runs on fewer points.
    const std::vector<Eigen::Vector2d> points = detail::evenly_thinned(edges.source_points, params.turn_check_points);
    std::vector<double> walls(alternatives.size());
    detail::for_each_index(alternatives.size(), params.threads, [&](std::size_t i) {
      const Similarity2 refined = refine_icp(points, edges.dest_lookup, alternatives[i], refinement);
      const auto [forward, reverse] = overlap_wall_agreements(source_fine, dest_fine, edges, refined, params.wall_inlier_distance_m);
      walls[i] = std::max(forward, reverse);
    });
    const double answer = std::max(result.evidence.forward_wall_agreement, result.evidence.reverse_wall_agreement);
    result.evidence.turn_margin = answer - *std::max_element(walls.begin(), walls.end());
  }

  /// Margins of the best finalist (by the finalists' score) over the best clearly different one and
  /// the best mirrored one.
  void compute_margins(const AreaRaster& source_fine, const AreaRaster& dest_fine,
                       const std::vector<detail::ScoredTransform>& finalists, MatchResult& result) const {
    const Similarity2& best = finalists.front().T;
    // Compare like with like: the finalists' own score in our selection; IoU for the paper's,
    // whose Σ OP is not comparable between transforms of different clusters.
    const double best_iou = params.selection == Selection::whole_map ? finalists.front().score
                                                                     : free_space_iou(source_fine, dest_fine, best);
    double rival_different = -1.0, rival_mirrored = -1.0;
    const Eigen::Vector2d centroid = centroid_of(source_fine);
    for (std::size_t i = 1; i < finalists.size(); ++i) {
      const Similarity2& T = finalists[i].T;
      const double iou = params.selection == Selection::whole_map ? finalists[i].score
                                                                  : free_space_iou(source_fine, dest_fine, T);
      if (T.reflected != best.reflected) rival_mirrored = std::max(rival_mirrored, iou);
      else if (different(best, T, centroid)) rival_different = std::max(rival_different, iou);
    }
    if (rival_different >= 0.0) result.margin_different = best_iou - rival_different;
    if (params.allow_reflection && rival_mirrored >= 0.0) result.margin_mirrored = best_iou - rival_mirrored;
    double confidence = best_iou;
    if (!std::isnan(result.margin_different)) confidence = std::min(confidence, result.margin_different);
    if (!std::isnan(result.margin_mirrored)) confidence = std::min(confidence, result.margin_mirrored);
    result.confidence = confidence;
  }
};

/// The paper's matcher as written (see `MatcherParams::paper()`).
class PaperMatcher : public Matcher<VoronoiSegmenter, PaperFeatures, PaperWeights, AngularClusterer> {
 public:
  PaperMatcher() : Matcher(MatcherParams::paper()) {}
  explicit PaperMatcher(MatcherParams p) : Matcher(std::move(p)) {}
};

}  // namespace areamatch
