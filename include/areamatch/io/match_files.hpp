#pragma once
/// \file io/match_files.hpp
/// Matching two maps end to end (files, or grids in memory): load both, segment each with its own door width, match,
/// and time every step. What `areamatch match` and `areamatch eval` run for one pair.
///
/// \code
/// areamatch::MapPairOptions options;
/// options.allow_reflection = true;
/// const areamatch::MapPairRun run = areamatch::match_map_files("robot.yaml", "layout.yaml", options);
/// if (run.result.ok) std::cout << run.result.T_dest_source.rotation << "\n";
///
/// // The same with a matcher of your own policies (its segmenter and parameters are used):
/// areamatch::Matcher<areamatch::VoronoiSegmenter, MyFeatures> mine;
/// const auto run2 = areamatch::match_map_files(mine, "robot.yaml", "layout.yaml", options);
/// \endcode

#include "../detail/parallel.hpp"
#include "../detail/timing.hpp"
#include "../io.hpp"
#include "../matcher.hpp"
#include "../parameters.hpp"
#include "../segment/voronoi_segmenter.hpp"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <optional>
#include <string>
#include <type_traits>

namespace areamatch {

/// How to load, segment and match one pair of map files. Unset fields keep the library defaults.
struct MapPairOptions {
  LoadOptions source_load;                    ///< e.g. a resolution for a bare image
  LoadOptions dest_load;
  std::optional<double> source_door_width_m;  ///< `VoronoiSegmenter` door width of the source
  std::optional<double> dest_door_width_m;
  bool paper = false;                         ///< `PaperMatcher` instead of `Matcher<>` (overloads without a matcher)
  /// Also try the source's mirror image. Unset: the matcher's own (`MatcherParams::allow_reflection`,
  /// false for the overloads without a matcher).
  std::optional<bool> allow_reflection;
  bool estimate_scale = false;                ///< the source's resolution is unknown (match/scale/scale.hpp)
  /// Load and segment the two maps side by side on this many threads (and build their match data
  /// so: `MatcherParams::threads`); the same result for any count. Unset: the matcher's own (1 for
  /// the overloads without a matcher).
  std::optional<unsigned> threads;
  /// Any settings of the table (parameters.hpp), in order, e.g. `{"k", "5"}`,
  /// `{"decision.min_agreement", "0.9"}`, `{"refinement.gates_m", "2,1,0.5"}`: a patch of the
  /// matcher's parameters, applied after `allow_reflection` and `threads`; the door widths apply
  /// last. A segmenter setting needs `VoronoiSegmenter`.
  std::vector<ParameterSetting> settings;
};

/// The thread count the `areamatch` program and the Python module use unless told (`--threads`,
/// `threads=`): a pair's two maps loaded and segmented side by side, two pairs of a merge at once.
/// The library's own default stays one thread (`MapPairOptions::threads`, `MatcherParams::threads`):
/// a program that embeds it chooses. Results are the same for any count.
inline constexpr unsigned default_program_threads = 2;

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

/// The matcher's segmenter with `door_width_m` applied. Only `VoronoiSegmenter` has a door
/// width; for another segmenter a door width is refused rather than ignored.
template <class Segmenter>
Segmenter segmenter_with_door(Segmenter segmenter, const std::optional<double>& door_width_m) {
  if (door_width_m) {
    if constexpr (std::is_same_v<Segmenter, VoronoiSegmenter>) {
      segmenter.params.with_door_width(*door_width_m);
    } else {
      throw parameter_error("MapPairOptions door width: only VoronoiSegmenter has one; set the parameters of your own segmenter instead");
    }
  }
  return segmenter;
}

/// Sets what the named fields of `options` ask of the matcher's parameters (the load, door-width,
/// `paper` and `settings` options are the caller's).
inline void apply_match_options(MatcherParams& params, const MapPairOptions& options) {
  // Only what is set: a matcher's own settings are kept otherwise (they were overwritten by the
  // defaults of these two until 2026-12-05).
  if (options.allow_reflection) params.allow_reflection = *options.allow_reflection;
  if (options.threads) params.threads = *options.threads;
}

/// `matcher` with what `options` asks of its parameters, then `options.settings`
/// (`set_parameters`: a segmenter setting only where the segmenter is `VoronoiSegmenter`).
template <class M>
M configured_matcher(const M& matcher, const MapPairOptions& options) {
  M out = matcher;
  apply_match_options(out.params, options);
  set_parameters(out, options.settings);
  return out;
}

/// One end-to-end run: `get_grid(0)` (the source) and `get_grid(1)` (the destination) are
/// fetched and segmented each on its own (side by side with `threads` ≥ 2, the map segmented
/// first having its match data built meanwhile: `Matcher::match_side_by_side`; with
/// estimate_scale the source is segmented at each candidate scale, inside the match), then
/// matched. `result.timings.total_s` counts from the first fetch. `matcher` is copied: its
/// segmenter (with the door widths) segments both maps, its parameters with `options` applied
/// match them.
template <class M, class GetGrid>
MapPairRun run_map_pair(const M& matcher, const MapPairOptions& options, GetGrid&& get_grid) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  MapPairRun run;
  double segment_s[2] = {0.0, 0.0};
  SerialProgress progress(matcher.progress);  // the two maps are made on two threads
  M configured = configured_matcher(matcher, options);
  auto make_map = [&](std::size_t i) {
    const bool source = i == 0;
    OccupancyGrid& grid = source ? run.source : run.dest;
    progress("load");
    grid = get_grid(i);
    if (source && options.estimate_scale) return;
    progress("segment");
    const auto segment_start = clock::now();
    (source ? run.source_graph : run.dest_graph) =
        segmenter_with_door(configured.segmenter, source ? options.source_door_width_m : options.dest_door_width_m).segment(grid);
    segment_s[i] = seconds_since(segment_start);
  };
  if (options.estimate_scale) {
    for_each_index(2, configured.params.threads, make_map);
    const auto match_start = clock::now();
    configured.params.estimate_scale = true;
    configured.segmenter = segmenter_with_door(configured.segmenter, options.source_door_width_m);
    run.result = configured.match_estimating_scale(run.source, run.dest, run.dest_graph, &run.source_graph);
    // segment_source_s from the match, which segments the source
    run.result.timings.match_s = seconds_since(match_start) - run.result.timings.segment_source_s;
  } else {
    run.result = configured.match_side_by_side(run.source, run.source_graph, run.dest, run.dest_graph, make_map);
    run.result.timings.segment_source_s = segment_s[0];
  }
  MatchTimings& t = run.result.timings;
  t.segment_dest_s = segment_s[1];
  t.total_s = seconds_since(start);
  return run;
}

}  // namespace detail

