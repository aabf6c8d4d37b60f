#pragma once
/// \file segment/area_tracing.hpp
/// Steps 8–11 of `build_areas`: the labels written onto the grid, the areas' polygons traced
/// along the labelled cells' sides, their widest free disc and kind, and the passages between them.

#include "../area_graph.hpp"
#include "../geometry.hpp"
#include "../grid.hpp"
#include "area_params.hpp"
#include "area_pieces.hpp"
#include "binarize.hpp"
#include "boundary.hpp"
#include "rooms.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <utility>
#include <vector>

namespace areamatch {
namespace detail {

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

inline Eigen::Vector2d lattice_to_world(const OccupancyGrid& grid, const Eigen::Vector2d& p) {
  return grid.pixel_to_world(p - Eigen::Vector2d(0.5, 0.5));
}

/// Lattice coordinates of the cropped mask → world metres.
struct LatticeFrame {
  const OccupancyGrid* grid;
  Eigen::Vector2d offset;
  Eigen::Vector2d operator()(const Eigen::Vector2d& lattice) const { return lattice_to_world(*grid, lattice + offset); }
};

/// Step 8: the final labels (the runs hold them) onto the whole grid, row by row, into the
/// graph's run-length `LabelImage`; the areas are traced on it next. The grid's free cells are
/// counted in the same pass, for `covered_fraction` (a separate count reread the whole grid).
inline void write_labels(const OccupancyGrid& grid, const FreeSpace& space, const LabelRuns& labelled, AreaGraph& graph) {
  constexpr auto free_byte = static_cast<std::uint8_t>(CellState::free);
  std::size_t labelled_cells = 0, free_cells = 0;
  graph.labels.clear();
  for (int gr = 0; gr < grid.height(); ++gr) {
    const CellState* state = &grid.cells()[grid.index(0, gr)];
    free_cells += count_byte_equal(reinterpret_cast<const std::uint8_t*>(state), static_cast<std::size_t>(grid.width()), free_byte);
    int written = 0;  // cells of this row in the image so far
    const int r = gr - space.offset_row;
    if (r >= 0 && r < space.height) {
      for (std::size_t k = labelled.row_start[r]; k < labelled.row_start[r + 1]; ++k) {
        const LabelRun& run = labelled.runs[k];
        if (run.label < 0) continue;
        const int first = std::max(run.begin + space.offset_col, 0);
        const int last = std::min(run.end + space.offset_col, grid.width());
        if (first >= last) continue;
        graph.labels.append(static_cast<std::size_t>(first - written), -1);
        graph.labels.append(static_cast<std::size_t>(last - first), run.label);
        written = last;
        labelled_cells += count_byte_equal(reinterpret_cast<const std::uint8_t*>(state + first), static_cast<std::size_t>(last - first), free_byte);
      }
    }
    graph.labels.append(static_cast<std::size_t>(grid.width() - written), -1);
  }
  graph.labels.shrink_to_fit();
  graph.covered_fraction = free_cells ? static_cast<double>(labelled_cells) / free_cells : 0.0;
}

/// Step 9: the areas' polygons, traced on the graph's final labels (`write_labels`: the mask's
/// cell (c, r) is the grid's (c + offset_col, r + offset_row); one walk over every area's boundary
/// at once), with their size, hull and centroid. An area is 4-connected: its largest loop is the
/// outline, and the loops turning the other way are its holes (some touching the outline at a
/// corner).
inline void trace_areas(const LabelRuns& labelled, const FreeSpace& space, double res, const LatticeFrame& to_world,
                        int area_count, AreaGraph& graph) {
  const int W = space.width, H = space.height;
  graph.areas.resize(area_count);
  for (const auto& run : labelled.runs) {
    if (run.label >= 0) graph.areas[run.label].size_m2 += (run.end - run.begin) * res * res;
  }
  const int grid_width = graph.grid.width, grid_height = graph.grid.height;
  auto label_at = [&](int c, int r) {
    const int col = c + space.offset_col, row = r + space.offset_row;
    if (col < 0 || row < 0 || col >= grid_width || row >= grid_height) return -1;  // the mask's border
    return graph.labels[static_cast<std::size_t>(row) * static_cast<std::size_t>(grid_width) + static_cast<std::size_t>(col)];
  };
  std::vector<std::vector<std::vector<LatticePoint>>> loops_of_area(area_count);
  auto keep_loops = [&](int a, const std::vector<LatticePoint>& ring, const std::vector<bool>& pinned) {
    for (auto& loop : split_pinched_ring(ring, pinned)) loops_of_area[a].push_back(std::move(loop));
  };
  // Every ring has vertical sides, and those lie at the ends of runs: start only there.
  RingTracer tracer(W, H, label_at);
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

/// What steps 10–11 read of the sample graph: each region's widest sample clearance and each
/// passage's sample (lattice units). Taken before the regions grow, so that the graph (the
/// largest piece of room detection on a large floor) can be let go first.
struct RoomFacts {
  std::vector<double> region_clearance;  ///< 0 for a region without samples
  std::vector<SkeletonSample> passage_sample;
};

inline RoomFacts room_facts(const RoomDetection& rooms) {
  const SampleGraph& g = rooms.graph;
  RoomFacts facts;
  facts.region_clearance.assign(static_cast<std::size_t>(rooms.region_count()), 0.0);
  for (std::size_t s = 0; s < g.samples.size(); ++s) {
    const int region = rooms.region_of_sample[s];
    if (region >= 0) facts.region_clearance[region] = std::max(facts.region_clearance[region], g.samples[s].clearance);
  }
  for (const auto& p : rooms.passages) facts.passage_sample.push_back(g.samples[p.sample]);
  return facts;
}

/// Step 10: each area's widest free disc (from its regions' skeleton samples) and its kind: a
/// corridor when its hull diameter exceeds `corridor_elongation` times that disc's diameter.
inline void measure_areas(const RoomFacts& facts, const std::vector<int>& area_of_region, double res,
                          const AreaParams& params, AreaGraph& graph) {
  for (std::size_t region = 0; region < facts.region_clearance.size(); ++region) {
    if (area_of_region[region] < 0) continue;
    Area& area = graph.areas[area_of_region[region]];
    area.max_clearance_m = std::max(area.max_clearance_m, facts.region_clearance[region] * res);
  }
  for (Area& area : graph.areas) {
    const double diameter = std::max(0.0, farthest_vertices(area.convex_hull).distance);
    const double width = 2.0 * std::max(area.max_clearance_m, res);
    area.kind = diameter > params.corridor_elongation * width ? AreaKind::corridor : AreaKind::room;
  }
}

/// Step 11: the passages between the areas their regions became (none inside one area).
inline void add_passages(const RoomDetection& rooms, const RoomFacts& facts, const std::vector<int>& area_of_region, double res,
                         const LatticeFrame& to_world, AreaGraph& graph) {
  std::vector<std::pair<std::pair<int, int>, const DetectedPassage*>> kept;
  for (const auto& p : rooms.passages) {
    const int a = area_of_region[p.region_a], b = area_of_region[p.region_b];
    if (a < 0 || b < 0 || a == b) continue;
    kept.push_back({{std::min(a, b), std::max(a, b)}, &p});
  }
  for (const auto& [areas, detected] : kept) {
    const SkeletonSample& s = facts.passage_sample[static_cast<std::size_t>(detected - rooms.passages.data())];
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

}  // namespace detail
}  // namespace areamatch
