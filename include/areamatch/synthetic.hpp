#pragma once
/// \file synthetic.hpp
/// Synthetic floor plans with exact ground truth, for tests, demos and benchmarks.
///
/// `generate_building` draws a layout map: corridors (straight, L, T, loop or a ladder of parallel
/// corridors for large footprints), rooms of varied sizes along both sides of every corridor,
/// one door per room onto its corridor, walls of a given thickness, optional pillars. It returns
/// the map with the rooms' polygons (metres, world frame), the doors and a per-cell label image.
///
/// `make_robot_map` turns a building into what a robot's SLAM would produce of it: another
/// resolution, turned, shifted, optionally mirrored, with wall jitter, smooth bending, furniture,
/// speckles, unknown outside, only some rooms explored — and the exact transform between the two.
///
/// Everything is deterministic in the seed (same seed, same map, bit for bit, on every platform).

#include "error.hpp"
#include "geometry.hpp"
#include "grid.hpp"
#include "image.hpp"
#include "transform.hpp"
#include "detail/random.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace areamatch {

/// The corridor system of a generated building.
enum class CorridorLayout {
  automatic,  ///< chosen from the seed (a ladder when the footprint is large)
  straight,   ///< one corridor along the long side
  l_shape,    ///< two corridors meeting at a corner
  t_shape,    ///< a corridor with a branch from its middle
  loop,       ///< a ring of four corridors with rooms inside and outside
  ladder      ///< parallel corridors joined at both ends (and in the middle when long)
};

/// Parameters of `generate_building`. Lengths in metres.
struct BuildingParams {
  CorridorLayout layout = CorridorLayout::automatic;
  double width_m = 30.0;               ///< footprint along x (interior extent of the building)
  double height_m = 20.0;              ///< footprint along y
  double corridor_width_m = 1.8;       ///< clear width of every corridor
  double min_room_width_m = 2.5;       ///< room extent along its corridor
  double max_room_width_m = 5.5;
  double min_room_depth_m = 3.0;       ///< room extent away from its corridor
  double max_room_depth_m = 6.0;
  double door_width_m = 0.9;           ///< clear width of every door
  double wall_thickness_m = 0.15;      ///< every wall, inner and outer
  double pillar_probability = 0.0;     ///< chance that a room larger than 20 m² gets a pillar
  double pillar_size_m = 0.4;          ///< side of a square pillar
  double margin_m = 1.0;               ///< space around the building inside the image
  double resolution = 0.05;            ///< metres per cell of the layout map
  bool unknown_outside = true;         ///< outside the walls: unknown (else occupied, as drawn plans)

  /// Throws `parameter_error` naming the first parameter out of its domain.
  void validate() const;
};

/// One ground-truth area of a generated building.
struct SyntheticArea {
  int id = 0;               ///< index in `SyntheticBuilding::areas`, also its label value
  bool corridor = false;    ///< the corridor system (one area) or a room
  Polygon2 polygon;         ///< free interior, world frame, metres
  double size_m2 = 0.0;     ///< area of `polygon`
};

/// One door of a generated building: an opening through a wall between two areas.
struct SyntheticDoor {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< centre of the opening (wall mid-line)
  double width_m = 0.0;
  int area_a = -1;  ///< the room
  int area_b = -1;  ///< the area the door leads to (the corridor)
  Eigen::Vector2d jamb_a = Eigen::Vector2d::Zero();  ///< the segment across the opening
  Eigen::Vector2d jamb_b = Eigen::Vector2d::Zero();
};

/// A generated layout map with its ground truth.
struct SyntheticBuilding {
  OccupancyGrid layout;               ///< free interiors, occupied walls, outside per params
  std::vector<SyntheticArea> areas;   ///< area 0 is the corridor system
  std::vector<SyntheticDoor> doors;
  std::vector<Box2> pillars;          ///< occupied squares inside rooms
  /// Per cell of `layout`: the id of the area whose interior holds it, −1 for walls, doors,
  /// pillars and outside.
  std::vector<int> labels;
  CorridorLayout layout_kind = CorridorLayout::straight;
  BuildingParams params;
};

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

// ------------------------------------------------------------------------------------------------

