#pragma once
/// \file match/verification/selection.hpp
/// Choosing the answer among the clusters: the Selection policy, `Matcher`'s fifth template
/// parameter.
///
/// A selection policy reads the clusters (best first, from the Clusterer) with everything the
/// matcher built for the pair, and returns its finalists, best first: the first is the answer,
/// the others are the rivals its margins are measured against (`MatchResult::margin`). It
/// must be deterministic, and with `MatcherParams::threads` ≥ 2 it may spread its work with
/// `detail::for_each_index` as long as the result does not depend on the thread count. The
/// smallest conforming type:
/// \code
/// struct FirstClusterSelection {   // trust the best cluster's best member
///   areamatch::Selected select(const areamatch::SelectionInputs& in, areamatch::MatchStatistics&) const {
///     areamatch::Selected out;
///     if (in.clusters.empty()) return out;
///     const int best = in.clusters.front().members.front();
///     out.finalists.push_back({in.hypotheses[static_cast<std::size_t>(best)].T_dest_source, 0.0});
///     return out;
///   }
/// };
/// \endcode
///
/// Two ship: `WholeMapSelection` (default) verifies the best members of every cluster on the
/// whole map and refines the best few by ICP; `LargestClusterSelection` is the paper's, the
/// largest cluster's member with the highest Σ OP.

#include "../../area_graph.hpp"
#include "../../detail/format.hpp"
#include "../../detail/parallel.hpp"
#include "../../detail/thinning.hpp"
#include "../../error.hpp"
#include "../../transform.hpp"
#include "../params.hpp"
#include "../proposal/clusterer.hpp"
#include "../proposal/costs.hpp"
#include "../proposal/hypotheses.hpp"
#include "../raster.hpp"
#include "../result.hpp"
#include "evidence.hpp"
#include "refine.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <queue>
#include <type_traits>
#include <utility>
#include <vector>

namespace areamatch {

/// A transform with a selection's score for it.
struct ScoredTransform {
  Similarity2 T;
  double score = 0.0;
};

/// What a selection may read: the matcher's parameters — those its stages share: `threads`,
/// `allow_reflection`, `estimate_scale`, `refine` and `refinement`, what counts as a different
/// answer, `wall_inlier_distance_m` — and what the matcher built for the pair. A selection's own
/// settings are its own (`WholeMapSelection::Params`).
struct SelectionInputs {
  const MatcherParams& params;
  const HypothesisInputs& maps;               ///< both Area Graphs, coarse rasters, wall directions
  const std::vector<AreaPair>& pairs;         ///< the mutual nearest area pairs
  const std::vector<Hypothesis>& hypotheses;
  const std::vector<Cluster>& clusters;       ///< best first, each best member first
  const AreaRaster& source_fine;              ///< area-covered free space on fine cells
  const AreaRaster& dest_fine;
  const MapEdges& edges;                      ///< both maps' free-space edges and lookups (`reach_m` away)
};

/// What a selection returns.
struct Selected {
  /// Best first; the first is the answer, the others its rivals for the margins. Empty: no answer.
  std::vector<ScoredTransform> finalists;
  /// The finalists' scores rank transforms of different clusters on one scale in [0, 1]: the
  /// margins are their differences and `DecisionParams::min_score` applies to the answer's. Else
  /// the matcher measures the margins by free-space IoU and `min_score` does not apply.
  bool comparable_scores = false;
  /// The finalists were refined by ICP (`MatcherParams::refinement`): the answer's quarter turns
  /// are then refined the same way and measured (`MatchEvidence::turn_margin`).
  bool refined = false;
};

namespace detail {

template <class S, class = void>
struct is_selection : std::false_type {};
template <class S>
struct is_selection<S, std::void_t<decltype(std::declval<const S&>().select(std::declval<const SelectionInputs&>(),
                                                                             std::declval<MatchStatistics&>()))>>
    : std::is_convertible<decltype(std::declval<const S&>().select(std::declval<const SelectionInputs&>(),
                                                                   std::declval<MatchStatistics&>())),
                          Selected> {};

/// The mean of a raster's labelled cell centres (the origin when it has none).
inline Eigen::Vector2d centroid_of(const AreaRaster& raster) {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k < raster.labelled_count(); ++k) centroid += raster.centre(k);
  return raster.labelled_count() == 0 ? centroid : Eigen::Vector2d(centroid / static_cast<double>(raster.labelled_count()));
}

/// Whether two transforms are clearly different answers: another side of the mirror, a
/// rotation apart, or the source's free-space centroid lands apart.
inline bool different(const Similarity2& a, const Similarity2& b, const Eigen::Vector2d& source_centroid,
                      const MatcherParams& params) {
  if (a.reflected != b.reflected) return true;
  if (std::abs(wrap_angle(a.rotation - b.rotation)) > params.different_rotation_rad) return true;
  return ((a * source_centroid) - (b * source_centroid)).norm() > params.different_translation_m;
}

/// The ICP that refines the finalists, and the answer's rivals in the turn margin (so that they
/// are placed as the answer was): `params.refinement`, fitting the scale too when the matcher
/// estimates it.
inline RefineParams finalist_refinement(const MatcherParams& params) {
  RefineParams refinement = params.refinement;
  refinement.estimate_scale = refinement.estimate_scale || params.estimate_scale;
  return refinement;
}

/// The sides of the mirror tried: unmirrored, and mirrored with `allow_reflection`.
inline std::vector<bool> mirror_sides(const MatcherParams& params) {
  return params.allow_reflection ? std::vector<bool>{false, true} : std::vector<bool>{false};
}

}  // namespace detail

