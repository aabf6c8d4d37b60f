#pragma once
/// \file merge/matching.hpp
/// Step 1 of `merge_maps` (merge.hpp): which pairs are matched and in which direction, the
/// matches, the lone matches not trusted, and the same-side refinement of the trusted ones.

#include "../detail/disjoint_sets.hpp"
#include "../detail/format.hpp"
#include "../detail/parallel.hpp"
#include "../grid.hpp"
#include "../match/decision/acceptance.hpp"
#include "../match/map_data.hpp"
#include "../match/params.hpp"
#include "../match/verification/refine.hpp"
#include "../progress.hpp"
#include "params.hpp"
#include "result.hpp"

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace areamatch {
namespace detail {

inline double free_area_m2(const OccupancyGrid& grid) {
  return static_cast<double>(grid.count().free) * grid.resolution() * grid.resolution();
}

/// The pairs to match: the reference's first (so that `until_connected` joins maps to it directly
/// where it can), then the others in order.
inline std::vector<std::pair<std::size_t, std::size_t>> merge_pairs(std::size_t n, std::size_t reference) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t i = 0; i < n; ++i) {
    if (i != reference) pairs.emplace_back(std::min(i, reference), std::max(i, reference));
  }
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      if (i != reference && j != reference) pairs.emplace_back(i, j);
    }
  }
  return pairs;
}

/// Matches the pairs (`MergeParams::strategy`), each the map with less free space onto the other,
/// with `quiet` (the caller's matcher without its progress). Reports "match" (pairs done / all).
template <class MatcherType, class Maps>
std::vector<MergeEdge> match_pairs(const MatcherType& quiet, const Maps& maps, const MergeParams& params,
                                   SerialProgress& progress) {
  const std::size_t n = maps.size();
  std::vector<double> free_m2(n);
  for (std::size_t i = 0; i < n; ++i) free_m2[i] = free_area_m2(maps[i].grid());
  const auto pairs = merge_pairs(n, params.reference);
  auto make_edge = [&](std::size_t i, std::size_t j) {
    MergeEdge edge;
    const bool i_is_source = free_m2[i] < free_m2[j] || (free_m2[i] == free_m2[j] && i > j);
    edge.source = i_is_source ? i : j;
    edge.dest = i_is_source ? j : i;
    return edge;
  };
  std::vector<MergeEdge> edges;
  progress("match", 0, pairs.size());
  if (params.strategy == MergeStrategy::until_connected) {
    detail::DisjointSets joined(n);  // by accepted matches
    for (const auto& [i, j] : pairs) {
      if (joined.find(i) != joined.find(j)) {  // else already joined: the pair is done without a match
        MergeEdge edge = make_edge(i, j);
        edge.match = quiet.match(maps[edge.source], maps[edge.dest]);
        if (edge.match.ok) joined.join(i, j);
        edges.push_back(std::move(edge));
      }
      progress.step("match", pairs.size());
    }
  } else {
    for (const auto& [i, j] : pairs) edges.push_back(make_edge(i, j));
    for_each_index(edges.size(), params.threads, [&](std::size_t e) {
      edges[e].match = quiet.match(maps[edges[e].source], maps[edges[e].dest]);
      progress.step("match", pairs.size());
    });
  }
  for (auto& edge : edges) {
    edge.T_dest_source = edge.match.T_dest_source;
    if (!edge.match.ok) edge.note = "rejected: " + edge.match.reason;
  }
  return edges;
}

/// Per edge, whether it is a lone match (the only accepted match of one of its maps) accepted by
/// the model alone below `MergeParams::lone_match_min_p_correct`: not trusted (its note says why).
inline std::vector<char> distrust_lone_matches(std::vector<MergeEdge>& edges, std::size_t map_count,
                                               const MatcherParams& matcher_params, const MergeParams& params) {
  std::vector<std::size_t> accepted_matches(map_count, 0);
  for (const auto& edge : edges) {
    if (!edge.match.ok) continue;
    ++accepted_matches[edge.source];
    ++accepted_matches[edge.dest];
  }
  std::vector<char> distrusted(edges.size(), 0);
  for (std::size_t e = 0; e < edges.size(); ++e) {
    MergeEdge& edge = edges[e];
    const bool lone = accepted_matches[edge.source] == 1 || accepted_matches[edge.dest] == 1;
    if (!edge.match.ok || !lone || passes_agreement_gate(edge.match, matcher_params.decision) ||
        edge.match.p_correct >= params.lone_match_min_p_correct) {
      continue;
    }
    distrusted[e] = 1;
    edge.note = "accepted by the model alone (p_correct " + format_fixed(edge.match.p_correct, 3) + ", agreement " +
                format_fixed(edge.match.evidence.agreement, 3) +
                "), but the only accepted match of its map: below MergeParams::lone_match_min_p_correct " +
                format_double(params.lone_match_min_p_correct) + " it is not trusted alone";
  }
  return distrusted;
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
}  // namespace areamatch