inline void BuildingParams::validate() const {
  auto positive = [](double v, const char* name) { detail::require_positive(v, std::string("BuildingParams::") + name); };
  positive(width_m, "width_m");
  positive(height_m, "height_m");
  positive(corridor_width_m, "corridor_width_m");
  positive(min_room_width_m, "min_room_width_m");
  positive(min_room_depth_m, "min_room_depth_m");
  positive(door_width_m, "door_width_m");
  positive(wall_thickness_m, "wall_thickness_m");
  positive(pillar_size_m, "pillar_size_m");
  check_resolution(resolution, "BuildingParams::resolution");
  if (max_room_width_m < min_room_width_m || max_room_depth_m < min_room_depth_m) {
    throw parameter_error("BuildingParams: max room width/depth must not be below the min");
  }
  detail::require_non_negative(margin_m, "BuildingParams::margin_m");
  if (wall_thickness_m < resolution) {
    throw parameter_error("BuildingParams::wall_thickness_m must be at least one cell (" +
                          std::to_string(resolution) + " m) or walls would have holes");
  }
  if (door_width_m + 0.2 > min_room_width_m) {
    throw parameter_error("BuildingParams::door_width_m must be at least 0.2 m narrower than min_room_width_m");
  }
  if (!(pillar_probability >= 0.0 && pillar_probability <= 1.0)) {
    throw parameter_error("BuildingParams::pillar_probability must be in [0, 1]");
  }
  const double cells = (width_m + 2 * margin_m) / resolution * ((height_m + 2 * margin_m) / resolution);
  if (cells > static_cast<double>(max_grid_cells)) {
    throw parameter_error("BuildingParams: the layout map would have more than areamatch::max_grid_cells (" +
                          std::to_string(max_grid_cells) + ") cells, more than a map may have to be segmented");
  }
}

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

namespace detail {

/// Axis-aligned rectangle in metres.
struct Rect {
  double x0, y0, x1, y1;
  double width() const { return x1 - x0; }
  double height() const { return y1 - y0; }
  /// True when the two rectangles come closer than `gap` (touching at exactly `gap` is fine).
  bool closer_than(const Rect& o, double gap) const {
    const double eps = 1e-9;
    return x0 < o.x1 + gap - eps && o.x0 < x1 + gap - eps && y0 < o.y1 + gap - eps && o.y0 < y1 + gap - eps;
  }
  bool inside(const Rect& o) const { return x0 >= o.x0 && y0 >= o.y0 && x1 <= o.x1 && y1 <= o.y1; }
  Rect grown(double d) const { return {x0 - d, y0 - d, x1 + d, y1 + d}; }
  Polygon2 polygon() const { return make_rectangle(x0, y0, x1, y1); }
};

/// Calls fn(col, row) for every cell of `grid` whose centre lies inside `rect` (world frame of a
/// grid with zero yaw).
template <class Fn>
void for_each_cell_in(const OccupancyGrid& grid, const Rect& rect, Fn&& fn) {
  const Eigen::Vector2d a = grid.world_to_pixel({rect.x0, rect.y0});
  const Eigen::Vector2d b = grid.world_to_pixel({rect.x1, rect.y1});
  const int c0 = std::max(0, static_cast<int>(std::ceil(std::min(a.x(), b.x()))));
  const int c1 = std::min(grid.width() - 1, static_cast<int>(std::floor(std::max(a.x(), b.x()))));
  const int r0 = std::max(0, static_cast<int>(std::ceil(std::min(a.y(), b.y()))));
  const int r1 = std::min(grid.height() - 1, static_cast<int>(std::floor(std::max(a.y(), b.y()))));
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c) fn(c, r);
}

/// A corridor: its clear rectangle and which of its long sides may carry rooms.
struct CorridorPiece {
  Rect rect;
  bool horizontal;
};

