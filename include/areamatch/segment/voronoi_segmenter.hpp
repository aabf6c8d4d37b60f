#pragma once
/// \file segment/voronoi_segmenter.hpp
/// `VoronoiSegmenter`: the default segmenter policy. Occupancy grid → Area Graph through the
/// stages of this folder:
///
///   binarize.hpp   free-space mask, speckles removed
///   boundary.hpp   obstacle boundary → simplified, validated lattice segments
///   skeleton.hpp   Boost.Polygon segment Voronoi → free-space skeleton with clearance
///   rooms.hpp      narrow/wide parts at half the door width → rooms, corridors, passages
///   areas.hpp      labelled free space cut at the passages → area polygons
///
/// The one parameter most maps need is the door width (`params.rooms.door_width_m`, default
/// 1.2 m): the widest opening that still separates two areas, with one grid cell of slack, so
/// that a door drawn exactly W wide counts (at 0.05 m cells the default separates openings up
/// to 1.25 m, the reference implementation's fallback).

#include "../area_graph.hpp"
#include "../detail/timing.hpp"
#include "../image.hpp"
#include "../grid.hpp"
#include "../segmenter.hpp"
#include "areas.hpp"
#include "binarize.hpp"
#include "boundary.hpp"
#include "rooms.hpp"
#include "skeleton.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <string>

namespace areamatch {

/// Wall-clock seconds per stage of one segmentation.
struct SegmentationTimings {
  double binarize_s = 0.0;
  double boundary_s = 0.0;
  double skeleton_s = 0.0;
  double rooms_s = 0.0;
  double areas_s = 0.0;
  double total_s = 0.0;
};

/// Everything a segmentation produced, for pictures and diagnostics.
struct SegmentationDetails {
  AreaGraph graph;
  Skeleton skeleton;
  RoomDetection rooms;
  std::size_t boundary_segments = 0;
  std::size_t refined_rings = 0;
  SegmentationTimings timings;
};

struct VoronoiSegmenter {
  struct Params {
    BinarizeParams binarize;
    BoundaryParams boundary;
    SkeletonParams skeleton;
    RoomParams rooms;
    AreaParams areas;

    /// Sets the door width (metres) everywhere it matters.
    Params& with_door_width(double door_width_m) {
      rooms.door_width_m = door_width_m;
      return *this;
    }

    /// Checks every field; the two that the segmenter derives from others (`skeleton.keep_clearance_m`
    /// from the door width, `areas.min_clearance_m` from `skeleton.min_clearance_m`) are refused
    /// when set, since a value there would be overwritten, not used.
    void validate() const {
      binarize.validate();
      boundary.validate();
      skeleton.validate();
      rooms.validate();
      areas.validate();
      // Parameters that must agree between stages are derived from one place; a value set in the
      // other place would be overwritten, so it is refused instead of silently ignored.
      if (skeleton.keep_clearance_m != SkeletonParams{}.keep_clearance_m) {
        throw parameter_error("SkeletonParams::keep_clearance_m is set by VoronoiSegmenter from the door width "
                              "(RoomParams::door_width_m, with_door_width); set that instead");
      }
      if (areas.min_clearance_m != AreaParams{}.min_clearance_m && areas.min_clearance_m != skeleton.min_clearance_m) {
        throw parameter_error("AreaParams::min_clearance_m is set by VoronoiSegmenter from SkeletonParams::min_clearance_m; "
                              "set that instead");
      }
    }
  };
  Params params;

  VoronoiSegmenter() = default;
  explicit VoronoiSegmenter(Params p) : params(std::move(p)) {}

  /// The Area Graph alone: the rooms' sample graph takes the skeleton's samples over (no copy),
  /// and both are let go before the areas are labelled (on a large floor the samples are a fifth
  /// of the peak memory).
  AreaGraph segment(const OccupancyGrid& grid) const { return run(grid, false).graph; }

  /// The Area Graph with what it was built from (skeleton, rooms) and the stages' timings.
  SegmentationDetails segment_with_details(const OccupancyGrid& grid) const { return run(grid, true); }

