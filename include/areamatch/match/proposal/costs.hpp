#pragma once
/// \file match/proposal/costs.hpp
/// Weighted cost matrix and mutual k-nearest-neighbour area pairs (paper §III-C,
/// docs/algorithm.md).
///
/// A weights policy gives one weight per feature of the feature set, in its order. The smallest
/// conforming type:
/// \code
/// struct EqualWeights {
///   std::array<double, 3> values{1.0 / 3, 1.0 / 3, 1.0 / 3};
/// };
/// \endcode
/// Weights should be ≥ 0 and sum to one so the total cost stays in [0, 1]; `weighted_cost`
/// checks this.

#include "../../detail/parallel.hpp"
#include "../../error.hpp"
#include "features.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace areamatch {

/// The paper's weights w = [w_a, w_p, w_l] = [0.1, 0.1, 0.8], from its grid search.
struct PaperWeights {
  std::array<double, 3> values{0.1, 0.1, 0.8};
};

namespace detail {
template <class W, std::size_t N, class = void>
struct has_weight_values : std::false_type {};
template <class W, std::size_t N>
struct has_weight_values<W, N, std::void_t<decltype(std::declval<const W&>().values)>>
    : std::is_convertible<std::decay_t<decltype(std::declval<const W&>().values)>, std::array<double, N>> {};
}  // namespace detail

/// True when W is a weights policy for N features.
template <class W, std::size_t N>
inline constexpr bool is_weights_v = detail::has_weight_values<W, N>::value;

namespace detail {
/// Throws `parameter_error` unless the weights are finite, ≥ 0 and sum to 1.
template <std::size_t N>
void check_weights(const std::array<double, N>& weights) {
  double sum = 0.0;
  for (double w : weights) {
    if (!(std::isfinite(w) && w >= 0.0)) throw parameter_error("weights must be finite and >= 0");
    sum += w;
  }
  if (std::abs(sum - 1.0) > 1e-6) throw parameter_error("weights must sum to 1, got " + std::to_string(sum));
}
}  // namespace detail

/// Σ_k w_k · C_k. Throws `parameter_error` unless the weights are finite, ≥ 0 and sum to 1.
template <std::size_t N>
Eigen::MatrixXd weighted_cost(const std::vector<Eigen::MatrixXd>& feature_costs, const std::array<double, N>& weights) {
  if (feature_costs.size() != N) {
    throw parameter_error("weights: " + std::to_string(N) + " weights for " + std::to_string(feature_costs.size()) +
                          " features");
  }
  detail::check_weights(weights);
  Eigen::MatrixXd total = Eigen::MatrixXd::Zero(feature_costs.front().rows(), feature_costs.front().cols());
  for (std::size_t k = 0; k < N; ++k) total += weights[k] * feature_costs[k];
  return total;
}

/// A source area i and a destination area j that chose each other.
struct AreaPair {
  int source = -1;
  int dest = -1;
  double cost = 0.0;
};

namespace detail {
/// By cost, then source, then destination: the pairs' one order.
inline void sort_pairs(std::vector<AreaPair>& pairs) {
  std::sort(pairs.begin(), pairs.end(), [](const AreaPair& a, const AreaPair& b) {
    return a.cost != b.cost ? a.cost < b.cost : a.source != b.source ? a.source < b.source : a.dest < b.dest;
  });
}

/// Indices of the k smallest entries of `values` (ties: lower index first).
inline std::vector<Eigen::Index> k_smallest(const Eigen::VectorXd& values, std::size_t k) {
  std::vector<Eigen::Index> order(static_cast<std::size_t>(values.size()));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  k = std::min(k, order.size());
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k), order.end(),
                    [&](Eigen::Index a, Eigen::Index b) { return values[a] < values[b] || (values[a] == values[b] && a < b); });
  order.resize(k);
  return order;
}
}  // namespace detail

