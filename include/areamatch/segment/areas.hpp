#pragma once
/// \file segment/areas.hpp
/// Stage 5–6 of segmentation: skeleton regions and passages → area polygons (the Area Graph).
///
/// Free space is labelled by growing every region from its skeleton samples, 4-connected, with
/// each passage's line (wall to wall) as a barrier, so every free cell ends up in exactly one
/// area. Growth first covers the *core* — free cells at least `min_clearance_m` from the walls,
/// where the skeleton lives — and then goes at most `min_clearance_m + fringe_m` further into
/// thinner space (room corners, cracks). Laser streaks through windows and doors — free space too thin to pass that leads
/// away from the building — stay outside every area; `AreaGraph::covered_fraction` says how much.
/// Areas smaller than `min_area_m2` merge into the neighbour they share the longest border with.
/// Polygons are traced along the labelled cells' sides (the same contour walk as the free-space
/// boundary, `detail::RingTracer`), so they follow the cell boundaries exactly and are valid.

#include "../area_graph.hpp"
#include "../detail/run_components.hpp"
#include "../error.hpp"
#include "../geometry.hpp"
#include "../grid.hpp"
#include "binarize.hpp"
#include "morphology.hpp"
#include "rooms.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <queue>
#include <string>
#include <utility>
#include <vector>

namespace areamatch {

/// Parameters of `build_areas`. Lengths in metres, areas in m².
struct AreaParams {
  /// Areas smaller than this merge into a neighbour (or are dropped when they have none).
  double min_area_m2 = 1.0;
  /// How far labelling continues beyond the space the skeleton reaches.
  double fringe_m = 0.5;
  /// The skeleton's `min_clearance_m` (the segmenter keeps them equal): labelling first grows
  /// over free cells at least this far from every wall, where the skeleton lives.
  double min_clearance_m = 0.25;
  /// An area whose hull diameter exceeds this many times its widest free disc's diameter is a
  /// corridor.
  double corridor_elongation = 3.5;

  void validate() const {
    detail::require_non_negative(min_area_m2, "AreaParams::min_area_m2");
    detail::require_non_negative(fringe_m, "AreaParams::fringe_m");
    detail::require_non_negative(min_clearance_m, "AreaParams::min_clearance_m");
    detail::require_non_negative(corridor_elongation, "AreaParams::corridor_elongation");
  }
};

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

/// Splits a closed lattice ring (first vertex not repeated) wherever it passes through the same
/// vertex twice, into simple loops. A ring does that only at vertices where its region's cells
/// touch diagonally, flagged in `pinned` (most rings have none and come back whole);
/// Boost.Geometry rejects such self-touching rings but accepts their loops as separate rings.
/// Walking the ring, each return to a vertex still on the walk closes the loop since its first
/// visit, which is cut out.
inline std::vector<std::vector<LatticePoint>> split_pinched_ring(std::vector<LatticePoint> ring,
                                                                 const std::vector<bool>& pinned) {
  std::vector<std::vector<LatticePoint>> loops;
  if (std::find(pinned.begin(), pinned.end(), true) == pinned.end()) {
    loops.push_back(std::move(ring));
    return loops;
  }
  std::vector<LatticePoint> walk;
  std::map<std::pair<int, int>, std::size_t> on_walk;  // pinned vertex → its index in `walk`
  for (std::size_t i = 0; i < ring.size(); ++i) {
    if (pinned[i]) {
      const auto [it, inserted] = on_walk.insert({{ring[i].x, ring[i].y}, walk.size()});
      if (!inserted) {
        const std::size_t first = it->second;
        for (std::size_t k = first + 1; k < walk.size(); ++k) on_walk.erase({walk[k].x, walk[k].y});
        loops.emplace_back(walk.begin() + static_cast<std::ptrdiff_t>(first), walk.end());
        walk.resize(first);
      }
    }
    walk.push_back(ring[i]);
  }
  loops.push_back(std::move(walk));
  return loops;
}

/// Twice the signed area of a lattice ring.
inline long long signed_area2(const std::vector<LatticePoint>& ring) {
  long long sum = 0;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const auto& a = ring[i];
    const auto& b = ring[(i + 1) % ring.size()];
    sum += static_cast<long long>(a.x) * b.y - static_cast<long long>(b.x) * a.y;
  }
  return sum;
}

