#pragma once
/// \file match/proposal/clusterer.hpp
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
/// What the matcher does with the clusters is the Selection policy's choice (match/verification/selection.hpp):
/// the paper's takes the first (largest) cluster; our default verifies the best members of every
/// cluster on the whole map, so there clustering only ranks and removes duplicates.

#include "../../error.hpp"
#include "../../transform.hpp"
#include "hypotheses.hpp"

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <tuple>
#include <cmath>
#include <limits>
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
    // Leaders indexed by (mirror side, rotation bin, translation bins), each bin twice its
    // tolerance wide: a leader within the tolerances lies in the hypothesis's own bin or, along
    // each axis, in the neighbour on the side the hypothesis is near — at most 2 × 2 × 2 bins to
    // look in. Looking in a bin needlessly costs time, never a different answer, so the edges are
    // judged with some slack. Tens of thousands of hypotheses (large buildings, all walls
    // axis-aligned) cluster in linear time; among several matches the earliest cluster wins, as
    // in a linear scan.
    struct Axis {
      long long bin;
      int below, above;  // the neighbours to look in: −1 or 0, 0 or 1
    };
    auto axis = [](double value, double width, double tolerance, double upper_limit) {
      const double cell = std::min(std::floor(value / width), upper_limit);
      const double lower = cell * width, upper = lower + width, slack = 1e-9 * width;
      return Axis{static_cast<long long>(cell), value - tolerance <= lower + slack ? -1 : 0,
                  value + tolerance >= upper - slack ? 1 : 0};
    };
    const int bins = std::max(1, static_cast<int>(pi / params.rotation_rad));
    const double bin_rad = 2.0 * pi / bins, cell_m = 2.0 * params.translation_m;
    const double unbounded = std::numeric_limits<double>::infinity();
    using Key = std::tuple<bool, int, long long, long long>;
    struct KeyHash {  // the lookup order never reaches the result: each bin's leaders are scanned in full
      std::size_t operator()(const Key& k) const {
        std::uint64_t h = static_cast<std::uint64_t>(std::get<0>(k)) * 0x9E3779B97F4A7C15ull;
        for (const std::uint64_t v : {static_cast<std::uint64_t>(std::get<1>(k)), static_cast<std::uint64_t>(std::get<2>(k)),
                                      static_cast<std::uint64_t>(std::get<3>(k))}) {
          h = (h ^ v) * 0xBF58476D1CE4E5B9ull;
          h ^= h >> 31;
        }
        return static_cast<std::size_t>(h);
      }
    };
    std::unordered_map<Key, std::vector<int>, KeyHash> leaders;
    for (int i : order) {
      const Similarity2& T = hypotheses[static_cast<std::size_t>(i)].T_dest_source;
      // wrap_angle + π lies in (0, 2π]; 2π itself belongs to the last bin.
      const Axis r = axis(wrap_angle(T.rotation) + pi, bin_rad, params.rotation_rad, bins - 1);
      const Axis x = axis(T.translation.x(), cell_m, params.translation_m, unbounded);
      const Axis y = axis(T.translation.y(), cell_m, params.translation_m, unbounded);
      const int rb = static_cast<int>(r.bin);
      int found = -1;
      for (int dr = r.below; dr <= r.above; ++dr) {
        for (int dx = x.below; dx <= x.above; ++dx) {
          for (int dy = y.below; dy <= y.above; ++dy) {
            const auto it = leaders.find(Key{T.reflected, (rb + dr + bins) % bins, x.bin + dx, y.bin + dy});
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
        leaders[Key{T.reflected, rb, x.bin, y.bin}].push_back(static_cast<int>(clusters.size()));
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