/// The corridors of a layout over the footprint [0, W] × [0, H].
inline std::vector<CorridorPiece> corridor_pieces(CorridorLayout layout, const BuildingParams& p, Random& random) {
  const double W = p.width_m, H = p.height_m, c = p.corridor_width_m;
  const double depth = 0.5 * (p.min_room_depth_m + p.max_room_depth_m);
  std::vector<CorridorPiece> pieces;
  auto horizontal = [&](double y, double xa, double xb) {
    pieces.push_back({{xa, y, xb, y + c}, true});
  };
  auto vertical = [&](double x, double ya, double yb) {
    pieces.push_back({{x, ya, x + c, yb}, false});
  };
  const double mid_y = std::max(0.0, 0.5 * (H - c));
  switch (layout) {
    case CorridorLayout::straight:
      horizontal(mid_y, 0.0, W);
      break;
    case CorridorLayout::l_shape: {
      const double y = std::min(mid_y, std::max(0.0, depth + p.wall_thickness_m));
      horizontal(y, 0.0, W);
      vertical(std::max(0.0, W - c - depth - p.wall_thickness_m), y, H);
      break;
    }
    case CorridorLayout::t_shape: {
      const double y = std::min(mid_y, std::max(0.0, depth + p.wall_thickness_m));
      horizontal(y, 0.0, W);
      const double x = std::clamp(random.uniform(0.35, 0.65) * W - 0.5 * c, 0.0, std::max(0.0, W - c));
      vertical(x, y, H);
      break;
    }
    case CorridorLayout::loop: {
      const double inset = std::min(depth + p.wall_thickness_m, 0.25 * std::min(W, H));
      const double xa = inset, xb = std::max(inset + 2 * c, W - inset);
      const double ya = inset, yb = std::max(inset + 2 * c, H - inset);
      horizontal(ya, xa, xb);
      horizontal(yb - c, xa, xb);
      vertical(xa, ya, yb);
      vertical(xb - c, ya, yb);
      break;
    }
    case CorridorLayout::ladder:
    case CorridorLayout::automatic: {
      const double band = 2.0 * (depth + p.wall_thickness_m) + c + p.wall_thickness_m;
      const int rungs = std::max(1, static_cast<int>(std::floor(H / band)));
      const double spacing = H / rungs;
      for (int i = 0; i < rungs; ++i) horizontal(std::max(0.0, (i + 0.5) * spacing - 0.5 * c), 0.0, W);
      if (rungs > 1) {
        const double y0 = pieces.front().rect.y0, y1 = pieces.back().rect.y1;
        vertical(0.0, y0, y1);
        vertical(std::max(0.0, W - c), y0, y1);
        if (W > 60.0) vertical(std::max(0.0, 0.5 * W - 0.5 * c), y0, y1);
      }
      break;
    }
  }
  // Keep every corridor inside the footprint.
  for (auto& piece : pieces) {
    piece.rect.x1 = std::min(piece.rect.x1, W);
    piece.rect.y1 = std::min(piece.rect.y1, H);
  }
  return pieces;
}

inline CorridorLayout choose_layout(const BuildingParams& p, Random& random) {
  if (p.layout != CorridorLayout::automatic) return p.layout;
  if (p.width_m > 60.0 && p.height_m > 40.0) return CorridorLayout::ladder;
  const CorridorLayout small[] = {CorridorLayout::straight, CorridorLayout::l_shape, CorridorLayout::t_shape,
                                  CorridorLayout::loop};
  return small[random.integer(0, 3)];
}

/// A room candidate beside a corridor side: the room rectangle, the door rectangle through the
/// wall, and the door's centre line.
struct RoomPlan {
  Rect room;
  Rect door;
  Eigen::Vector2d door_center;
  Eigen::Vector2d jamb_a, jamb_b;
};

