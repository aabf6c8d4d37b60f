#pragma once
/// \file segment/area_growth.hpp
/// Steps 1–3 of `build_areas`: every passage sealed with a line of barrier cells, then every
/// skeleton region grown over free space from its samples (the core first, then the fringe), and
/// the barrier cells given to a neighbouring region. One image of working labels says all the
/// growth needs per cell — free or not, core or not, sealed, reached — so neither the free-space
/// mask nor the core is kept beside it.

#include "../detail/run_components.hpp"
#include "binarize.hpp"
#include "morphology.hpp"
#include "rooms.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <queue>
#include <utility>
#include <vector>

namespace areamatch {
namespace detail {

/// Marks the cells a straight line crosses, with no diagonal gaps (so a 4-connected flood
/// cannot slip through).
template <class Mark>
void supercover_line(const Eigen::Vector2d& a, const Eigen::Vector2d& b, Mark&& mark) {
  const double length = (b - a).norm();
  const int steps = std::max(1, static_cast<int>(std::ceil(length * 4.0)));
  int pc = static_cast<int>(std::floor(a.x())), pr = static_cast<int>(std::floor(a.y()));
  mark(pc, pr);
  for (int i = 1; i <= steps; ++i) {
    const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(i) / steps);
    const int c = static_cast<int>(std::floor(p.x())), r = static_cast<int>(std::floor(p.y()));
    if (c != pc && r != pr) mark(c, pr);  // close the diagonal step
    if (c != pc || r != pr) mark(c, r);
    pc = c;
    pr = r;
  }
}

/// Index offsets of a cell's right, left, lower and upper neighbours in a row-major image `W`
/// cells wide (callers keep off the image's border).
inline std::array<std::ptrdiff_t, 4> four_neighbour_offsets(int W) {
  return {1, -1, static_cast<std::ptrdiff_t>(W), -static_cast<std::ptrdiff_t>(W)};
}

/// The working labels while areas are built: a region id (≥ 0) per cell of the cropped mask, or
/// one of these; held as `Label`, 16 bits when the region ids fit (`build_areas`). A free cell not
/// yet reached is `unlabelled` or, in the core (free cells at least the skeleton's clearance from
/// every wall, where growth runs first), `open_core`.
inline constexpr int unlabelled = -1, open_core = -2, barrier = -3, not_free = -4;

/// Whether a working label is a free cell no region has reached yet.
inline bool unreached(int label) { return label == unlabelled || label == open_core; }

/// The working labels before growth: each cell `not_free`, `unlabelled` or `open_core`, from the
/// free space's runs (`free`: a W x H mask's, taken so they go on return) and its erosion by
/// `core_distance` cells (`erode_rows`, a band at a time). The runs, not the byte mask: on a large
/// floor they are a small fraction of it, and the labels are the largest buffer of the stage.
template <class Label>
std::vector<Label> initial_labels(RowRuns free, int W, int H, double core_distance) {
  const auto w = static_cast<std::size_t>(W);
  std::vector<Label> label(w * static_cast<std::size_t>(H), static_cast<Label>(not_free));
  erode_rows(free, W, H, core_distance, [&](int r, const std::uint8_t* core) {
    Label* out = &label[static_cast<std::size_t>(r) * w];
    for (const CellRun& run : free.row(r)) {
      for (int c = run.begin; c < run.end; ++c) out[c] = static_cast<Label>(core[c] ? open_core : unlabelled);
    }
  });
  return label;
}

/// The first step of labelling, done on runs instead of cells. `core_pieces` are the connected
/// pieces of the open core (barrier cells already taken out), found before `seed_cells` were
/// labelled; growth from the seeds runs over the open core, 4-connected. A piece that the seeds
/// of just one region touch ends up wholly in that region, whatever the order of growth: such
/// pieces are labelled here, so they are no longer open. Pieces that seeds of several regions
/// touch are left for the cell-by-cell growth, which decides their borders by distance.
template <class Label>
void fill_uncontested_core(const RunComponents& core_pieces, std::vector<Label>& label,
                           const std::vector<std::uint32_t>& seed_cells, int W) {
  constexpr int unreached_piece = -1, contested = -2;
  std::vector<int> region_of_piece(core_pieces.runs.size(), unreached_piece);
  auto touch = [&](std::size_t cell, int region) {
    const std::size_t run = core_pieces.run_at(static_cast<int>(cell % W), static_cast<int>(cell / W));
    if (run == RunComponents::none) return false;
    int& slot = region_of_piece[core_pieces.component[run]];
    if (slot == unreached_piece) slot = region;
    else if (slot != region) slot = contested;
    return true;
  };
  for (std::uint32_t seed : seed_cells) {
    const int region = label[seed];
    if (touch(seed, region)) continue;
    // A seed off the core grows into every core neighbour. Seeds are free cells and the mask's
    // border is not free, so all four neighbours exist.
    for (std::ptrdiff_t d : four_neighbour_offsets(W)) {
      touch(static_cast<std::size_t>(static_cast<std::ptrdiff_t>(seed) + d), region);
    }
  }
  for (std::size_t i = 0; i < core_pieces.runs.size(); ++i) {
    const int region = region_of_piece[core_pieces.component[i]];
    if (region < 0) continue;
    const CellRun& run = core_pieces.runs[i];
    const auto from = static_cast<std::ptrdiff_t>(static_cast<std::size_t>(run.row) * W + run.begin);
    const auto to = static_cast<std::ptrdiff_t>(static_cast<std::size_t>(run.row) * W + run.end);
    std::fill(label.begin() + from, label.begin() + to, static_cast<Label>(region));
  }
}

/// Step 1: seals every passage with a line of barrier cells (marked in `label`, so also out of
/// the open core), so growth cannot cross it. Doors are sealed one cell beyond both walls;
/// junction spokes start at the junction. Returns the barrier cells, ascending.
template <class Label>
std::vector<std::uint32_t> seal_passages(const FreeSpace& space, const RoomDetection& rooms, std::vector<Label>& label) {
  const int W = space.width;
  std::vector<std::uint32_t> barrier_cells;
  for (const auto& p : rooms.passages) {
    const Eigen::Vector2d direction = (p.line_b - p.line_a).normalized();
    supercover_line(p.junction ? p.line_a : Eigen::Vector2d(p.line_a - direction), p.line_b + direction, [&](int c, int r) {
      if (c < 0 || r < 0 || c >= W || r >= space.height) return;
      const std::size_t i = static_cast<std::size_t>(r) * W + c;
      if (label[i] == barrier || label[i] == not_free) return;
      label[i] = static_cast<Label>(barrier);
      barrier_cells.push_back(static_cast<std::uint32_t>(i));
    });
  }
  std::sort(barrier_cells.begin(), barrier_cells.end());
  return barrier_cells;
}

/// A region's seed: the free cell under one of its skeleton samples (row-major in the mask).
struct Seed {
  std::uint32_t cell;
  int region;
};

/// Every region's seeds, in sample order (samples off the free space, whose runs are `free` in a
/// mask `width` cells wide, left out): all that growth reads of the sample graph, so the graph can
/// be let go before the labels are made.
inline std::vector<Seed> region_seeds(const RowRuns& free, int width, const RoomDetection& rooms) {
  const SampleGraph& g = rooms.graph;
  std::vector<Seed> seeds;
  seeds.reserve(g.samples.size());  // made beside the graph, at its largest: no growth by doubling
  for (std::size_t s = 0; s < g.samples.size(); ++s) {
    const int region = rooms.region_of_sample[s];
    if (region < 0) continue;
    const int c = static_cast<int>(std::floor(g.samples[s].position.x()));
    const int r = static_cast<int>(std::floor(g.samples[s].position.y()));
    if (!free.contains(c, r)) continue;
    seeds.push_back({static_cast<std::uint32_t>(static_cast<std::size_t>(r) * width + c), region});
  }
  return seeds;
}

/// Step 2: grows every region from its seeds (`region_seeds`) over the working labels
/// (`initial_labels`, passages sealed), 4-connected: first over the core, then `fringe_steps`
/// rings of cells into thinner space (corners and cracks; laser streaks only that far). The mask's
/// border is not free, so a free cell's four neighbours are always inside it.
template <class Label>
void grow_regions(int W, int H, const std::vector<Seed>& seeds, int fringe_steps, std::vector<Label>& label) {
  // Most core pieces are reached by one region only: those are filled run by run, so the
  // cell-by-cell growth only settles the contested ones — with the same result, since growth
  // never crosses from one piece into another. The pieces are found before the seeds are
  // labelled: a seed in the core belongs to its piece.
  const RunComponents core_pieces = run_components_of(label, W, H, static_cast<Label>(open_core), false);
  std::vector<std::uint32_t> frontier, next;
  for (const Seed& seed : seeds) {
    if (!unreached(label[seed.cell])) continue;  // a barrier, or seeded already
    label[seed.cell] = static_cast<Label>(seed.region);
    frontier.push_back(seed.cell);
  }
  const auto neighbour_offset = four_neighbour_offsets(W);
  // Breadth-first, one ring of cells per call: over the core, into `open_core` cells only; into
  // the fringe, into any free cell not reached yet.
  auto grow_ring = [&](bool into_fringe) {
    next.clear();
    for (const std::uint32_t i : frontier) {
      for (std::ptrdiff_t d : neighbour_offset) {
        const std::size_t j = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(i) + d);
        if (into_fringe ? !unreached(label[j]) : label[j] != open_core) continue;
        label[j] = label[i];
        next.push_back(static_cast<std::uint32_t>(j));
      }
    }
    frontier.swap(next);
  };
  fill_uncontested_core(core_pieces, label, frontier, W);
  while (!frontier.empty()) grow_ring(false);
  // The fringe starts from labelled cells next to free space not reached yet (stretches of one
  // unlabelled state, most of all outside the free space, skipped a word at a time).
  for (int r = 0; r < H; ++r) {
    const Label* row = &label[static_cast<std::size_t>(r) * static_cast<std::size_t>(W)];
    for (int c = 0; c < W;) {
      if (row[c] < 0) {
        c = find_value(row, c + 1, W, row[c], false);
        continue;
      }
      const std::size_t i = static_cast<std::size_t>(r) * static_cast<std::size_t>(W) + static_cast<std::size_t>(c);
      for (std::ptrdiff_t d : neighbour_offset) {
        if (unreached(label[static_cast<std::size_t>(static_cast<std::ptrdiff_t>(i) + d)])) {
          frontier.push_back(static_cast<std::uint32_t>(i));
          break;
        }
      }
      ++c;
    }
  }
  for (int ring = 0; ring < fringe_steps && !frontier.empty(); ++ring) grow_ring(true);
}

