#pragma once
/// \file synthetic/robot_map_params.hpp
/// What `make_robot_map` is asked for (`RobotMapParams`) and gives (`RobotMap`: the map and its exact
/// ground truth, with the distortions it was drawn with).

#include "../error.hpp"
#include "../geometry.hpp"
#include "../grid.hpp"
#include "../image.hpp"
#include "../transform.hpp"

#include <Eigen/Core>

#include <cmath>
#include <string>
#include <vector>

namespace areamatch {

/// Parameters of `make_robot_map`. Lengths in metres, angles in radians.
struct RobotMapParams {
  double rotation_rad = 0.0;               ///< turn of the robot map relative to the layout
  Eigen::Vector2d translation_m = Eigen::Vector2d::Zero();  ///< extra shift of the robot frame
  double resolution = 0.05;                ///< metres per cell of the robot map
  bool mirror = false;                     ///< the robot map is a mirror image of the layout
  double wall_noise_m = 0.0;               ///< std dev of per-cell jitter of the sampled position
  double wall_bend_m = 0.0;                ///< amplitude of a smooth distortion (SLAM drift)
  /// wavelength of that distortion (0: half the building's longer side, at least 10 m); longer
  /// is gentler (a building-wide drift rather than a wavy map)
  double bend_wavelength_m = 0.0;
  /// Scale drift (odometry that over- or under-counts distance more and more): along the
  /// building's longer side the layout metres per map metre grow linearly from 1 at its start to
  /// 1 + `scale_drift` at its end (negative: shrink), on top of the bend. 0.02 stretches a 40 m
  /// building's far end by 2 % and shifts it by 0.4 m. The truth is `RobotMap::drift`.
  double scale_drift = 0.0;
  /// Broken pieces (a failed loop closure): this many straight cuts across the building's longer
  /// side, evenly spaced; everything beyond a cut is turned about the cut's middle by an angle
  /// drawn from [break_min_rotation_rad, break_max_rotation_rad] (either sign) and shifted by up
  /// to `break_shift_m`, on top of the cuts before it. The truth is `RobotMap::breaks`.
  int break_count = 0;
  double break_min_rotation_rad = 2.0 * pi / 180.0;
  double break_max_rotation_rad = 10.0 * pi / 180.0;
  double break_shift_m = 0.2;
  int max_clutter_per_room = 0;            ///< furniture blobs per explored room: 0..this
  double explored_fraction = 1.0;          ///< share of rooms the robot entered (corridors always)
  double speckle_per_m2 = 0.0;             ///< isolated occupied cells per m² of free space
  bool unknown_outside = true;             ///< outside the walls: unknown (else occupied)
  double margin_m = 1.0;                   ///< space around the building inside the image

  // Hand-held depth-sensor maps (see `handheld()`, calibrated in docs/synthetic.md).
  /// Walls are seen as a layer this thick on the explored side only, the rest of the wall and what
  /// lies behind it unknown (0: whole walls, as a laser SLAM map draws them).
  double seen_wall_m = 0.0;
  /// Share of the seen wall surface that is missing (free space meets unknown there), in patches
  /// of `wall_gap_patch_m`.
  double wall_gap_fraction = 0.0;
  double wall_gap_patch_m = 1.0;
  /// Share of the explored rooms' doors shown closed (a wall across the doorway).
  double closed_door_fraction = 0.0;
  /// The explored rooms are those nearest a random start room (one walk), not a random choice.
  bool explore_from_start = false;
  /// The corridor is explored only within this distance of an explored room's door (0: all of it).
  double corridor_reach_m = 0.0;

  /// A hand-held depth-sensor scan of part of a floor: 0.02 m cells, walls seen as a thin ragged
  /// layer with gaps, some doors closed, furniture, 40 % of the rooms near one start and the
  /// corridor near them, and a smooth drift of 0.3 m (docs/synthetic.md: measured against
  /// shared/handheld).
  static RobotMapParams handheld() {
    RobotMapParams p;
    p.resolution = 0.02;
    p.wall_noise_m = 0.015;
    p.wall_bend_m = 0.3;
    p.max_clutter_per_room = 4;
    p.explored_fraction = 0.4;
    p.speckle_per_m2 = 0.05;
    p.margin_m = 2.0;
    p.seen_wall_m = 0.06;
    p.wall_gap_fraction = 0.25;
    p.closed_door_fraction = 0.25;
    p.explore_from_start = true;
    p.corridor_reach_m = 5.0;
    return p;
  }

