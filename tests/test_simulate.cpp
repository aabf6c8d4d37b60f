// The simulated laser-SLAM map (simulate.hpp): deterministic, ground truth that holds, the
// matcher finds it, what it simulates is there (bend, mirror, broken piece), bad input refused.
#include <areamatch/areamatch.hpp>
#include <areamatch/simulate.hpp>

#include <doctest/doctest.h>

#include "test_support.hpp"

#include <cmath>

using namespace areamatch;

namespace {

/// A generated building's plan (seeds away from the calibration sets' ranges).
OccupancyGrid plan_of(std::uint64_t seed) {
  BuildingParams p;
  p.width_m = 24;
  p.height_m = 16;
  return generate_building(p, seed).layout;
}

/// Share of the map's occupied cells next to free space that the ground truth lays within 0.2 m
/// of the plan's non-free cells.
double surfaces_on_plan(const SimulatedSlamMap& s, const OccupancyGrid& plan) {
  std::size_t seen = 0, on = 0;
  const int reach = static_cast<int>(std::lround(0.2 / plan.resolution()));
  for (int y = 0; y < s.grid.height(); ++y) {
    for (int x = 0; x < s.grid.width(); ++x) {
      if (s.grid.at(x, y) != CellState::occupied) continue;
      const Eigen::Vector2d q = s.pixel_transform * Eigen::Vector3d(x, y, 1.0);
      ++seen;
      bool near = false;
      for (int dy = -reach; dy <= reach && !near; ++dy) {
        for (int dx = -reach; dx <= reach && !near; ++dx) {
          const int px = static_cast<int>(std::lround(q.x())) + dx, py = static_cast<int>(std::lround(q.y())) + dy;
          near = plan.contains(px, py) && plan.at(px, py) != CellState::free;
        }
      }
      on += near;
    }
  }
  return seen ? static_cast<double>(on) / static_cast<double>(seen) : 0.0;
}

}  // namespace

TEST_CASE("simulate: the same seed gives the same map, another seed another") {
  const OccupancyGrid plan = plan_of(910);
  LidarSlamParams p;
  p.beams = 181;
  const SimulatedSlamMap a = simulate_lidar_slam(plan, p, 3), b = simulate_lidar_slam(plan, p, 3), c = simulate_lidar_slam(plan, p, 4);
  CHECK(a.grid == b.grid);
  CHECK(a.pixel_transform == b.pixel_transform);
  CHECK(a.grid != c.grid);
  CHECK(a.scans > 20);
  CHECK(a.furniture > 0);
}

TEST_CASE("simulate: walls land on the plan's walls through the ground truth, the bend as asked, the matcher finds it") {
  const OccupancyGrid plan = plan_of(911);
  LidarSlamParams p;
  p.beams = 271;
  p.rotation_rad = 1.1;
  p.bend_m = 0.2;
  p.people = 0;
  p.furniture_per_m2 = 0.0;
  p.small_clutter_per_m2 = 0.0;
  p.glass_share = 0.0;
  const SimulatedSlamMap s = simulate_lidar_slam(plan, p, 5);
  CHECK(s.bend_m <= 0.2 + 3 * p.scan_jitter_m + 1e-9);
  CHECK(s.bend_m > 0.0);
  CHECK(std::abs(wrap_angle(s.T_dest_source.rotation - (-1.1))) < 0.05);  // the map turned by +1.1 rad
  CHECK(surfaces_on_plan(s, plan) > 0.9);
  const auto counts = s.grid.count();
  CHECK(counts.free > 10 * counts.occupied / 2);
  CHECK(counts.unknown > 0);  // around the building: nothing seen
  Matcher<> matcher;
  const MatchResult r = matcher.match(s.grid, plan);
  REQUIRE(r.ok);
  CHECK(std::abs(wrap_angle(r.T_dest_source.rotation - s.T_dest_source.rotation)) < 3.0 * pi / 180.0);
  CHECK((r.T_dest_source.translation - s.T_dest_source.translation).norm() < 1.0);
}

TEST_CASE("simulate: clutter the plan does not have, a mirror, a broken piece, a binary map") {
  const OccupancyGrid plan = plan_of(912);
  LidarSlamParams p;
  p.beams = 271;
  const double clean = [&] {
    LidarSlamParams q = p;
    q.furniture_per_m2 = q.small_clutter_per_m2 = 0.0;
    q.people = 0;
    return surfaces_on_plan(simulate_lidar_slam(plan, q, 6), plan);
  }();
  p.furniture_per_m2 = 0.1;
  p.people = 4;
  CHECK(surfaces_on_plan(simulate_lidar_slam(plan, p, 6), plan) < clean - 0.05);
  p.mirror = true;
  const SimulatedSlamMap mirrored = simulate_lidar_slam(plan, p, 6);
  CHECK(mirrored.T_dest_source.reflected);
  CHECK(surfaces_on_plan(mirrored, plan) > 0.6);
  p.mirror = false;
  p.break_probability = 1.0;
  p.break_rotation_rad = 5.0 * pi / 180.0;
  const SimulatedSlamMap broken = simulate_lidar_slam(plan, p, 6);
  CHECK(broken.broken);
  CHECK(broken.bend_m > 0.3);  // part of the path turned by 5 degrees does not fit one rigid motion
  p.break_probability = 0.0;
  LidarSlamParams schematic = p;  // the building as built off its plan by up to 0.8 m, nothing else in the way
  schematic.furniture_per_m2 = schematic.small_clutter_per_m2 = 0.0;
  schematic.people = 0;
  schematic.plan_error_m = 0.8;
  CHECK(surfaces_on_plan(simulate_lidar_slam(plan, schematic, 6), plan) < clean - 0.05);
  p.binary = true;
  const auto counts = simulate_lidar_slam(plan, p, 6).grid.count();
  CHECK(counts.unknown == 0);
}

TEST_CASE("simulate: bad parameters and plans are refused with the reason named") {
  const OccupancyGrid plan = plan_of(913);
  LidarSlamParams p;
  p.beams = 0;
  CHECK_THROWS_WITH_AS(simulate_lidar_slam(plan, p, 1), doctest::Contains("beams"), parameter_error);
  p = {};
  p.bend_m = -1.0;
  CHECK_THROWS_WITH_AS(simulate_lidar_slam(plan, p, 1), doctest::Contains("bend_m"), parameter_error);
  p = {};
  p.plan_error_m = -0.1;
  CHECK_THROWS_WITH_AS(simulate_lidar_slam(plan, p, 1), doctest::Contains("plan_error_m"), parameter_error);
  p = {};
  p.max_range_m = std::nan("");
  CHECK_THROWS_WITH_AS(simulate_lidar_slam(plan, p, 1), doctest::Contains("max_range_m"), parameter_error);
  p = {};
  const OccupancyGrid walls(40, 30, 0.05, {}, CellState::occupied);
  CHECK_THROWS_WITH_AS(simulate_lidar_slam(walls, p, 1), doctest::Contains("no free space wide enough"), parameter_error);
  CHECK_THROWS_AS(simulate_lidar_slam(OccupancyGrid{}, p, 1), parameter_error);
  p.max_cells = 1000;
  CHECK_THROWS_WITH_AS(simulate_lidar_slam(plan, p, 1), doctest::Contains("max_cells"), limit_error);
}