/// Lines one side of a corridor with rooms. `side` = +1 places rooms above/right, −1 below/left.
inline void place_rooms_along(const CorridorPiece& corridor, int side, const BuildingParams& p,
                              const Rect& footprint, std::vector<Rect>& occupied,
                              std::vector<RoomPlan>& rooms, Random& random) {
  const double t = p.wall_thickness_m;
  const Rect& c = corridor.rect;
  const double along0 = corridor.horizontal ? c.x0 : c.y0;
  const double along1 = corridor.horizontal ? c.x1 : c.y1;
  const double edge = corridor.horizontal ? (side > 0 ? c.y1 : c.y0) : (side > 0 ? c.x1 : c.x0);
  double cursor = along0;
  while (cursor + p.min_room_width_m <= along1 + 1e-9) {
    const double width = std::min(random.uniform(p.min_room_width_m, p.max_room_width_m), along1 - cursor);
    const double wanted_depth = random.uniform(p.min_room_depth_m, p.max_room_depth_m);
    bool placed = false;
    // Shrink a room that does not fit until it does or gets too shallow.
    for (double depth = wanted_depth; depth >= p.min_room_depth_m - 1e-9; depth -= 0.5) {
      const double near = edge + side * t, far = near + side * depth;
      Rect room = corridor.horizontal ? Rect{cursor, std::min(near, far), cursor + width, std::max(near, far)}
                                      : Rect{std::min(near, far), cursor, std::max(near, far), cursor + width};
      if (!room.inside(footprint)) continue;
      if (std::any_of(occupied.begin(), occupied.end(), [&](const Rect& o) { return room.closer_than(o, t); })) continue;
      // The door: somewhere along the room's corridor side, away from the corners.
      const double slack = width - p.door_width_m - 0.4;
      const double start = cursor + 0.2 + (slack > 0 ? random.uniform(0.0, slack) : 0.5 * (width - p.door_width_m - 0.4));
      const double end = start + p.door_width_m;
      const double wall0 = std::min(edge, edge + side * t), wall1 = std::max(edge, edge + side * t);
      const double wall_mid = 0.5 * (wall0 + wall1);
      RoomPlan plan;
      plan.room = room;
      if (corridor.horizontal) {
        plan.door = {start, wall0, end, wall1};
        plan.jamb_a = {start, wall_mid};
        plan.jamb_b = {end, wall_mid};
      } else {
        plan.door = {wall0, start, wall1, end};
        plan.jamb_a = {wall_mid, start};
        plan.jamb_b = {wall_mid, end};
      }
      plan.door_center = 0.5 * (plan.jamb_a + plan.jamb_b);
      occupied.push_back(room);
      rooms.push_back(plan);
      placed = true;
      break;
    }
    cursor += placed ? width + t : 1.0;
  }
}

/// A uniform number in [0, 1) from a seed and two integers (a fixed hash, not a stream), for
/// noise that depends on where, not on the order cells are visited.
inline double hash_unit(std::uint64_t seed, std::int64_t a, std::int64_t b) {
  std::uint64_t z = seed ^ (static_cast<std::uint64_t>(a) * 0x9E3779B97F4A7C15ull) ^
                    (static_cast<std::uint64_t>(b) * 0xC2B2AE3D27D4EB4Full);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * (1.0 / 9007199254740992.0);
}

/// Per cell of `grid`, the distance in metres to the nearest seed cell (a two-pass 3-4 chamfer
/// transform: within 8 % of Euclidean), +infinity without seeds.
inline std::vector<double> chamfer_distance(const OccupancyGrid& grid, const std::vector<bool>& seed) {
  const int w = grid.width(), h = grid.height();
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::vector<double> d(seed.size(), inf);
  for (std::size_t i = 0; i < seed.size(); ++i) if (seed[i]) d[i] = 0.0;
  auto relax = [&](int c, int r, int dc, int dr, double step) {
    const int nc = c + dc, nr = r + dr;
    if (nc < 0 || nr < 0 || nc >= w || nr >= h) return;
    double& here = d[static_cast<std::size_t>(r) * w + c];
    here = std::min(here, d[static_cast<std::size_t>(nr) * w + nc] + step);
  };
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      relax(c, r, -1, 0, 3.0), relax(c, r, -1, -1, 4.0), relax(c, r, 0, -1, 3.0), relax(c, r, 1, -1, 4.0);
    }
  for (int r = h - 1; r >= 0; --r)
    for (int c = w - 1; c >= 0; --c) {
      relax(c, r, 1, 0, 3.0), relax(c, r, 1, 1, 4.0), relax(c, r, 0, 1, 3.0), relax(c, r, -1, 1, 4.0);
    }
  for (double& v : d) v *= grid.resolution() / 3.0;
  return d;
}

}  // namespace detail

