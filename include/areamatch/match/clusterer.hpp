#pragma once
/// \file match/clusterer.hpp
/// Clustering of hypotheses (paper §III-E, docs/algorithm.md).
///
/// A clusterer policy groups hypotheses and returns the groups best first; it must be
/// deterministic (the same hypotheses in the same order give the same clusters) and must not put
/// a mirrored and an unmirrored hypothesis into one cluster. The smallest conforming type:
/// \code
/// struct OneClusterEach {   // no grouping: every hypothesis its own cluster, input order
///   std::vector<areamatch::Cluster> cluster(const std::vector<areamatch::Hypothesis>& hypotheses) const {
///     std::vector<areamatch::Cluster> out;
///     for (int i = 0; i < static_cast<int>(hypotheses.size()); ++i) out.push_back({{i}});
///     return out;
///   }
/// };
/// \endcode
/// What the matcher does with the clusters is the Selection policy's choice (match/selection.hpp):
/// the paper's takes the first (largest) cluster; our default verifies the best members of every
/// cluster on the whole map, so there clustering only ranks and removes duplicates.

#include "../error.hpp"
#include "../transform.hpp"
#include "hypotheses.hpp"

#include <algorithm>
#include <map>
#include <tuple>
#include <cmath>
#include <numeric>
#include <type_traits>
#include <utility>
#include <vector>

namespace areamatch {

/// A group of hypotheses: indices into the hypothesis list, best member first.
struct Cluster {
  std::vector<int> members;
  double rotation = 0.0;        ///< circular mean of the members' rotations
  double total_overlap = 0.0;   ///< Σ OP of the members
};

namespace detail {
template <class C, class = void>
struct is_clusterer : std::false_type {};
template <class C>
struct is_clusterer<C, std::void_t<decltype(std::declval<const C&>().cluster(std::declval<const std::vector<Hypothesis>&>()))>>
    : std::is_convertible<decltype(std::declval<const C&>().cluster(std::declval<const std::vector<Hypothesis>&>())),
                          std::vector<Cluster>> {};

/// Hypothesis indices sorted by OP (descending), then pair cost, then index: the order both
/// clusterers consume them in, so their result does not depend on how hypotheses were generated.
inline std::vector<int> by_overlap(const std::vector<Hypothesis>& hypotheses) {
  std::vector<int> order(hypotheses.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    const Hypothesis& x = hypotheses[static_cast<std::size_t>(a)];
    const Hypothesis& y = hypotheses[static_cast<std::size_t>(b)];
    if (x.area_overlap != y.area_overlap) return x.area_overlap > y.area_overlap;
    return x.pair_cost < y.pair_cost;
  });
  return order;
}

inline double circular_mean(const std::vector<Hypothesis>& hypotheses, const std::vector<int>& members) {
  double s = 0.0, c = 0.0;
  for (int i : members) {
    s += std::sin(hypotheses[static_cast<std::size_t>(i)].T_dest_source.rotation);
    c += std::cos(hypotheses[static_cast<std::size_t>(i)].T_dest_source.rotation);
  }
  return std::atan2(s, c);
}

/// Fills each cluster's mean rotation and Σ OP and puts its members in `order` (best first).
inline void finish_clusters(const std::vector<Hypothesis>& hypotheses, const std::vector<int>& order,
                            std::vector<Cluster>& clusters) {
  std::vector<int> rank(hypotheses.size());
  for (std::size_t r = 0; r < order.size(); ++r) rank[static_cast<std::size_t>(order[r])] = static_cast<int>(r);
  for (Cluster& cluster : clusters) {
    std::sort(cluster.members.begin(), cluster.members.end(),
              [&](int a, int b) { return rank[static_cast<std::size_t>(a)] < rank[static_cast<std::size_t>(b)]; });
    cluster.rotation = circular_mean(hypotheses, cluster.members);
    cluster.total_overlap = 0.0;
    for (int i : cluster.members) cluster.total_overlap += hypotheses[static_cast<std::size_t>(i)].area_overlap;
  }
}
}  // namespace detail

/// True when C is a clusterer policy (see the file comment).
template <class C>
inline constexpr bool is_clusterer_v = detail::is_clusterer<C>::value;

/// The paper's greedy angular clustering: a hypothesis joins the nearest cluster whose mean
/// rotation is within `threshold_rad`, else opens a new one; members are then reassigned until
/// each is within the threshold of its cluster's mean. Made deterministic by consuming the
/// hypotheses in order of OP (the paper's result depends on their order). Clusters come out
/// largest first, ties broken by Σ OP.
struct AngularClusterer {
  struct Params {
    double threshold_rad = 3.0 * pi / 180.0;  ///< the paper's 3°
    int max_reassignments = 100;              ///< guards the reassignment loop
  } params;

