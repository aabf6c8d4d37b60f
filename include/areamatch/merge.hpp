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

#include "detail/format.hpp"
#include "detail/parallel.hpp"
#include "detail/timing.hpp"
#include "error.hpp"
#include "grid.hpp"
#include "match/acceptance.hpp"
#include "match/map_data.hpp"
#include "match/params.hpp"
#include "match/refine.hpp"
#include "match/result.hpp"
#include "progress.hpp"
#include "merge/double_walls.hpp"
#include "merge/fuse.hpp"
#include "merge/pose_graph.hpp"
#include "transform.hpp"
#include "warp/fit.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace areamatch {

/// Which pairs of maps are matched.
enum class MergeStrategy {
  all_pairs,        ///< every pair: loops of matches check each other (the default)
  until_connected   ///< a pair only while its two maps are not yet joined by accepted matches:
                    ///< fewer matches (N − 1 at best), no loop checks
};

/// Parameters of `merge_maps`.
struct MergeParams {
  /// The map whose world frame is the merged frame (index into the maps).
  std::size_t reference = 0;
  MergeStrategy strategy = MergeStrategy::all_pairs;
  /// An accepted match whose anchors land further apart than this (RMS, metres) under the fitted
  /// poses is contradicted by the others and dropped. 1 m: above what right matches leave on
  /// bending hand-held scans (0.1–0.5 m, their ground truth itself is good to ~0.3 m) and below
  /// the smallest wrong answer that matters, a slide by one room (≥ 2.5 m).
  double max_residual_m = 1.0;
  /// A map joined to the others by one accepted match only, and that accepted by the calibrated
  /// model alone (not through the agreement gate: `MatcherParams::min_agreement`,
  /// `gate_max_lower_walls`), must reach this p_correct:
  /// nothing else corroborates it, and a merge tries every pair, so one false accept would place
  /// a map of another building. 0.9: the model-alone threshold of the decision until 2026-12-01
  /// (its cross-validated false accepts 5 of 3567). In the F5 merge every scan has at least five
  /// accepted matches; an apartment scan added to it had one, at 0.814 (docs/merging.md).
  double lone_match_min_p_correct = 0.9;
  /// How the merged grid is made (its resolution: the finest map's by default).
  FuseParams fuse;
  /// Threads matching pairs at once (`all_pairs` only; 0: one per hardware thread). The results
  /// are the same, bit for bit, for any count: each pair's match lands in its own place.
  unsigned threads = 1;
  /// Refine each accepted match before the pose fit (when the matcher refines at all) by ICP from
  /// its transform with the matcher's last (smallest) gate, pairing each wall point with the
  /// nearest wall facing the same way (`RefineParams::same_side_only`). The matcher's ICP pairs nearest points, and where one
  /// partial map entered a room the other did not, that room's side of a wall is pulled onto the
  /// other side: N = 2 generated merges placed maps up to 0.13 m off (0.013 m with this).
  bool refine_same_side = true;
  /// Bend each placed map onto the reference's walls before fusing (step 4 of the file comment);
  /// false: each map is laid by its rigid pose alone.
  bool non_rigid = false;
  /// The warps' settings (`non_rigid`).
  WarpParams warp;
  /// How the merged map's doubled walls are counted (`MergeResult::double_walls`).
  DoubleWallParams double_walls;
  /// Build the merged grid (false: poses only).
  bool build_merged_map = true;
  /// The maps' names in messages (e.g. their paths); "map i" when empty.
  std::vector<std::string> names;

