#pragma once
/// \file match/raster.hpp
/// An Area Graph's labelled free space on square cells of a chosen size (e.g. 0.2 m), so that
/// the overlap of two maps under a candidate transform is a few thousand lookups instead of a
/// polygon intersection. The verification stage scores hundreds of candidates this way
/// (docs/algorithm.md).

#include "../area_graph.hpp"
#include "../error.hpp"
#include "../transform.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace areamatch {

/// A half-open pixel rectangle [col0, col1) × [row0, row1).
struct PixelBounds {
  int col0 = 0, row0 = 0, col1 = 0, row1 = 0;
  bool empty() const { return col1 <= col0 || row1 <= row0; }
  bool contains(int col, int row) const { return col >= col0 && col < col1 && row >= row0 && row < row1; }
};

namespace detail {

/// The row-major cell indices of `cells` (of a grid `width` cells wide) that lie within `bounds`,
/// in their order.
inline std::vector<std::size_t> cells_within(const std::vector<std::size_t>& cells, const PixelBounds& bounds, int width) {
  const auto w = static_cast<std::size_t>(width);
  std::vector<std::size_t> within;
  within.reserve(cells.size());
  for (const std::size_t i : cells) {
    if (bounds.contains(static_cast<int>(i % w), static_cast<int>(i / w))) within.push_back(i);
  }
  return within;
}

/// The distinct values of `labels` with how often each occurs, values ascending (`labels` is
/// sorted in place): the areas one area's cells fell into, without a table of every area.
inline std::vector<std::pair<int, std::size_t>> counted(std::vector<int>& labels) {
  std::sort(labels.begin(), labels.end());
  std::vector<std::pair<int, std::size_t>> out;
  for (std::size_t k = 0; k < labels.size();) {
    std::size_t end = k;
    while (end < labels.size() && labels[end] == labels[k]) ++end;
    out.emplace_back(labels[k], end - k);
    k = end;
  }
  return out;
}

}  // namespace detail

/// The pixels that can hold an area: the envelope of the area polygons, grown by `margin` pixels
/// and clipped to the grid. Scans over the labels stay inside it, so a building in a corner of a
/// huge image costs what the building costs.
inline PixelBounds label_bounds(const AreaGraph& graph, int margin = 2) {
  const GridInfo& g = graph.grid;
  PixelBounds b{g.width, g.height, 0, 0};
  const Eigen::Affine2d pixel_from_world = g.world_from_pixel().inverse();
  for (const Area& area : graph.areas) {
    for (const auto& p : area.polygon.outer()) {
      const Eigen::Vector2d q = pixel_from_world * to_vector(p);
      b.col0 = std::min(b.col0, static_cast<int>(std::floor(q.x())) - margin);
      b.row0 = std::min(b.row0, static_cast<int>(std::floor(q.y())) - margin);
      b.col1 = std::max(b.col1, static_cast<int>(std::ceil(q.x())) + margin + 1);
      b.row1 = std::max(b.row1, static_cast<int>(std::ceil(q.y())) + margin + 1);
    }
  }
  b.col0 = std::max(0, b.col0);
  b.row0 = std::max(0, b.row0);
  b.col1 = std::min(g.width, b.col1);
  b.row1 = std::min(g.height, b.row1);
  if (b.empty()) b = {0, 0, 0, 0};
  return b;
}

/// The areas of one map resampled onto cells of side `cell_m`. A cell belongs to the area that
/// holds most of its map cells, and to none when less than half of it is in some area.
struct AreaRaster {
  double cell_m = 0.0;
  int width = 0;
  int height = 0;
  /// World metres → continuous raster coordinates; cell (c, r) covers [c, c+1) × [r, r+1).
  Eigen::Affine2d cell_from_world = Eigen::Affine2d::Identity();
  Eigen::Affine2d world_from_cell = Eigen::Affine2d::Identity();  ///< its inverse
  std::vector<int> labels;                   ///< per cell (row-major): area id or −1
  std::vector<Eigen::Vector2i> centre_cells;  ///< the labelled cells (col, row), in row-major order
  std::vector<int> centre_labels;            ///< their area ids
  std::vector<std::vector<int>> area_cells;  ///< per area: indices into `centre_cells`

  std::size_t labelled_count() const { return centre_cells.size(); }
  /// World centre of labelled cell k (of `centre_cells`): computed, not stored — on a large floor
  /// stored centres were 16 bytes a labelled cell in both maps' match data, the cells are 8.
  Eigen::Vector2d centre(std::size_t k) const {
    const Eigen::Vector2i& cell = centre_cells[k];
    return world_from_cell * Eigen::Vector2d(cell.x() + 0.5, cell.y() + 0.5);
  }
  double cell_area() const { return cell_m * cell_m; }

