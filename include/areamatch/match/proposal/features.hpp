#pragma once
/// \file match/proposal/features.hpp
/// Per-area features and their costs (paper §III-B, docs/algorithm.md), and `FeatureSet`,
/// which composes them.
///
/// A feature policy describes one area by a value (its descriptor) and compares two descriptors
/// by a cost in [0, 1] (0 = alike). It may also say which segment of each area the comparison
/// matched: the hypothesis stage turns such a segment pair into a rotation. The smallest
/// conforming feature:
/// \code
/// struct PassageCount {
///   using descriptor_type = double;
///   descriptor_type describe(const areamatch::AreaGraph&, const areamatch::Area& area) const {
///     return static_cast<double>(area.passages.size());
///   }
///   double cost(const descriptor_type& a, const descriptor_type& b) const {
///     return areamatch::relative_difference(a, b);
///   }
///   // optional: std::optional<areamatch::SegmentMatch> segments(const descriptor_type& source,
///   //                                                             const descriptor_type& dest) const;
///   // optional: double bound_key(const descriptor_type& d) const { return d; }
/// };
/// \endcode
/// `bound_key`, when a feature has it, is a number ≥ 0 per descriptor with
/// cost(a, b) ≥ relative_difference(bound_key(a), bound_key(b)) for every a, b. The pairing then
/// skips area pairs whose keys differ too much for the pair to be among the k nearest: the same
/// pairs, found without comparing every area with every other (match/proposal/costs.hpp).
/// The paper's three features are `AreaSize`, `PassageDistances` and `HullDiameter`
/// (match/proposal/paper_features.hpp).

#include "../../area_graph.hpp"
#include "../../geometry.hpp"
#include "paper_features.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace areamatch {

// --- The feature concept ------------------------------------------------------------------------

namespace detail {
template <class F, class = void>
struct has_describe_and_cost : std::false_type {};
template <class F>
struct has_describe_and_cost<
    F, std::void_t<typename F::descriptor_type,
                   decltype(std::declval<const F&>().describe(std::declval<const AreaGraph&>(), std::declval<const Area&>())),
                   decltype(std::declval<const F&>().cost(std::declval<const typename F::descriptor_type&>(),
                                                          std::declval<const typename F::descriptor_type&>()))>>
    : std::bool_constant<
          std::is_convertible_v<decltype(std::declval<const F&>().describe(std::declval<const AreaGraph&>(),
                                                                           std::declval<const Area&>())),
                                typename F::descriptor_type> &&
          std::is_convertible_v<decltype(std::declval<const F&>().cost(
                                    std::declval<const typename F::descriptor_type&>(),
                                    std::declval<const typename F::descriptor_type&>())),
                                double>> {};

template <class F, class = void>
struct has_bound_key : std::false_type {};
template <class F>
struct has_bound_key<F, std::void_t<decltype(std::declval<const F&>().bound_key(
                            std::declval<const typename F::descriptor_type&>()))>>
    : std::is_convertible<decltype(std::declval<const F&>().bound_key(
                              std::declval<const typename F::descriptor_type&>())),
                          double> {};

template <class F, class = void>
struct has_segments : std::false_type {};
template <class F>
struct has_segments<F, std::void_t<decltype(std::declval<const F&>().segments(
                           std::declval<const typename F::descriptor_type&>(),
                           std::declval<const typename F::descriptor_type&>()))>>
    : std::is_convertible<decltype(std::declval<const F&>().segments(
                              std::declval<const typename F::descriptor_type&>(),
                              std::declval<const typename F::descriptor_type&>())),
                          std::optional<SegmentMatch>> {};
}  // namespace detail

/// True when F is a feature policy (see the file comment).
template <class F>
inline constexpr bool is_feature_v = detail::has_describe_and_cost<F>::value;

/// True when the feature gives a key that bounds its cost from below (see the file comment).
template <class F>
inline constexpr bool feature_has_bound_key_v = detail::has_bound_key<F>::value;

/// True when the feature also reports the segments it matched.
template <class F>
inline constexpr bool feature_has_segments_v = detail::has_segments<F>::value;

// --- FeatureSet ---------------------------------------------------------------------------------

/// Several features side by side. `FeatureSet<AreaSize, PassageDistances, HullDiameter>` is the
/// paper's set; weights are given per feature, in this order.
template <class... Features>
struct FeatureSet {
  static_assert(sizeof...(Features) > 0, "areamatch: FeatureSet needs at least one feature");
  static_assert((is_feature_v<Features> && ...),
                "areamatch: every FeatureSet member must be a feature policy: a type with "
                "`using descriptor_type = ...;`, `descriptor_type describe(const AreaGraph&, const Area&) const` "
                "and `double cost(const descriptor_type&, const descriptor_type&) const` (see match/proposal/features.hpp)");

  static constexpr std::size_t size = sizeof...(Features);
  using descriptors_type = std::tuple<std::vector<typename Features::descriptor_type>...>;

  std::tuple<Features...> features;

  /// Every feature's descriptor of every area of the graph.
  descriptors_type describe(const AreaGraph& graph) const {
    descriptors_type out;
    describe_each(graph, out, std::index_sequence_for<Features...>{});
    return out;
  }