/// Generates a building (see the file comment). Throws `parameter_error` for invalid parameters.
inline SyntheticBuilding generate_building(const BuildingParams& params, std::uint64_t seed) {
  params.validate();
  detail::Random random(seed);
  SyntheticBuilding building;
  building.params = params;
  building.layout_kind = detail::choose_layout(params, random);

  const detail::Rect footprint{0.0, 0.0, params.width_m, params.height_m};
  const auto corridors = detail::corridor_pieces(building.layout_kind, params, random);

  std::vector<detail::Rect> occupied;
  for (const auto& piece : corridors) occupied.push_back(piece.rect);
  std::vector<detail::RoomPlan> rooms;
  for (const auto& piece : corridors) {
    for (int side : {+1, -1}) detail::place_rooms_along(piece, side, params, footprint, occupied, rooms, random);
  }

  // Areas: 0 = the corridor system, then the rooms in placement order.
  SyntheticArea corridor_area;
  corridor_area.id = 0;
  corridor_area.corridor = true;
  {
    MultiPolygon2 merged;
    for (const auto& piece : corridors) {
      MultiPolygon2 next;
      bg::union_(merged, piece.rect.polygon(), next);
      merged = std::move(next);
    }
    // The corridors are connected by construction; keep the largest part should rounding split it.
    std::sort(merged.begin(), merged.end(), [](const Polygon2& a, const Polygon2& b) { return bg::area(a) > bg::area(b); });
    corridor_area.polygon = merged.empty() ? Polygon2{} : merged.front();
    corridor_area.size_m2 = std::abs(bg::area(corridor_area.polygon));
  }
  building.areas.push_back(corridor_area);
  for (const auto& plan : rooms) {
    SyntheticArea area;
    area.id = static_cast<int>(building.areas.size());
    area.polygon = plan.room.polygon();
    area.size_m2 = plan.room.width() * plan.room.height();
    SyntheticDoor door;
    door.position = plan.door_center;
    door.width_m = params.door_width_m;
    door.area_a = area.id;
    door.area_b = 0;
    door.jamb_a = plan.jamb_a;
    door.jamb_b = plan.jamb_b;
    building.areas.push_back(area);
    building.doors.push_back(door);
    if (area.size_m2 > 20.0 && random.chance(params.pillar_probability)) {
      const double s = params.pillar_size_m;
      const Eigen::Vector2d centre(random.uniform(plan.room.x0 + 1.0 + s, plan.room.x1 - 1.0 - s),
                                   random.uniform(plan.room.y0 + 1.0 + s, plan.room.y1 - 1.0 - s));
      building.pillars.push_back(Box2({centre.x() - s / 2, centre.y() - s / 2}, {centre.x() + s / 2, centre.y() + s / 2}));
    }
  }

  // Rasterise: walls around every interior, then the interiors, doors and pillars.
  const double m = params.margin_m;
  const int width = static_cast<int>(std::ceil((params.width_m + 2 * m) / params.resolution));
  const int height = static_cast<int>(std::ceil((params.height_m + 2 * m) / params.resolution));
  building.layout = OccupancyGrid(width, height, params.resolution, Pose2{-m, -m, 0.0},
                                  params.unknown_outside ? CellState::unknown : CellState::occupied);
  OccupancyGrid& grid = building.layout;
  building.labels.assign(grid.cells().size(), -1);
  std::vector<detail::Rect> interiors;
  for (const auto& piece : corridors) interiors.push_back(piece.rect);
  for (const auto& plan : rooms) interiors.push_back(plan.room);
  for (const auto& rect : interiors) {
    detail::for_each_cell_in(grid, rect.grown(params.wall_thickness_m),
                             [&](int c, int r) { grid.set(c, r, CellState::occupied); });
  }
  auto carve = [&](const detail::Rect& rect, int label) {
    detail::for_each_cell_in(grid, rect, [&](int c, int r) {
      grid.set(c, r, CellState::free);
      building.labels[grid.index(c, r)] = label;
    });
  };
  for (const auto& piece : corridors) carve(piece.rect, 0);
  for (std::size_t i = 0; i < rooms.size(); ++i) carve(rooms[i].room, static_cast<int>(i) + 1);
  for (const auto& plan : rooms) carve(plan.door, -1);
  for (const auto& pillar : building.pillars) {
    const detail::Rect rect{pillar.min_corner().x(), pillar.min_corner().y(), pillar.max_corner().x(),
                            pillar.max_corner().y()};
    detail::for_each_cell_in(grid, rect, [&](int c, int r) {
      grid.set(c, r, CellState::occupied);
      building.labels[grid.index(c, r)] = -1;
    });
  }
  return building;
}

