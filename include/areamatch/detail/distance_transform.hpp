#pragma once
/// \file detail/distance_transform.hpp
/// Exact squared Euclidean distance transform on a grid (Felzenszwalb & Huttenlocher's lower
/// envelope of parabolas along rows after a 1D pass along columns, O(cells)).

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace areamatch::detail {

/// For every cell, the squared distance (in cells) to the nearest cell where `is_source` is true;
/// a large value when there is none. Cells outside the grid are not sources.
template <class IsSource>
std::vector<float> squared_distance_transform(int width, int height, IsSource&& is_source) {
  const float infinity = 1e20f;
  const std::size_t n = static_cast<std::size_t>(width) * height;
  // Pass 1, along columns: distance to the nearest source in the same column. For binary sources
  // this is two linear scans, done row by row so memory is read in order.
  std::vector<float> d(n);
  const float far = static_cast<float>(width + height);
  for (int r = 0; r < height; ++r) {
    float* row = &d[static_cast<std::size_t>(r) * width];
    const float* above = r > 0 ? row - width : nullptr;
    for (int c = 0; c < width; ++c) row[c] = is_source(c, r) ? 0.0f : (above ? std::min(above[c] + 1.0f, far) : far);
  }
  for (int r = height - 2; r >= 0; --r) {
    float* row = &d[static_cast<std::size_t>(r) * width];
    const float* below = row + width;
    for (int c = 0; c < width; ++c) row[c] = std::min(row[c], below[c] + 1.0f);
  }
  for (float& v : d) v = v >= far ? infinity : v * v;

  const int longest = width > height ? width : height;
  std::vector<float> f(longest), out(longest), z(longest + 1);
  std::vector<int> v(longest);
  // 1D transform of f[0..count) into out[0..count): the lower envelope of the parabolas
  // (q − p)² + f[p] over the finite samples p.
  auto transform_1d = [&](int count) {
    int k = -1;
    for (int q = 0; q < count; ++q) {
      if (f[q] >= infinity) continue;
      double s = 0.0;
      while (k >= 0) {
        const int p = v[k];
        s = ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * (q - p));
        if (s > z[k]) break;
        --k;
      }
      if (k < 0) {
        k = 0;
        v[0] = q;
        z[0] = -infinity;
      } else {
        ++k;
        v[k] = q;
        z[k] = static_cast<float>(s);
      }
      z[k + 1] = infinity;
    }
    if (k < 0) {
      for (int q = 0; q < count; ++q) out[q] = infinity;
      return;
    }
    k = 0;
    for (int q = 0; q < count; ++q) {
      while (z[k + 1] < q) ++k;
      const float diff = static_cast<float>(q - v[k]);
      out[q] = diff * diff + f[v[k]];
    }
  };
  for (int r = 0; r < height; ++r) {
    float* row = &d[static_cast<std::size_t>(r) * width];
    for (int c = 0; c < width; ++c) f[c] = row[c];
    transform_1d(width);
    for (int c = 0; c < width; ++c) row[c] = out[c];
  }
  return d;
}

}  // namespace areamatch::detail
