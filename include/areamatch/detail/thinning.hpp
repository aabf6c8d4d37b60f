#pragma once
// Thinned point lists, for a cheap first look before the full one: a fixed stride, or about a
// given number of points.

#include <Eigen/Core>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace areamatch::detail {

/// Every `stride`-th of `points` (a stride of 0 counts as 1), from the first, in order.
inline std::vector<Eigen::Vector2d> every_kth(const std::vector<Eigen::Vector2d>& points, std::size_t stride) {
  stride = std::max<std::size_t>(1, stride);
  std::vector<Eigen::Vector2d> out;
  out.reserve(points.size() / stride + 1);
  for (std::size_t i = 0; i < points.size(); i += stride) out.push_back(points[i]);
  return out;
}

/// Every k-th of `points`, k = max(1, size / about): about `about` of them (at most 2·about − 1),
/// evenly spread, in order. `about` > 0.
inline std::vector<Eigen::Vector2d> evenly_thinned(const std::vector<Eigen::Vector2d>& points, std::size_t about) {
  return every_kth(points, points.size() / about);
}

}  // namespace areamatch::detail