  void validate() const;
};

/// The smooth distortion of a generated robot map (`RobotMapParams::wall_bend_m`): two long sine
/// waves per axis, in the layout's frame.
struct BendField {
  double amplitude_m = 0.0;
  double wavelength_m = 10.0;
  Eigen::Vector4d phase = Eigen::Vector4d::Zero();
  /// How far the robot map shows layout point p away from where the rigid transform puts it.
  Eigen::Vector2d operator()(const Eigen::Vector2d& p) const {
    if (amplitude_m == 0.0) return Eigen::Vector2d::Zero();
    const double k = 2.0 * pi / wavelength_m;
    return amplitude_m * Eigen::Vector2d(std::sin(k * p.y() + phase[0]) * std::cos(0.5 * k * p.x() + phase[1]),
                                         std::sin(k * p.x() + phase[2]) * std::cos(0.5 * k * p.y() + phase[3]));
  }
};

/// The scale drift of a generated robot map (`RobotMapParams::scale_drift`), in the layout's
/// frame: a point `s` metres along `axis` from `start_m` moves `rate · s² / (2 · length_m)` along
/// it, so that the local scale along the axis is 1 + rate · s / length_m.
struct ScaleDrift {
  double rate = 0.0;
  Eigen::Vector2d axis = Eigen::Vector2d::UnitX();
  double start_m = 0.0;
  double length_m = 1.0;
  /// Where the drifting map shows layout point p (p itself without drift).
  Eigen::Vector2d operator()(const Eigen::Vector2d& p) const {
    if (rate == 0.0) return p;
    const double s = p.dot(axis) - start_m;
    return p + (rate * s * s / (2.0 * length_m)) * axis;
  }
};

/// One broken piece's cut of a generated robot map (`RobotMapParams::break_count`), in the
/// layout's frame: layout points beyond the cut ((p − point) · normal > 0) are shown moved by
/// `motion` (after the bend; the cuts in order, each on top of the ones before it).
struct MapBreak {
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  Eigen::Vector2d normal = Eigen::Vector2d::UnitX();
  Similarity2 motion;
  bool beyond(const Eigen::Vector2d& p) const { return (p - point).dot(normal) > 0.0; }
};

/// A robot map of a building with the exact ground truth.
struct RobotMap {
  OccupancyGrid grid;
  /// robot-map world → layout world (source → destination), rigid; the exact correspondence of a
  /// bent map is `true_dest` (wall jitter aside)
  Similarity2 T_dest_source;
  PixelTransform pixel_transform;     ///< robot-map pixel → layout pixel
  std::vector<int> explored_areas;    ///< ids of the areas the robot entered, ascending
  std::vector<Polygon2> clutter;      ///< furniture, layout world frame
  BendField bend;                     ///< the smooth distortion (none unless `wall_bend_m`)
  ScaleDrift drift;                   ///< the scale drift (none unless `scale_drift`)
  std::vector<MapBreak> breaks;       ///< the broken pieces' cuts (none unless `break_count`)
  /// A layout point (rigid transform applied) with the smooth distortions applied: the bend, then
  /// the scale drift.
  Eigen::Vector2d smooth(Eigen::Vector2d p) const {
    p += bend(p);
    return drift(p);
  }
  /// The point `smooth` takes to `q` (by fixed-point iteration; the distortions are gentle).
  Eigen::Vector2d smooth_inverse(const Eigen::Vector2d& q) const {
    Eigen::Vector2d p = q;
    for (int it = 0; it < 100; ++it) {
      const Eigen::Vector2d step = q - smooth(p);
      p += step;
      if (step.norm() < 1e-9) break;
    }
    return p;
  }
  /// Which piece a layout point (rigid transform and smooth distortions applied) falls in: the
  /// number of cuts it lies beyond (0: the piece that did not move).
  int piece_at(const Eigen::Vector2d& bent) const {
    int piece = 0;
    for (const MapBreak& b : breaks) piece += b.beyond(bent);
    return piece;
  }
  /// The motion of piece `k` (its first k cuts' motions, in order): layout → layout.
  Similarity2 piece_motion(int k) const {
    Similarity2 m;
    for (int i = 0; i < k && i < static_cast<int>(breaks.size()); ++i) m = breaks[static_cast<std::size_t>(i)].motion * m;
    return m;
  }
  /// The layout point a robot-map point shows: the rigid transform, the bend and scale drift, then
  /// its piece's motion.
  Eigen::Vector2d true_dest(const Eigen::Vector2d& source_world) const {
    const Eigen::Vector2d p = smooth(T_dest_source * source_world);
    return breaks.empty() ? p : piece_motion(piece_at(p)) * p;
  }
};

inline void RobotMapParams::validate() const {
  check_resolution(resolution, "RobotMapParams::resolution");
  if (!std::isfinite(rotation_rad) || !translation_m.allFinite()) {
    throw parameter_error("RobotMapParams: rotation and translation must be finite");
  }
  auto non_negative = [](double v, const char* name) { detail::require_non_negative(v, std::string("RobotMapParams::") + name); };
  non_negative(wall_noise_m, "wall_noise_m");
  non_negative(wall_bend_m, "wall_bend_m");
  non_negative(bend_wavelength_m, "bend_wavelength_m");
  if (!(std::abs(scale_drift) <= 0.2)) throw parameter_error("RobotMapParams::scale_drift must be within [-0.2, 0.2] (a share), got " + std::to_string(scale_drift));
  if (break_count < 0 || break_count > 20) throw parameter_error("RobotMapParams::break_count must be in [0, 20]");
  non_negative(break_min_rotation_rad, "break_min_rotation_rad");
  if (!(break_max_rotation_rad >= break_min_rotation_rad && break_max_rotation_rad < pi)) {
    throw parameter_error("RobotMapParams::break_max_rotation_rad must be in [break_min_rotation_rad, pi)");
  }
  non_negative(break_shift_m, "break_shift_m");
  non_negative(speckle_per_m2, "speckle_per_m2");
  non_negative(margin_m, "margin_m");
  non_negative(seen_wall_m, "seen_wall_m");
  non_negative(corridor_reach_m, "corridor_reach_m");
  detail::require_positive(wall_gap_patch_m, "RobotMapParams::wall_gap_patch_m");
  for (const auto& [v, name] : {std::pair{wall_gap_fraction, "wall_gap_fraction"}, std::pair{closed_door_fraction, "closed_door_fraction"}}) {
    if (!(v >= 0.0 && v <= 1.0)) throw parameter_error(std::string("RobotMapParams::") + name + " must be in [0, 1]");
  }
  if (max_clutter_per_room < 0) throw parameter_error("RobotMapParams::max_clutter_per_room must be >= 0");
  if (!(explored_fraction >= 0.0 && explored_fraction <= 1.0)) {
    throw parameter_error("RobotMapParams::explored_fraction must be in [0, 1]");
  }
}

}  // namespace areamatch