/// Makes a robot map of `building` (see the file comment and `RobotMapParams`).
inline RobotMap make_robot_map(const SyntheticBuilding& building, const RobotMapParams& params, std::uint64_t seed) {
  params.validate();
  detail::Random random(seed);
  const OccupancyGrid& layout = building.layout;
  RobotMap robot;

  // Which rooms were explored: a seeded choice of round(fraction · rooms) rooms, or (one walk)
  // the rooms nearest a seeded start room.
  std::vector<int> rooms;
  for (const auto& area : building.areas) if (!area.corridor) rooms.push_back(area.id);
  for (std::size_t i = rooms.size(); i > 1; --i) std::swap(rooms[i - 1], rooms[random.integer(0, static_cast<int>(i) - 1)]);
  if (params.explore_from_start && !rooms.empty()) {
    auto centre = [&](int id) {
      Point2 c(0.0, 0.0);
      bg::centroid(building.areas[static_cast<std::size_t>(id)].polygon, c);
      return Eigen::Vector2d(c.x(), c.y());
    };
    const Eigen::Vector2d start = centre(rooms.front());
    std::stable_sort(rooms.begin(), rooms.end(), [&](int a, int b) { return (centre(a) - start).norm() < (centre(b) - start).norm(); });
  }
  rooms.resize(static_cast<std::size_t>(std::lround(params.explored_fraction * rooms.size())));
  std::vector<bool> explored(building.areas.size(), false);
  for (const auto& area : building.areas) if (area.corridor) explored[area.id] = true;
  for (int id : rooms) explored[id] = true;
  for (std::size_t id = 0; id < explored.size(); ++id) if (explored[id]) robot.explored_areas.push_back(static_cast<int>(id));

  // Doors of explored rooms: some shown closed; the corridor is seen near the others' rooms.
  std::vector<const SyntheticDoor*> closed_doors, explored_doors;
  for (const auto& d : building.doors) {
    if (d.area_a < 0 || !explored[static_cast<std::size_t>(d.area_a)]) continue;
    explored_doors.push_back(&d);
    // Drawn only when asked for, so that maps without closed doors keep their random stream.
    if (params.closed_door_fraction > 0.0 && random.uniform() < params.closed_door_fraction) closed_doors.push_back(&d);
  }
  auto corridor_seen = [&](const Eigen::Vector2d& p) {
    if (params.corridor_reach_m <= 0.0) return true;
    return std::any_of(explored_doors.begin(), explored_doors.end(),
                       [&](const SyntheticDoor* d) { return (d->position - p).norm() <= params.corridor_reach_m; });
  };
  auto in_closed_door = [&](const Eigen::Vector2d& p) {
    return std::any_of(closed_doors.begin(), closed_doors.end(), [&](const SyntheticDoor* d) {
      return (d->position - p).norm() <= 0.5 * d->width_m + building.params.wall_thickness_m;
    });
  };
  // Seen walls: layout cells within seen_wall_m of explored free space.
  std::vector<double> to_explored;
  if (params.seen_wall_m > 0.0) {
    std::vector<bool> seeds(building.labels.size(), false);
    for (int r = 0; r < layout.height(); ++r) {
      for (int c = 0; c < layout.width(); ++c) {
        const std::size_t i = layout.index(c, r);
        const int label = building.labels[i];
        if (label < 0 || !explored[static_cast<std::size_t>(label)]) continue;
        seeds[i] = !building.areas[static_cast<std::size_t>(label)].corridor || corridor_seen(layout.cell_center(c, r));
      }
    }
    to_explored = detail::chamfer_distance(layout, seeds);
  }
  const std::uint64_t gap_seed = seed ^ 0x5EEDull;

  // Furniture: boxes against a wall of explored rooms, kept 1 m clear of doors.
  for (const auto& area : building.areas) {
    if (area.corridor || !explored[area.id]) continue;
    Box2 box;
    bg::envelope(area.polygon, box);
    const int count = random.integer(0, params.max_clutter_per_room);
    for (int k = 0; k < count; ++k) {
      const double w = random.uniform(0.4, 1.2), h = random.uniform(0.4, 1.2);
      double x = random.uniform(box.min_corner().x(), box.max_corner().x() - w);
      double y = random.uniform(box.min_corner().y(), box.max_corner().y() - h);
      switch (random.integer(0, 3)) {  // push it against one wall
        case 0: x = box.min_corner().x(); break;
        case 1: x = box.max_corner().x() - w; break;
        case 2: y = box.min_corner().y(); break;
        default: y = box.max_corner().y() - h; break;
      }
      const Eigen::Vector2d centre(x + w / 2, y + h / 2);
      const bool blocks_door = std::any_of(building.doors.begin(), building.doors.end(), [&](const SyntheticDoor& d) {
        return (d.position - centre).norm() < 1.0 + 0.5 * std::hypot(w, h);
      });
      if (!blocks_door) robot.clutter.push_back(make_rectangle(x, y, x + w, y + h));
    }
  }

  // The robot frame: layout turned (and mirrored), then placed so the image starts at the origin.
  Similarity2 T_source_dest;
  T_source_dest.rotation = params.rotation_rad;
  T_source_dest.reflected = params.mirror;
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  const auto& bp = building.params;
  for (double cx : {-bp.wall_thickness_m, bp.width_m + bp.wall_thickness_m}) {
    for (double cy : {-bp.wall_thickness_m, bp.height_m + bp.wall_thickness_m}) {
      const Eigen::Vector2d q = T_source_dest * Eigen::Vector2d(cx, cy);
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
  }
  T_source_dest.translation = params.translation_m;
  lo += params.translation_m;
  hi += params.translation_m;
  const double m = params.margin_m;
  const int width = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x() + 2 * m) / params.resolution)));
  const int height = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y() + 2 * m) / params.resolution)));
  if (static_cast<double>(width) * height > static_cast<double>(max_grid_cells)) {
    throw parameter_error("RobotMapParams: the robot map would have more than areamatch::max_grid_cells (" +
                          std::to_string(max_grid_cells) + ") cells, more than a map may have to be segmented");
  }
  robot.grid = OccupancyGrid(width, height, params.resolution, Pose2{lo.x() - m, lo.y() - m, 0.0});
  robot.T_dest_source = T_source_dest.inverse();
  robot.pixel_transform = to_pixel_transform(robot.T_dest_source, robot.grid, layout);

  // A smooth, seeded distortion: two long sine waves per axis.
  const double wavelength =
      params.bend_wavelength_m > 0.0 ? params.bend_wavelength_m : std::max(10.0, 0.5 * std::max(bp.width_m, bp.height_m));
  // Phases drawn from [0, 6.3): a full turn and a little more, which is harmless for a sine (the
  // value is kept so that the same seed draws the same maps as before).
  constexpr double phase_range = 6.3;
  const Eigen::Vector4d phase(random.uniform(0, phase_range), random.uniform(0, phase_range), random.uniform(0, phase_range),
                              random.uniform(0, phase_range));
  robot.bend = BendField{params.wall_bend_m, wavelength, phase};
  const bool drift_along_x = bp.width_m >= bp.height_m;
  robot.drift = ScaleDrift{params.scale_drift, drift_along_x ? Eigen::Vector2d::UnitX() : Eigen::Vector2d::UnitY(), 0.0,
                           std::max(bp.width_m, bp.height_m)};
  // Broken pieces: cuts across the longer side (drawn only when asked for, so that maps without
  // them keep their random stream).
  const bool along_x = bp.width_m >= bp.height_m;
  for (int k = 0; k < params.break_count; ++k) {
    MapBreak cut;
    const double at = (k + 1.0) / (params.break_count + 1.0);
    cut.point = along_x ? Eigen::Vector2d(at * bp.width_m, 0.5 * bp.height_m) : Eigen::Vector2d(0.5 * bp.width_m, at * bp.height_m);
    cut.normal = along_x ? Eigen::Vector2d::UnitX() : Eigen::Vector2d::UnitY();
    const double turn = (random.chance(0.5) ? 1.0 : -1.0) *
                        random.uniform(params.break_min_rotation_rad, params.break_max_rotation_rad);
    const double direction = random.uniform(0.0, 2.0 * pi), shift = random.uniform(0.0, params.break_shift_m);
    // Turned about the cut's middle (where the previous pieces' motions have put it), then shifted.
    const Eigen::Vector2d pivot = robot.piece_motion(k) * cut.point;
    cut.motion.rotation = turn;
    cut.motion.translation = pivot - Eigen::Rotation2Dd(turn) * pivot + shift * Eigen::Vector2d(std::cos(direction), std::sin(direction));
    robot.breaks.push_back(cut);
  }

  std::vector<Box2> clutter_boxes;
  for (const auto& c : robot.clutter) {
    Box2 b;
    bg::envelope(c, b);
    clutter_boxes.push_back(b);
  }
  const CellState outside = params.unknown_outside ? CellState::unknown : CellState::occupied;
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      Eigen::Vector2d p = robot.smooth(robot.T_dest_source * robot.grid.cell_center(col, row));
      if (!robot.breaks.empty()) p = robot.piece_motion(robot.piece_at(p)) * p;
      if (params.wall_noise_m > 0.0) p += params.wall_noise_m * Eigen::Vector2d(random.normal(), random.normal());
      const Eigen::Vector2i cell = layout.world_to_cell(p);
      CellState state = outside;
      if (layout.contains(cell.x(), cell.y())) {
        state = layout.at(cell.x(), cell.y());
        const int label = building.labels[layout.index(cell.x(), cell.y())];
        if (state == CellState::unknown) state = outside;
        if (state == CellState::free && label >= 0 && !explored[label]) state = CellState::unknown;
        if (state == CellState::free && label >= 0 && building.areas[static_cast<std::size_t>(label)].corridor &&
            !corridor_seen(p)) {
          state = CellState::unknown;
        }
        if (state == CellState::free && label < 0 && in_closed_door(p)) state = CellState::occupied;
        if (state == CellState::free && label < 0 && !to_explored.empty() &&
            to_explored[layout.index(cell.x(), cell.y())] > building.params.wall_thickness_m + params.seen_wall_m) {
          state = CellState::unknown;  // a doorway the scan did not come near
        }
        if (!to_explored.empty() && state != CellState::free && state != outside) {
          const double d = to_explored[layout.index(cell.x(), cell.y())];
          const auto patch = [&](double v) { return static_cast<std::int64_t>(std::floor(v / params.wall_gap_patch_m)); };
          const bool gap = detail::hash_unit(gap_seed, patch(p.x()), patch(p.y())) < params.wall_gap_fraction;
          state = d <= params.seen_wall_m && !gap ? CellState::occupied : CellState::unknown;
        }
        if (state == CellState::free) {
          const Point2 q(p.x(), p.y());
          for (const auto& b : clutter_boxes) {
            if (bg::within(q, b)) {
              state = CellState::occupied;
              break;
            }
          }
        }
      }
      robot.grid.set(col, row, state);
    }
  }

  // Speckles: isolated occupied cells scattered over free space.
  if (params.speckle_per_m2 > 0.0) {
    const auto counts = robot.grid.count();
    const double free_m2 = counts.free * params.resolution * params.resolution;
    const auto n = static_cast<std::size_t>(std::lround(free_m2 * params.speckle_per_m2));
    for (std::size_t k = 0; k < n; ++k) {
      const int col = random.integer(0, width - 1), row = random.integer(0, height - 1);
      if (robot.grid.at(col, row) == CellState::free) robot.grid.set(col, row, CellState::occupied);
    }
  }
  return robot;
}

