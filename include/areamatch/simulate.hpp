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

#include "detail/random.hpp"
#include "error.hpp"
#include "grid.hpp"
#include "simulate/drift.hpp"
#include "simulate/integrate.hpp"
#include "simulate/params.hpp"
#include "simulate/path.hpp"
#include "simulate/world.hpp"
#include "transform.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace areamatch {

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

  const std::vector<Similarity2> to_map = detail::scan_frames(poses, drift, params, random);
  out.T_dest_source = detail::rigid_ground_truth(poses, to_map, params.mirror);
  for (std::size_t k = 0; k < poses.size(); ++k) {
    out.path.push_back(poses[k].head<2>());
    out.bend_m = std::max(out.bend_m, (out.T_dest_source * (to_map[k] * poses[k].head<2>()) - poses[k].head<2>()).norm());
  }
  out.grid = detail::integrate_beams(detail::cast_scans(world, poses, to_map, params, random), params);
  out.pixel_transform = to_pixel_transform(out.T_dest_source, out.grid, plan);
  return out;
}

}  // namespace areamatch
