#pragma once
/// \file detail/run_components.hpp
/// Connected components of a binary mask, computed on horizontal runs of cells.

#include "blocks.hpp"
#include "disjoint_sets.hpp"
#include "span.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace areamatch::detail {

struct CellRun {
  int row, begin, end;
};

/// Horizontal runs of cells, in raster order: a mask kept as its runs, far smaller than its bytes
/// on a map.
struct RowRuns {
  std::vector<CellRun> runs;
  std::vector<std::size_t> row_start;  ///< the runs of row r are [row_start[r], row_start[r + 1])

  static constexpr std::size_t none = static_cast<std::size_t>(-1);

  /// Row r's runs, left to right; r within the image.
  ConstSpan<CellRun> row(int r) const {
    return {runs.data() + row_start[static_cast<std::size_t>(r)], runs.data() + row_start[static_cast<std::size_t>(r) + 1]};
  }
  /// The run holding cell (col, row), or `none`; `row` within the image.
  std::size_t run_at(int col, int row) const {
    const ConstSpan<CellRun> in_row = this->row(row);
    const CellRun* after = std::upper_bound(in_row.begin(), in_row.end(), col, [](int c, const CellRun& run) { return c < run.begin; });
    if (after == in_row.begin() || col >= (after - 1)->end) return none;
    return static_cast<std::size_t>(after - 1 - runs.data());
  }
  /// Whether cell (col, row) lies in a run; a cell outside the image lies in none.
  bool contains(int col, int row) const {
    return row >= 0 && static_cast<std::size_t>(row) + 1 < row_start.size() && run_at(col, row) != none;
  }
};

/// The runs of the cells of an image (`width` x `height` values, row-major) that equal `value`
/// (`equal`) or differ from it.
template <class T>
RowRuns row_runs_of(const T* values, int width, int height, T value, bool equal) {
  RowRuns out;
  out.row_start.assign(static_cast<std::size_t>(height) + 1, 0);
  for (int r = 0; r < height; ++r) {
    out.row_start[r] = out.runs.size();
    const T* row = values + static_cast<std::size_t>(r) * static_cast<std::size_t>(width);
    for (int c = find_value(row, 0, width, value, equal); c < width; c = find_value(row, c, width, value, equal)) {
      const int begin = c;
      c = find_value(row, c, width, value, !equal);
      out.runs.push_back({r, begin, c});
    }
  }
  out.row_start[height] = out.runs.size();
  return out;
}

/// The horizontal runs of the cells with `mask == value`, in raster order, and their connected
/// components (fast on maps, which are long runs).
struct RunComponents : RowRuns {
  std::vector<std::size_t> component;  ///< per run: the first run of its component
};

/// Calls `touch(upper, lower)` (indices into `runs`) for every two runs of consecutive rows that
/// share a horizontal border, or with `reach` 1 also those meeting only at a corner. `runs` are
/// in raster order (any type with `begin` and `end` columns); row r's are [row_start[r],
/// row_start[r + 1]). Pairs come in the order of the lower run, then of the upper one.
template <class Run, class Touch>
void for_each_vertical_contact(const std::vector<Run>& runs, const std::vector<std::size_t>& row_start, int reach,
                               Touch&& touch) {
  const std::size_t rows = row_start.size() - 1;
  for (std::size_t r = 1; r < rows; ++r) {
    std::size_t j = row_start[r - 1];
    for (std::size_t i = row_start[r]; i < row_start[r + 1]; ++i) {
      while (j < row_start[r] && runs[j].end + reach <= runs[i].begin) ++j;
      for (std::size_t k = j; k < row_start[r] && runs[k].begin < runs[i].end + reach; ++k) touch(k, i);
    }
  }
}

/// `RunComponents` of the cells with `values == value` in an image of bytes or wider values,
/// 4-connected or with `eight` 8-connected.
template <class T>
RunComponents run_components_of(const std::vector<T>& values, int width, int height, T value, bool eight) {
  RunComponents out{row_runs_of(values.data(), width, height, value, true), {}};
  const auto& runs = out.runs;
  DisjointSets joined(runs.size());
  // 8-connectivity also joins runs touching at a corner.
  for_each_vertical_contact(runs, out.row_start, eight ? 1 : 0,
                            [&](std::size_t upper, std::size_t lower) { joined.join(lower, upper); });
  out.component.resize(runs.size());
  for (std::size_t i = 0; i < runs.size(); ++i) out.component[i] = joined.find(i);
  return out;
}

/// `RunComponents` of the cells with `mask == value` of a byte mask.
inline RunComponents run_components(const std::vector<std::uint8_t>& mask, int width, int height, std::uint8_t value,
                                    bool eight) {
  return run_components_of(mask, width, height, value, eight);
}

/// A component's runs: a view into `for_each_run_component`'s storage.
using RunSpan = ConstSpan<CellRun>;

/// Connected components of the cells with `mask == value`: calls `on_component(runs)` with each
/// component's runs (a `RunSpan`, in raster order), components in the order of their first run.
/// The components are all found before the first call, so `on_component` may change `mask`.
template <class OnComponent>
void for_each_run_component(const std::vector<std::uint8_t>& mask, int width, int height, std::uint8_t value, bool eight,
                            OnComponent&& on_component) {
  const RunComponents rc = run_components(mask, width, height, value, eight);
  // Runs grouped by component (a counting sort on the component's first run).
  const std::size_t n = rc.runs.size();
  std::vector<std::size_t> start(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++start[rc.component[i] + 1];
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<CellRun> grouped(n);
  std::vector<std::size_t> next(start.begin(), start.end() - 1);
  for (std::size_t i = 0; i < n; ++i) grouped[next[rc.component[i]]++] = rc.runs[i];
  for (std::size_t c = 0; c < n; ++c)
    if (start[c + 1] > start[c]) on_component(RunSpan{grouped.data() + start[c], grouped.data() + start[c + 1]});
}

}  // namespace areamatch::detail
