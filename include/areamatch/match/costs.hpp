#pragma once
/// \file match/costs.hpp
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

#include "../error.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
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

/// Σ_k w_k · C_k. Throws `parameter_error` unless the weights are finite, ≥ 0 and sum to 1.
template <std::size_t N>
Eigen::MatrixXd weighted_cost(const std::vector<Eigen::MatrixXd>& feature_costs, const std::array<double, N>& weights) {
  if (feature_costs.size() != N) {
    throw parameter_error("weights: " + std::to_string(N) + " weights for " + std::to_string(feature_costs.size()) +
                          " features");
  }
  double sum = 0.0;
  for (double w : weights) {
    if (!(std::isfinite(w) && w >= 0.0)) throw parameter_error("weights must be finite and >= 0");
    sum += w;
  }
  if (std::abs(sum - 1.0) > 1e-6) throw parameter_error("weights must sum to 1, got " + std::to_string(sum));
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
  std::sort(pairs.begin(), pairs.end(), [](const AreaPair& a, const AreaPair& b) {
    return a.cost != b.cost ? a.cost < b.cost : a.source != b.source ? a.source < b.source : a.dest < b.dest;
  });
  return pairs;
}

}  // namespace areamatch
