#pragma once
/// \file synthetic/robot_map.hpp
/// `make_robot_map` turns a building into what a robot's SLAM would produce of it: another
/// resolution, turned, shifted, optionally mirrored, with wall jitter, smooth bending, scale drift,
/// broken pieces, furniture, speckles, unknown outside, only some rooms explored — and the exact
/// transform between the two.
///
/// Deterministic in the seed (same seed, same map, bit for bit, on every platform). The steps
/// below draw from one random stream in a fixed order (explored rooms, closed doors, furniture,
/// bend phases, breaks, wall jitter per cell, speckles); a step that is not asked for draws
/// nothing, so that maps without it keep their stream.

#include "../error.hpp"
#include "../geometry.hpp"
#include "../grid.hpp"
#include "../image.hpp"
#include "../transform.hpp"
#include "../detail/random.hpp"
#include "building_params.hpp"
#include "line_drawing.hpp"
#include "robot_map_params.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace areamatch {
namespace detail {

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

/// Which areas the robot entered, per area id: the corridors, and a seeded choice of
/// round(fraction · rooms) rooms or (one walk) the rooms nearest a seeded start room.
inline std::vector<bool> explored_areas(const SyntheticBuilding& building, const RobotMapParams& params, Random& random) {
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
  return explored;
}

/// What the robot saw of the layout: explored areas, the doors of explored rooms (some shown
/// closed), the corridor near them, and (seen walls only) each layout cell's distance to
/// explored free space.
struct SeenLayout {
  const SyntheticBuilding* building = nullptr;
  double corridor_reach_m = 0.0;
  std::vector<bool> explored;
  std::vector<const SyntheticDoor*> explored_doors, closed_doors;
  std::vector<double> to_explored;  ///< per layout cell; empty unless `RobotMapParams::seen_wall_m`

  bool corridor_seen(const Eigen::Vector2d& p) const {
    if (corridor_reach_m <= 0.0) return true;
    return std::any_of(explored_doors.begin(), explored_doors.end(),
                       [&](const SyntheticDoor* d) { return (d->position - p).norm() <= corridor_reach_m; });
  }
  bool in_closed_door(const Eigen::Vector2d& p) const {
    return std::any_of(closed_doors.begin(), closed_doors.end(), [&](const SyntheticDoor* d) {
      return (d->position - p).norm() <= 0.5 * d->width_m + building->params.wall_thickness_m;
    });
  }
};

inline SeenLayout seen_layout(const SyntheticBuilding& building, const RobotMapParams& params, std::vector<bool> explored,
                              Random& random) {
  SeenLayout seen;
  seen.building = &building;
  seen.corridor_reach_m = params.corridor_reach_m;
  seen.explored = std::move(explored);
  for (const auto& d : building.doors) {
    if (d.area_a < 0 || !seen.explored[static_cast<std::size_t>(d.area_a)]) continue;
    seen.explored_doors.push_back(&d);
    // Drawn only when asked for, so that maps without closed doors keep their random stream.
    if (params.closed_door_fraction > 0.0 && random.uniform() < params.closed_door_fraction) seen.closed_doors.push_back(&d);
  }
  // Seen walls: layout cells within seen_wall_m of explored free space.
  if (params.seen_wall_m > 0.0) {
    const OccupancyGrid& layout = building.layout;
    std::vector<bool> seeds(building.labels.size(), false);
    for (int r = 0; r < layout.height(); ++r) {
      for (int c = 0; c < layout.width(); ++c) {
        const std::size_t i = layout.index(c, r);
        const int label = building.labels[i];
        if (label < 0 || !seen.explored[static_cast<std::size_t>(label)]) continue;
        seeds[i] = !building.areas[static_cast<std::size_t>(label)].corridor || seen.corridor_seen(layout.cell_center(c, r));
      }
    }
    seen.to_explored = chamfer_distance(layout, seeds);
  }
  return seen;
}

/// Furniture: boxes against a wall of explored rooms, kept 1 m clear of doors (layout frame).
inline std::vector<Polygon2> furniture(const SyntheticBuilding& building, const RobotMapParams& params,
                                       const std::vector<bool>& explored, Random& random) {
  std::vector<Polygon2> clutter;
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
      if (!blocks_door) clutter.push_back(make_rectangle(x, y, x + w, y + h));
    }
  }
  return clutter;
}

