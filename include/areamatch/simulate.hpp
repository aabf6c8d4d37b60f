#pragma once
/// \file simulate.hpp
/// A simulated laser-SLAM map of any floor plan, with exact ground truth: what a robot with a 2D
/// laser scanner would map driving through the plan's rooms. Generated robot maps
/// (`make_robot_map`) are the plan with noise added; a real SLAM map is made by rays, and the
/// rays are what make it hard to match: furniture and people seen as walls, streaks through
/// windows, ragged free space where beams thin out with range, unknown behind everything, and a
/// bend where odometry drifted and the loop closure did not quite undo it.
///
/// The simulation: furniture placed in the plan's rooms; waypoints over the free space, visited
/// nearest-first along shortest paths that keep clear of walls, back to the start; a scan every
/// `scan_spacing_m` (beams over the field of view, range noise, dropouts, people near the robot,
/// glass panes in outer walls that rays pass through); odometry drift (heading and distance
/// random walks) with an imperfect loop closure (the drift at the end taken out linearly along
/// the path, leaving a bend scaled to `bend_m`) and, optionally, a broken piece (the rest of the
/// path turned and shifted from some scan on, as after a wrong loop closure); each beam
/// integrated at its drifted pose into log-odds, thresholded into a ROS trinary map.
///
/// Everything is in metres and radians; the same seed gives the same map on every platform.

#include "detail/format.hpp"
#include "detail/random.hpp"
#include "error.hpp"
#include "grid.hpp"
#include "synthetic.hpp"
#include "transform.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <string>
#include <vector>

namespace areamatch {

/// How the simulated robot, its laser and its SLAM behave (defaults: an indoor robot with a
/// 270° scanner of 15 m range and a map bent by 0.3 m).
struct LidarSlamParams {
  // The laser.
  int beams = 541;                                      ///< per scan, evenly over the field of view
  double field_of_view_rad = 1.5 * pi;                  ///< centred on the direction of travel
  double max_range_m = 15.0;                            ///< beams reaching this far return nothing
  double range_noise_m = 0.02;                          ///< standard deviation of each range
  double dropout = 0.02;                                ///< share of beams that return nothing
  double scan_spacing_m = 0.4;                          ///< a scan every this much travel
  // The world the rays meet, beyond the plan.
  double furniture_per_m2 = 0.05;                       ///< furniture blobs per m² of free space
  double furniture_min_m = 0.3, furniture_max_m = 1.4;  ///< their sides
  double small_clutter_per_m2 = 0.3;                    ///< chair legs, bins: 0.05–0.15 m blobs per m²
  double glass_share = 0.1;     ///< share of the outer walls' 1 m panes that are glass
  double glass_pass = 0.3;      ///< share of the rays meeting glass that pass through
  double outside_hit = 0.5;     ///< a ray through glass hits something outside with this probability
  int people = 2;               ///< people (0.25 m discs) within a few metres of the robot, per scan
  // Where the robot drives.
  double explored_fraction = 1.0;  ///< share of the waypoints visited (those nearest the start)
  double path_clearance_m = 0.3;   ///< the path keeps this far from walls and furniture
  double waypoint_spacing_m = 2.5;
  // SLAM's errors.
  /// The building as built differs from its plan by a smooth warp of at most this size (0: the
  /// plan is exact). Layouts drawn by hand, or redrawn from a distorted map, are off by 0.3–0.6 m
  /// in places (shared/maps/README.md); a CAD plan of the building as built is not.
  double plan_error_m = 0.0;
  double bend_m = 0.3;  ///< largest distance of a scan position from where the ground truth puts it
  /// Each scan's own registration error (independent per scan): what makes SLAM walls a few cells
  /// thick and ragged rather than one clean line.
  double scan_jitter_m = 0.03, scan_jitter_rad = 0.005;
  double break_probability = 0.0;  ///< chance of a broken piece
  double break_rotation_rad = 3.0 * pi / 180.0, break_shift_m = 0.2;
  // The map.
  double resolution_m = 0.05;
  double hit_log_odds = 0.85, miss_log_odds = -0.4;       ///< per beam, at its end cell and on the way
  double occupied_log_odds = 0.6, free_log_odds = -1.2;   ///< the trinary thresholds (ROS: p 0.65 / 0.23)
  double rotation_rad = 0.0;  ///< the map's frame turned against the plan's
  bool mirror = false;        ///< and mirrored (y flipped), as an image with rows downwards can be
  /// Unknown cells written as occupied: free against non-free only, as the SLAM maps of the
  /// room-segmentation dataset are (there, walls, unknown and outside are all non-free).
  bool binary = false;
  std::size_t max_cells = 50'000'000;  ///< larger maps are refused (memory: ~5 bytes per cell)

