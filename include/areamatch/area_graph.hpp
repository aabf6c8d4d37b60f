#pragma once
/// \file area_graph.hpp
/// The Area Graph: areas (rooms, corridors) as nodes, passages (doors, junctions) as edges.
/// Everything in metres in the source map's world frame.

#include "geometry.hpp"
#include "grid.hpp"
#include "label_image.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace areamatch {

/// What an area looks like (a hint from its shape, not ground truth).
enum class AreaKind : std::uint8_t {
  room,      ///< compact
  corridor,  ///< long and narrow: its hull diameter is over `corridor_elongation` × its width
  other      ///< for custom segmenters; VoronoiSegmenter assigns only room and corridor
};

inline const char* to_string(AreaKind kind) {
  return kind == AreaKind::room ? "room" : kind == AreaKind::corridor ? "corridor" : "other";
}

/// What joins two areas.
enum class PassageKind : std::uint8_t {
  door,     ///< a narrowing of free space between two areas
  junction  ///< where corridor pieces meet
};

inline const char* to_string(PassageKind kind) { return kind == PassageKind::door ? "door" : "junction"; }

/// An opening between two areas.
struct Passage {
  int id = -1;
  PassageKind kind = PassageKind::door;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< centre of the opening
  double width_m = 0.0;                                ///< clear width of the opening
  int area_a = -1;                                     ///< the two areas it joins (a < b)
  int area_b = -1;
  Segment2 line;                                       ///< across the opening, wall to wall
};

/// A room or corridor.
struct Area {
  int id = -1;
  AreaKind kind = AreaKind::room;
  Polygon2 polygon;                                    ///< valid, with holes (furniture, pillars)
  double size_m2 = 0.0;                                ///< area of the free cells it holds
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  Polygon2 convex_hull;
  double max_clearance_m = 0.0;                        ///< radius of the largest free disc in it
  std::vector<int> passages;                           ///< ids of its passages, ascending
};

/// The source grid's frame, so results can go back to pixels.
struct GridInfo {
  int width = 0;
  int height = 0;
  double resolution = 0.05;
  Pose2 origin{};

  /// The frame of `grid`.
  static GridInfo of(const OccupancyGrid& grid) { return {grid.width(), grid.height(), grid.resolution(), grid.origin()}; }

  /// Continuous pixel coordinates (col, row) → world metres, as `OccupancyGrid::world_from_pixel`.
  Eigen::Affine2d world_from_pixel() const { return detail::world_from_pixel(height, resolution, origin); }

  friend bool operator==(const GridInfo& a, const GridInfo& b) {
    return a.width == b.width && a.height == b.height && a.resolution == b.resolution && a.origin == b.origin;
  }
};

/// Areas and passages of one map, with a label per cell.
struct AreaGraph {
  GridInfo grid;
  std::vector<Area> areas;
  std::vector<Passage> passages;
  /// Per cell of the source grid (image order): the id of the area holding it, −1 for none.
  LabelImage labels;
  /// Share of the map's free cells that belong to some area (laser streaks outside the
  /// building and crumbs too thin to pass are left out on purpose).
  double covered_fraction = 0.0;
  /// Why there are no areas (empty when there are some): no free cells, free space too narrow
  /// to pass, or every piece smaller than the minimum area.
  std::string reason;

  /// Neighbouring areas (through any passage) of each area, ascending, without repeats.
  std::vector<std::vector<int>> adjacency() const {
    std::vector<std::vector<int>> adj(areas.size());
    for (const auto& p : passages) {
      adj[p.area_a].push_back(p.area_b);
      adj[p.area_b].push_back(p.area_a);
    }
    for (auto& list : adj) {
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
    }
    return adj;
  }
};

}  // namespace areamatch