  /// The area id at a world point, −1 outside every area or outside the raster.
  int label_at(const Eigen::Vector2d& world) const { return label_at_cell(cell_from_world * world); }
  /// The area id at continuous raster coordinates, −1 outside.
  int label_at_cell(const Eigen::Vector2d& p) const {
    if (!(p.x() >= 0.0 && p.y() >= 0.0 && p.x() < width && p.y() < height)) return -1;
    return labels[static_cast<std::size_t>(static_cast<int>(p.y())) * static_cast<std::size_t>(width) +
                  static_cast<std::size_t>(static_cast<int>(p.x()))];
  }
};

/// Resamples `graph.labels` onto cells of side `cell_m` (metres, > 0; cells smaller than a map
/// cell are allowed but gain nothing).
inline AreaRaster make_area_raster(const AreaGraph& graph, double cell_m) {
  detail::require_positive(cell_m, "raster cell size");
  const GridInfo& g = graph.grid;
  const std::size_t expected = static_cast<std::size_t>(g.width) * static_cast<std::size_t>(g.height);
  if (graph.labels.size() != expected) throw parameter_error("area raster: the graph's labels do not match its grid");
  const double factor = cell_m / g.resolution;  // map cells per raster cell, along one side
  const PixelBounds bounds = label_bounds(graph);
  AreaRaster r;
  r.cell_m = cell_m;
  r.width = std::max(1, static_cast<int>(std::ceil((bounds.col1 - bounds.col0) / factor)));
  r.height = std::max(1, static_cast<int>(std::ceil((bounds.row1 - bounds.row0) / factor)));
  // Pixel (c, row) covers continuous pixel coordinates [c − ½, c + ½]; the raster starts at the
  // bounds' corner: u = (c − col0 + ½) / factor.
  Eigen::Affine2d cell_from_pixel = Eigen::Affine2d::Identity();
  cell_from_pixel.linear() = Eigen::Matrix2d::Identity() / factor;
  cell_from_pixel.translation() = Eigen::Vector2d(0.5 - bounds.col0, 0.5 - bounds.row0) / factor;
  r.cell_from_world = cell_from_pixel * g.world_from_pixel().inverse();
  r.world_from_cell = r.cell_from_world.inverse();

  r.labels.assign(static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height), -1);
  r.area_cells.resize(graph.areas.size());
  // Raster cell k starts at map cell `origin + first_cell(k)` (row or column), and ends where k + 1 starts.
  auto first_cell = [&](int k) { return static_cast<int>(std::ceil(k * factor - 0.5)); };
  // The map columns [first, end) of each raster column, and the raster column of each map column.
  const int span = bounds.col1 - bounds.col0;
  std::vector<int> col_first(static_cast<std::size_t>(r.width)), col_end(static_cast<std::size_t>(r.width));
  std::vector<int> col_of(static_cast<std::size_t>(std::max(span, 0)), -1);
  for (int col = 0; col < r.width; ++col) {
    col_first[col] = std::max(bounds.col0, bounds.col0 + first_cell(col));
    col_end[col] = std::min(bounds.col1, bounds.col0 + first_cell(col + 1));
    for (int x = col_first[col]; x < col_end[col]; ++x) col_of[static_cast<std::size_t>(x - bounds.col0)] = col;
  }
  // Per raster column of the current raster row: (area id, map cells) and the labelled cells.
  std::vector<std::vector<std::pair<int, int>>> votes(static_cast<std::size_t>(r.width));
  std::vector<int> labelled(static_cast<std::size_t>(r.width));
  auto vote = [&](int col, int label, int count) {
    auto& list = votes[static_cast<std::size_t>(col)];
    labelled[static_cast<std::size_t>(col)] += count;
    if (!list.empty() && list.back().first == label) {  // the usual case: same as the last one
      list.back().second += count;
      return;
    }
    auto it = std::find_if(list.begin(), list.end(), [&](const auto& v) { return v.first == label; });
    if (it == list.end()) list.emplace_back(label, count);
    else it->second += count;
  };
  for (int row = 0; row < r.height; ++row) {
    const int row0 = std::max(bounds.row0, bounds.row0 + first_cell(row));
    const int row1 = std::min(bounds.row1, bounds.row0 + first_cell(row + 1));
    for (auto& list : votes) list.clear();
    std::fill(labelled.begin(), labelled.end(), 0);
    // The map rows a run at a time (the labels are held as runs), split at the raster columns.
    for (int y = row0; y < row1; ++y) {
      const std::size_t base = static_cast<std::size_t>(y) * static_cast<std::size_t>(g.width);
      graph.labels.for_each_run(base + static_cast<std::size_t>(bounds.col0), base + static_cast<std::size_t>(bounds.col1),
                                [&](std::size_t first, std::size_t last, int label) {
                                  if (label < 0) return;
                                  for (int x = static_cast<int>(first - base), end = static_cast<int>(last - base); x < end;) {
                                    const int col = col_of[static_cast<std::size_t>(x - bounds.col0)];
                                    if (col < 0) {
                                      ++x;
                                      continue;
                                    }
                                    const int stop = std::min(end, col_end[static_cast<std::size_t>(col)]);
                                    vote(col, label, stop - x);
                                    x = stop;
                                  }
                                });
    }
    for (int col = 0; col < r.width; ++col) {
      const int cells = std::max(0, row1 - row0) * std::max(0, col_end[col] - col_first[col]);
      const auto& list = votes[static_cast<std::size_t>(col)];
      if (cells == 0 || 2 * labelled[static_cast<std::size_t>(col)] < cells) continue;
      // Most map cells wins; the lower id on ties, so the result does not depend on scan order.
      auto best = std::max_element(list.begin(), list.end(), [](const auto& a, const auto& b) {
        return a.second < b.second || (a.second == b.second && a.first > b.first);
      });
      const int label = best->first;
      r.labels[static_cast<std::size_t>(row) * static_cast<std::size_t>(r.width) + static_cast<std::size_t>(col)] = label;
      r.area_cells[static_cast<std::size_t>(label)].push_back(static_cast<int>(r.centre_cells.size()));
      r.centre_cells.emplace_back(col, row);
      r.centre_labels.push_back(label);
    }
  }
  // Kept with the match data: without the growth's slack (up to half).
  r.centre_cells.shrink_to_fit();
  r.centre_labels.shrink_to_fit();
  for (auto& cells : r.area_cells) cells.shrink_to_fit();
  return r;
}

