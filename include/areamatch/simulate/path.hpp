#pragma once
/// \file simulate/path.hpp
/// Where the simulated robot drives (simulate.hpp): waypoints over the free space, visited
/// nearest-first along clear shortest paths, and a scan pose every so far along the way.

#include "../detail/format.hpp"
#include "../detail/random.hpp"
#include "../error.hpp"
#include "../grid.hpp"
#include "params.hpp"
#include "world.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <string>
#include <vector>

namespace areamatch::detail {

/// The free space the robot can drive through, on cells of at least 0.2 m (a cell is open when
/// its centre keeps the path's clearance), with breadth-first shortest paths over it.
struct DriveGrid {
  const OccupancyGrid* plan = nullptr;
  int step = 1, w = 0, h = 0;
  std::vector<std::uint8_t> open;
  std::vector<int> parent;        ///< after `search`: the previous cell on a shortest path, −1 unreached
  std::vector<double> distance;   ///< after `search`: path length in cells, +infinity unreached

  DriveGrid(const RayWorld& world, const LidarSlamParams& p) : plan(&world.built) {
    const double cell_m = std::max(plan->resolution(), 0.2);
    step = std::max(1, static_cast<int>(std::lround(cell_m / plan->resolution())));
    w = (plan->width() + step - 1) / step;
    h = (plan->height() + step - 1) / step;
    open.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        open[static_cast<std::size_t>(y) * w + x] = world.clearance[plan->index(fine_col(x), fine_row(y))] >= p.path_clearance_m + 0.5 * cell_m;
      }
    }
  }
  double cell_m() const { return step * plan->resolution(); }
  int fine_col(int x) const { return std::min(plan->width() - 1, x * step + step / 2); }
  int fine_row(int y) const { return std::min(plan->height() - 1, y * step + step / 2); }
  Eigen::Vector2d centre(int index) const { return plan->cell_center(fine_col(index % w), fine_row(index / w)); }

  /// Visits the open 8-neighbours of each cell reached from `from`, in breadth-first order.
  template <class Visit>
  void flood(int from, Visit visit) const {
    std::deque<int> queue{from};
    while (!queue.empty()) {
      const int at = queue.front();
      queue.pop_front();
      const int x = at % w, y = at / w;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          const int next = ny * w + nx;
          if (open[static_cast<std::size_t>(next)] && visit(at, next, dx && dy)) queue.push_back(next);
        }
      }
    }
  }
  void search(int from) {
    parent.assign(open.size(), -1);
    distance.assign(open.size(), std::numeric_limits<double>::infinity());
    distance[static_cast<std::size_t>(from)] = 0.0;
    parent[static_cast<std::size_t>(from)] = from;
    flood(from, [&](int at, int next, bool diagonal) {
      if (parent[static_cast<std::size_t>(next)] >= 0) return false;
      parent[static_cast<std::size_t>(next)] = at;
      distance[static_cast<std::size_t>(next)] = distance[static_cast<std::size_t>(at)] + (diagonal ? 1.41421356 : 1.0);
      return true;
    });
  }
  /// The open cells of the largest connected part (the first such part in index order), in index order.
  std::vector<int> largest_part() const {
    std::vector<int> part_of(open.size(), -1), size_of;
    for (int c = 0; c < static_cast<int>(open.size()); ++c) {
      if (!open[static_cast<std::size_t>(c)] || part_of[static_cast<std::size_t>(c)] >= 0) continue;
      const int part = static_cast<int>(size_of.size());
      size_of.push_back(1);
      part_of[static_cast<std::size_t>(c)] = part;
      flood(c, [&](int, int next, bool) {
        if (part_of[static_cast<std::size_t>(next)] >= 0) return false;
        part_of[static_cast<std::size_t>(next)] = part;
        ++size_of.back();
        return true;
      });
    }
    const auto best = std::max_element(size_of.begin(), size_of.end());  // the first of the largest
    std::vector<int> cells;
    if (best == size_of.end()) return cells;
    for (int c = 0; c < static_cast<int>(open.size()); ++c) {
      if (part_of[static_cast<std::size_t>(c)] == static_cast<int>(best - size_of.begin())) cells.push_back(c);
    }
    return cells;
  }
};

