#pragma once
/// \file match/verification/occupied_walls.hpp
/// Walls against walls (`MatchEvidence::occupied_wall_agreement`): each map's occupied cells,
/// thinned, and two masks of where the map has an occupied cell nearby — within the agreement
/// distance ("near") and within the context distance — on a coarse square raster, so that
/// judging a transform costs two mask reads per point.

#include "../../grid.hpp"
#include "../../transform.hpp"
#include "../raster.hpp"
#include "refine.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace areamatch::detail {

/// A square raster of bits, a row of 64-bit words per raster row: cheap to grow (a whole word of
/// cells per operation) and to read.
struct BitRaster {
  int width = 0, height = 0;
  std::size_t words_per_row = 0;
  std::vector<std::uint64_t> words;

  BitRaster() = default;
  BitRaster(int w, int h)
      : width(w), height(h), words_per_row((static_cast<std::size_t>(w) + 63) / 64),
        words(words_per_row * static_cast<std::size_t>(h), 0) {}
  std::uint64_t* row(int y) { return words.data() + static_cast<std::size_t>(y) * words_per_row; }
  const std::uint64_t* row(int y) const { return words.data() + static_cast<std::size_t>(y) * words_per_row; }
  void set(int x, int y) { row(y)[static_cast<std::size_t>(x) / 64] |= std::uint64_t{1} << (x % 64); }
  bool test(int x, int y) const { return (row(y)[static_cast<std::size_t>(x) / 64] >> (x % 64)) & 1u; }
};

/// `in` with every row shifted by `k` cells towards higher x (`k` > 0) or lower x (`k` < 0),
/// OR-ed into `out` (cells shifted past either end are dropped).
inline void or_shifted_rows(const BitRaster& in, int k, BitRaster& out) {
  const std::size_t n = in.words_per_row;
  const auto shift = static_cast<std::size_t>(k < 0 ? -k : k);
  const std::size_t word_shift = shift / 64;
  const unsigned bit_shift = static_cast<unsigned>(shift % 64);
  for (int y = 0; y < in.height; ++y) {
    const std::uint64_t* src = in.row(y);
    std::uint64_t* dst = out.row(y);
    for (std::size_t i = 0; i < n; ++i) {
      std::uint64_t v = 0;
      if (k > 0) {  // bit j of the result is bit j - shift of the source
        if (i >= word_shift) {
          v = src[i - word_shift] << bit_shift;
          if (bit_shift && i >= word_shift + 1) v |= src[i - word_shift - 1] >> (64 - bit_shift);
        }
      } else {  // bit j of the result is bit j + shift of the source
        if (i + word_shift < n) {
          v = src[i + word_shift] >> bit_shift;
          if (bit_shift && i + word_shift + 1 < n) v |= src[i + word_shift + 1] << (64 - bit_shift);
        }
      }
      dst[i] |= v;
    }
  }
  // Bits past `width` in the last word stay clear, so a later shift cannot bring them back in.
  if (const int spare = static_cast<int>(n * 64) - in.width; spare > 0 && n > 0) {
    const std::uint64_t keep = ~std::uint64_t{0} >> spare;
    for (int y = 0; y < out.height; ++y) out.row(y)[n - 1] &= keep;
  }
}

/// `mask` grown by `radius` cells in x and y (a square). Separable, and each direction in steps
/// that double: a set cell covering the offsets up to `reach` covers those up to `reach + k` after
/// OR-ing in the mask shifted by ±k. k ≤ reach + 1 keeps that exact at the raster's edges too (a
/// cell reached by a longer step would come through an intermediate cell beyond the edge, which
/// the shift drops) — so 1, 2, 4, ... and a radius of 15 cells costs four passes of whole words
/// per direction.
inline BitRaster dilated(const BitRaster& mask, int radius) {
  BitRaster out = mask;
  auto steps = [radius] {
    std::vector<int> k;
    for (int reach = 0; reach < radius;) {
      const int step = std::min(reach + 1, radius - reach);
      k.push_back(step);
      reach += step;
    }
    return k;
  }();
  for (const int k : steps) {  // along x
    const BitRaster before = out;
    or_shifted_rows(before, k, out);
    or_shifted_rows(before, -k, out);
  }
  const std::size_t n = out.words_per_row;
  for (const int k : steps) {  // along y
    const BitRaster before = out;
    for (int y = 0; y < out.height; ++y) {
      std::uint64_t* dst = out.row(y);
      if (y >= k) {
        const std::uint64_t* above = before.row(y - k);
        for (std::size_t i = 0; i < n; ++i) dst[i] |= above[i];
      }
      if (y + k < out.height) {
        const std::uint64_t* below = before.row(y + k);
        for (std::size_t i = 0; i < n; ++i) dst[i] |= below[i];
      }
    }
  }
  return out;
}

