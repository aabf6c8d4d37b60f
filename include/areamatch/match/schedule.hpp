#pragma once
/// \file match/schedule.hpp
/// Where the matcher's work runs (`MatcherParams::threads`) and how long it took, kept out of the
/// pipeline (matcher.hpp): a map segmented beside what its cells alone give, two maps made side
/// by side with the first one's match data built meanwhile, and the match data the maps lack
/// built on the threads there are. Every schedule gives the same result, bit for bit.

#include "../area_graph.hpp"
#include "../detail/parallel.hpp"
#include "../detail/timing.hpp"
#include "../error.hpp"
#include "../grid.hpp"
#include "../image.hpp"
#include "map_data.hpp"
#include "params.hpp"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <optional>
#include <type_traits>
#include <utility>

namespace areamatch {
namespace detail {

/// Runs `work()` and sets `seconds` to how long it took; returns what `work` returns.
template <class Work>
decltype(auto) timed(double& seconds, Work&& work) {
  const auto start = Clock::now();
  if constexpr (std::is_void_v<std::invoke_result_t<Work&>>) {
    work();
    seconds = seconds_since(start);
  } else {
    decltype(auto) out = work();
    seconds = seconds_since(start);
    return out;
  }
}

/// `segment(grid)`; with `params.threads` ≥ 2, builds what of the map's match data needs only the
/// cells (`grid_only_data`) into `from_grid` on a second thread meanwhile. Errors: the
/// segmentation's first, as on one thread. A grid the segmenter refuses outright is not scanned
/// beside it. The caller has validated `params`.
template <class Segment>
AreaGraph segment_beside_grid_data(const OccupancyGrid& grid, const MatcherParams& params, const Segment& segment,
                                   std::optional<GridOnlyData>& from_grid) {
  const long long cells = static_cast<long long>(grid.width()) * grid.height();
  if (resolved_threads(params.threads) < 2 || grid.empty() || cells > max_grid_cells) return segment(grid);
  AreaGraph graph;
  for_each_index(2, params.threads, [&](std::size_t i) {
    if (i == 0) graph = segment(grid);
    else from_grid = grid_only_data(grid, params);
  });
  return graph;
}

/// The match data of whichever of two maps was made first, built while the other is made.
template <class Data>
struct EarlyData {
  std::optional<Data> data;
  std::size_t side = 2;       ///< 0: the source's, 1: the destination's, 2: none
  double seconds = 0.0;       ///< building it
  Clock::time_point both_made;
  const Data* of(std::size_t i) const { return side == i ? &*data : nullptr; }
};

/// Makes maps 0 and 1 (`make_map(i)`) side by side on `params.threads`; with `build_early`, the
/// one made first gets `build(i)` (its match data, or nothing) while the other is still made.
template <class Data, class MakeMap, class Build>
EarlyData<Data> make_two_maps(const MatcherParams& params, bool build_early, const MakeMap& make_map, const Build& build) {
  EarlyData<Data> early;
  std::atomic<bool> one_made{false};
  Clock::time_point made_at[2];
  for_each_index(2, params.threads, [&](std::size_t i) {
    make_map(i);
    made_at[i] = Clock::now();
    if (!build_early || one_made.exchange(true)) return;  // the second map: the match builds its data
    early.data = build(i);
    if (!early.data) return;
    early.side = i;
    early.seconds = seconds_since(made_at[i]);
  });
  early.both_made = std::max(made_at[0], made_at[1]);
  return early;
}

/// The match data the two views lack, built on `params.threads`, then `then(source_data,
/// dest_data, threads)` (pairs, hypotheses, clusters) on the threads left: both built here, one
/// thread each; only the source, with threads to spare, its areas' part and then `then` on one
/// thread beside its cells' part (the edge lookup, the longest piece) on another; only the
/// destination, its two parts side by side. Returns the seconds spent building.
template <class Descriptors, class Features, class Then>
double build_missing_data(const MapView<Descriptors>& source_map, const MapView<Descriptors>& dest_map, const Features& features,
                          const MatcherParams& params, const GridOnlyData* source_grid_data,
                          std::optional<MapData<Descriptors>>& source_own, std::optional<MapData<Descriptors>>& dest_own,
                          const Then& then) {
  const AreaGraph& source = *source_map.graph;
  const AreaGraph& dest = *dest_map.graph;
  if (!source_map.data && dest_map.data && resolved_threads(params.threads) >= 2) {
    source_own.emplace();
    double part_s[2] = {0.0, 0.0};
    for_each_index(2, params.threads, [&](std::size_t part) {
      if (part == 1) {
        timed(part_s[1], [&] { build_edge_data(*source_own, *source_map.grid, source, params, false, source_grid_data); });
        return;
      }
      timed(part_s[0], [&] { build_area_data(*source_own, source, features, params); });
      then(*source_own, *dest_map.data, 1u);
    });
    return part_s[0] + part_s[1];
  }
  const auto start = Clock::now();
  if (!source_map.data && !dest_map.data) {
    for_each_index(2, params.threads, [&](std::size_t i) {
      if (i == 0) source_own = build_map_data(*source_map.grid, source, features, params, false, 1, source_grid_data);
      else dest_own = build_map_data(*dest_map.grid, dest, features, params, true);
    });
  } else if (!source_map.data) {
    source_own = build_map_data(*source_map.grid, source, features, params, false, params.threads, source_grid_data);
  } else if (!dest_map.data) {
    dest_own = build_map_data(*dest_map.grid, dest, features, params, true, params.threads);
  }
  const double built_s = source_own || dest_own ? seconds_since(start) : 0.0;
  then(source_map.data ? *source_map.data : *source_own, dest_map.data ? *dest_map.data : *dest_own, params.threads);
  return built_s;
}

}  // namespace detail
}  // namespace areamatch