/// Step 3: each barrier cell joins the region most of its neighbours belong to (ties: the lower id).
template <class Label>
void assign_barrier_cells(const std::vector<std::uint32_t>& barrier_cells, int W, std::vector<Label>& label) {
  const auto neighbour_offset = four_neighbour_offsets(W);
  auto majority_of_neighbours = [&](std::size_t i) {
    int candidates[4], votes[4], count = 0;
    for (std::ptrdiff_t d : neighbour_offset) {
      const int l = label[static_cast<std::size_t>(static_cast<std::ptrdiff_t>(i) + d)];
      if (l < 0) continue;
      int k = 0;
      while (k < count && candidates[k] != l) ++k;
      if (k == count) candidates[count] = l, votes[count++] = 0;
      ++votes[k];
    }
    int best = -1, best_votes = 0;
    for (int k = 0; k < count; ++k)
      if (votes[k] > best_votes || (votes[k] == best_votes && candidates[k] < best)) best = candidates[k], best_votes = votes[k];
    return best;
  };
  std::vector<int> barrier_labels;
  for (std::uint32_t i : barrier_cells) barrier_labels.push_back(majority_of_neighbours(i));
  for (std::size_t k = 0; k < barrier_cells.size(); ++k) label[barrier_cells[k]] = static_cast<Label>(barrier_labels[k]);
}

}  // namespace detail
}  // namespace areamatch