  void validate(std::size_t map_count) const {
    if (map_count < 2) throw parameter_error("merging needs at least two maps, got " + std::to_string(map_count));
    if (reference >= map_count) {
      throw parameter_error("MergeParams::reference is " + std::to_string(reference) + " but there are only " +
                            std::to_string(map_count) + " maps");
    }
    detail::require_positive(max_residual_m, "MergeParams::max_residual_m");
    if (!(lone_match_min_p_correct >= 0.0 && lone_match_min_p_correct <= 1.0)) {
      throw parameter_error("MergeParams::lone_match_min_p_correct must be in [0, 1]");
    }
    if (!names.empty() && names.size() != map_count) throw parameter_error("MergeParams::names: one name per map, or none");
    fuse.validate();
    if (non_rigid) warp.validate();
    double_walls.validate();
  }
  std::string name(std::size_t i) const { return names.empty() ? "map " + std::to_string(i) : names[i]; }
};

/// One pairwise match of the merge.
struct MergeEdge {
  std::size_t source = 0;   ///< index of the map matched onto `dest`
  std::size_t dest = 0;
  MatchResult match;
  /// The transform the pose fit uses: `match.T_dest_source`, refined when accepted
  /// (`MergeParams::refine_same_side`).
  Similarity2 T_dest_source;
  /// Whether the edge took part in the final pose fit (accepted and not contradicted).
  bool used = false;
  /// Why not used: the match's rejection reason, or the contradiction; empty when used.
  std::string note;
  /// RMS distance (m) between its anchors laid both ways round under the final poses; NaN when
  /// the edge is not used.
  double residual_m = std::numeric_limits<double>::quiet_NaN();
};

/// Where one map ended up.
struct MergedMap {
  bool placed = false;
  std::string reason;              ///< why not placed (empty when placed)
  Similarity2 T_reference_map;     ///< this map's world → the reference map's world
  PixelTransform pixel_transform = PixelTransform::Zero();  ///< this map's pixel → the reference's pixel
  /// RMS of the residuals of the used edges that touch it (0 when only tree edges place it, NaN
  /// when not placed).
  double residual_m = std::numeric_limits<double>::quiet_NaN();
  /// With `MergeParams::non_rigid`: the warp that lays this map on the reference (its rigid part
  /// is `T_reference_map`) and how well it lays the walls; none for the reference, a map not
  /// placed, or a rigid merge.
  std::optional<WarpResult> warp;
};

/// Wall-clock seconds per step.
struct MergeTimings {
  double matching_s = 0.0;
  double refine_s = 0.0;  ///< `MergeParams::refine_same_side`
  double fit_s = 0.0;
  double warp_s = 0.0;  ///< `MergeParams::non_rigid`
  double fuse_s = 0.0;
  double total_s = 0.0;
};

struct MergeResult {
  bool ok = false;                  ///< every map placed
  std::size_t reference = 0;
  std::vector<MergedMap> maps;      ///< in the order given
  std::vector<MergeEdge> edges;     ///< every match run, in the order run
  /// The fused map in the reference's world frame (empty when not built or nothing placed but the
  /// reference; see merge/fuse.hpp).
  OccupancyGrid merged;
  /// The merged map's walls and how many of them are doubled (merge/double_walls.hpp): what a
  /// non-rigid merge should leave fewer of.
  DoubleWalls double_walls;
  MergeTimings timings;
};

namespace detail {

/// Points of the source's world frame where a match is grounded: the centroids of its matched
/// areas and the corners of their bounding box (so the fit sees the match's lever arm).
inline std::vector<Eigen::Vector2d> match_anchors(const AreaGraph& source_graph, const MatchResult& match,
                                                  const OccupancyGrid& source_grid) {
  std::vector<Eigen::Vector2d> anchors;
  Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), high = -low;
  for (const auto& pair : match.matched_areas) {
    if (pair.source < 0 || static_cast<std::size_t>(pair.source) >= source_graph.areas.size()) continue;
    const Area& area = source_graph.areas[static_cast<std::size_t>(pair.source)];
    anchors.push_back(area.centroid);
    for (const auto& p : area.convex_hull.outer()) {
      low = low.cwiseMin(Eigen::Vector2d(p.x(), p.y()));
      high = high.cwiseMax(Eigen::Vector2d(p.x(), p.y()));
    }
  }
  if (anchors.empty() || !((high - low).minCoeff() > 0.0)) {  // no areas to go by: the whole map
    low = high = source_grid.pixel_to_world({-0.5, -0.5});
    for (const auto& corner : grid_corners(source_grid)) {
      low = low.cwiseMin(corner);
      high = high.cwiseMax(corner);
    }
  }
  for (const auto& corner : {low, Eigen::Vector2d(high.x(), low.y()), high, Eigen::Vector2d(low.x(), high.y())}) {
    anchors.push_back(corner);
  }
  return anchors;
}