  /// One cost matrix per feature: rows = source areas, columns = destination areas.
  std::vector<Eigen::MatrixXd> costs(const descriptors_type& source, const descriptors_type& dest) const {
    std::vector<Eigen::MatrixXd> out;
    costs_each(source, dest, out, std::index_sequence_for<Features...>{});
    return out;
  }

  /// Σ_k weights_k · cost_k for source area i and destination area j, each cost clamped to
  /// [0, 1] (NaN: 1): entry (i, j) of `weighted_cost(costs(source, dest), weights)`, bit for bit.
  double weighted_cost(const descriptors_type& source, const descriptors_type& dest, std::size_t i, std::size_t j,
                       const std::array<double, size>& weights) const {
    double total = 0.0;
    weighted_cost_each(source, dest, i, j, weights, total, std::index_sequence_for<Features...>{});
    return total;
  }

  /// Per feature, every area's `bound_key` (empty for a feature without one).
  std::array<std::vector<double>, size> bound_keys(const descriptors_type& descriptors) const {
    std::array<std::vector<double>, size> out;
    bound_keys_each(descriptors, out, std::index_sequence_for<Features...>{});
    return out;
  }

  /// The segment evidence of every feature that gives one, for source area i and destination
  /// area j, in feature order.
  std::vector<SegmentMatch> segments(const descriptors_type& source, const descriptors_type& dest, std::size_t i,
                                     std::size_t j) const {
    std::vector<SegmentMatch> out;
    segments_each(source, dest, i, j, out, std::index_sequence_for<Features...>{});
    return out;
  }

 private:
  template <std::size_t... I>
  void describe_each(const AreaGraph& graph, descriptors_type& out, std::index_sequence<I...>) const {
    (describe_one<I>(graph, std::get<I>(out)), ...);
  }
  template <std::size_t I, class Vector>
  void describe_one(const AreaGraph& graph, Vector& out) const {
    out.reserve(graph.areas.size());
    for (const Area& area : graph.areas) out.push_back(std::get<I>(features).describe(graph, area));
  }

  template <std::size_t... I>
  void costs_each(const descriptors_type& s, const descriptors_type& d, std::vector<Eigen::MatrixXd>& out,
                  std::index_sequence<I...>) const {
    (out.push_back(cost_matrix<I>(std::get<I>(s), std::get<I>(d))), ...);
  }
  template <std::size_t I, class Descriptor>
  double unit_cost(const Descriptor& s, const Descriptor& d) const {
    const double c = std::get<I>(features).cost(s, d);
    // A user feature returning NaN or values outside [0, 1] must not derail the ranking.
    return std::isfinite(c) ? std::clamp(c, 0.0, 1.0) : 1.0;
  }
  template <std::size_t I, class Vector>
  Eigen::MatrixXd cost_matrix(const Vector& s, const Vector& d) const {
    Eigen::MatrixXd m(static_cast<Eigen::Index>(s.size()), static_cast<Eigen::Index>(d.size()));
    for (std::size_t i = 0; i < s.size(); ++i) {
      for (std::size_t j = 0; j < d.size(); ++j) {
        m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = unit_cost<I>(s[i], d[j]);
      }
    }
    return m;
  }

  template <std::size_t... I>
  void weighted_cost_each(const descriptors_type& s, const descriptors_type& d, std::size_t i, std::size_t j,
                          const std::array<double, size>& weights, double& total, std::index_sequence<I...>) const {
    // In feature order, one product added at a time: the sum `weighted_cost` forms matrix-wise.
    ((total += weights[I] * unit_cost<I>(std::get<I>(s)[i], std::get<I>(d)[j])), ...);
  }

  template <std::size_t... I>
  void bound_keys_each(const descriptors_type& descriptors, std::array<std::vector<double>, size>& out,
                       std::index_sequence<I...>) const {
    (bound_keys_one<I>(std::get<I>(descriptors), out[I]), ...);
  }
  template <std::size_t I, class Vector>
  void bound_keys_one(const Vector& descriptors, std::vector<double>& out) const {
    using F = std::tuple_element_t<I, std::tuple<Features...>>;
    if constexpr (feature_has_bound_key_v<F>) {
      out.reserve(descriptors.size());
      for (const auto& d : descriptors) out.push_back(std::get<I>(features).bound_key(d));
    }
  }

  template <std::size_t... I>
  void segments_each(const descriptors_type& s, const descriptors_type& d, std::size_t i, std::size_t j,
                     std::vector<SegmentMatch>& out, std::index_sequence<I...>) const {
    (segments_one<I>(std::get<I>(s)[i], std::get<I>(d)[j], out), ...);
  }
  template <std::size_t I, class Descriptor>
  void segments_one(const Descriptor& s, const Descriptor& d, std::vector<SegmentMatch>& out) const {
    using F = std::tuple_element_t<I, std::tuple<Features...>>;
    if constexpr (feature_has_segments_v<F>) {
      if (auto match = std::get<I>(features).segments(s, d)) out.push_back(*match);
    }
  }
};

/// The paper's features: area size, passage distances, convex-hull longest distance.
using PaperFeatures = FeatureSet<AreaSize, PassageDistances, HullDiameter>;

template <class T>
struct is_feature_set : std::false_type {};
template <class... F>
struct is_feature_set<FeatureSet<F...>> : std::true_type {};

}  // namespace areamatch
