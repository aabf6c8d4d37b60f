#pragma once
/// \file detail/run_components.hpp
/// Connected components of a binary mask, computed on horizontal runs of cells.

#include <algorithm>
#include <cstdint>
#include <vector>

namespace areamatch::detail {

/// Connected components of the cells with `mask == value`, found on horizontal runs (fast on
/// maps, which are long runs). Calls `on_component(runs)` with each component's runs as
/// (row, first col, end col) triples.
struct CellRun {
  int row, begin, end;
};

template <class OnComponent>
void for_each_run_component(const std::vector<std::uint8_t>& mask, int width, int height, std::uint8_t value, bool eight,
                            OnComponent&& on_component) {
  std::vector<CellRun> runs;
  std::vector<std::size_t> row_start(static_cast<std::size_t>(height) + 1, 0);
  for (int r = 0; r < height; ++r) {
    row_start[r] = runs.size();
    const std::uint8_t* row = &mask[static_cast<std::size_t>(r) * width];
    int c = 0;
    while (c < width) {
      if (row[c] != value) {
        ++c;
        continue;
      }
      const int begin = c;
      while (c < width && row[c] == value) ++c;
      runs.push_back({r, begin, c});
    }
  }
  row_start[height] = runs.size();
  std::vector<std::size_t> parent(runs.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = i;
  auto find = [&](std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  const int reach = eight ? 1 : 0;  // 8-connectivity also joins runs touching at a corner
  for (int r = 1; r < height; ++r) {
    std::size_t j = row_start[r - 1];
    for (std::size_t i = row_start[r]; i < row_start[r + 1]; ++i) {
      while (j < row_start[r] && runs[j].end + reach <= runs[i].begin) ++j;
      for (std::size_t k = j; k < row_start[r] && runs[k].begin < runs[i].end + reach; ++k) {
        const std::size_t a = find(i), b = find(k);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
      }
    }
  }
  std::vector<std::vector<CellRun>> components(runs.size());
  for (std::size_t i = 0; i < runs.size(); ++i) components[find(i)].push_back(runs[i]);
  for (const auto& component : components)
    if (!component.empty()) on_component(component);
}

}  // namespace areamatch::detail