/// The layout drawn as a floor plan is: every wall as a line `line_width_m` wide along its
/// middle, the rest of the wall free on a room's side and unknown outside (hand-held datasets give
/// layouts as line drawings). Same frame and cells as `building.layout`.
inline OccupancyGrid layout_line_drawing(const SyntheticBuilding& building, double line_width_m) {
  detail::require_positive(line_width_m, "layout_line_drawing: line_width_m");
  const OccupancyGrid& layout = building.layout;
  std::vector<bool> free_seed(layout.cells().size()), unknown_seed(layout.cells().size());
  for (std::size_t i = 0; i < free_seed.size(); ++i) {
    free_seed[i] = layout.cells()[i] == CellState::free;
    unknown_seed[i] = layout.cells()[i] == CellState::unknown;
  }
  const std::vector<double> to_free = detail::chamfer_distance(layout, free_seed);
  const std::vector<double> to_unknown = detail::chamfer_distance(layout, unknown_seed);
  // A wall cell's centre lies half a cell further from the nearest other cell's centre than from
  // the wall's surface.
  const double keep = 0.5 * (building.params.wall_thickness_m - line_width_m) + 0.5 * layout.resolution();
  OccupancyGrid out = layout;
  for (int r = 0; r < layout.height(); ++r) {
    for (int c = 0; c < layout.width(); ++c) {
      const std::size_t i = layout.index(c, r);
      if (layout.cells()[i] != CellState::occupied || std::min(to_free[i], to_unknown[i]) >= keep - 1e-9) continue;
      out.set(c, r, to_free[i] <= to_unknown[i] ? CellState::free : CellState::unknown);
    }
  }
  return out;
}

}  // namespace areamatch