  void validate() const {
    auto positive = [](double v, const char* name) {
      if (!(v > 0.0) || !std::isfinite(v)) throw parameter_error(std::string("LidarSlamParams::") + name + " must be positive");
    };
    auto share = [](double v, const char* name) {
      if (!(v >= 0.0 && v <= 1.0)) throw parameter_error(std::string("LidarSlamParams::") + name + " must be in [0, 1]");
    };
    auto non_negative = [](double v, const char* name) {
      if (!(v >= 0.0) || !std::isfinite(v)) throw parameter_error(std::string("LidarSlamParams::") + name + " must be >= 0");
    };
    if (beams < 1 || beams > 100000) throw parameter_error("LidarSlamParams::beams must be in [1, 100000]");
    if (!(field_of_view_rad > 0.0 && field_of_view_rad <= 2.0 * pi)) {
      throw parameter_error("LidarSlamParams::field_of_view_rad must be in (0, 2 pi]");
    }
    positive(max_range_m, "max_range_m");
    non_negative(range_noise_m, "range_noise_m");
    share(dropout, "dropout");
    positive(scan_spacing_m, "scan_spacing_m");
    non_negative(furniture_per_m2, "furniture_per_m2");
    positive(furniture_min_m, "furniture_min_m");
    if (!(furniture_max_m >= furniture_min_m)) throw parameter_error("LidarSlamParams::furniture_max_m must be >= furniture_min_m");
    non_negative(small_clutter_per_m2, "small_clutter_per_m2");
    share(glass_share, "glass_share");
    share(glass_pass, "glass_pass");
    non_negative(scan_jitter_m, "scan_jitter_m");
    non_negative(scan_jitter_rad, "scan_jitter_rad");
    share(outside_hit, "outside_hit");
    if (people < 0 || people > 1000) throw parameter_error("LidarSlamParams::people must be in [0, 1000]");
    if (!(explored_fraction > 0.0 && explored_fraction <= 1.0)) throw parameter_error("LidarSlamParams::explored_fraction must be in (0, 1]");
    non_negative(path_clearance_m, "path_clearance_m");
    positive(waypoint_spacing_m, "waypoint_spacing_m");
    non_negative(bend_m, "bend_m");
    non_negative(plan_error_m, "plan_error_m");
    share(break_probability, "break_probability");
    non_negative(break_rotation_rad, "break_rotation_rad");
    non_negative(break_shift_m, "break_shift_m");
    positive(resolution_m, "resolution_m");
    positive(hit_log_odds, "hit_log_odds");
    if (!(miss_log_odds < 0.0)) throw parameter_error("LidarSlamParams::miss_log_odds must be negative");
    if (!(occupied_log_odds > 0.0) || !(free_log_odds < 0.0)) {
      throw parameter_error("LidarSlamParams: occupied_log_odds must be positive and free_log_odds negative");
    }
    if (!std::isfinite(rotation_rad)) throw parameter_error("LidarSlamParams::rotation_rad must be finite");
  }
};

/// A simulated SLAM map and its ground truth.
struct SimulatedSlamMap {
  OccupancyGrid grid;                 ///< the SLAM map (free, occupied, unknown)
  Similarity2 T_dest_source;          ///< map world → plan world: the rigid fit of the drifted scan poses to the true ones
  PixelTransform pixel_transform;     ///< map pixel → plan pixel
  std::vector<Eigen::Vector2d> path;  ///< the true scan positions, plan world
  double bend_m = 0.0;  ///< largest distance of a scan position, mapped by T_dest_source, from the true one
  bool broken = false;  ///< whether a broken piece was made
  std::size_t furniture = 0, scans = 0;
};

namespace detail {

/// The plan as the rays see it: solid cells (the plan's non-free cells, furniture), which of
/// them are glass, and which lie outside (unknown, or deeper than a wall in non-free space).
struct RayWorld {
  OccupancyGrid built;  ///< the building as built: the plan, warped by `plan_error_m`
  std::vector<std::uint8_t> solid, glass, outside;
  std::vector<double> clearance;  ///< metres to the nearest solid cell (after furniture)
};

/// The building as built: `plan` resampled through a smooth displacement field of largest size
/// `error_m` (two waves per axis, 8–20 m long, random directions and phases), so that its walls
/// sit up to that far from where the plan draws them, as a schematic plan's do.
inline OccupancyGrid as_built(const OccupancyGrid& plan, double error_m, Random& random) {
  if (!(error_m > 0.0)) return plan;
  struct Wave {
    Eigen::Vector2d k;
    double phase;
  };
  std::array<std::array<Wave, 2>, 2> waves;
  for (auto& axis : waves) {
    for (Wave& w : axis) {
      const double angle = random.uniform(0.0, 2.0 * pi), length = random.uniform(8.0, 20.0);
      w.k = (2.0 * pi / length) * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      w.phase = random.uniform(0.0, 2.0 * pi);
    }
  }
  OccupancyGrid out = plan;
  const Eigen::Affine2d to_pixel = plan.pixel_from_world();
  for (int r = 0; r < plan.height(); ++r) {
    for (int c = 0; c < plan.width(); ++c) {
      const Eigen::Vector2d w = plan.cell_center(c, r);
      Eigen::Vector2d d;
      for (int axis = 0; axis < 2; ++axis) {
        d[axis] = 0.5 * error_m * (std::sin(waves[axis][0].k.dot(w) + waves[axis][0].phase) +
                                   std::sin(waves[axis][1].k.dot(w) + waves[axis][1].phase));
      }
      const Eigen::Vector2d px = to_pixel * (w + d / std::sqrt(2.0));
      const int x = static_cast<int>(std::floor(px.x() + 0.5)), y = static_cast<int>(std::floor(px.y() + 0.5));
      out.set(c, r, plan.contains(x, y) ? plan.at(x, y) : CellState::unknown);
    }
  }
  return out;
}

inline RayWorld make_ray_world(const OccupancyGrid& drawn, const LidarSlamParams& p, std::uint64_t seed, Random& random,
                               std::size_t& furniture) {
  RayWorld world;
  world.built = as_built(drawn, p.plan_error_m, random);
  const OccupancyGrid& plan = world.built;
  const std::size_t n = plan.cells().size();
  world.solid.assign(n, 0);
  std::vector<bool> non_free(n), free(n);
  for (std::size_t i = 0; i < n; ++i) {
    free[i] = plan.cells()[i] == CellState::free;
    non_free[i] = !free[i];
    world.solid[i] = !free[i];
  }
  const std::vector<double> to_free = chamfer_distance(plan, free);
  const std::vector<double> to_wall = chamfer_distance(plan, non_free);
  world.outside.assign(n, 0);
  world.glass.assign(n, 0);
  constexpr double wall_depth_m = 0.6;  // non-free deeper than a wall is outside (or a solid block)
  for (std::size_t i = 0; i < n; ++i) {
    world.outside[i] = !free[i] && (plan.cells()[i] == CellState::unknown || to_free[i] >= wall_depth_m);
  }
  // Glass: outer walls (wall cells near the outside), in 1 m panes.
  const std::vector<bool> outside_seed(world.outside.begin(), world.outside.end());
  const std::vector<double> to_outside = chamfer_distance(plan, outside_seed);
  for (int r = 0; r < plan.height(); ++r) {
    for (int c = 0; c < plan.width(); ++c) {
      const std::size_t i = plan.index(c, r);
      if (free[i] || world.outside[i] || to_outside[i] > wall_depth_m) continue;
      const Eigen::Vector2d w = plan.cell_center(c, r);
      world.glass[i] = hash_unit(seed ^ 0x61A55ull, static_cast<std::int64_t>(std::floor(w.x())),
                                 static_cast<std::int64_t>(std::floor(w.y()))) < p.glass_share;
    }
  }
  // Furniture: axis-parallel blobs where the room is wide enough to keep a way round them.
  std::size_t free_cells = 0;
  for (bool f : free) free_cells += f;
  const double free_m2 = static_cast<double>(free_cells) * plan.resolution() * plan.resolution();
  const auto wanted = static_cast<std::size_t>(std::floor(p.furniture_per_m2 * free_m2));
  for (std::size_t k = 0, tries = 0; k < wanted && tries < 20 * wanted + 20; ++tries) {
    const int c = random.integer(0, plan.width() - 1), r = random.integer(0, plan.height() - 1);
    const double w = random.uniform(p.furniture_min_m, p.furniture_max_m), h = random.uniform(p.furniture_min_m, p.furniture_max_m);
    const std::size_t i = plan.index(c, r);
    if (!free[i] || to_wall[i] < 0.5 * std::hypot(w, h) + p.path_clearance_m + 0.4) continue;
    const int half_w = static_cast<int>(std::ceil(0.5 * w / plan.resolution())), half_h = static_cast<int>(std::ceil(0.5 * h / plan.resolution()));
    for (int y = std::max(0, r - half_h); y <= std::min(plan.height() - 1, r + half_h); ++y) {
      for (int x = std::max(0, c - half_w); x <= std::min(plan.width() - 1, c + half_w); ++x) world.solid[plan.index(x, y)] = 1;
    }
    ++k;
    ++furniture;
  }
  // Small clutter: anywhere in the free space off the walls, not in doorways.
  const auto small = static_cast<std::size_t>(std::floor(p.small_clutter_per_m2 * free_m2));
  for (std::size_t k = 0, tries = 0; k < small && tries < 20 * small + 20; ++tries) {
    const int c = random.integer(0, plan.width() - 1), r = random.integer(0, plan.height() - 1);
    const double size = random.uniform(0.05, 0.15);
    const std::size_t i = plan.index(c, r);
    if (!free[i] || to_wall[i] < size + p.path_clearance_m + 0.3) continue;
    const int half = static_cast<int>(std::floor(0.5 * size / plan.resolution()));
    for (int y = std::max(0, r - half); y <= std::min(plan.height() - 1, r + half); ++y) {
      for (int x = std::max(0, c - half); x <= std::min(plan.width() - 1, c + half); ++x) world.solid[plan.index(x, y)] = 1;
    }
    ++k;
  }
  std::vector<bool> solid_seed(world.solid.begin(), world.solid.end());
  world.clearance = chamfer_distance(plan, solid_seed);
  return world;
}

/// The robot's path through the plan (plan world, metres): waypoints on a lattice where the path
/// keeps its clearance, in the largest connected part, visited nearest-first (by path length),
/// joined by shortest paths on a coarse grid, back to the start.
inline std::vector<Eigen::Vector2d> exploration_path(const RayWorld& world, const LidarSlamParams& p, Random& random) {
  const OccupancyGrid& plan = world.built;
  const double cell_m = std::max(plan.resolution(), 0.2);
  const int step = std::max(1, static_cast<int>(std::lround(cell_m / plan.resolution())));
  const int w = (plan.width() + step - 1) / step, h = (plan.height() + step - 1) / step;
  std::vector<std::uint8_t> open(static_cast<std::size_t>(w) * h, 0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const int c = std::min(plan.width() - 1, x * step + step / 2), r = std::min(plan.height() - 1, y * step + step / 2);
      open[static_cast<std::size_t>(y) * w + x] = world.clearance[plan.index(c, r)] >= p.path_clearance_m + 0.5 * cell_m;
    }
  }
  auto centre = [&](int index) {
    const int x = index % w, y = index / w;
    return plan.cell_center(std::min(plan.width() - 1, x * step + step / 2), std::min(plan.height() - 1, y * step + step / 2));
  };
  // Breadth-first distances (8-neighbourhood) and parents from one cell.
  std::vector<int> parent(open.size());
  std::vector<double> distance(open.size());
  auto search = [&](int from) {
    std::fill(parent.begin(), parent.end(), -1);
    std::fill(distance.begin(), distance.end(), std::numeric_limits<double>::infinity());
    std::deque<int> queue{from};
    distance[static_cast<std::size_t>(from)] = 0.0;
    parent[static_cast<std::size_t>(from)] = from;
    while (!queue.empty()) {
      const int at = queue.front();
      queue.pop_front();
      const int x = at % w, y = at / w;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          const int next = ny * w + nx;
          if (!open[static_cast<std::size_t>(next)] || parent[static_cast<std::size_t>(next)] >= 0) continue;
          parent[static_cast<std::size_t>(next)] = at;
          distance[static_cast<std::size_t>(next)] = distance[static_cast<std::size_t>(at)] + ((dx && dy) ? 1.41421356 : 1.0);
          queue.push_back(next);
        }
      }
    }
  };
  std::vector<int> cells;
  for (int i = 0; i < static_cast<int>(open.size()); ++i) {
    if (open[static_cast<std::size_t>(i)]) cells.push_back(i);
  }
  if (cells.empty()) {
    throw parameter_error("simulate: the plan has no free space wide enough to drive through (path clearance " +
                          format_double(p.path_clearance_m) + " m)");
  }
  // The largest connected part holds the start; waypoints on a lattice within it.
  std::vector<int> part_of(open.size(), -1);
  int best_part = -1;
  std::size_t best_size = 0;
  int best_seed = cells.front();
  for (int c : cells) {
    if (part_of[static_cast<std::size_t>(c)] >= 0) continue;
    search(c);
    std::size_t size = 0;
    for (int d : cells) {
      if (parent[static_cast<std::size_t>(d)] >= 0) part_of[static_cast<std::size_t>(d)] = c, ++size;
    }
    if (size > best_size) best_size = size, best_part = c, best_seed = c;
  }
  const int lattice = std::max(1, static_cast<int>(std::lround(p.waypoint_spacing_m / cell_m)));
  std::vector<int> waypoints;
  for (int c : cells) {
    if (part_of[static_cast<std::size_t>(c)] == best_part && (c % w) % lattice == 0 && (c / w) % lattice == 0) waypoints.push_back(c);
  }
  if (waypoints.empty()) waypoints.push_back(best_seed);
  const int start = waypoints[static_cast<std::size_t>(random.integer(0, static_cast<int>(waypoints.size()) - 1))];
  search(start);
  std::sort(waypoints.begin(), waypoints.end(), [&](int a, int b) {
    return distance[static_cast<std::size_t>(a)] < distance[static_cast<std::size_t>(b)] ||
           (distance[static_cast<std::size_t>(a)] == distance[static_cast<std::size_t>(b)] && a < b);
  });
  waypoints.resize(std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(p.explored_fraction * static_cast<double>(waypoints.size())))));
  std::vector<char> visited(open.size(), 0);
  std::vector<Eigen::Vector2d> path{centre(start)};
  int at = start;
  auto walk_to = [&](int goal) {
    std::vector<int> leg;
    for (int c = goal; c != at; c = parent[static_cast<std::size_t>(c)]) leg.push_back(c);
    for (auto it = leg.rbegin(); it != leg.rend(); ++it) path.push_back(centre(*it));
    at = goal;
  };
  visited[static_cast<std::size_t>(start)] = 1;
  for (std::size_t left = waypoints.size() - 1; left > 0; --left) {
    search(at);
    int next = -1;
    for (int c : waypoints) {
      if (visited[static_cast<std::size_t>(c)] || !std::isfinite(distance[static_cast<std::size_t>(c)])) continue;
      if (next < 0 || distance[static_cast<std::size_t>(c)] < distance[static_cast<std::size_t>(next)]) next = c;
    }
    if (next < 0) break;
    visited[static_cast<std::size_t>(next)] = 1;
    walk_to(next);
  }
  search(at);
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