/// Index offsets of a cell's right, left, lower and upper neighbours in a row-major image `W`
/// cells wide (callers keep off the image's border).
inline std::array<std::ptrdiff_t, 4> four_neighbour_offsets(int W) {
  return {1, -1, static_cast<std::ptrdiff_t>(W), -static_cast<std::ptrdiff_t>(W)};
}

/// The first step of labelling, done on runs instead of cells. `label` holds only the seeds
/// (listed in `seeds`); growth from them runs over the cells of `core` (barrier cells already
/// taken out), 4-connected. A connected piece of the core that the seeds of just one region touch
/// ends up wholly in that region, whatever the order of growth: such pieces are labelled here and
/// cleared from `core`. Pieces that seeds of several regions touch are left for the cell-by-cell
/// growth, which decides their borders by distance exactly as before.
inline void fill_uncontested_core(std::vector<std::uint8_t>& core, std::vector<int>& label,
                                  const std::vector<std::uint32_t>& seeds, int W, int H) {
  const RunComponents pieces = run_components(core, W, H, 1, false);
  constexpr int unreached = -1, contested = -2;
  std::vector<int> region_of_piece(pieces.runs.size(), unreached);
  auto touch = [&](std::size_t cell, int region) {
    const std::size_t run = pieces.run_at(static_cast<int>(cell % W), static_cast<int>(cell / W));
    if (run == RunComponents::none) return false;
    int& slot = region_of_piece[pieces.component[run]];
    if (slot == unreached) slot = region;
    else if (slot != region) slot = contested;
    return true;
  };
  for (std::uint32_t seed : seeds) {
    const int region = label[seed];
    if (touch(seed, region)) continue;
    // A seed off the passable cells grows into every passable neighbour. Seeds are free cells
    // and the mask's border is obstacle, so all four neighbours exist.
    for (std::ptrdiff_t d : four_neighbour_offsets(W)) {
      touch(static_cast<std::size_t>(static_cast<std::ptrdiff_t>(seed) + d), region);
    }
  }
  for (std::size_t i = 0; i < pieces.runs.size(); ++i) {
    const int region = region_of_piece[pieces.component[i]];
    if (region < 0) continue;
    const CellRun& run = pieces.runs[i];
    const auto from = static_cast<std::ptrdiff_t>(static_cast<std::size_t>(run.row) * W + run.begin);
    const auto to = static_cast<std::ptrdiff_t>(static_cast<std::size_t>(run.row) * W + run.end);
    std::fill(label.begin() + from, label.begin() + to, region);
    std::fill(core.begin() + from, core.begin() + to, std::uint8_t{0});
  }
}

inline Eigen::Vector2d lattice_to_world(const OccupancyGrid& grid, const Eigen::Vector2d& p) {
  return grid.pixel_to_world(p - Eigen::Vector2d(0.5, 0.5));
}

}  // namespace detail

