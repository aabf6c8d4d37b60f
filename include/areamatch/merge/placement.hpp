#pragma once
/// \file merge/placement.hpp
/// Steps 2–3 of `merge_maps` (merge.hpp): the poses fitted over the trusted accepted matches, the
/// contradicted ones dropped (the worst first), and each map's pose or why it has none.

#include "../area_graph.hpp"
#include "../detail/format.hpp"
#include "../grid.hpp"
#include "../match/result.hpp"
#include "../transform.hpp"
#include "params.hpp"
#include "pose_graph.hpp"
#include "result.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace areamatch {
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

/// The poses over the accepted, trusted edges: fitted, then refitted without each contradicted
/// edge — first those whose reflection disagrees, then the one with the largest residual above
/// `MergeParams::max_residual_m` — until none is left. Sets each edge's `used`, `residual_m` and
/// note.
template <class Maps>
PoseFit fit_merge_poses(const Maps& maps, const MergeParams& params, std::vector<MergeEdge>& edges,
                        const std::vector<char>& distrusted) {
  std::vector<PoseConstraint> constraints;
  std::vector<std::size_t> edge_of;  // constraint → edge
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const MergeEdge& edge = edges[e];
    if (!edge.match.ok || distrusted[e]) continue;
    PoseConstraint c;
    c.source = edge.source;
    c.dest = edge.dest;
    c.T_dest_source = edge.T_dest_source;
    c.anchors = match_anchors(maps[edge.source].graph(), edge.match, maps[edge.source].grid());
    c.weight = std::max(edge.match.p_correct, 0.01);
    constraints.push_back(std::move(c));
    edge_of.push_back(e);
  }
  std::vector<bool> active(constraints.size(), true);
  PoseFit fit;
  for (;;) {
    fit = fit_poses(maps.size(), params.reference, constraints, active);
    bool changed = false;
    for (std::size_t c = 0; c < constraints.size(); ++c) {
      if (fit.mirror_conflict[c]) {
        active[c] = false;
        edges[edge_of[c]].note = "contradicted: its reflection disagrees with the stronger matches'";
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
    edges[edge_of[worst]].note = "contradicted by the other matches: its areas land " + format_fixed(fit.residual_m[worst], 2) +
                                 " m apart under the fitted poses (limit " + format_fixed(params.max_residual_m, 2) + " m)";
  }
  for (std::size_t c = 0; c < constraints.size(); ++c) {
    MergeEdge& edge = edges[edge_of[c]];
    edge.used = active[c] && std::isfinite(fit.residual_m[c]);
    if (edge.used) edge.residual_m = fit.residual_m[c];
    else if (edge.note.empty()) edge.note = "accepted, but joins maps not connected to the reference";
  }
  return fit;
}

/// Why map `m` was not placed: its best failed match says.
inline std::string unplaced_reason(std::size_t m, const std::vector<MergeEdge>& edges, const MergeParams& params) {
  const MergeEdge* best = nullptr;
  bool accepted_any = false;
  for (const auto& edge : edges) {
    if (edge.source != m && edge.dest != m) continue;
    accepted_any = accepted_any || edge.match.ok;
    if (!best || edge.match.p_correct > best->match.p_correct) best = &edge;
  }
  if (!best) return "not matched with any other map";
  const std::string other = params.name(best->source == m ? best->dest : best->source);
  return accepted_any ? "its accepted matches do not join it to the reference " + params.name(params.reference) +
                            "; the best, with " + other + " (p_correct " + format_fixed(best->match.p_correct, 3) +
                            "): " + (best->used ? std::string("joins maps not connected to the reference") : best->note)
                      : "no accepted match with any other map; the best, with " + other + " (p_correct " +
                            format_fixed(best->match.p_correct, 3) + "), was rejected: " + best->match.reason;
}

/// Each map's pose in the reference's frame (and the RMS residual of its used edges), or why it
/// has none; `result.ok` when every map is placed.
template <class Maps>
void place_maps(const Maps& maps, const MergeParams& params, const PoseFit& fit, MergeResult& result) {
  const std::size_t n = maps.size();
  result.maps.resize(n);
  const OccupancyGrid& reference_grid = maps[params.reference].grid();
  for (std::size_t m = 0; m < n; ++m) {
    MergedMap& out = result.maps[m];
    out.placed = fit.placed[m];
    if (!out.placed) {
      out.reason = unplaced_reason(m, result.edges, params);
      continue;
    }
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
  }
  result.ok = std::all_of(result.maps.begin(), result.maps.end(), [](const MergedMap& m) { return m.placed; });
}

}  // namespace detail
}  // namespace areamatch