/// Per scan, where SLAM believes it was: the position and heading errors of a random-walk
/// odometry whose end error is taken out linearly along the path (the loop closure), scaled so
/// that the largest position error is `bend_m` (the ground truth's rigid fit leaves at most about
/// that), plus the broken piece.
struct Drift {
  std::vector<Eigen::Vector2d> position;
  std::vector<double> heading;
  bool broken = false;
};

inline Drift odometry_drift(const std::vector<Eigen::Vector3d>& poses, const LidarSlamParams& p, Random& random) {
  const std::size_t n = poses.size();
  Drift drift;
  drift.position.assign(n, Eigen::Vector2d::Zero());
  drift.heading.assign(n, 0.0);
  std::vector<double> along(n, 0.0);
  for (std::size_t k = 1; k < n; ++k) {
    const Eigen::Vector2d step = poses[k].head<2>() - poses[k - 1].head<2>();
    const double ds = step.norm();
    along[k] = along[k - 1] + ds;
    drift.heading[k] = drift.heading[k - 1] + 0.01 * std::sqrt(ds) * random.normal();
    const Eigen::Vector2d turned = Eigen::Rotation2Dd(drift.heading[k]) * step;
    drift.position[k] = drift.position[k - 1] + (turned - step) + 0.01 * std::sqrt(ds) * Eigen::Vector2d(random.normal(), random.normal());
  }
  const double total = n > 1 ? along.back() : 0.0;
  if (total > 0.0) {
    const Eigen::Vector2d end = drift.position.back();
    const double end_heading = drift.heading.back();
    for (std::size_t k = 0; k < n; ++k) {
      drift.position[k] -= (along[k] / total) * end;
      drift.heading[k] -= (along[k] / total) * end_heading;
    }
  }
  double largest = 0.0;
  for (const auto& e : drift.position) largest = std::max(largest, e.norm());
  const double gain = largest > 1e-9 ? p.bend_m / largest : 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    drift.position[k] *= gain;
    drift.heading[k] *= gain;
  }
  if (n > 8 && random.chance(p.break_probability)) {
    drift.broken = true;
    const std::size_t from = n / 4 + static_cast<std::size_t>(random.integer(0, static_cast<int>(n / 2)));
    const double turn = (random.chance(0.5) ? 1.0 : -1.0) * p.break_rotation_rad;
    const double direction = random.uniform(0.0, 2.0 * pi);
    const Eigen::Vector2d shift = p.break_shift_m * Eigen::Vector2d(std::cos(direction), std::sin(direction));
    const Eigen::Vector2d pivot = poses[from].head<2>() + drift.position[from];
    const Eigen::Rotation2Dd R(turn);
    for (std::size_t k = from; k < n; ++k) {
      const Eigen::Vector2d believed = poses[k].head<2>() + drift.position[k];
      drift.position[k] = pivot + R * (believed - pivot) + shift - poses[k].head<2>();
      drift.heading[k] += turn;
    }
  }
  return drift;
}