/// Mutual k-nearest neighbours: (i, j) is kept when j is among the k cheapest columns of row i
/// and i among the k cheapest rows of column j (k is clamped to the matrix size). Sorted by
/// cost, then by indices: deterministic.
inline std::vector<AreaPair> mutual_nearest_pairs(const Eigen::MatrixXd& cost, std::size_t k) {
  if (k == 0) throw parameter_error("mutual nearest neighbours: k must be >= 1");
  const Eigen::Index rows = cost.rows(), cols = cost.cols();
  Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> row_choice = decltype(row_choice)::Constant(rows, cols, false);
  for (Eigen::Index i = 0; i < rows; ++i) {
    for (Eigen::Index j : detail::k_smallest(cost.row(i).transpose(), k)) row_choice(i, j) = true;
  }
  std::vector<AreaPair> pairs;
  for (Eigen::Index j = 0; j < cols; ++j) {
    for (Eigen::Index i : detail::k_smallest(cost.col(j), k)) {
      if (row_choice(i, j)) pairs.push_back({static_cast<int>(i), static_cast<int>(j), cost(i, j)});
    }
  }
  detail::sort_pairs(pairs);
  return pairs;
}

namespace detail {

/// One side's nearest neighbours among the other side's areas, found without comparing every
/// pair: the other side's areas sorted by one feature's `bound_key` (the heaviest-weighted one
/// that has keys), searched outward from the query's key until that feature's weighted cost
/// alone exceeds the k-th best total so far. Every skipped area's cost is above it, so the k
/// found are exactly the k smallest (cost, then index) of the full row.
class NearestSearch {
 public:
  /// `own_keys` / `other_keys`: per feature, the keys of the querying and the searched side
  /// (empty: the feature has none). Features whose keys are missing, negative or not finite on
  /// either side do not bound.
  template <std::size_t N>
  NearestSearch(const std::array<std::vector<double>, N>& own_keys, const std::array<std::vector<double>, N>& other_keys,
                const std::array<double, N>& weights, std::size_t other_count) {
    auto usable = [](const std::vector<double>& keys, std::size_t count) {
      return keys.size() == count &&
             std::all_of(keys.begin(), keys.end(), [](double v) { return std::isfinite(v) && v >= 0.0; });
    };
    for (std::size_t f = 0; f < N; ++f) {
      if (weights[f] <= 0.0 || !usable(other_keys[f], other_count)) continue;
      if (own_keys[f].empty() || !usable(own_keys[f], own_keys[f].size())) continue;
      bounds_.push_back({weights[f], &own_keys[f], &other_keys[f]});
    }
    // The heaviest bound orders the search; the others only skip single comparisons.
    std::stable_sort(bounds_.begin(), bounds_.end(), [](const Bound& a, const Bound& b) { return a.weight > b.weight; });
    order_.resize(other_count);
    std::iota(order_.begin(), order_.end(), std::size_t{0});
    if (!bounds_.empty()) {
      const std::vector<double>& keys = *bounds_.front().other;
      std::stable_sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) { return keys[a] < keys[b]; });
      sorted_keys_.reserve(other_count);
      for (std::size_t j : order_) sorted_keys_.push_back(keys[j]);
    }
  }

  /// The k smallest of cost(i, j) over the other side's j, by (cost, j), ascending.
  template <class Cost>
  std::vector<std::pair<double, std::size_t>> nearest(std::size_t i, std::size_t k, const Cost& cost) const {
    std::vector<std::pair<double, std::size_t>> best;  // a max-heap by (cost, index)
    best.reserve(k + 1);
    auto threshold = [&] { return best.size() < k ? std::numeric_limits<double>::infinity() : best.front().first; };
    auto consider = [&](std::size_t j) {
      // Rounding in a bound is far below this; a pair within it of the threshold is compared.
      constexpr double slack = 1e-9;
      if (lower_bound(i, j) > threshold() + slack) return;
      const std::pair<double, std::size_t> candidate{cost(j), j};
      if (best.size() == k && !(candidate < best.front())) return;
      best.push_back(candidate);
      std::push_heap(best.begin(), best.end());
      if (best.size() > k) {
        std::pop_heap(best.begin(), best.end());
        best.pop_back();
      }
    };
    const std::size_t n = order_.size();
    if (bounds_.empty()) {
      for (std::size_t j = 0; j < n; ++j) consider(j);
    } else {
      const Bound& lead = bounds_.front();
      const double key = (*lead.own)[i];
      auto bound_at = [&](std::size_t position) { return lead.weight * relative_difference(key, sorted_keys_[position]); };
      // Outward from the query's key: the lead bound grows on both sides (relative_difference of
      // non-negative numbers grows with their distance apart).
      std::size_t right = static_cast<std::size_t>(std::lower_bound(sorted_keys_.begin(), sorted_keys_.end(), key) -
                                                   sorted_keys_.begin());
      std::size_t left = right;  // positions below `left` are still to visit
      constexpr double slack = 1e-9;
      while (left > 0 || right < n) {
        const double left_bound = left > 0 ? bound_at(left - 1) : std::numeric_limits<double>::infinity();
        const double right_bound = right < n ? bound_at(right) : std::numeric_limits<double>::infinity();
        if (std::min(left_bound, right_bound) > threshold() + slack) break;
        consider(left_bound <= right_bound ? order_[--left] : order_[right++]);
      }
    }
    std::sort(best.begin(), best.end());
    return best;
  }

 private:
  struct Bound {
    double weight;
    const std::vector<double>* own;
    const std::vector<double>* other;
  };
  double lower_bound(std::size_t i, std::size_t j) const {
    double sum = 0.0;
    for (const Bound& b : bounds_) sum += b.weight * relative_difference((*b.own)[i], (*b.other)[j]);
    return sum;
  }
  std::vector<Bound> bounds_;
  std::vector<std::size_t> order_;  ///< the other side's areas by the lead key
  std::vector<double> sorted_keys_;
};

}  // namespace detail