/// template<class S> constexpr bool: S is a selection policy (`select(const SelectionInputs&,
/// MatchStatistics&) const` returning `Selected`).
template <class S>
inline constexpr bool is_selection_v = detail::is_selection<S>::value;

/// Ours: the best members of every cluster, ranked by how much of the source's walls land near
/// the destination's (sparse, then all wall points); the best few refined by ICP and scored.
/// The answer is the best of those, whatever cluster it came from.
struct WholeMapSelection {
  /// Its own budgets and distances (what it shares with other stages: `SelectionInputs::params`).
  struct Params {
    std::size_t members_per_cluster = 1;  ///< best members of each cluster that get verified
    std::size_t sparse_samples = 300;     ///< source wall points of the first, cheap ranking pass
    std::size_t verify_candidates = 48;   ///< candidates ranked again on all source wall points
    /// Before ICP, candidates are ranked by the share of the source's walls within this distance
    /// of the destination's free-space edge: loose, as an unrefined hypothesis can be decimetres
    /// off; walls, as free-space IoU saturates for a partial map (docs/matching.md). At most the
    /// lookups' reach (the largest ICP gate, 2 m by default).
    double candidate_wall_distance_m = 0.5;
    std::size_t refine_candidates = 8;    ///< candidates refined by ICP and scored on the fine raster
    bool refine_on_free_edges = true;     ///< ICP on the maps' free-space edges (else the areas' edges)
    /// Finalists' score: (1 − w) · free-space IoU + w · share of the source's free-space edge on
    /// the destination's (within `MatcherParams::wall_inlier_distance_m`).
    double wall_score_weight = 1.0;

    void validate() const {
      detail::require_positive(candidate_wall_distance_m, "WholeMapSelection::Params::candidate_wall_distance_m");
      if (members_per_cluster < 1 || sparse_samples < 1 || verify_candidates < 1 || refine_candidates < 1) {
        throw parameter_error("WholeMapSelection::Params: members_per_cluster, sparse_samples, verify_candidates and "
                              "refine_candidates must be >= 1");
      }
      if (!(wall_score_weight >= 0.0 && wall_score_weight <= 1.0)) {
        throw parameter_error("WholeMapSelection::Params::wall_score_weight must be in [0, 1]");
      }
    }
  };
  Params params;

