#pragma once
/// \file io/match_files.hpp
/// Matching two map files end to end: load both, segment each with its own door width, match,
/// and time every step. What `areamatch match` and `areamatch eval` run for one pair.
///
/// \code
/// areamatch::MapPairOptions options;
/// options.allow_reflection = true;
/// const areamatch::MapPairRun run = areamatch::match_map_files("robot.yaml", "layout.yaml", options);
/// if (run.result.ok) std::cout << run.result.T_dest_source.rotation << "\n";
/// \endcode

#include "../io.hpp"
#include "../matcher.hpp"
#include "../segment/voronoi_segmenter.hpp"

#include <chrono>
#include <cstddef>
#include <optional>
#include <string>

namespace areamatch {

/// How to load, segment and match one pair of map files. Unset fields keep the library defaults.
struct MapPairOptions {
  LoadOptions source_load;                    ///< e.g. a resolution for a bare image
  LoadOptions dest_load;
  std::optional<double> source_door_width_m;  ///< `VoronoiSegmenter` door width of the source
  std::optional<double> dest_door_width_m;
  bool paper = false;                         ///< `PaperMatcher` instead of `Matcher<>`
  bool allow_reflection = false;              ///< also try the source's mirror image
  std::optional<std::size_t> k;               ///< mutual nearest neighbours per area
  std::optional<double> min_score;            ///< reject below this whole-map score
  std::optional<double> min_agreement;        ///< reject below this agreement (MatchEvidence)
  std::optional<double> min_p_correct;        ///< reject below this p_correct (match/decision.hpp)
  bool estimate_scale = false;                ///< the source's resolution is unknown (match/scale.hpp)
};

/// Everything one end-to-end run produced: the maps, their Area Graphs and the match, with
/// `result.timings` covering loading too (`total_s` = load + segment both + match). With
/// `estimate_scale`, `source_graph` is the source's graph at the estimated scale.
struct MapPairRun {
  OccupancyGrid source;
  OccupancyGrid dest;
  AreaGraph source_graph;
  AreaGraph dest_graph;
  MatchResult result;
};

namespace detail {

inline VoronoiSegmenter segmenter_with_door(const std::optional<double>& door_width_m) {
  VoronoiSegmenter segmenter;
  if (door_width_m) segmenter.params.with_door_width(*door_width_m);
  return segmenter;
}

template <class M>
MatchResult configured_match(M matcher, const MapPairOptions& options, MapPairRun& run) {
  matcher.params.allow_reflection = options.allow_reflection;
  if (options.k) matcher.params.k = *options.k;
  if (options.min_score) matcher.params.min_score = *options.min_score;
  if (options.min_agreement) matcher.params.min_agreement = *options.min_agreement;
  if (options.min_p_correct) matcher.params.decision.min_p_correct = *options.min_p_correct;
  if (options.estimate_scale) {
    matcher.params.estimate_scale = true;
    matcher.segmenter = segmenter_with_door(options.source_door_width_m);
    return matcher.match_estimating_scale(run.source, run.dest, run.dest_graph, &run.source_graph);
  }
  return matcher.match(run.source, run.source_graph, run.dest, run.dest_graph);
}

}  // namespace detail

/// Loads, segments and matches `source_path` onto `dest_path`. Throws what `load_map` and the
/// segmenter throw on bad input; "no acceptable match" is `result.ok == false`.
inline MapPairRun match_map_files(const std::string& source_path, const std::string& dest_path,
                                  const MapPairOptions& options = {}) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  MapPairRun run;
  run.source = load_map(source_path, options.source_load);
  run.dest = load_map(dest_path, options.dest_load);
  const auto source_start = clock::now();
  // With estimate_scale the source is segmented at each candidate scale, inside the match.
  if (!options.estimate_scale) run.source_graph = detail::segmenter_with_door(options.source_door_width_m).segment(run.source);
  const auto dest_start = clock::now();
  run.dest_graph = detail::segmenter_with_door(options.dest_door_width_m).segment(run.dest);
  const auto match_start = clock::now();
  run.result = options.paper ? detail::configured_match(PaperMatcher{}, options, run)
                             : detail::configured_match(Matcher<>{}, options, run);
  const auto end = clock::now();
  using seconds = std::chrono::duration<double>;
  MatchTimings& t = run.result.timings;
  t.segment_dest_s = seconds(match_start - dest_start).count();
  if (options.estimate_scale) {
    t.match_s = seconds(end - match_start).count() - t.segment_source_s;  // segment_source_s from the match
  } else {
    t.segment_source_s = seconds(dest_start - source_start).count();
    t.match_s = seconds(end - match_start).count();
  }
  t.total_s = seconds(end - start).count();
  return run;
}

}  // namespace areamatch