namespace detail {

/// The labels while areas are built: a region id (≥ 0) per cell of the cropped mask, or one of
/// these.
inline constexpr int unlabelled = -1, barrier = -2;

/// Lattice coordinates of the cropped mask → world metres.
struct LatticeFrame {
  const OccupancyGrid* grid;
  Eigen::Vector2d offset;
  Eigen::Vector2d operator()(const Eigen::Vector2d& lattice) const { return lattice_to_world(*grid, lattice + offset); }
};

/// Step 1: seals every passage with a line of barrier cells (marked in `label`, taken out of
/// `core`), so growth cannot cross it. Doors are sealed one cell beyond both walls; junction
/// spokes start at the junction. Returns the barrier cells, ascending.
inline std::vector<std::uint32_t> seal_passages(const FreeSpace& space, const RoomDetection& rooms, std::vector<int>& label,
                                                std::vector<std::uint8_t>& core) {
  const int W = space.width;
  std::vector<std::uint32_t> barrier_cells;
  for (const auto& p : rooms.passages) {
    const Eigen::Vector2d direction = (p.line_b - p.line_a).normalized();
    supercover_line(p.junction ? p.line_a : Eigen::Vector2d(p.line_a - direction), p.line_b + direction, [&](int c, int r) {
      if (!space.is_free(c, r)) return;
      const std::size_t i = static_cast<std::size_t>(r) * W + c;
      if (label[i] == barrier) return;
      label[i] = barrier;
      core[i] = 0;  // growth never enters a barrier cell
      barrier_cells.push_back(static_cast<std::uint32_t>(i));
    });
  }
  std::sort(barrier_cells.begin(), barrier_cells.end());
  return barrier_cells;
}

/// Step 2: grows every region from its skeleton samples, 4-connected: first over the core, then
/// `fringe_steps` rings of cells into thinner space (corners and cracks; laser streaks only that
/// far). The mask's border is obstacle, so a free cell's four neighbours are always inside it.
inline void grow_regions(const FreeSpace& space, const RoomDetection& rooms, int fringe_steps, std::vector<int>& label,
                         std::vector<std::uint8_t>& core) {
  const int W = space.width, H = space.height;
  const SampleGraph& g = rooms.graph;
  std::vector<std::uint32_t> queue;
  for (std::size_t s = 0; s < g.samples.size(); ++s) {
    const int region = rooms.region_of_sample[s];
    if (region < 0) continue;
    const int c = static_cast<int>(std::floor(g.samples[s].position.x()));
    const int r = static_cast<int>(std::floor(g.samples[s].position.y()));
    if (!space.is_free(c, r)) continue;
    const std::size_t i = static_cast<std::size_t>(r) * W + c;
    if (label[i] != unlabelled) continue;  // a barrier, or seeded already
    label[i] = region;
    queue.push_back(static_cast<std::uint32_t>(i));
  }
  const auto neighbour_offset = four_neighbour_offsets(W);
  // Breadth-first growth; into_fringe grows one step (one ring of cells) per call. Over the core,
  // a cell is taken out of `core` when it is labelled, so `core` alone says what is still open.
  auto grow = [&](std::vector<std::uint32_t>& frontier, bool into_fringe) {
    std::vector<std::uint32_t> next;
    for (std::size_t head = 0; head < frontier.size(); ++head) {
      const std::size_t i = frontier[head];
      for (std::ptrdiff_t d : neighbour_offset) {
        const std::size_t j = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(i) + d);
        if (into_fringe) {
          if (label[j] != unlabelled || !space.free[j]) continue;
        } else {
          if (!core[j]) continue;
          core[j] = 0;
        }
        label[j] = label[i];
        (into_fringe ? next : frontier).push_back(static_cast<std::uint32_t>(j));
      }
    }
    frontier.swap(next);
  };
  // Most core components are reached by one region only: those are filled run by run and taken
  // out of `core`, so the cell-by-cell growth only settles the contested ones — with the same
  // result, since growth never crosses from one component into another.
  fill_uncontested_core(core, label, queue, W, H);
  for (std::uint32_t seed : queue) core[seed] = 0;  // labelled: no longer open
  grow(queue, false);
  queue.clear();
  // The fringe starts from labelled cells next to unlabelled free space (labelled cells are
  // free: only free runs are looked at).
  for (int r = 0; r < H; ++r) {
    const std::uint8_t* free_row = &space.free[static_cast<std::size_t>(r) * W];
    for (int c = find_byte_equal(free_row, 0, W, 1); c < W; c = find_byte_equal(free_row, c, W, 1)) {
      const int end = find_byte_not_equal(free_row, c, W, 1);
      for (; c < end; ++c) {
        const std::size_t i = static_cast<std::size_t>(r) * W + c;
        if (label[i] < 0) continue;
        for (std::ptrdiff_t d : neighbour_offset) {
          const std::size_t j = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(i) + d);
          if (label[j] == unlabelled && space.free[j]) {
            queue.push_back(static_cast<std::uint32_t>(i));
            break;
          }
        }
      }
    }
  }
  for (int ring = 0; ring < fringe_steps && !queue.empty(); ++ring) grow(queue, true);
}