/// The range of one beam in the true world, or a negative value when it returns nothing.
inline double cast_ray(const RayWorld& world, const Eigen::Vector2d& from, double angle, const LidarSlamParams& p,
                       const std::vector<Eigen::Vector2d>& people, Random& random) {
  const OccupancyGrid& plan = world.built;
  const Eigen::Vector2d dir(std::cos(angle), std::sin(angle));
  double limit = p.max_range_m;
  constexpr double person_radius_m = 0.25;
  for (const auto& person : people) {  // the nearest crossing of a person's disc
    const Eigen::Vector2d to = person - from;
    const double along = to.dot(dir);
    const double off2 = to.squaredNorm() - along * along;
    if (along > 0.0 && off2 < person_radius_m * person_radius_m) {
      limit = std::min(limit, along - std::sqrt(person_radius_m * person_radius_m - off2));
    }
  }
  const Eigen::Affine2d to_pixel = plan.pixel_from_world();
  const double step = 0.5 * plan.resolution();
  bool through_glass = false;
  for (double t = 0.0; t < limit; t += step) {
    const Eigen::Vector2d px = to_pixel * (from + t * dir);
    const int c = static_cast<int>(std::floor(px.x() + 0.5)), r = static_cast<int>(std::floor(px.y() + 0.5));
    if (!plan.contains(c, r)) return through_glass && random.chance(p.outside_hit) ? random.uniform(t, p.max_range_m) : -1.0;
    const std::size_t i = plan.index(c, r);
    if (!world.solid[i]) continue;
    if (world.glass[i] && !through_glass) through_glass = random.chance(p.glass_pass);
    if (through_glass && (world.glass[i] || world.outside[i])) {
      if (world.outside[i]) return random.chance(p.outside_hit) ? random.uniform(t, p.max_range_m) : -1.0;
      continue;
    }
    return t;
  }
  return limit < p.max_range_m ? limit : -1.0;
}

}  // namespace detail