  std::vector<Cluster> cluster(const std::vector<Hypothesis>& hypotheses) const {
    detail::require_positive(params.threshold_rad, "AngularClusterer::Params::threshold_rad");
    const std::vector<int> order = detail::by_overlap(hypotheses);

    std::vector<Cluster> clusters;
    auto nearest = [&](const Hypothesis& h) {
      int best = -1;
      double best_distance = params.threshold_rad;
      for (std::size_t c = 0; c < clusters.size(); ++c) {
        const Hypothesis& first = hypotheses[static_cast<std::size_t>(clusters[c].members.front())];
        if (first.T_dest_source.reflected != h.T_dest_source.reflected) continue;
        const double d = std::abs(wrap_angle(h.T_dest_source.rotation - clusters[c].rotation));
        if (d <= best_distance) {
          best_distance = d;
          best = static_cast<int>(c);
        }
      }
      return best;
    };
    for (int i : order) {
      const Hypothesis& h = hypotheses[static_cast<std::size_t>(i)];
      const int c = nearest(h);
      if (c < 0) {
        clusters.push_back({{i}, h.T_dest_source.rotation, 0.0});
      } else {
        clusters[static_cast<std::size_t>(c)].members.push_back(i);
        clusters[static_cast<std::size_t>(c)].rotation =
            detail::circular_mean(hypotheses, clusters[static_cast<std::size_t>(c)].members);
      }
    }
    // Reassign until every member is within the threshold of its own cluster's mean.
    for (int round = 0; round < params.max_reassignments; ++round) {
      bool moved = false;
      std::vector<Cluster> next;
      for (const Cluster& cluster : clusters) next.push_back({{}, cluster.rotation, 0.0});
      std::vector<int> orphans;
      for (int i : order) {
        const Hypothesis& h = hypotheses[static_cast<std::size_t>(i)];
        int home = -1;
        for (std::size_t c = 0; c < clusters.size() && home < 0; ++c) {
          if (std::find(clusters[c].members.begin(), clusters[c].members.end(), i) != clusters[c].members.end()) {
            home = static_cast<int>(c);
          }
        }
        const double d = std::abs(wrap_angle(h.T_dest_source.rotation - clusters[static_cast<std::size_t>(home)].rotation));
        if (d <= params.threshold_rad) {
          next[static_cast<std::size_t>(home)].members.push_back(i);
        } else {
          orphans.push_back(i);
          moved = true;
        }
      }
      next.erase(std::remove_if(next.begin(), next.end(), [](const Cluster& c) { return c.members.empty(); }), next.end());
      for (Cluster& c : next) c.rotation = detail::circular_mean(hypotheses, c.members);
      clusters = std::move(next);
      for (int i : orphans) {
        const Hypothesis& h = hypotheses[static_cast<std::size_t>(i)];
        const int c = nearest(h);
        if (c < 0) clusters.push_back({{i}, h.T_dest_source.rotation, 0.0});
        else clusters[static_cast<std::size_t>(c)].members.push_back(i);
      }
      if (!moved) break;
    }
    detail::finish_clusters(hypotheses, order, clusters);
    std::stable_sort(clusters.begin(), clusters.end(), [](const Cluster& a, const Cluster& b) {
      if (a.members.size() != b.members.size()) return a.members.size() > b.members.size();
      return a.total_overlap > b.total_overlap;
    });
    return clusters;
  }
};

/// Groups hypotheses that are the same transform: rotation within `rotation_rad`, translation
/// within `translation_m` of the cluster's first (highest-OP) member, same side of the mirror.
/// Clusters come out by Σ OP. Our default: clusters only remove duplicates before the whole-map
/// verification, so they must not merge transforms that differ by more than the refinement can
/// fix.
struct PoseClusterer {
  struct Params {
    double rotation_rad = 3.0 * pi / 180.0;
    double translation_m = 1.0;
  } params;

  std::vector<Cluster> cluster(const std::vector<Hypothesis>& hypotheses) const {
    detail::require_positive(params.rotation_rad, "PoseClusterer::Params::rotation_rad");
    detail::require_positive(params.translation_m, "PoseClusterer::Params::translation_m");
    const std::vector<int> order = detail::by_overlap(hypotheses);
    std::vector<Cluster> clusters;
    // Leaders indexed by (mirror side, rotation bin, translation bins): a hypothesis compares only
    // with leaders in the neighbouring bins, so tens of thousands of hypotheses (large buildings,
    // all walls axis-aligned) cluster in linear time. Bins are at least the tolerances wide, so
    // no match is missed; among several matches the earliest cluster wins, as in a linear scan.
    const int bins = std::max(1, static_cast<int>(2.0 * pi / params.rotation_rad));
    auto rotation_bin = [&](double rotation) {
      return std::min(bins - 1, static_cast<int>((wrap_angle(rotation) + pi) / (2.0 * pi) * bins));
    };
    auto translation_bin = [&](double t) { return static_cast<long long>(std::floor(t / params.translation_m)); };
    using Key = std::tuple<bool, int, long long, long long>;
    std::map<Key, std::vector<int>> leaders;
    for (int i : order) {
      const Similarity2& T = hypotheses[static_cast<std::size_t>(i)].T_dest_source;
      const int rb = rotation_bin(T.rotation);
      const long long xb = translation_bin(T.translation.x()), yb = translation_bin(T.translation.y());
      int found = -1;
      for (int dr = -1; dr <= 1; ++dr) {
        for (long long dx = -1; dx <= 1; ++dx) {
          for (long long dy = -1; dy <= 1; ++dy) {
            const auto it = leaders.find(Key{T.reflected, (rb + dr + bins) % bins, xb + dx, yb + dy});
            if (it == leaders.end()) continue;
            for (int c : it->second) {
              const Similarity2& L =
                  hypotheses[static_cast<std::size_t>(clusters[static_cast<std::size_t>(c)].members.front())].T_dest_source;
              if ((found < 0 || c < found) && std::abs(wrap_angle(L.rotation - T.rotation)) <= params.rotation_rad &&
                  (L.translation - T.translation).norm() <= params.translation_m) {
                found = c;
              }
            }
          }
        }
      }
      if (found < 0) {
        leaders[Key{T.reflected, rb, xb, yb}].push_back(static_cast<int>(clusters.size()));
        clusters.push_back({{i}, T.rotation, 0.0});
      } else {
        clusters[static_cast<std::size_t>(found)].members.push_back(i);
      }
    }
    detail::finish_clusters(hypotheses, order, clusters);
    std::stable_sort(clusters.begin(), clusters.end(),
                     [](const Cluster& a, const Cluster& b) { return a.total_overlap > b.total_overlap; });
    return clusters;
  }
};

}  // namespace areamatch