 private:
  SegmentationDetails run(const OccupancyGrid& grid, bool keep_skeleton) const {
    using clock = std::chrono::steady_clock;
    const auto seconds = detail::seconds_between;
    if (grid.empty()) throw parameter_error("cannot segment an empty grid");
    if (static_cast<long long>(grid.width()) * grid.height() > max_grid_cells) {
      throw limit_error("cannot segment a grid of " + std::to_string(grid.width()) + "x" + std::to_string(grid.height()) +
                        " cells: more than areamatch::max_grid_cells (" + std::to_string(max_grid_cells) + ")");
    }
    params.validate();
    SkeletonParams skeleton_params = params.skeleton;
    skeleton_params.keep_clearance_m = detail::room_clearance_m(params.rooms.door_width_m, grid.resolution());
    AreaParams area_params = params.areas;
    area_params.min_clearance_m = params.skeleton.min_clearance_m;

    SegmentationDetails out;
    const double res = grid.resolution();
    const auto t0 = clock::now();
    FreeSpace space = binarize(grid, params.binarize);
    const bool space_empty = std::none_of(space.free.begin(), space.free.end(), [](std::uint8_t f) { return f != 0; });
    // Free space too thin to matter is not traced (BoundaryParams::min_traced_width_m); the
    // areas still cover the whole free space. Without the option no copy of the mask is made.
    const bool open_traced = params.boundary.min_traced_width_m > 0.0;
    FreeSpace opened = open_traced ? open_free_space(space, 0.5 * params.boundary.min_traced_width_m / res) : FreeSpace{};
    const FreeSpace& passable = open_traced ? opened : space;
    const auto t1 = clock::now();
    BoundarySegments boundary = trace_boundary(passable, res, params.boundary);
    out.boundary_segments = boundary.segments.size();
    if (boundary.segments.size() > params.boundary.max_segments) {
      throw limit_error("the map's obstacle boundary has " + std::to_string(boundary.segments.size()) +
                        " segments, more than BoundaryParams::max_segments (" +
                        std::to_string(params.boundary.max_segments) +
                        "): a very noisy map; raise the limit, or simplify more (BoundaryParams::simplify_tolerance_m) or "
                        "erase more speckles (BinarizeParams::max_speckle_area_m2)");
    }
    out.refined_rings = boundary.refined_rings;
    const auto t2 = clock::now();
    // Traced: from here on the free space is read cell by cell only, so it is held as its runs
    // (on a large floor a quarter of the mask) and the mask is let go; `space` keeps its extent.
    detail::RowRuns free_runs = detail::nonzero_runs(space.free, space.width, space.height);
    std::vector<std::uint8_t>().swap(space.free);
    out.skeleton = open_traced ? build_skeleton(opened, boundary, res, skeleton_params)
                               : detail::skeleton_of([&free_runs](int col, int row) { return free_runs.contains(col, row); },
                                                     Eigen::Vector2d(space.offset_col, space.offset_row), boundary, res,
                                                     skeleton_params);
    opened = FreeSpace{};  // traced: neither is read again
    boundary = BoundarySegments{};
    const auto t3 = clock::now();
    if (keep_skeleton) {
      out.rooms = detect_rooms(out.skeleton, res, params.rooms);
    } else {  // the rooms' graph takes the skeleton's samples over, no copy beside them
      out.rooms = detail::detect_rooms_taking_samples(out.skeleton, res, params.rooms);
      out.skeleton = Skeleton{};
    }
    const auto t4 = clock::now();
    const bool no_samples = out.rooms.graph.samples.empty();
    // Without details, the rooms' sample graph is let go before the labels are made.
    out.graph = keep_skeleton ? detail::build_areas_on_runs(grid, space, std::move(free_runs), out.rooms, area_params)
                              : detail::build_areas_releasing(grid, space, std::move(free_runs), out.rooms, area_params);
    if (out.graph.areas.empty()) {
      if (grid.count().free == 0 && !params.binarize.unknown_is_free) {
        out.graph.reason = "the map has no free cells";
      } else if (space_empty) {
        out.graph.reason = "its free cells form only specks smaller than " +
                           std::to_string(params.binarize.min_free_area_m2) + " m^2";
      } else if (no_samples) {
        out.graph.reason = "no free space is wide enough to pass (it needs places at least " +
                           std::to_string(2.0 * params.skeleton.min_clearance_m) + " m across)";
      } else {
        out.graph.reason = "every free region is smaller than the minimum area of " +
                           std::to_string(params.areas.min_area_m2) + " m^2";
      }
    }
    const auto t5 = clock::now();
    out.timings = {seconds(t0, t1), seconds(t1, t2), seconds(t2, t3), seconds(t3, t4), seconds(t4, t5), seconds(t0, t5)};
    return out;
  }
};

static_assert(is_segmenter_v<VoronoiSegmenter>);

}  // namespace areamatch
