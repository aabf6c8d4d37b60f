#pragma once
/// \file segment/area_pieces.hpp
/// Steps 4–7 of `build_areas`: the labelling as runs, its 4-connected pieces, small pieces merged
/// into the neighbour they share the longest border with, and which skeleton region became which area.

#include "../detail/blocks.hpp"
#include "../detail/disjoint_sets.hpp"
#include "binarize.hpp"

#include <algorithm>
#include <cstddef>
#include <map>
#include <queue>
#include <utility>
#include <vector>

namespace areamatch {
namespace detail {

/// A horizontal run of equal label; `piece`: the 4-connected piece of that label it belongs to.
struct LabelRun {
  int row, begin, end, label, piece;
};

/// The labelling as runs (far fewer than cells), in raster order; row r's are
/// [row_start[r], row_start[r + 1]).
struct LabelRuns {
  std::vector<LabelRun> runs;
  std::vector<std::size_t> row_start;
};

/// Step 4: the labelled cells (labels ≥ 0; `W` x `H`, row-major) as runs of equal label.
template <class Label>
LabelRuns label_runs(const std::vector<Label>& label, int W, int H) {
  LabelRuns out;
  out.row_start.assign(static_cast<std::size_t>(H) + 1, 0);
  for (int r = 0; r < H; ++r) {
    out.row_start[r] = out.runs.size();
    const Label* row = &label[static_cast<std::size_t>(r) * static_cast<std::size_t>(W)];
    for (int c = 0; c < W;) {
      const Label l = row[c];
      const int end = find_value(row, c + 1, W, l, false);
      if (l >= 0) out.runs.push_back({r, c, end, static_cast<int>(l), -1});
      c = end;
    }
  }
  out.row_start[H] = out.runs.size();
  return out;
}

/// The 4-connected pieces of equal label: their cell counts and regions, numbered in raster order
/// of their first run.
struct Pieces {
  std::vector<std::size_t> size;
  std::vector<int> region;
};

/// Step 5: every 4-connected piece of a label is its own piece at first (union-find over runs of
/// equal label that overlap in consecutive rows); sets each run's `piece`.
inline Pieces find_pieces(LabelRuns& labelled) {
  auto& runs = labelled.runs;
  DisjointSets joined(runs.size());
  for_each_vertical_contact(runs, labelled.row_start, 0, [&](std::size_t upper, std::size_t lower) {
    if (runs[upper].label == runs[lower].label) joined.join(upper, lower);
  });
  Pieces pieces;
  std::vector<int> piece_of_root(runs.size(), -1);
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const std::size_t root = joined.find(i);
    if (piece_of_root[root] < 0) {
      piece_of_root[root] = static_cast<int>(pieces.size.size());
      pieces.size.push_back(0);
      pieces.region.push_back(runs[i].label);
    }
    runs[i].piece = piece_of_root[root];
    pieces.size[runs[i].piece] += static_cast<std::size_t>(runs[i].end - runs[i].begin);
  }
  return pieces;
}

/// What merging small pieces leaves: the areas.
struct PieceAreas {
  std::vector<int> area_of_piece;  ///< per piece: its area, −1 when dropped
  int area_count = 0;
};

/// Step 6: repeatedly, the smallest piece below `min_cells` joins the neighbour it shares the
/// longest border with (union-find over pieces; borders counted once); a small piece with no
/// neighbour is dropped. The surviving pieces are the areas, numbered in raster order of their
/// first run; each run's `label` becomes its area (−1: dropped).
inline PieceAreas merge_small_pieces(LabelRuns& labelled, const Pieces& pieces, std::size_t min_cells) {
  auto& runs = labelled.runs;
  const auto& row_start = labelled.row_start;
  const std::size_t piece_count = pieces.size.size();
  const int H = static_cast<int>(row_start.size()) - 1;
  std::map<std::pair<int, int>, std::size_t> border;
  auto add_border = [&](int p, int q, std::size_t length) {
    if (p != q) border[{std::min(p, q), std::max(p, q)}] += length;
  };
  for (int r = 0; r < H; ++r)
    for (std::size_t i = row_start[r]; i + 1 < row_start[r + 1]; ++i)
      if (runs[i].end == runs[i + 1].begin) add_border(runs[i].piece, runs[i + 1].piece, 1);
  for_each_vertical_contact(runs, row_start, 0, [&](std::size_t upper, std::size_t lower) {
    const int overlap = std::min(runs[upper].end, runs[lower].end) - std::max(runs[upper].begin, runs[lower].begin);
    add_border(runs[upper].piece, runs[lower].piece, static_cast<std::size_t>(overlap));
  });
  DisjointSets merged(piece_count);  // the caller picks the survivor: `attach`, not `join`
  auto find = [&](int p) { return static_cast<int>(merged.find(static_cast<std::size_t>(p))); };
  std::vector<std::size_t> size(pieces.size);
  std::vector<bool> dropped(piece_count, false);
  std::vector<std::map<int, std::size_t>> neighbours(piece_count);  // piece → border length
  for (const auto& [pair, length] : border) {
    neighbours[pair.first][pair.second] += length;
    neighbours[pair.second][pair.first] += length;
  }
  // Smallest first (ties: lowest id); entries go stale when a piece grows or merges away.
  using Entry = std::pair<std::size_t, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> small;
  for (std::size_t p = 0; p < piece_count; ++p)
    if (size[p] < min_cells) small.push({size[p], static_cast<int>(p)});
  while (!small.empty()) {
    const auto [entry_size, p] = small.top();
    small.pop();
    if (find(p) != p || dropped[p] || size[p] != entry_size) continue;
    std::map<int, std::size_t> shared;
    for (const auto& [q, length] : neighbours[p]) {
      const int root = find(q);
      if (root != p && !dropped[root]) shared[root] += length;
    }
    int target = -1;
    std::size_t most = 0;
    for (const auto& [q, length] : shared)
      if (length > most) target = q, most = length;
    if (target < 0) {
      dropped[p] = true;
      continue;
    }
    merged.attach(static_cast<std::size_t>(p), static_cast<std::size_t>(target));
    size[target] += size[p];
    for (const auto& [q, length] : shared) neighbours[target][q] += length;
    neighbours[p].clear();
    if (size[target] < min_cells) small.push({size[target], target});
  }
  std::vector<int> area_of_root(piece_count, -1);
  int area_count = 0;
  for (auto& run : runs) {
    const int root = find(run.piece);
    if (dropped[root]) {
      run.label = -1;
      continue;
    }
    if (area_of_root[root] < 0) area_of_root[root] = area_count++;
    run.label = area_of_root[root];
  }
  std::vector<int> area_of_piece(piece_count, -1);
  for (std::size_t p = 0; p < piece_count; ++p) {
    const int root = find(static_cast<int>(p));
    if (!dropped[root]) area_of_piece[p] = area_of_root[root];
  }
  return {std::move(area_of_piece), area_count};
}

/// Step 7: which skeleton region became which area: the area holding most of the region's cells
/// (counted per piece: a piece lies wholly in one area); −1 for a region with no cells left.
inline std::vector<int> area_of_regions(int region_count, const Pieces& pieces, const std::vector<int>& area_of_piece) {
  std::vector<std::map<int, std::size_t>> region_votes(static_cast<std::size_t>(region_count));
  for (std::size_t p = 0; p < pieces.size.size(); ++p) {
    if (area_of_piece[p] >= 0) region_votes[pieces.region[p]][area_of_piece[p]] += pieces.size[p];
  }
  std::vector<int> area_of_region(static_cast<std::size_t>(region_count), -1);
  for (int r = 0; r < region_count; ++r) {
    std::size_t most = 0;
    for (const auto& [a, v] : region_votes[r])
      if (v > most) area_of_region[r] = a, most = v;
  }
  return area_of_region;
}

}  // namespace detail
}  // namespace areamatch
