#pragma once
/// \file detail/span.hpp
/// A read-only view of consecutive elements held elsewhere (C++17 has no std::span): a
/// component's runs, a sample's neighbours, a skeleton branch's samples.

#include <cstddef>

namespace areamatch::detail {

/// [first, last) of an array owned by someone else; valid while that array is neither changed nor gone.
template <class T>
struct ConstSpan {
  const T* first = nullptr;
  const T* last = nullptr;
  const T* begin() const { return first; }
  const T* end() const { return last; }
  std::size_t size() const { return static_cast<std::size_t>(last - first); }
  bool empty() const { return first == last; }
  const T& operator[](std::size_t i) const { return first[i]; }
  const T& front() const { return *first; }
  const T& back() const { return *(last - 1); }
};

}  // namespace areamatch::detail