/// Mutual k-nearest neighbours of two maps' areas under the weighted cost of `features`: the
/// pairs `mutual_nearest_pairs(weighted_cost(features.costs(source, dest), weights), k)` gives,
/// without the areas_source × areas_dest matrices. Each area's k nearest are searched outward
/// along the features' `bound_key`s (detail::NearestSearch), so maps of thousands of areas cost
/// about k comparisons per area, not one per area of the other map; rows run on `threads`
/// threads (0: all) with the same result for any count.
template <class FeatureSetType, std::size_t N>
std::vector<AreaPair> mutual_nearest_pairs(const FeatureSetType& features,
                                           const typename FeatureSetType::descriptors_type& source,
                                           const typename FeatureSetType::descriptors_type& dest,
                                           const std::array<double, N>& weights, std::size_t k, unsigned threads = 1) {
  static_assert(N == FeatureSetType::size, "mutual_nearest_pairs: one weight per feature");
  if (k == 0) throw parameter_error("mutual nearest neighbours: k must be >= 1");
  detail::check_weights(weights);
  const std::size_t rows = std::get<0>(source).size(), cols = std::get<0>(dest).size();
  const auto source_keys = features.bound_keys(source), dest_keys = features.bound_keys(dest);
  const detail::NearestSearch along_dest(source_keys, dest_keys, weights, cols);
  const detail::NearestSearch along_source(dest_keys, source_keys, weights, rows);
  std::vector<std::vector<std::pair<double, std::size_t>>> row_best(rows), col_best(cols);
  detail::for_each_index(rows, threads, [&](std::size_t i) {
    row_best[i] = along_dest.nearest(i, k, [&](std::size_t j) { return features.weighted_cost(source, dest, i, j, weights); });
  });
  detail::for_each_index(cols, threads, [&](std::size_t j) {
    col_best[j] = along_source.nearest(j, k, [&](std::size_t i) { return features.weighted_cost(source, dest, i, j, weights); });
  });
  std::vector<AreaPair> pairs;
  for (std::size_t j = 0; j < cols; ++j) {
    for (const auto& [cost, i] : col_best[j]) {
      const auto& row = row_best[i];
      const bool mutual = std::any_of(row.begin(), row.end(), [&, j = j](const auto& entry) { return entry.second == j; });
      if (mutual) pairs.push_back({static_cast<int>(i), static_cast<int>(j), cost});
    }
  }
  detail::sort_pairs(pairs);
  return pairs;
}

}  // namespace areamatch