/// A simulated laser-SLAM map of `plan` (a floor plan: free space, walls, unknown or outside) and
/// its ground truth (see the file comment). Throws `parameter_error` for invalid parameters or a
/// plan without free space to drive through, `limit_error` when the map would exceed `max_cells`.
inline SimulatedSlamMap simulate_lidar_slam(const OccupancyGrid& plan, const LidarSlamParams& params, std::uint64_t seed) {
  params.validate();
  if (plan.empty()) throw parameter_error("simulate: the plan is empty");
  detail::Random random(seed);
  SimulatedSlamMap out;
  const detail::RayWorld world = detail::make_ray_world(plan, params, seed, random, out.furniture);
  const std::vector<Eigen::Vector2d> path = detail::exploration_path(world, params, random);
  const std::vector<Eigen::Vector3d> poses = detail::scan_poses(path, params.scan_spacing_m);
  const detail::Drift drift = detail::odometry_drift(poses, params, random);
  out.broken = drift.broken;
  out.scans = poses.size();

  // The map's frame: the believed poses, turned and mirrored. Per scan, the rigid motion from
  // the true world into it.
  Similarity2 frame;
  frame.rotation = params.rotation_rad;
  frame.reflected = params.mirror;
  std::vector<Similarity2> to_map(poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    // About the true position: turned by the heading error, moved by the position error, and the
    // scan's own registration error on top (not in the ground truth: it averages out).
    const double turn = drift.heading[k] + params.scan_jitter_rad * random.normal();
    const Eigen::Vector2d jitter = params.scan_jitter_m * Eigen::Vector2d(random.normal(), random.normal());
    Similarity2 local;
    local.rotation = turn;
    local.translation = poses[k].head<2>() + drift.position[k] + jitter - Eigen::Rotation2Dd(turn) * poses[k].head<2>();
    to_map[k] = frame * local;
  }
  // Ground truth: the rigid motion that best lays the believed scan positions on the true ones
  // (least squares, closed form in 2D), with the mirror put back after.
  std::vector<Eigen::Vector2d> believed(poses.size());
  Eigen::Vector2d believed_mean = Eigen::Vector2d::Zero(), true_mean = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k < poses.size(); ++k) {
    believed[k] = to_map[k] * poses[k].head<2>();
    if (params.mirror) believed[k].y() = -believed[k].y();
    believed_mean += believed[k];
    true_mean += poses[k].head<2>();
  }
  believed_mean /= static_cast<double>(poses.size());
  true_mean /= static_cast<double>(poses.size());
  double dot = 0.0, cross = 0.0;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const Eigen::Vector2d a = believed[k] - believed_mean, b = poses[k].head<2>() - true_mean;
    dot += a.dot(b);
    cross += a.x() * b.y() - a.y() * b.x();
  }
  Similarity2 fit;
  fit.rotation = std::atan2(cross, dot);
  fit.translation = true_mean - Eigen::Rotation2Dd(fit.rotation) * believed_mean;
  Similarity2 unmirror;
  unmirror.reflected = params.mirror;
  out.T_dest_source = fit * unmirror;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    out.path.push_back(poses[k].head<2>());
    out.bend_m = std::max(out.bend_m, (out.T_dest_source * (to_map[k] * poses[k].head<2>()) - poses[k].head<2>()).norm());
  }

  // The beams: each scan's ranges cast in the true world, their ends carried into the map frame.
  struct Beam {
    Eigen::Vector2d from, to;
    bool hit;
  };
  std::vector<Beam> beams;
  beams.reserve(poses.size() * static_cast<std::size_t>(params.beams));
  const bool full_circle = params.field_of_view_rad >= 2.0 * pi - 1e-9;
  const double spacing = params.field_of_view_rad / (full_circle ? params.beams : std::max(1, params.beams - 1));
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const Eigen::Vector2d at = poses[k].head<2>();
    std::vector<Eigen::Vector2d> people;
    for (int person = 0; person < params.people; ++person) {
      const double a = random.uniform(0.0, 2.0 * pi), d = random.uniform(1.0, 4.0);
      const Eigen::Vector2d q = at + d * Eigen::Vector2d(std::cos(a), std::sin(a));
      const Eigen::Vector2i cell = plan.world_to_cell(q);
      if (plan.contains(cell.x(), cell.y()) && world.clearance[plan.index(cell.x(), cell.y())] >= 0.3) people.push_back(q);
    }
    for (int b = 0; b < params.beams; ++b) {
      const double angle = poses[k].z() - 0.5 * params.field_of_view_rad + b * spacing;
      if (random.chance(params.dropout)) continue;
      const double range = detail::cast_ray(world, at, angle, params, people, random);
      const bool hit = range >= 0.0;
      const double measured = hit ? std::max(0.0, range + params.range_noise_m * random.normal()) : params.max_range_m;
      const Eigen::Vector2d end = at + measured * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      beams.push_back({to_map[k] * at, to_map[k] * end, hit});
    }
  }

  // Log-odds on a grid around every beam, then the trinary map.
  Eigen::Vector2d lo = beams.empty() ? Eigen::Vector2d::Zero() : beams.front().from, hi = lo;
  for (const Beam& b : beams) {
    lo = lo.cwiseMin(b.from).cwiseMin(b.to);
    hi = hi.cwiseMax(b.from).cwiseMax(b.to);
  }
  const double res = params.resolution_m, margin = 2.0 * res;
  const double cols = std::ceil((hi.x() - lo.x() + 2.0 * margin) / res), rows = std::ceil((hi.y() - lo.y() + 2.0 * margin) / res);
  if (!(cols * rows <= static_cast<double>(params.max_cells))) {
    throw limit_error("simulate: the map would have " + std::to_string(static_cast<long long>(cols * rows)) +
                      " cells, more than LidarSlamParams::max_cells (" + std::to_string(params.max_cells) + ")");
  }
  OccupancyGrid grid(static_cast<int>(cols), static_cast<int>(rows), res,
                     Pose2{lo.x() - margin, lo.y() - margin, 0.0}, CellState::unknown);
  std::vector<float> log_odds(grid.cells().size(), 0.0f);
  std::vector<std::uint8_t> seen(grid.cells().size(), 0);
  const Eigen::Affine2d to_pixel = grid.pixel_from_world();
  for (const Beam& b : beams) {
    const Eigen::Vector2d a = to_pixel * b.from, e = to_pixel * b.to;
    int x = static_cast<int>(std::floor(a.x() + 0.5)), y = static_cast<int>(std::floor(a.y() + 0.5));
    const int x1 = static_cast<int>(std::floor(e.x() + 0.5)), y1 = static_cast<int>(std::floor(e.y() + 0.5));
    const int dx = std::abs(x1 - x), dy = -std::abs(y1 - y), sx = x < x1 ? 1 : -1, sy = y < y1 ? 1 : -1;
    int error = dx + dy;
    while (x != x1 || y != y1) {  // Bresenham: every cell before the end is seen free
      if (grid.contains(x, y)) {
        const std::size_t i = grid.index(x, y);
        log_odds[i] += static_cast<float>(params.miss_log_odds);
        seen[i] = 1;
      }
      const int twice = 2 * error;
      if (twice >= dy) error += dy, x += sx;
      if (twice <= dx) error += dx, y += sy;
    }
    if (b.hit && grid.contains(x1, y1)) {
      const std::size_t i = grid.index(x1, y1);
      log_odds[i] += static_cast<float>(params.hit_log_odds);
      seen[i] = 1;
    }
  }
  const CellState unknown = params.binary ? CellState::occupied : CellState::unknown;
  for (std::size_t i = 0; i < log_odds.size(); ++i) {
    grid.cells()[i] = !seen[i]                                  ? unknown
                      : log_odds[i] >= params.occupied_log_odds ? CellState::occupied
                      : log_odds[i] <= params.free_log_odds     ? CellState::free
                                                                : unknown;
  }
  out.grid = std::move(grid);
  out.pixel_transform = to_pixel_transform(out.T_dest_source, out.grid, plan);
  return out;
}

}  // namespace areamatch