/// Loads, segments and matches `source_path` onto `dest_path` with `matcher` (any `Matcher<...>`:
/// its segmenter and parameters, then what `options` sets; `options.paper` is not used). Throws
/// what `load_map` and the segmenter throw on bad input, `format_error` for a map without free
/// cells, and `parameter_error` for a door width
/// with a segmenter other than `VoronoiSegmenter`; "no acceptable match" is `result.ok == false`.
template <class M>
MapPairRun match_map_files(const M& matcher, const std::string& source_path, const std::string& dest_path,
                           const MapPairOptions& options = {}) {
  return detail::run_map_pair(matcher, options, [&](std::size_t i) {
    const std::string& path = i == 0 ? source_path : dest_path;
    OccupancyGrid grid = load_map(path, i == 0 ? options.source_load : options.dest_load);
    // A map without free space (all unknown, all wall, one pixel) is bad input, not a pair that
    // does not match.
    if (std::find(grid.cells().begin(), grid.cells().end(), CellState::free) == grid.cells().end()) {
      throw format_error(path + ": the map has no free cells (" + std::to_string(grid.width()) + " x " + std::to_string(grid.height()) +
                         " cells, all unknown or occupied): nothing to match; check the image and its free_thresh / negate");
    }
    return grid;
  });
}

/// Segments and matches two grids already in memory with `matcher`, exactly as `match_map_files`
/// does for two files (the load options are not used): the same maps give the same result either way.
template <class M>
MapPairRun match_grids(const M& matcher, const OccupancyGrid& source, const OccupancyGrid& dest,
                       const MapPairOptions& options = {}) {
  return detail::run_map_pair(matcher, options, [&](std::size_t i) { return i == 0 ? source : dest; });
}

namespace detail {

/// `run(matcher)` with the matcher of the overloads that take none: `PaperMatcher` when
/// `options.paper`, else the default `Matcher<>` (a caller may set it up first, e.g. its
/// `progress`).
template <class Run>
MapPairRun with_default_matcher(const MapPairOptions& options, Run&& run) {
  return options.paper ? run(PaperMatcher{}) : run(Matcher<>{});
}

}  // namespace detail

/// `match_map_files` with the default `Matcher<>`, or `PaperMatcher` when `options.paper`.
inline MapPairRun match_map_files(const std::string& source_path, const std::string& dest_path,
                                  const MapPairOptions& options = {}) {
  return detail::with_default_matcher(options, [&](const auto& matcher) { return match_map_files(matcher, source_path, dest_path, options); });
}

/// `match_grids` with the default `Matcher<>`, or `PaperMatcher` when `options.paper`.
inline MapPairRun match_grids(const OccupancyGrid& source, const OccupancyGrid& dest, const MapPairOptions& options = {}) {
  return detail::with_default_matcher(options, [&](const auto& matcher) { return match_grids(matcher, source, dest, options); });
}

}  // namespace areamatch
