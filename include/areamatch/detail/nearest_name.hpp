#pragma once
/// \file detail/nearest_name.hpp
/// The known name nearest a mistyped one, for error messages ("did you mean ...?").

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

namespace areamatch::detail {

/// Edit distance (insertions, deletions, substitutions) between two names.
inline std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

/// The name of `known` nearest `name` when it is a typo away (at most a quarter of its letters,
/// and at least one, differ); else "". The first of equally near ones.
template <class Names>
std::string nearest_name(const std::string& name, const Names& known) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(1, name.size() / 4) + 1;
  for (const std::string& k : known) {
    const std::size_t d = edit_distance(name, k);
    if (d < best_distance) best = k, best_distance = d;
  }
  return best;
}

}  // namespace areamatch::detail