/// The robot frame: the layout turned (and mirrored), then placed so the image starts at the
/// origin. Sets the robot map's empty grid, `T_dest_source` and `pixel_transform`.
inline void place_robot_frame(const SyntheticBuilding& building, const RobotMapParams& params, RobotMap& robot) {
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
  robot.pixel_transform = to_pixel_transform(robot.T_dest_source, robot.grid, building.layout);
}

/// The seeded distortions: the bend (two long sine waves per axis), the scale drift and the
/// broken pieces' cuts across the building's longer side.
inline void draw_distortions(const BuildingParams& bp, const RobotMapParams& params, Random& random, RobotMap& robot) {
  const double wavelength =
      params.bend_wavelength_m > 0.0 ? params.bend_wavelength_m : std::max(10.0, 0.5 * std::max(bp.width_m, bp.height_m));
  // Phases drawn from [0, 6.3): a full turn and a little more, which is harmless for a sine (the
  // value is kept so that the same seed draws the same maps as before).
  constexpr double phase_range = 6.3;
  const Eigen::Vector4d phase(random.uniform(0, phase_range), random.uniform(0, phase_range), random.uniform(0, phase_range),
                              random.uniform(0, phase_range));
  robot.bend = BendField{params.wall_bend_m, wavelength, phase};
  const bool along_x = bp.width_m >= bp.height_m;
  robot.drift = ScaleDrift{params.scale_drift, along_x ? Eigen::Vector2d::UnitX() : Eigen::Vector2d::UnitY(), 0.0,
                           std::max(bp.width_m, bp.height_m)};
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
}

/// The furniture's bounding boxes binned on a square grid, so that a point is tested only against
/// the boxes of its bin: every cell of a robot map used to test every box of the floor, and both
/// grow with the floor (a 400 x 300 m robot map took minutes).
class BoxBins {
 public:
  BoxBins(std::vector<Box2> boxes, double bin_m) : boxes_(std::move(boxes)), bin_m_(bin_m) {
    if (boxes_.empty()) return;
    Box2 extent = boxes_.front();
    for (const Box2& b : boxes_) bg::expand(extent, b);
    x0_ = extent.min_corner().x();
    y0_ = extent.min_corner().y();
    columns_ = bin_of(extent.max_corner().x(), x0_) + 1;
    rows_ = bin_of(extent.max_corner().y(), y0_) + 1;
    bins_.resize(static_cast<std::size_t>(columns_) * static_cast<std::size_t>(rows_));
    for (std::size_t k = 0; k < boxes_.size(); ++k) {
      const Box2& b = boxes_[k];
      for (int r = bin_of(b.min_corner().y(), y0_); r <= bin_of(b.max_corner().y(), y0_); ++r) {
        for (int c = bin_of(b.min_corner().x(), x0_); c <= bin_of(b.max_corner().x(), x0_); ++c) {
          bins_[static_cast<std::size_t>(r) * static_cast<std::size_t>(columns_) + static_cast<std::size_t>(c)].push_back(k);
        }
      }
    }
  }
  /// Whether `q` lies within some box (Boost.Geometry's `within`: inside, not on the edge).
  bool any_within(const Point2& q) const {
    if (bins_.empty() || !(q.x() >= x0_ && q.y() >= y0_)) return false;
    const int c = bin_of(q.x(), x0_), r = bin_of(q.y(), y0_);
    if (c >= columns_ || r >= rows_) return false;
    for (std::size_t k : bins_[static_cast<std::size_t>(r) * static_cast<std::size_t>(columns_) + static_cast<std::size_t>(c)]) {
      if (bg::within(q, boxes_[k])) return true;
    }
    return false;
  }

 private:
  int bin_of(double v, double origin) const { return static_cast<int>(std::floor((v - origin) / bin_m_)); }
  std::vector<Box2> boxes_;
  double bin_m_;
  double x0_ = 0.0, y0_ = 0.0;
  int columns_ = 0, rows_ = 0;
  std::vector<std::vector<std::size_t>> bins_;
};

