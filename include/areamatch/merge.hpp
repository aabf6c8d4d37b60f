#pragma once
/// \file merge.hpp
/// Several maps of one building in one frame: robots' SLAM maps, hand-held scans, old and new
/// maps, a floor plan.
///
/// \code
/// areamatch::Matcher<> matcher;
/// std::vector<areamatch::Matcher<>::PreparedMap> maps;
/// for (const auto& grid : grids) maps.push_back(matcher.prepare(grid));
/// const areamatch::MergeResult merged = areamatch::merge_maps(matcher, maps);
/// for (const auto& m : merged.maps) if (!m.placed) std::cerr << m.reason << "\n";
/// \endcode
///
/// The steps:
///  1. **Pairwise matches** between the prepared maps (`MergeStrategy`): each pair matched once,
///     the map with less free space onto the one with more (a partial map onto a fuller one is the
///     direction the matcher is built and calibrated for). Only accepted matches (`ok`) become
///     edges, weighted by their `p_correct`. Each accepted match is refined once more by ICP that
///     pairs a wall only with a wall facing the same way (`MergeParams::refine_same_side`): two
///     partial maps' rooms that only one of them entered otherwise pull it a wall's thickness off.
///  2. **Poses** by a weighted least-squares fit over all edges at once (merge/pose_graph.hpp):
///     the reference map (`MergeParams::reference`) fixes the frame. An edge the fit contradicts
///     (its anchors land more than `MergeParams::max_residual_m` apart both ways round) is dropped,
///     the worst first, and the fit repeated; so is an edge whose reflection disagrees with the
///     stronger edges'. Dropped edges are reported, not hidden.
///  3. **Unplaced maps**: a map joined to the reference by no edge is reported with the reason of
///     its best failed match — never dropped silently.
///  4. **Warps** (`MergeParams::non_rigid`): each placed map is bent onto the reference map's walls
///     (warp/fit.hpp) from its fitted pose, so that maps that bend differently lay their walls on
///     one line instead of side by side (merge/double_walls.hpp counts what is left doubled).
///     Parts of a map the reference did not see stay where its pose puts them: choose as the
///     reference the map that covers the building best (a floor plan, the fullest map).
///  5. **The merged map** (merge/fuse.hpp) in the reference map's world frame.

#include "detail/parallel.hpp"
#include "detail/timing.hpp"
#include "grid.hpp"
#include "merge/double_walls.hpp"
#include "merge/fuse.hpp"
#include "merge/matching.hpp"
#include "merge/params.hpp"
#include "merge/picture.hpp"
#include "merge/placement.hpp"
#include "merge/result.hpp"
#include "progress.hpp"
#include "transform.hpp"
#include "warp/fit.hpp"

#include <chrono>
#include <cstddef>
#include <vector>

namespace areamatch {
namespace detail {

/// Step 5: the merged grid of the placed maps (each laid by its warp when there is one) and its
/// doubled walls.
template <class Maps>
void fuse_placed_maps(const Maps& maps, const MergeParams& params, MergeResult& result) {
  std::vector<const OccupancyGrid*> grids;
  std::vector<Similarity2> poses;
  std::vector<WarpField> warps;
  for (std::size_t m = 0; m < maps.size(); ++m) {
    if (!result.maps[m].placed) continue;
    grids.push_back(&maps[m].grid());
    poses.push_back(result.maps[m].T_reference_map);
    if (params.non_rigid) {
      warps.push_back(result.maps[m].warp ? result.maps[m].warp->field : WarpField(result.maps[m].T_reference_map));
    }
  }
  result.merged = params.non_rigid ? fuse_warped_maps(grids, warps, params.fuse) : fuse_maps(grids, poses, params.fuse);
  result.double_walls = count_double_walls(result.merged, params.double_walls);
}

}  // namespace detail

/// Merges prepared maps (see the file comment). `matcher` is any `Matcher<...>` (its parameters
/// decide each match: `allow_reflection` lets a map be a mirror image of the others); the maps
/// must have been prepared by it. Throws `parameter_error` for fewer than two maps or bad
/// parameters; maps that cannot be placed are results (`MergedMap::placed == false`).
template <class MatcherType>
MergeResult merge_maps(const MatcherType& matcher, const std::vector<typename MatcherType::PreparedMap>& maps,
                       const MergeParams& params = {}) {
  const auto start = std::chrono::steady_clock::now();
  params.validate(maps.size());
  MergeResult result;
  result.reference = params.reference;

  // 1. Pairwise matches. The merge reports its own stages (the matcher's `progress`); the
  //    matches, run side by side, report none of theirs.
  MatcherType quiet = matcher;
  quiet.progress = nullptr;
  detail::SerialProgress progress(matcher.progress);
  result.edges = detail::match_pairs(quiet, maps, params, progress);
  const std::vector<char> distrusted = detail::distrust_lone_matches(result.edges, maps.size(), matcher.params, params);
  const auto matched = std::chrono::steady_clock::now();
  const bool refine = params.refine_same_side && matcher.params.refine;
  if (refine) {
    std::vector<char> trusted(result.edges.size(), 0);
    for (std::size_t e = 0; e < result.edges.size(); ++e) trusted[e] = result.edges[e].match.ok && !distrusted[e];
    detail::refine_edges_same_side(matcher, maps, result.edges, trusted, params.threads);
  }
  const auto refined = std::chrono::steady_clock::now();

  // 2–3. Poses over the trusted accepted edges, then each map's pose or why it has none.
  progress("poses");
  const PoseFit fit = detail::fit_merge_poses(maps, params, result.edges, distrusted);
  detail::place_maps(maps, params, fit, result);
  const auto fitted = std::chrono::steady_clock::now();

  // 4. Each placed map bent onto the reference's walls, each on its own (any thread count gives
  //    the same warps).
  if (params.non_rigid) {
    progress("warp");
    const OccupancyGrid& reference_grid = maps[params.reference].grid();
    detail::for_each_index(maps.size(), params.threads, [&](std::size_t m) {
      if (m == params.reference || !result.maps[m].placed) return;
      result.maps[m].warp = fit_warp(maps[m].grid(), reference_grid, result.maps[m].T_reference_map, params.warp);
    });
  }
  const auto warped = std::chrono::steady_clock::now();

  // 5. The merged grid of the placed maps.
  progress("fuse");
  if (params.build_merged_map) detail::fuse_placed_maps(maps, params, result);
  const auto end = std::chrono::steady_clock::now();
  result.timings.matching_s = detail::seconds_between(start, matched);
  result.timings.refine_s = refine ? detail::seconds_between(matched, refined) : 0.0;
  result.timings.fit_s = detail::seconds_between(refined, fitted);
  result.timings.warp_s = detail::seconds_between(fitted, warped);
  result.timings.fuse_s = detail::seconds_between(warped, end);
  result.timings.total_s = detail::seconds_between(start, end);
  return result;
}

}  // namespace areamatch