/// How many of the source cells (every `stride`-th) land in some destination area under
/// T_dest_source.
inline std::size_t count_overlap(const AreaRaster& source, const AreaRaster& dest, const Similarity2& T_dest_source,
                                 std::size_t stride = 1) {
  // Fold the transform into the destination's raster map: one affine per point.
  const Eigen::Affine2d to_cell = dest.cell_from_world * T_dest_source.affine();
  const Eigen::Matrix2d m = to_cell.linear();
  const Eigen::Vector2d t = to_cell.translation();
  std::size_t hits = 0;
  for (std::size_t i = 0; i < source.labelled_count(); i += stride) {
    if (dest.label_at_cell(m * source.centre(i) + t) >= 0) ++hits;
  }
  return hits;
}

/// Intersection over union of the two maps' area-covered free space under T_dest_source, from
/// every `stride`-th source cell. Both rasters must have the same cell size (a rigid transform
/// keeps areas, so source cells and destination cells count alike).
inline double free_space_iou(const AreaRaster& source, const AreaRaster& dest, const Similarity2& T_dest_source,
                             std::size_t stride = 1) {
  if (source.centre_cells.empty() || dest.centre_cells.empty()) return 0.0;
  stride = std::max<std::size_t>(1, stride);
  const std::size_t samples = (source.labelled_count() + stride - 1) / stride;
  const double hits = static_cast<double>(count_overlap(source, dest, T_dest_source, stride)) *
                      static_cast<double>(source.labelled_count()) / static_cast<double>(samples);
  const double scale2 = T_dest_source.scale * T_dest_source.scale;
  const double union_cells = static_cast<double>(source.labelled_count()) * scale2 +
                             static_cast<double>(dest.labelled_count()) - hits * scale2;
  return union_cells > 0.0 ? std::clamp(hits * scale2 / union_cells, 0.0, 1.0) : 0.0;
}

/// The paper's overlap percentage OP = area(T(P_i) ∩ P_j) / min(a_i, a_j), counted on the rasters
/// from at most `max_samples` of the source area's cells.
inline double raster_area_overlap(const AreaRaster& source, const AreaRaster& dest, int source_area, int dest_area,
                                  double source_size_m2, double dest_size_m2, const Similarity2& T_dest_source,
                                  std::size_t max_samples = 128) {
  const double denominator = std::min(source_size_m2, dest_size_m2);
  if (!(denominator > 0.0)) return 0.0;
  const Eigen::Affine2d to_cell = dest.cell_from_world * T_dest_source.affine();
  const auto& cells = source.area_cells[static_cast<std::size_t>(source_area)];
  // An estimate from evenly spread cells is plenty for a filter; large corridors would dominate.
  const std::size_t stride = std::max<std::size_t>(1, (cells.size() + max_samples - 1) / std::max<std::size_t>(1, max_samples));
  std::size_t hits = 0, samples = 0;
  for (std::size_t k = 0; k < cells.size(); k += stride, ++samples) {
    if (dest.label_at_cell(to_cell * source.centre(static_cast<std::size_t>(cells[k]))) == dest_area) ++hits;
  }
  if (samples == 0) return 0.0;
  const double overlap_m2 = static_cast<double>(hits) * static_cast<double>(cells.size()) / static_cast<double>(samples) *
                            source.cell_area() * T_dest_source.scale * T_dest_source.scale;
  return std::min(1.0, overlap_m2 / denominator);
}

}  // namespace areamatch
