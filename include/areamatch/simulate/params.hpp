#pragma once
/// \file simulate/params.hpp
/// The settings of a simulated laser-SLAM map and what it returns (simulate.hpp).

#include "../error.hpp"
#include "../grid.hpp"
#include "../transform.hpp"

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
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

}  // namespace areamatch
