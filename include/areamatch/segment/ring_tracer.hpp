#pragma once
/// \file segment/ring_tracer.hpp
/// Contour following on the pixel-corner lattice (segment/boundary.hpp explains the lattice): the
/// closed boundaries of the free space, or of any labelled regions, as corner lists.

#include "../detail/blocks.hpp"
#include "binarize.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace areamatch {

/// A point of the pixel-corner lattice.
struct LatticePoint {
  int x = 0;
  int y = 0;
  friend bool operator==(const LatticePoint& a, const LatticePoint& b) { return a.x == b.x && a.y == b.y; }
  friend bool operator!=(const LatticePoint& a, const LatticePoint& b) { return !(a == b); }
};

namespace detail {

/// Closed boundary rings of the free space, as corner lists (first vertex not repeated), each
/// with a flag per vertex: true where the vertex is shared with another ring (a pinch).
struct TracedRings {
  std::vector<std::vector<LatticePoint>> rings;
  std::vector<std::vector<bool>> pinned;
};

/// Contour following on cell sides of a labelled lattice: traces the closed boundaries
/// (outlines and holes) of the 4-connected regions of equal label ≥ 0. `label_at(c, r)` gives a
/// cell's label (< 0: none); labelled cells must not lie on the lattice's border, so their
/// neighbours are inside it. Corners are listed with the region on the left (outlines
/// counter-clockwise on screen, y down; holes clockwise); `pinned` marks vertices where the region's cells touch
/// only diagonally, which the walk keeps apart (a ring bounding both cells passes there twice).
template <class LabelAt>
class RingTracer {
 public:
  RingTracer(int W, int H, LabelAt label_at)
      : W_(W), label_at_(std::move(label_at)), visited_(static_cast<std::size_t>(std::max(W, 0)) * std::max(H, 0), 0) {}

  /// Traces the ring running along side k (0 top, 1 left, 2 bottom, 3 right) of cell (c, r) and
  /// calls `on_ring(label, corners, pinned)`, unless that side is no boundary or already traced.
  template <class OnRing>
  void trace_from(int c0, int r0, int k0, OnRing&& on_ring) {
    const int label = label_at_(c0, r0);
    if (label < 0) return;
    auto inside = [&](int c, int r) { return label_at_(c, r) == label; };
    // Side k is walked with the cell on the left (top westwards, left southwards, …); its travel
    // direction is the outward normal of side k + 1.
    static const int nx[4] = {0, -1, 0, 1}, ny[4] = {-1, 0, 1, 0};   // outward normals
    static const int sx[4] = {1, 0, 0, 1}, sy[4] = {0, 0, 1, 1};     // start vertex offsets
    auto boundary_side = [&](int c, int r, int k) { return !inside(c + nx[k], r + ny[k]); };
    auto seen = [&](int c, int r, int k) { return visited_[static_cast<std::size_t>(r) * W_ + c] >> k & 1; };
    if (!boundary_side(c0, r0, k0) || seen(c0, r0, k0)) return;
    auto is_pinch = [&](int x, int y) {
      const bool tl = inside(x - 1, y - 1), tr = inside(x, y - 1), bl = inside(x - 1, y), br = inside(x, y);
      return tl == br && tr == bl && tl != tr;
    };
    ring_.clear();
    pinned_.clear();
    int c = c0, r = r0, k = k0, previous = -1;
    while (!seen(c, r, k)) {
      visited_[static_cast<std::size_t>(r) * W_ + c] |= static_cast<std::uint8_t>(1 << k);
      if (k != previous) {  // a corner: the walk changes direction here
        const int x = c + sx[k], y = r + sy[k];
        ring_.push_back({x, y});
        pinned_.push_back(is_pinch(x, y));
      }
      previous = k;
      const int next = (k + 1) & 3;
      const int ahead_c = c + nx[next], ahead_r = r + ny[next];
      if (boundary_side(c, r, next)) {
        k = next;  // turn around this cell (at a pinch this keeps diagonal cells apart)
      } else if (inside(ahead_c + nx[k], ahead_r + ny[k])) {
        c = ahead_c + nx[k];  // turn the other way, onto the diagonal cell
        r = ahead_r + ny[k];
        k = (k + 3) & 3;
      } else {
        c = ahead_c;  // straight on along the next cell's same side
        r = ahead_r;
      }
    }
    // The first vertex is a corner only if the walk turns there.
    if (ring_.size() > 1 && previous == k0) {
      ring_.erase(ring_.begin());
      pinned_.erase(pinned_.begin());
    }
    on_ring(label, ring_, pinned_);
  }

 private:
  int W_;
  LabelAt label_at_;
  std::vector<std::uint8_t> visited_;  ///< per cell, a bit per traced side
  std::vector<LatticePoint> ring_;
  std::vector<bool> pinned_;
};

/// out = cell free and some 4-neighbour not (masks of 0/1); `count` cells, see detail/blocks.hpp.
inline void boundary_flags(std::uint8_t* __restrict out, const std::uint8_t* __restrict cell,
                           const std::uint8_t* __restrict left, const std::uint8_t* __restrict right,
                           const std::uint8_t* __restrict above, const std::uint8_t* __restrict below, int count) {
  for (int k = 0; k < count; ++k)
    out[k] = static_cast<std::uint8_t>(cell[k] & ~(left[k] & right[k] & above[k] & below[k]) & 1);
}

inline TracedRings trace_rings(const FreeSpace& space) {
  const int W = space.width, H = space.height;
  TracedRings traced;
  RingTracer tracer(W, H, [&](int c, int r) { return space.free[static_cast<std::size_t>(r) * W + c] ? 0 : -1; });
  auto keep = [&](int, const std::vector<LatticePoint>& ring, const std::vector<bool>& pinned) {
    traced.rings.push_back(ring);
    traced.pinned.push_back(pinned);
  };
  // Boundary cells (free, with a non-free neighbour) in raster order. Free cells never lie on
  // the mask's border, so rows 0 and H − 1 hold none and the four neighbours exist. The test is
  // done a row at a time without branches (vectorised) and the row then scanned for hits.
  std::vector<std::uint8_t> boundary_cell(static_cast<std::size_t>(std::max(W, 0)), 0);
  for (int r = 1; r + 1 < H; ++r) {
    const std::uint8_t* row = &space.free[static_cast<std::size_t>(r) * W];
    in_blocks(1, W - 1, [&](int c, int count) {
      boundary_flags(&boundary_cell[c], row + c, row + c - 1, row + c + 1, row + c - W, row + c + W, count);
    });
    for (int c = find_byte_equal(boundary_cell.data(), 1, W - 1, 1); c + 1 < W;
         c = find_byte_equal(boundary_cell.data(), c + 1, W - 1, 1)) {
      for (int k = 0; k < 4; ++k) tracer.trace_from(c, r, k, keep);
    }
  }
  return traced;
}

}  // namespace detail
}  // namespace areamatch