/// What the robot map shows at layout point `p` (distortions applied): the layout's cell as the
/// robot saw it — unexplored rooms, unseen corridor and far doorways unknown, closed doors and
/// furniture occupied, walls seen only as a layer with gaps where asked for.
inline CellState robot_cell_state(const SyntheticBuilding& building, const RobotMapParams& params, const SeenLayout& seen,
                                  const BoxBins& clutter_boxes, std::uint64_t gap_seed, const Eigen::Vector2d& p) {
  const OccupancyGrid& layout = building.layout;
  const CellState outside = params.unknown_outside ? CellState::unknown : CellState::occupied;
  const Eigen::Vector2i cell = layout.world_to_cell(p);
  if (!layout.contains(cell.x(), cell.y())) return outside;
  const std::size_t index = layout.index(cell.x(), cell.y());
  CellState state = layout.at(cell.x(), cell.y());
  const int label = building.labels[index];
  if (state == CellState::unknown) state = outside;
  if (state == CellState::free && label >= 0 && !seen.explored[label]) state = CellState::unknown;
  if (state == CellState::free && label >= 0 && building.areas[static_cast<std::size_t>(label)].corridor && !seen.corridor_seen(p)) {
    state = CellState::unknown;
  }
  if (state == CellState::free && label < 0 && seen.in_closed_door(p)) state = CellState::occupied;
  if (state == CellState::free && label < 0 && !seen.to_explored.empty() &&
      seen.to_explored[index] > building.params.wall_thickness_m + params.seen_wall_m) {
    state = CellState::unknown;  // a doorway the scan did not come near
  }
  if (!seen.to_explored.empty() && state != CellState::free && state != outside) {
    const double d = seen.to_explored[index];
    const auto patch = [&](double v) { return static_cast<std::int64_t>(std::floor(v / params.wall_gap_patch_m)); };
    const bool gap = hash_unit(gap_seed, patch(p.x()), patch(p.y())) < params.wall_gap_fraction;
    state = d <= params.seen_wall_m && !gap ? CellState::occupied : CellState::unknown;
  }
  if (state == CellState::free && clutter_boxes.any_within(Point2(p.x(), p.y()))) return CellState::occupied;
  return state;
}

/// Speckles: isolated occupied cells scattered over free space.
inline void add_speckles(const RobotMapParams& params, Random& random, OccupancyGrid& grid) {
  if (params.speckle_per_m2 <= 0.0) return;
  const auto counts = grid.count();
  const double free_m2 = counts.free * params.resolution * params.resolution;
  const auto n = static_cast<std::size_t>(std::lround(free_m2 * params.speckle_per_m2));
  for (std::size_t k = 0; k < n; ++k) {
    const int col = random.integer(0, grid.width() - 1), row = random.integer(0, grid.height() - 1);
    if (grid.at(col, row) == CellState::free) grid.set(col, row, CellState::occupied);
  }
}

}  // namespace detail

/// Makes a robot map of `building` (see the file comment and `RobotMapParams`).
inline RobotMap make_robot_map(const SyntheticBuilding& building, const RobotMapParams& params, std::uint64_t seed) {
  params.validate();
  detail::Random random(seed);
  RobotMap robot;
  std::vector<bool> explored = detail::explored_areas(building, params, random);
  for (std::size_t id = 0; id < explored.size(); ++id) if (explored[id]) robot.explored_areas.push_back(static_cast<int>(id));
  const detail::SeenLayout seen = detail::seen_layout(building, params, std::move(explored), random);
  robot.clutter = detail::furniture(building, params, seen.explored, random);
  detail::place_robot_frame(building, params, robot);
  detail::draw_distortions(building.params, params, random, robot);

  std::vector<Box2> boxes;
  for (const auto& c : robot.clutter) {
    Box2 b;
    bg::envelope(c, b);
    boxes.push_back(b);
  }
  const detail::BoxBins clutter_boxes(std::move(boxes), 2.0);  // bins of about a room's furniture
  const std::uint64_t gap_seed = seed ^ 0x5EEDull;
  for (int row = 0; row < robot.grid.height(); ++row) {
    for (int col = 0; col < robot.grid.width(); ++col) {
      Eigen::Vector2d p = robot.smooth(robot.T_dest_source * robot.grid.cell_center(col, row));
      if (!robot.breaks.empty()) p = robot.piece_motion(robot.piece_at(p)) * p;
      if (params.wall_noise_m > 0.0) p += params.wall_noise_m * Eigen::Vector2d(random.normal(), random.normal());
      robot.grid.set(col, row, detail::robot_cell_state(building, params, seen, clutter_boxes, gap_seed, p));
    }
  }
  detail::add_speckles(params, random, robot.grid);
  return robot;
}

}  // namespace areamatch