/// One map's occupied cells as walls against walls reads them.
struct OccupiedWalls {
  std::vector<Eigen::Vector2d> points;  ///< one occupied cell's centre per `spacing_m` square (world)
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  ///< world position of the masks' corner
  double cell_m = 0.1;
  BitRaster near, context;  ///< per mask cell: an occupied surface cell within the distance

  /// 0: outside the masks or nothing near; 1: within the context distance only; 2: also near.
  int classify(const Eigen::Vector2d& world) const {
    const double fx = (world.x() - origin.x()) / cell_m, fy = (world.y() - origin.y()) / cell_m;
    if (!(fx >= 0.0 && fy >= 0.0 && fx < context.width && fy < context.height)) return 0;
    const int x = static_cast<int>(fx), y = static_cast<int>(fy);
    return context.test(x, y) ? (near.test(x, y) ? 2 : 1) : 0;
  }
};

/// A map's walls against walls: the surface of its occupied space (an occupied cell with a
/// 4-neighbour that is not — solid filled regions, like a layout's outside, count by their
/// outline only), as points thinned to one per `spacing_m` square and as masks on `cell_m` cells
/// grown by `near_m` and `context_m`.
inline OccupiedWalls occupied_walls(const OccupancyGrid& grid, const GridInfo& info, double spacing_m, double cell_m,
                                    double near_m, double context_m) {
  OccupiedWalls w;
  w.cell_m = cell_m;
  const auto& cells = grid.cells();
  const std::vector<std::size_t> surface =
      edge_cells(info, PixelBounds{0, 0, grid.width(), grid.height()}, [&](std::size_t i) { return cells[i] == CellState::occupied; });
  if (surface.empty()) return w;
  w.points = boundary_points(info, surface, spacing_m);
  const Eigen::Affine2d world = info.world_from_pixel();
  const auto width = static_cast<std::size_t>(grid.width());
  auto position = [&](std::size_t i) {
    return Eigen::Vector2d(world * Eigen::Vector2d(static_cast<double>(i % width), static_cast<double>(i / width)));
  };
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::max()), hi = -lo;
  for (const std::size_t i : surface) {
    const Eigen::Vector2d p = position(i);
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  w.origin = lo - Eigen::Vector2d::Constant(context_m + cell_m);
  const int width_cells = static_cast<int>(std::ceil((hi.x() - w.origin.x() + context_m + cell_m) / cell_m)) + 1;
  const int height_cells = static_cast<int>(std::ceil((hi.y() - w.origin.y() + context_m + cell_m) / cell_m)) + 1;
  BitRaster mask(width_cells, height_cells);
  for (const std::size_t i : surface) {
    const Eigen::Vector2d p = position(i);
    mask.set(static_cast<int>((p.x() - w.origin.x()) / cell_m), static_cast<int>((p.y() - w.origin.y()) / cell_m));
  }
  w.near = dilated(mask, static_cast<int>(std::lround(near_m / cell_m)));
  w.context = dilated(mask, static_cast<int>(std::lround(context_m / cell_m)));
  return w;
}

/// Of `from`'s points (under T) that land within the context of `onto`'s walls, the share that
/// land near them; NaN when none lands within the context.
inline double near_share(const OccupiedWalls& from, const OccupiedWalls& onto, const Similarity2& T) {
  std::size_t in_context = 0, near = 0;
  for (const auto& p : from.points) {
    const int c = onto.classify(T * p);
    in_context += c > 0;
    near += c == 2;
  }
  return in_context ? static_cast<double>(near) / static_cast<double>(in_context) : std::numeric_limits<double>::quiet_NaN();
}

/// `MatchEvidence::occupied_wall_agreement`: the higher of the two directions' shares (one
/// direction alone when the other's walls come near nothing). The higher: a SLAM map's furniture
/// and laser streaks have nothing to land on in a floor plan, but the plan's walls all land on
/// the SLAM map's; two alike buildings' differing dividers disagree both ways.
inline double occupied_wall_agreement(const OccupiedWalls& source, const OccupiedWalls& dest, const Similarity2& T_dest_source) {
  return std::fmax(near_share(source, dest, T_dest_source), near_share(dest, source, T_dest_source.inverse()));
}

}  // namespace areamatch::detail
