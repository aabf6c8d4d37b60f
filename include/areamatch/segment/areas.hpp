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
#include "area_growth.hpp"
#include "area_params.hpp"
#include "area_pieces.hpp"
#include "area_tracing.hpp"
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

namespace detail {

/// Steps 1–4 on working labels of type `Label` (`initial_labels`: a region id or a state per cell
/// of the free space's extent, `space`, from its runs `free`, let go once the labels are made):
/// passages sealed, regions grown from `seeds` over the core and then the fringe, barrier cells
/// assigned, and the result as runs — the working labels and the seeds are let go on return.
template <class Label>
LabelRuns grow_labels(const FreeSpace& space, RowRuns free, const RoomDetection& rooms, std::vector<Seed> seeds,
                      const AreaParams& params, double res) {
  const int W = space.width, H = space.height;
  // The core: free cells at least min_clearance from every wall, where the skeleton lives.
  std::vector<Label> label = initial_labels<Label>(std::move(free), W, H, params.min_clearance_m / res + 0.5);
  const std::vector<std::uint32_t> barrier_cells = seal_passages(space, rooms, label);
  const int fringe_steps = static_cast<int>(std::ceil((params.min_clearance_m + params.fringe_m) / res));
  grow_regions(W, H, seeds, fringe_steps, label);
  std::vector<Seed>().swap(seeds);
  assign_barrier_cells(barrier_cells, W, label);
  return label_runs(label, W, H);
}

/// `build_areas` from the free space's runs (`free`; of `space` only the extent is read, so its
/// mask may be let go already) and what it reads of the rooms: their passages and region count
/// (`rooms`; its sample graph is not read), the regions' seeds and the facts of steps 10–11.
inline AreaGraph build_areas_from(const OccupancyGrid& grid, const FreeSpace& space, RowRuns free,
                                  const RoomDetection& rooms, std::vector<Seed> seeds, const RoomFacts& facts,
                                  const AreaParams& params) {
  params.validate();
  const std::size_t N = static_cast<std::size_t>(space.width) * static_cast<std::size_t>(space.height);
  const double res = grid.resolution();
  AreaGraph graph;
  graph.grid = GridInfo::of(grid);
  if (N == 0) {
    graph.labels.assign(grid.cells().size(), -1);
    return graph;
  }
  if (N > std::numeric_limits<std::uint32_t>::max()) throw parameter_error("grid too large to segment");
  const LatticeFrame to_world{&grid, Eigen::Vector2d(space.offset_col, space.offset_row)};

  // 16-bit working labels when the region ids fit: on a large floor they were the largest buffer.
  LabelRuns runs = rooms.region_count() < std::numeric_limits<std::int16_t>::max()
                       ? grow_labels<std::int16_t>(space, std::move(free), rooms, std::move(seeds), params, res)
                       : grow_labels<std::int32_t>(space, std::move(free), rooms, std::move(seeds), params, res);
  const Pieces pieces = find_pieces(runs);
  const auto min_cells = static_cast<std::size_t>(std::ceil(params.min_area_m2 / (res * res)));
  const PieceAreas areas = merge_small_pieces(runs, pieces, min_cells);
  const std::vector<int> area_of_region = area_of_regions(rooms.region_count(), pieces, areas.area_of_piece);

  write_labels(grid, space, runs, graph);
  trace_areas(runs, space, res, to_world, areas.area_count, graph);
  measure_areas(facts, area_of_region, res, params, graph);
  add_passages(rooms, facts, area_of_region, res, to_world, graph);
  return graph;
}

/// `build_areas` from the free space's runs (`free`; of `space` only the extent is read).
inline AreaGraph build_areas_on_runs(const OccupancyGrid& grid, const FreeSpace& space, RowRuns free,
                                     const RoomDetection& rooms, const AreaParams& params) {
  std::vector<Seed> seeds = region_seeds(free, space.width, rooms);
  return build_areas_from(grid, space, std::move(free), rooms, std::move(seeds), room_facts(rooms), params);
}

/// `build_areas_on_runs` that lets go of `rooms`' sample graph (and its samples' regions) before
/// the labels are made: what `VoronoiSegmenter::segment` uses, which returns only the graph.
inline AreaGraph build_areas_releasing(const OccupancyGrid& grid, const FreeSpace& space, RowRuns free,
                                       RoomDetection& rooms, const AreaParams& params) {
  std::vector<Seed> seeds = region_seeds(free, space.width, rooms);
  const RoomFacts facts = room_facts(rooms);
  rooms.graph = SampleGraph{};
  std::vector<int>().swap(rooms.region_of_sample);
  return build_areas_from(grid, space, std::move(free), rooms, std::move(seeds), facts, params);
}

}  // namespace detail

/// Builds the Area Graph from detected rooms (see the file comment). `grid` gives the frame and
/// the free-cell count for `covered_fraction`.
inline AreaGraph build_areas(const OccupancyGrid& grid, const FreeSpace& space, const RoomDetection& rooms,
                             const AreaParams& params = {}) {
  return detail::build_areas_on_runs(grid, space, detail::nonzero_runs(space.free, space.width, space.height), rooms,
                                     params);
}

}  // namespace areamatch
