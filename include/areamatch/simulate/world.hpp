#pragma once
/// \file simulate/world.hpp
/// The world a simulated laser's rays meet (simulate.hpp): the building as built, furniture,
/// clutter, glass panes in outer walls, people; and one ray cast through it.

#include "../detail/random.hpp"
#include "../error.hpp"
#include "../grid.hpp"
#include "../synthetic.hpp"
#include "../transform.hpp"
#include "params.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace areamatch::detail {

/// The plan as the rays see it: solid cells (the plan's non-free cells, furniture), which of
/// them are glass, and which lie outside (unknown, or deeper than a wall in non-free space).
struct RayWorld {
  OccupancyGrid built;  ///< the building as built: the plan, warped by `plan_error_m`
  Eigen::Affine2d to_pixel = Eigen::Affine2d::Identity();  ///< `built.pixel_from_world()`, once for every ray
  std::vector<std::uint8_t> solid, glass, outside;
  std::vector<double> clearance;  ///< metres to the nearest solid cell (after furniture)
};

/// Marks the cells of `built` within `half_cols` / `half_rows` of (col, row) in `solid`.
inline void fill_solid_box(const OccupancyGrid& built, int col, int row, int half_cols, int half_rows, std::vector<std::uint8_t>& solid) {
  for (int y = std::max(0, row - half_rows); y <= std::min(built.height() - 1, row + half_rows); ++y) {
    for (int x = std::max(0, col - half_cols); x <= std::min(built.width() - 1, col + half_cols); ++x) solid[built.index(x, y)] = 1;
  }
}

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
  world.to_pixel = world.built.pixel_from_world();
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
    fill_solid_box(plan, c, r, static_cast<int>(std::ceil(0.5 * w / plan.resolution())),
                   static_cast<int>(std::ceil(0.5 * h / plan.resolution())), world.solid);
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
    fill_solid_box(plan, c, r, half, half, world.solid);
    ++k;
  }
  std::vector<bool> solid_seed(world.solid.begin(), world.solid.end());
  world.clearance = chamfer_distance(plan, solid_seed);
  return world;
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
  const Eigen::Affine2d& to_pixel = world.to_pixel;
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


/// One beam in the map's frame: from the sensor to where it ended, and whether it hit something.
struct Beam {
  Eigen::Vector2d from, to;
  bool hit;
};

/// Every scan's beams: ranges cast in the true world (people placed anew per scan), their ends
/// carried into the map's frame by the scan's `to_map`.
inline std::vector<Beam> cast_scans(const RayWorld& world, const std::vector<Eigen::Vector3d>& poses,
                                    const std::vector<Similarity2>& to_map, const LidarSlamParams& params, Random& random) {
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
      const Eigen::Vector2i cell = world.built.world_to_cell(q);
      if (world.built.contains(cell.x(), cell.y()) && world.clearance[world.built.index(cell.x(), cell.y())] >= 0.3) people.push_back(q);
    }
    for (int b = 0; b < params.beams; ++b) {
      const double angle = poses[k].z() - 0.5 * params.field_of_view_rad + b * spacing;
      if (random.chance(params.dropout)) continue;
      const double range = cast_ray(world, at, angle, params, people, random);
      const bool hit = range >= 0.0;
      const double measured = hit ? std::max(0.0, range + params.range_noise_m * random.normal()) : params.max_range_m;
      const Eigen::Vector2d end = at + measured * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      beams.push_back({to_map[k] * at, to_map[k] * end, hit});
    }
  }
  return beams;
}

}  // namespace areamatch::detail