inline double free_area_m2(const OccupancyGrid& grid) {
  return static_cast<double>(grid.count().free) * grid.resolution() * grid.resolution();
}

/// Refines the accepted, trusted edges' transforms (`MergeParams::refine_same_side`); each map's
/// facing edges are built once (`Matcher::facing_edges`, reaching the refinement's gate: no pair
/// is ever further), and only for maps such an edge joins.
template <class MatcherType, class Maps>
void refine_edges_same_side(const MatcherType& matcher, const Maps& maps, std::vector<MergeEdge>& edges,
                            const std::vector<char>& trusted, unsigned threads) {
  std::vector<char> needed(maps.size(), 0);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    if (trusted[e]) needed[edges[e].source] = needed[edges[e].dest] = 1;
  }
  RefineParams refinement = matcher.params.refinement;
  refinement.same_side_only = true;
  refinement.estimate_scale = false;
  refinement.gates_m = {refinement.gates_m.back()};  // the match is near: only the last gate's pairs
  std::vector<FacingEdges> facing(maps.size());
  for_each_index(maps.size(), threads, [&](std::size_t m) {
    if (needed[m]) facing[m] = matcher.facing_edges(maps[m], refinement.gates_m.front());
  });
  for_each_index(edges.size(), threads, [&](std::size_t e) {
    MergeEdge& edge = edges[e];
    if (!trusted[e]) return;
    const FacingEdges& source = facing[edge.source];
    edge.T_dest_source = refine_icp(source.points, facing[edge.dest].lookup, edge.T_dest_source, refinement, &source.sides);
  });
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
  const std::size_t n = maps.size();
  MergeResult result;
  result.reference = params.reference;

  // 1. Pairwise matches, the map with less free space as the source. The reference's pairs first,
  //    so that `until_connected` joins maps to it directly where it can.
  std::vector<double> free_m2(n);
  for (std::size_t i = 0; i < n; ++i) free_m2[i] = detail::free_area_m2(maps[i].grid());
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t i = 0; i < n; ++i) {
    if (i != params.reference) pairs.emplace_back(std::min(i, params.reference), std::max(i, params.reference));
  }
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      if (i != params.reference && j != params.reference) pairs.emplace_back(i, j);
    }
  }
  std::vector<std::size_t> component(n);  // of accepted matches, for until_connected
  for (std::size_t i = 0; i < n; ++i) component[i] = i;
  auto root = [&](std::size_t i) {
    while (component[i] != i) i = component[i] = component[component[i]];
    return i;
  };
  auto make_edge = [&](std::size_t i, std::size_t j) {
    MergeEdge edge;
    const bool i_is_source = free_m2[i] < free_m2[j] || (free_m2[i] == free_m2[j] && i > j);
    edge.source = i_is_source ? i : j;
    edge.dest = i_is_source ? j : i;
    return edge;
  };
  // The merge reports its own stages (the matcher's `progress`); the matches, run side by side,
  // report none of theirs.
  MatcherType quiet = matcher;
  quiet.progress = nullptr;
  detail::SerialProgress progress(matcher.progress);
  progress("match", 0, pairs.size());
  if (params.strategy == MergeStrategy::until_connected) {
    for (const auto& [i, j] : pairs) {
      if (root(i) != root(j)) {  // else already joined: the pair is done without a match
        MergeEdge edge = make_edge(i, j);
        edge.match = quiet.match(maps[edge.source], maps[edge.dest]);
        if (edge.match.ok) component[root(i)] = root(j);
        result.edges.push_back(std::move(edge));
      }
      progress.step("match", pairs.size());
    }
  } else {
    for (const auto& [i, j] : pairs) result.edges.push_back(make_edge(i, j));
    detail::for_each_index(result.edges.size(), params.threads, [&](std::size_t e) {
      MergeEdge& edge = result.edges[e];
      edge.match = quiet.match(maps[edge.source], maps[edge.dest]);
      progress.step("match", pairs.size());
    });
  }
  for (auto& edge : result.edges) {
    edge.T_dest_source = edge.match.T_dest_source;
    if (!edge.match.ok) edge.note = "rejected: " + edge.match.reason;
  }
  // A lone match accepted by the model alone below lone_match_min_p_correct is not trusted.
  std::vector<std::size_t> accepted_matches(n, 0);
  for (const auto& edge : result.edges) {
    if (!edge.match.ok) continue;
    ++accepted_matches[edge.source];
    ++accepted_matches[edge.dest];
  }
  std::vector<char> distrusted(result.edges.size(), 0);
  for (std::size_t e = 0; e < result.edges.size(); ++e) {
    MergeEdge& edge = result.edges[e];
    const bool lone = accepted_matches[edge.source] == 1 || accepted_matches[edge.dest] == 1;
    if (!edge.match.ok || !lone || detail::passes_agreement_gate(edge.match.evidence, matcher.params) ||
        edge.match.p_correct >= params.lone_match_min_p_correct) {
      continue;
    }
    distrusted[e] = 1;
    edge.note = "accepted by the model alone (p_correct " + detail::format_fixed(edge.match.p_correct, 3) +
                ", agreement " + detail::format_fixed(edge.match.evidence.agreement, 3) +
                "), but the only accepted match of its map: below MergeParams::lone_match_min_p_correct " +
                detail::format_double(params.lone_match_min_p_correct) + " it is not trusted alone";
  }
  const auto matched = std::chrono::steady_clock::now();
  const bool refine = params.refine_same_side && matcher.params.refine;
  if (refine) {
    std::vector<char> trusted(result.edges.size(), 0);
    for (std::size_t e = 0; e < result.edges.size(); ++e) trusted[e] = result.edges[e].match.ok && !distrusted[e];
    detail::refine_edges_same_side(matcher, maps, result.edges, trusted, params.threads);
  }
  const auto refined = std::chrono::steady_clock::now();

  // 2. Poses over the accepted edges; drop the contradicted ones, the worst first.
  progress("poses");
  std::vector<PoseConstraint> constraints;
  std::vector<std::size_t> edge_of;  // constraint → edge
  for (std::size_t e = 0; e < result.edges.size(); ++e) {
    const MergeEdge& edge = result.edges[e];
    if (!edge.match.ok || distrusted[e]) continue;
    PoseConstraint c;
    c.source = edge.source;
    c.dest = edge.dest;
    c.T_dest_source = edge.T_dest_source;
    c.anchors = detail::match_anchors(maps[edge.source].graph(), edge.match, maps[edge.source].grid());
    c.weight = std::max(edge.match.p_correct, 0.01);
    constraints.push_back(std::move(c));
    edge_of.push_back(e);
  }
  std::vector<bool> active(constraints.size(), true);
  PoseFit fit;
  for (;;) {
    fit = fit_poses(n, params.reference, constraints, active);
    bool changed = false;
    for (std::size_t c = 0; c < constraints.size(); ++c) {
      if (fit.mirror_conflict[c]) {
        active[c] = false;
        result.edges[edge_of[c]].note = "contradicted: its reflection disagrees with the stronger matches'";
        changed = true;
      }
    }
    if (changed) continue;
    std::size_t worst = constraints.size();
    for (std::size_t c = 0; c < constraints.size(); ++c) {
      if (active[c] && std::isfinite(fit.residual_m[c]) && fit.residual_m[c] > params.max_residual_m &&
          (worst == constraints.size() || fit.residual_m[c] > fit.residual_m[worst])) {
        worst = c;
      }
    }
    if (worst == constraints.size()) break;
    active[worst] = false;
    result.edges[edge_of[worst]].note = "contradicted by the other matches: its areas land " +
                                        detail::format_fixed(fit.residual_m[worst], 2) + " m apart under the fitted poses (limit " +
                                        detail::format_fixed(params.max_residual_m, 2) + " m)";
  }
  for (std::size_t c = 0; c < constraints.size(); ++c) {
    MergeEdge& edge = result.edges[edge_of[c]];
    edge.used = active[c] && std::isfinite(fit.residual_m[c]);
    if (edge.used) edge.residual_m = fit.residual_m[c];
    else if (edge.note.empty()) edge.note = "accepted, but joins maps not connected to the reference";
  }

  // 3. Each map's pose, or why it has none.
  result.maps.resize(n);
  const OccupancyGrid& reference_grid = maps[params.reference].grid();
  for (std::size_t m = 0; m < n; ++m) {
    MergedMap& out = result.maps[m];
    out.placed = fit.placed[m];
    if (out.placed) {
      out.T_reference_map = fit.T_reference_map[m];
      out.pixel_transform = to_pixel_transform(out.T_reference_map, maps[m].grid(), reference_grid);
      double sum = 0.0;
      std::size_t count = 0;
      for (const auto& edge : result.edges) {
        if (edge.used && (edge.source == m || edge.dest == m)) {
          sum += edge.residual_m * edge.residual_m;
          ++count;
        }
      }
      out.residual_m = count ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
      continue;
    }
    // Not placed: its best failed match says why.
    const MergeEdge* best = nullptr;
    bool accepted_any = false;
    for (const auto& edge : result.edges) {
      if (edge.source != m && edge.dest != m) continue;
      accepted_any = accepted_any || edge.match.ok;
      if (!best || edge.match.p_correct > best->match.p_correct) best = &edge;
    }
    if (!best) {
      out.reason = "not matched with any other map";
    } else {
      const std::string other = params.name(best->source == m ? best->dest : best->source);
      out.reason = accepted_any ? "its accepted matches do not join it to the reference " + params.name(params.reference) +
                                      "; the best, with " + other + " (p_correct " + detail::format_fixed(best->match.p_correct, 3) +
                                      "): " + (best->used ? std::string("joins maps not connected to the reference") : best->note)
                                : "no accepted match with any other map; the best, with " + other + " (p_correct " +
                                      detail::format_fixed(best->match.p_correct, 3) + "), was rejected: " + best->match.reason;
    }
  }
  result.ok = std::all_of(result.maps.begin(), result.maps.end(), [](const MergedMap& m) { return m.placed; });
  const auto fitted = std::chrono::steady_clock::now();

  // 4. Each placed map bent onto the reference's walls, each on its own (any thread count gives
  //    the same warps).
  if (params.non_rigid) {
    progress("warp");
    detail::for_each_index(n, params.threads, [&](std::size_t m) {
      if (m == params.reference || !result.maps[m].placed) return;
      result.maps[m].warp = fit_warp(maps[m].grid(), reference_grid, result.maps[m].T_reference_map, params.warp);
    });
  }
  const auto warped = std::chrono::steady_clock::now();

  // 5. The merged grid of the placed maps.
  progress("fuse");
  if (params.build_merged_map) {
    std::vector<const OccupancyGrid*> grids;
    std::vector<Similarity2> poses;
    std::vector<WarpField> warps;
    for (std::size_t m = 0; m < n; ++m) {
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