  Selected select(const SelectionInputs& in, MatchStatistics& statistics) const {
    params.validate();
    const MatcherParams& shared = in.params;
    const double reach = in.edges.dest_lookup.reach_m();
    if (!in.edges.dest_lookup.empty() && params.candidate_wall_distance_m > reach) {
      throw parameter_error("WholeMapSelection::Params::candidate_wall_distance_m (" + detail::format_double(params.candidate_wall_distance_m) +
                            " m) reaches beyond the edge lookups (" + detail::format_double(reach) +
                            " m: the largest of refinement.gates_m, scale.sweep_gates_m and wall_inlier_distance_m)");
    }
    // The candidates: the best few members of every cluster, named by their hypotheses (on a
    // large floor there are ~10^5; their transforms are copied once the verified few are known).
    std::vector<Ranked> ranked;
    std::size_t candidate_count = 0;
    for (const Cluster& cluster : in.clusters) candidate_count += std::min(params.members_per_cluster, cluster.members.size());
    ranked.reserve(candidate_count);
    for (const Cluster& cluster : in.clusters) {
      for (std::size_t m = 0; m < std::min(params.members_per_cluster, cluster.members.size()); ++m) {
        ranked.push_back({0.0, static_cast<std::size_t>(cluster.members[m])});
      }
    }
    auto by_score = [](const auto& a, const auto& b) { return a.score > b.score; };
    // Unrefined candidates are ranked by the share of the source's walls near the destination's
    // edge (frontiers left out: a partial map's frontier is not a wall of the other map), first
    // on a few hundred wall points, then on all of them.
    const MapEdges& edges = in.edges;
    const std::vector<Eigen::Vector2d>& walls = edges.source_walls.empty() ? edges.source_points : edges.source_walls;
    const std::vector<Eigen::Vector2d> sparse_walls = detail::evenly_thinned(walls, params.sparse_samples);
    score_sparse(ranked, in.hypotheses, sparse_walls, edges.dest_lookup, params, shared.threads);
    std::stable_sort(ranked.begin(), ranked.end(), by_score);
    if (ranked.size() > params.verify_candidates) ranked.resize(params.verify_candidates);
    std::vector<ScoredTransform> candidates;
    candidates.reserve(ranked.size());
    for (const Ranked& r : ranked) candidates.push_back({in.hypotheses[r.hypothesis].T_dest_source, r.score});
    std::vector<Ranked>().swap(ranked);
    auto score_on = [&](const std::vector<Eigen::Vector2d>& points) {
      detail::for_each_index(candidates.size(), shared.threads, [&](std::size_t i) {
        candidates[i].score = boundary_inlier_fraction(points, edges.dest_lookup, candidates[i].T, params.candidate_wall_distance_m);
      });
    };
    score_on(walls);
    statistics.verified = candidates.size();
    std::stable_sort(candidates.begin(), candidates.end(), by_score);

    // Finalists: the best few, plus the best on the other side of the mirror and the best clearly
    // different transform, so that the margins compare refined with refined.
    Selected out;
    out.comparable_scores = true;
    out.refined = shared.refine;
    std::vector<ScoredTransform>& finalists = out.finalists;
    const Eigen::Vector2d centroid = detail::centroid_of(*in.maps.source_raster);
    auto add_finalist = [&](const ScoredTransform& c) {
      for (const auto& f : finalists) {
        if (!detail::different(f.T, c.T, centroid, shared)) return;
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

    refine_and_score(in, params, finalists, statistics);
    std::stable_sort(finalists.begin(), finalists.end(), by_score);
    return out;
  }

 private:
  /// A candidate before it is verified: its first score and its hypothesis.
  struct Ranked {
    double score;
    std::size_t hypothesis;
  };

  /// The first, cheap ranking: each candidate's share of `points`, moved by its hypothesis, within
  /// `candidate_wall_distance_m` of the destination's edge. Only the best `verify_candidates` go
  /// on, so a candidate stops counting once it cannot reach the worst of the best so far (its
  /// score is then below theirs, and it is cut as before): the kept candidates, their scores and
  /// their order are those of counting every point.
  static void score_sparse(std::vector<Ranked>& candidates, const std::vector<Hypothesis>& hypotheses,
                           const std::vector<Eigen::Vector2d>& points, const BoundaryLookup& dest, const Params& params,
                           unsigned threads) {
    if (points.empty() || dest.empty()) {
      for (auto& c : candidates) c.score = 0.0;
      return;
    }
    const std::size_t keep = params.verify_candidates, n = points.size();
    const std::size_t blocks = std::min<std::size_t>(detail::resolved_threads(threads), std::max<std::size_t>(1, candidates.size()));
    const std::size_t per_block = (candidates.size() + blocks - 1) / blocks;
    // One block of consecutive candidates per thread, each with its own best-so-far: how many
    // points a cut candidate was counted on depends on the blocks, what is kept does not.
    detail::for_each_index(blocks, threads, [&](std::size_t b) {
      std::priority_queue<std::size_t, std::vector<std::size_t>, std::greater<>> best;  // the `keep` highest counts
      for (std::size_t i = b * per_block; i < std::min(candidates.size(), (b + 1) * per_block); ++i) {
        const std::size_t enough = keep == 0 || best.size() < keep ? 0 : best.top();
        const std::size_t count =
            dest.count_within(points, hypotheses[candidates[i].hypothesis].T_dest_source, params.candidate_wall_distance_m, enough);
        candidates[i].score = static_cast<double>(count) / static_cast<double>(n);
        if (count < enough) continue;  // stopped early: below every kept count
        best.push(count);
        if (best.size() > keep) best.pop();
      }
    });
  }

  /// Refines the finalists by ICP and scores them: a blend of the fine free-space IoU and the
  /// share of the source's free-space edge that lies on the destination's.
  static void refine_and_score(const SelectionInputs& in, const Params& params, std::vector<ScoredTransform>& finalists,
                               MatchStatistics& statistics) {
    const MatcherParams& shared = in.params;
    const std::vector<Eigen::Vector2d>& edge = in.edges.source_points;
    const BoundaryLookup& dest_edge = in.edges.dest_lookup;
    if (shared.refine) {
      const RefineParams refinement = detail::finalist_refinement(shared);
      const std::vector<Eigen::Vector2d>* points = &edge;
      const std::vector<Eigen::Vector2d>* sides = &in.edges.source_sides;
      const BoundaryLookup* lookup = &dest_edge;
      std::vector<Eigen::Vector2d> area_points;
      BoundaryLookup area_lookup;
      if (!params.refine_on_free_edges) {
        area_points = detail::area_boundary_points(*in.maps.source, shared.refinement.point_spacing_m,
                                                   static_cast<std::size_t>(shared.refinement.max_points));
        area_lookup = BoundaryLookup(detail::area_boundary_points(*in.maps.dest, 0.5 * shared.refinement.lookup_cell_m),
                                     shared.refinement.lookup_cell_m, shared.refinement.gates_m.front(),
                                     shared.refinement.point_to_line ? shared.refinement.normal_radius_m : 0.0);
        points = &area_points;
        sides = nullptr;
        lookup = &area_lookup;
      }
      detail::for_each_index(finalists.size(), shared.threads, [&](std::size_t i) {
        finalists[i].T = refine_icp(*points, *lookup, finalists[i].T, refinement, sides);
      });
      statistics.refined = finalists.size();
    }
    detail::for_each_index(finalists.size(), shared.threads, [&](std::size_t i) {
      auto& f = finalists[i];
      const double iou = free_space_iou(in.source_fine, in.dest_fine, f.T);
      const double walls = boundary_inlier_fraction(edge, dest_edge, f.T, shared.wall_inlier_distance_m);
      f.score = (1.0 - params.wall_score_weight) * iou + params.wall_score_weight * walls;
    });
  }
};

/// The paper: on each side of the mirror, the largest cluster's member with the highest Σ OP
/// over all mutual pairs; the sides compare by that Σ OP. The first member of every other cluster
/// follows as a rival for the margins (Σ OP does not compare transforms of different clusters:
/// the matcher scores the rivals by IoU).
struct LargestClusterSelection {
  Selected select(const SelectionInputs& in, MatchStatistics& statistics) const {
    const MatcherParams& params = in.params;
    auto total_overlap = [&](const Similarity2& T) {
      double sum = 0.0;
      for (const AreaPair& pair : in.pairs) {
        sum += pair_overlap(in.maps, pair, params.hypotheses.exact_overlap, T, &statistics.overlay_failures);
      }
      return sum;
    };
    Selected out;
    std::vector<ScoredTransform> others;  // first members of the other clusters
    for (bool side : detail::mirror_sides(params)) {
      bool first = true;
      for (const Cluster& cluster : in.clusters) {
        if (in.hypotheses[static_cast<std::size_t>(cluster.members.front())].T_dest_source.reflected != side) continue;
        if (first) {
          first = false;
          ScoredTransform best{{}, -1.0};
          for (int m : cluster.members) {
            const Similarity2& T = in.hypotheses[static_cast<std::size_t>(m)].T_dest_source;
            const double s = total_overlap(T);
            ++statistics.verified;
            if (s > best.score) best = {T, s};
          }
          out.finalists.push_back(best);
        } else {
          others.push_back({in.hypotheses[static_cast<std::size_t>(cluster.members.front())].T_dest_source, -1.0});
        }
      }
    }
    std::stable_sort(out.finalists.begin(), out.finalists.end(),
                     [](const auto& a, const auto& b) { return a.score > b.score; });
    out.finalists.insert(out.finalists.end(), others.begin(), others.end());
    return out;
  }
};

}  // namespace areamatch