/// Step 3: each barrier cell joins the region most of its neighbours belong to (ties: the lower id).
inline void assign_barrier_cells(const std::vector<std::uint32_t>& barrier_cells, int W, std::vector<int>& label) {
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
  for (std::size_t k = 0; k < barrier_cells.size(); ++k) label[barrier_cells[k]] = barrier_labels[k];
}

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

/// Step 4: the labelled cells as runs (labelled cells are free: non-free stretches are skipped).
inline LabelRuns label_runs(const FreeSpace& space, const std::vector<int>& label) {
  const int W = space.width, H = space.height;
  LabelRuns out;
  out.row_start.assign(static_cast<std::size_t>(H) + 1, 0);
  for (int r = 0; r < H; ++r) {
    out.row_start[r] = out.runs.size();
    const int* row = &label[static_cast<std::size_t>(r) * W];
    const std::uint8_t* free_row = &space.free[static_cast<std::size_t>(r) * W];
    int c = 0;
    while ((c = find_byte_equal(free_row, c, W, 1)) < W) {
      const int l = row[c];
      int end = c + 1;
      while (end < W && row[end] == l) ++end;
      if (l >= 0) out.runs.push_back({r, c, end, l, -1});
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
  std::vector<int> run_parent(runs.size());
  std::iota(run_parent.begin(), run_parent.end(), 0);
  auto find_run = [&](int i) {
    while (run_parent[i] != i) i = run_parent[i] = run_parent[run_parent[i]];
    return i;
  };
  for_each_vertical_contact(runs, labelled.row_start, 0, [&](std::size_t upper, std::size_t lower) {
    if (runs[upper].label != runs[lower].label) return;
    const int x = find_run(static_cast<int>(upper)), y = find_run(static_cast<int>(lower));
    if (x != y) run_parent[std::max(x, y)] = std::min(x, y);
  });
  Pieces pieces;
  std::vector<int> piece_of_root(runs.size(), -1);
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const int root = find_run(static_cast<int>(i));
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
  std::vector<int> parent(piece_count);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int p) {
    while (parent[p] != p) p = parent[p] = parent[parent[p]];
    return p;
  };
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
    parent[p] = target;
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

/// Step 8: the areas' polygons, traced on the final labels (written back into `label` from the
/// runs; one walk over every area's boundary at once), with their size, hull and centroid. An
/// area is 4-connected: its largest loop is the outline, and the loops turning the other way are
/// its holes (some touching the outline at a corner).
inline void trace_areas(const LabelRuns& labelled, int W, int H, double res, const LatticeFrame& to_world, int area_count,
                        std::vector<int>& label, AreaGraph& graph) {
  graph.areas.resize(area_count);
  for (const auto& run : labelled.runs) {
    const auto row = static_cast<std::ptrdiff_t>(run.row) * W;
    std::fill(label.begin() + row + run.begin, label.begin() + row + run.end, run.label);
    if (run.label >= 0) graph.areas[run.label].size_m2 += (run.end - run.begin) * res * res;
  }
  std::vector<std::vector<std::vector<LatticePoint>>> loops_of_area(area_count);
  auto keep_loops = [&](int a, const std::vector<LatticePoint>& ring, const std::vector<bool>& pinned) {
    for (auto& loop : split_pinched_ring(ring, pinned)) loops_of_area[a].push_back(std::move(loop));
  };
  // Every ring has vertical sides, and those lie at the ends of runs: start only there.
  RingTracer tracer(W, H, [&](int c, int r) { return label[static_cast<std::size_t>(r) * W + c]; });
  for (const auto& run : labelled.runs) {
    tracer.trace_from(run.begin, run.row, 1, keep_loops);
    tracer.trace_from(run.end - 1, run.row, 3, keep_loops);
  }
  auto world_ring = [&](const std::vector<LatticePoint>& lattice) {
    bg::model::ring<Point2> ring;
    for (const auto& v : lattice) {
      const Eigen::Vector2d w = to_world(Eigen::Vector2d(v.x, v.y));
      ring.push_back({w.x(), w.y()});
    }
    if (!ring.empty()) ring.push_back(ring.front());
    return ring;
  };
  for (int a = 0; a < area_count; ++a) {
    Area& area = graph.areas[a];
    area.id = a;
    auto& loops = loops_of_area[a];
    std::vector<long long> area2;
    for (const auto& loop : loops) area2.push_back(signed_area2(loop));
    std::size_t outline = 0;
    for (std::size_t k = 1; k < loops.size(); ++k)
      if (std::llabs(area2[k]) > std::llabs(area2[outline])) outline = k;
    Polygon2 polygon;
    polygon.outer() = world_ring(loops[outline]);
    for (std::size_t k = 0; k < loops.size(); ++k)
      if ((area2[k] > 0) != (area2[outline] > 0)) polygon.inners().push_back(world_ring(loops[k]));
    bg::correct(polygon);
    area.polygon = std::move(polygon);
    bg::convex_hull(area.polygon, area.convex_hull);
    Point2 centroid(0.0, 0.0);
    bg::centroid(area.polygon, centroid);
    area.centroid = to_vector(centroid);
  }
}

/// Step 9: each area's widest free disc (from its regions' skeleton samples) and its kind: a
/// corridor when its hull diameter exceeds `corridor_elongation` times that disc's diameter.
inline void measure_areas(const RoomDetection& rooms, const std::vector<int>& area_of_region, double res,
                          const AreaParams& params, AreaGraph& graph) {
  const SampleGraph& g = rooms.graph;
  for (std::size_t s = 0; s < g.samples.size(); ++s) {
    const int region = rooms.region_of_sample[s];
    if (region < 0 || area_of_region[region] < 0) continue;
    Area& area = graph.areas[area_of_region[region]];
    area.max_clearance_m = std::max(area.max_clearance_m, g.samples[s].clearance * res);
  }
  for (Area& area : graph.areas) {
    const double diameter = std::max(0.0, farthest_vertices(area.convex_hull).distance);
    const double width = 2.0 * std::max(area.max_clearance_m, res);
    area.kind = diameter > params.corridor_elongation * width ? AreaKind::corridor : AreaKind::room;
  }
}

/// Step 10: the passages between the areas their regions became (none inside one area).
inline void add_passages(const RoomDetection& rooms, const std::vector<int>& area_of_region, double res,
                         const LatticeFrame& to_world, AreaGraph& graph) {
  const SampleGraph& g = rooms.graph;
  std::vector<std::pair<std::pair<int, int>, const DetectedPassage*>> kept;
  for (const auto& p : rooms.passages) {
    const int a = area_of_region[p.region_a], b = area_of_region[p.region_b];
    if (a < 0 || b < 0 || a == b) continue;
    kept.push_back({{std::min(a, b), std::max(a, b)}, &p});
  }
  for (const auto& [areas, detected] : kept) {
    const SkeletonSample& s = g.samples[detected->sample];
    Passage passage;
    passage.id = static_cast<int>(graph.passages.size());
    passage.kind = detected->junction ? PassageKind::junction : PassageKind::door;
    passage.area_a = areas.first;
    passage.area_b = areas.second;
    passage.position = to_world(s.position);
    const Eigen::Vector2d fa = to_world(detected->line_a), fb = to_world(detected->line_b);
    passage.width_m = detected->junction ? 2.0 * s.clearance * res : (fb - fa).norm();
    passage.line = Segment2(to_point(fa), to_point(fb));
    graph.areas[areas.first].passages.push_back(passage.id);
    graph.areas[areas.second].passages.push_back(passage.id);
    graph.passages.push_back(passage);
  }
}

/// Step 11: the labels back onto the whole grid, row by row, into the working labels' buffer
/// (`label`, moved in: the runs hold the final labels, the buffer is no longer read): each row is
/// written once, while in cache (filling the grid with −1 first and scattering the runs after
/// cost office_g ~1.3 ms more). The grid's free cells are counted in the same pass, for
/// `covered_fraction` (a separate count reread the whole grid).
inline void write_labels(const OccupancyGrid& grid, const FreeSpace& space, const LabelRuns& labelled,
                         std::vector<int>&& label, AreaGraph& graph) {
  constexpr auto free_byte = static_cast<std::uint8_t>(CellState::free);
  std::size_t labelled_cells = 0, free_cells = 0;
  graph.labels = std::move(label);
  graph.labels.resize(grid.cells().size());
  for (int gr = 0; gr < grid.height(); ++gr) {
    int* out = &graph.labels[grid.index(0, gr)];
    std::fill(out, out + grid.width(), -1);
    const CellState* state = &grid.cells()[grid.index(0, gr)];
    free_cells += count_byte_equal(reinterpret_cast<const std::uint8_t*>(state), static_cast<std::size_t>(grid.width()), free_byte);
    const int r = gr - space.offset_row;
    if (r < 0 || r >= space.height) continue;
    for (std::size_t k = labelled.row_start[r]; k < labelled.row_start[r + 1]; ++k) {
      const LabelRun& run = labelled.runs[k];
      if (run.label < 0) continue;
      const int first = std::max(run.begin + space.offset_col, 0);
      const int last = std::min(run.end + space.offset_col, grid.width());
      if (first >= last) continue;
      std::fill(out + first, out + last, run.label);
      labelled_cells += count_byte_equal(reinterpret_cast<const std::uint8_t*>(state + first), static_cast<std::size_t>(last - first), free_byte);
    }
  }
  graph.covered_fraction = free_cells ? static_cast<double>(labelled_cells) / free_cells : 0.0;
}

}  // namespace detail

/// Builds the Area Graph from detected rooms (see the file comment). `grid` gives the frame and
/// the free-cell count for `covered_fraction`.
inline AreaGraph build_areas(const OccupancyGrid& grid, const FreeSpace& space, const RoomDetection& rooms,
                             const AreaParams& params = {}) {
  params.validate();
  const int W = space.width, H = space.height;
  const std::size_t N = static_cast<std::size_t>(W) * H;
  const double res = grid.resolution();
  AreaGraph graph;
  graph.grid = GridInfo::of(grid);
  if (N == 0) {
    graph.labels.assign(grid.cells().size(), -1);
    return graph;
  }
  if (N > std::numeric_limits<std::uint32_t>::max()) throw parameter_error("grid too large to segment");
  const detail::LatticeFrame to_world{&grid, Eigen::Vector2d(space.offset_col, space.offset_row)};

  // The core: free cells at least min_clearance from every wall, where the skeleton lives.
  std::vector<std::uint8_t> core = detail::erode(space, params.min_clearance_m / res + 0.5);
  // The working labels' buffer becomes `graph.labels` at the end (the grid's size, at least N):
  // one large allocation instead of two, whose first touch of every page costs most of a pass.
  std::vector<int> label;
  label.reserve(std::max(N, grid.cells().size()));
  label.assign(N, detail::unlabelled);

  const std::vector<std::uint32_t> barrier_cells = detail::seal_passages(space, rooms, label, core);
  const int fringe_steps = static_cast<int>(std::ceil((params.min_clearance_m + params.fringe_m) / res));
  detail::grow_regions(space, rooms, fringe_steps, label, core);
  detail::assign_barrier_cells(barrier_cells, W, label);

  detail::LabelRuns runs = detail::label_runs(space, label);
  const detail::Pieces pieces = detail::find_pieces(runs);
  const auto min_cells = static_cast<std::size_t>(std::ceil(params.min_area_m2 / (res * res)));
  const detail::PieceAreas areas = detail::merge_small_pieces(runs, pieces, min_cells);
  const std::vector<int> area_of_region = detail::area_of_regions(rooms.region_count(), pieces, areas.area_of_piece);

  detail::trace_areas(runs, W, H, res, to_world, areas.area_count, label, graph);
  detail::measure_areas(rooms, area_of_region, res, params, graph);
  detail::add_passages(rooms, area_of_region, res, to_world, graph);
  detail::write_labels(grid, space, runs, std::move(label), graph);
  return graph;
}

}  // namespace areamatch