/// The robot's path through the plan (plan world, metres): waypoints on a lattice where the path
/// keeps its clearance, in the largest connected part, visited nearest-first (by path length),
/// joined by shortest paths on the drive grid, back to the start.
inline std::vector<Eigen::Vector2d> exploration_path(const RayWorld& world, const LidarSlamParams& p, Random& random) {
  DriveGrid grid(world, p);
  const std::vector<int> part = grid.largest_part();
  if (part.empty()) {
    throw parameter_error("simulate: the plan has no free space wide enough to drive through (path clearance " +
                          format_double(p.path_clearance_m) + " m)");
  }
  const int lattice = std::max(1, static_cast<int>(std::lround(p.waypoint_spacing_m / grid.cell_m())));
  std::vector<int> waypoints;
  for (int c : part) {
    if ((c % grid.w) % lattice == 0 && (c / grid.w) % lattice == 0) waypoints.push_back(c);
  }
  if (waypoints.empty()) waypoints.push_back(part.front());
  const int start = waypoints[static_cast<std::size_t>(random.integer(0, static_cast<int>(waypoints.size()) - 1))];
  grid.search(start);
  const auto& distance = grid.distance;
  auto nearer = [&](int a, int b) {
    return distance[static_cast<std::size_t>(a)] < distance[static_cast<std::size_t>(b)] ||
           (distance[static_cast<std::size_t>(a)] == distance[static_cast<std::size_t>(b)] && a < b);
  };
  std::sort(waypoints.begin(), waypoints.end(), nearer);
  waypoints.resize(std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(p.explored_fraction * static_cast<double>(waypoints.size())))));
  std::vector<char> visited(grid.open.size(), 0);
  std::vector<Eigen::Vector2d> path{grid.centre(start)};
  int at = start;
  auto walk_to = [&](int goal) {
    std::vector<int> leg;
    for (int c = goal; c != at; c = grid.parent[static_cast<std::size_t>(c)]) leg.push_back(c);
    for (auto it = leg.rbegin(); it != leg.rend(); ++it) path.push_back(grid.centre(*it));
    at = goal;
  };
  visited[static_cast<std::size_t>(start)] = 1;
  for (std::size_t left = waypoints.size() - 1; left > 0; --left) {
    grid.search(at);
    int next = -1;
    for (int c : waypoints) {
      if (visited[static_cast<std::size_t>(c)] || !std::isfinite(distance[static_cast<std::size_t>(c)])) continue;
      if (next < 0 || distance[static_cast<std::size_t>(c)] < distance[static_cast<std::size_t>(next)]) next = c;
    }
    if (next < 0) break;
    visited[static_cast<std::size_t>(next)] = 1;
    walk_to(next);
  }
  grid.search(at);
  walk_to(start);  // back to the start: the loop SLAM closes
  return path;
}

/// Scan poses (position, heading) every `spacing` along a polyline.
inline std::vector<Eigen::Vector3d> scan_poses(const std::vector<Eigen::Vector2d>& path, double spacing) {
  std::vector<Eigen::Vector3d> poses;
  double carried = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Eigen::Vector2d d = path[i] - path[i - 1];
    const double length = d.norm();
    if (length <= 0.0) continue;
    const double heading = std::atan2(d.y(), d.x());
    for (double s = carried; s < length; s += spacing) {
      const Eigen::Vector2d at = path[i - 1] + d * (s / length);
      poses.emplace_back(at.x(), at.y(), heading);
    }
    carried = std::fmod(carried - length, spacing);
    if (carried < 0.0) carried += spacing;
  }
  if (poses.empty() && !path.empty()) poses.emplace_back(path.front().x(), path.front().y(), 0.0);
  return poses;
}


}  // namespace areamatch::detail
