// The synthetic building generator: closed walls, doors where reported, ground truth that holds.
#include <areamatch/synthetic.hpp>

#include <doctest/doctest.h>

#include "test_support.hpp"

#include <queue>

using namespace areamatch;

namespace {

const CorridorLayout kLayouts[] = {CorridorLayout::straight, CorridorLayout::l_shape, CorridorLayout::t_shape,
                                   CorridorLayout::loop, CorridorLayout::ladder};

BuildingParams params_for(CorridorLayout layout) {
  BuildingParams p;
  p.layout = layout;
  p.width_m = 32;
  p.height_m = layout == CorridorLayout::ladder ? 40 : 22;
  p.pillar_probability = 0.5;
  return p;
}

/// Share of `robot` cells in `state` whose ground-truth image in the layout has a cell in the same
/// state within one pixel.
double agreement(const SyntheticBuilding& b, const RobotMap& robot, CellState state) {
  std::size_t total = 0, hits = 0;
  const auto& m = robot.pixel_transform;
  for (int r = 0; r < robot.grid.height(); ++r) {
    for (int c = 0; c < robot.grid.width(); ++c) {
      if (robot.grid.at(c, r) != state) continue;
      ++total;
      const Eigen::Vector2d q = m.leftCols<2>() * Eigen::Vector2d(c, r) + m.col(2);
      const int qc = static_cast<int>(std::lround(q.x())), qr = static_cast<int>(std::lround(q.y()));
      bool hit = false;
      for (int dr = -1; dr <= 1 && !hit; ++dr)
        for (int dc = -1; dc <= 1 && !hit; ++dc)
          hit = b.layout.contains(qc + dc, qr + dr) && b.layout.at(qc + dc, qr + dr) == state;
      hits += hit;
    }
  }
  return total ? static_cast<double>(hits) / total : 0.0;
}

}  // namespace

TEST_CASE("every layout kind gives rooms, one door each, valid non-overlapping polygons") {
  for (CorridorLayout layout : kLayouts) {
    for (std::uint64_t seed : {1u, 2u, 3u}) {
      const auto b = generate_building(params_for(layout), seed);
      INFO("layout " << static_cast<int>(layout) << " seed " << seed);
      CHECK(b.layout_kind == layout);
      REQUIRE(b.areas.size() >= 5);
      CHECK(b.areas.front().corridor);
      CHECK(b.doors.size() == b.areas.size() - 1);
      for (const auto& area : b.areas) {
        std::string reason;
        CHECK_MESSAGE(bg::is_valid(area.polygon, reason), reason);
        CHECK(area.size_m2 > 0.0);
      }
      for (std::size_t i = 0; i < b.areas.size(); ++i)
        for (std::size_t j = i + 1; j < b.areas.size(); ++j) {
          MultiPolygon2 common;
          bg::intersection(b.areas[i].polygon, b.areas[j].polygon, common);
          CHECK(bg::area(common) < 1e-9);
        }
    }
  }
}

TEST_CASE("walls are closed: no free cell touches unknown space or the image border") {
  for (CorridorLayout layout : kLayouts) {
    const auto b = generate_building(params_for(layout), 7);
    const OccupancyGrid& g = b.layout;
    std::size_t leaks = 0;
    for (int r = 0; r < g.height(); ++r)
      for (int c = 0; c < g.width(); ++c) {
        if (g.at(c, r) != CellState::free) continue;
        const int dc[] = {1, -1, 0, 0}, dr[] = {0, 0, 1, -1};
        for (int k = 0; k < 4; ++k)
          leaks += !g.contains(c + dc[k], r + dr[k]) || g.at(c + dc[k], r + dr[k]) == CellState::unknown;
      }
    CHECK(leaks == 0);
  }
}

TEST_CASE("all free space is connected through the doors") {
  const auto b = generate_building(params_for(CorridorLayout::loop), 11);
  const OccupancyGrid& g = b.layout;
  std::vector<char> seen(g.cells().size(), 0);
  std::queue<std::pair<int, int>> queue;
  for (int r = 0; r < g.height() && queue.empty(); ++r)
    for (int c = 0; c < g.width() && queue.empty(); ++c)
      if (g.at(c, r) == CellState::free) {
        queue.push({c, r});
        seen[g.index(c, r)] = 1;
      }
  std::size_t reached = 0;
  while (!queue.empty()) {
    auto [c, r] = queue.front();
    queue.pop();
    ++reached;
    const int dc[] = {1, -1, 0, 0}, dr[] = {0, 0, 1, -1};
    for (int k = 0; k < 4; ++k) {
      const int nc = c + dc[k], nr = r + dr[k];
      if (g.contains(nc, nr) && g.at(nc, nr) == CellState::free && !seen[g.index(nc, nr)]) {
        seen[g.index(nc, nr)] = 1;
        queue.push({nc, nr});
      }
    }
  }
  CHECK(reached == g.count().free);
}

TEST_CASE("doors are where reported: an opening between the two areas they join") {
  for (CorridorLayout layout : kLayouts) {
    const auto b = generate_building(params_for(layout), 5);
    const OccupancyGrid& g = b.layout;
    for (const auto& door : b.doors) {
      CHECK(door.width_m == doctest::Approx(b.params.door_width_m));
      CHECK((door.jamb_b - door.jamb_a).norm() == doctest::Approx(door.width_m));
      const Eigen::Vector2i centre = g.world_to_cell(door.position);
      CHECK(g.at(centre.x(), centre.y()) == CellState::free);
      // Step across the wall both ways: one side is the room, the other the corridor.
      const Eigen::Vector2d along = (door.jamb_b - door.jamb_a).normalized();
      const Eigen::Vector2d normal(-along.y(), along.x());
      const double step = 0.5 * b.params.wall_thickness_m + 0.1;
      const Eigen::Vector2i p = g.world_to_cell(door.position + step * normal);
      const Eigen::Vector2i q = g.world_to_cell(door.position - step * normal);
      const int lp = b.labels[g.index(p.x(), p.y())], lq = b.labels[g.index(q.x(), q.y())];
      CHECK(((lp == door.area_a && lq == door.area_b) || (lp == door.area_b && lq == door.area_a)));
      // The jambs are walls: just beyond each end of the opening the wall is occupied.
      const Eigen::Vector2i beyond = g.world_to_cell(door.jamb_b + 0.1 * along);
      CHECK(g.at(beyond.x(), beyond.y()) == CellState::occupied);
    }
  }
}

TEST_CASE("labels match the area polygons") {
  const auto b = generate_building(params_for(CorridorLayout::t_shape), 9);
  const OccupancyGrid& g = b.layout;
  std::size_t mismatches = 0, labelled = 0;
  for (int r = 0; r < g.height(); ++r)
    for (int c = 0; c < g.width(); ++c) {
      const int label = b.labels[g.index(c, r)];
      if (label < 0) continue;
      ++labelled;
      const Eigen::Vector2d p = g.cell_center(c, r);
      mismatches += !bg::covered_by(Point2(p.x(), p.y()), b.areas[label].polygon);
      mismatches += g.at(c, r) != CellState::free;
    }
  CHECK(labelled > 0);
  CHECK(mismatches == 0);
}

TEST_CASE("generation is deterministic in the seed") {
  const auto a = generate_building(params_for(CorridorLayout::automatic), 42);
  const auto b = generate_building(params_for(CorridorLayout::automatic), 42);
  const auto c = generate_building(params_for(CorridorLayout::automatic), 43);
  CHECK(a.layout == b.layout);
  CHECK(a.labels == b.labels);
  CHECK_FALSE(a.layout == c.layout);
  RobotMapParams rp;
  rp.rotation_rad = 1.0;
  rp.wall_noise_m = 0.03;
  rp.max_clutter_per_room = 3;
  rp.speckle_per_m2 = 0.05;
  rp.explored_fraction = 0.6;
  CHECK(make_robot_map(a, rp, 1).grid == make_robot_map(b, rp, 1).grid);
  CHECK_FALSE(make_robot_map(a, rp, 1).grid == make_robot_map(a, rp, 2).grid);
}

TEST_CASE("the ground-truth transform maps robot walls onto layout walls and free onto free") {
  const auto b = generate_building(params_for(CorridorLayout::l_shape), 21);
  for (bool mirror : {false, true}) {
    for (double rotation : {0.0, 0.6, 2.5, -1.9}) {
      RobotMapParams rp;
      rp.rotation_rad = rotation;
      rp.mirror = mirror;
      rp.resolution = 0.04;
      rp.translation_m = {3.0, -7.0};
      const auto robot = make_robot_map(b, rp, 3);
      INFO("mirror " << mirror << " rotation " << rotation);
      CHECK(robot.T_dest_source.reflected == mirror);
      CHECK(agreement(b, robot, CellState::occupied) > 0.99);
      CHECK(agreement(b, robot, CellState::free) > 0.99);
      // The robot map has the area of the layout's free space, at its own resolution.
      const double robot_free = robot.grid.count().free * 0.04 * 0.04;
      const double layout_free = b.layout.count().free * 0.05 * 0.05;
      CHECK(robot_free == doctest::Approx(layout_free).epsilon(0.03));
      // The pixel transform scales by the resolution ratio.
      CHECK(std::sqrt(std::abs(robot.pixel_transform.leftCols<2>().determinant())) == doctest::Approx(0.8));
    }
  }
}

TEST_CASE("robot-map degradations: partial exploration, clutter, noise, outside") {
  const auto b = generate_building(params_for(CorridorLayout::straight), 4);
  RobotMapParams rp;
  rp.explored_fraction = 0.5;
  rp.max_clutter_per_room = 4;
  rp.wall_noise_m = 0.03;
  rp.speckle_per_m2 = 0.02;
  const auto robot = make_robot_map(b, rp, 8);
  const std::size_t rooms = b.areas.size() - 1;
  CHECK(robot.explored_areas.size() == 1 + static_cast<std::size_t>(std::lround(0.5 * rooms)));
  CHECK(robot.explored_areas.front() == 0);  // the corridor is always explored
  CHECK_FALSE(robot.clutter.empty());
  // Unexplored rooms are unknown: the robot map has much less free space than the layout.
  CHECK(robot.grid.count().free < 0.85 * b.layout.count().free);
  // Clutter puts occupied cells where the layout is free: wall agreement drops below the clean map's.
  CHECK(agreement(b, robot, CellState::occupied) < 0.95);
  // Jitter alone leaves the walls where the ground truth says, give or take a cell.
  RobotMapParams noisy;
  noisy.rotation_rad = 0.3;
  noisy.wall_noise_m = 0.03;
  CHECK(agreement(b, make_robot_map(b, noisy, 8), CellState::occupied) > 0.97);
  RobotMapParams occupied_outside;
  occupied_outside.unknown_outside = false;
  CHECK(make_robot_map(b, occupied_outside, 1).grid.count().unknown == 0);
}

TEST_CASE("hand-held scans: thin seen walls on the ground truth, partial coverage, a line-drawn layout") {
  // Under the sanitizers (quick mode) test_matcher's hand-held case runs this generator; here the
  // 0.02 m maps would push this file past its time limit.
  if (areamatch_test::quick_tests()) return;
  BuildingParams small = params_for(CorridorLayout::straight);  // 0.02 m scans: kept small for the sanitizers
  small.width_m = 18;
  small.height_m = 12;
  const auto b = generate_building(small, 6);
  RobotMapParams rp = RobotMapParams::handheld();
  rp.rotation_rad = 0.8;
  rp.wall_bend_m = 0.0;  // so that the ground truth is exact cell by cell
  rp.wall_noise_m = 0.0;
  rp.speckle_per_m2 = 0.0;
  rp.max_clutter_per_room = 0;
  const auto scan = make_robot_map(b, rp, 3);
  CHECK(scan.grid.resolution() == 0.02);
  // Seen walls lie on the layout's walls, and the scan is partial: 40 % of the rooms.
  CHECK(agreement(b, scan, CellState::occupied) > 0.97);
  CHECK(agreement(b, scan, CellState::free) > 0.99);
  const std::size_t rooms = b.areas.size() - 1;
  CHECK(scan.explored_areas.size() == 1 + static_cast<std::size_t>(std::lround(0.4 * rooms)));
  const double free_m2 = scan.grid.count().free * 0.02 * 0.02, layout_free_m2 = b.layout.count().free * 0.05 * 0.05;
  CHECK(free_m2 < 0.7 * layout_free_m2);
  CHECK(free_m2 > 0.1 * layout_free_m2);
  // Walls are seen from the explored side only: far fewer occupied cells than whole walls give.
  RobotMapParams whole = rp;
  whole.seen_wall_m = 0.0;
  whole.wall_gap_fraction = 0.0;
  whole.closed_door_fraction = 0.0;
  CHECK(scan.grid.count().occupied < 0.7 * make_robot_map(b, whole, 3).grid.count().occupied);
  // Deterministic in the seed.
  CHECK(make_robot_map(b, RobotMapParams::handheld(), 4).grid == make_robot_map(b, RobotMapParams::handheld(), 4).grid);

  // The line drawing: the same free rooms, walls 0.05 m thin, outside unknown.
  const OccupancyGrid drawn = layout_line_drawing(b, 0.05);
  CHECK(drawn.width() == b.layout.width());
  CHECK(drawn.count().occupied < 0.6 * b.layout.count().occupied);
  CHECK(drawn.count().free > b.layout.count().free);
  for (int r = 0; r < b.layout.height(); ++r) {
    for (int c = 0; c < b.layout.width(); ++c) {
      if (b.layout.at(c, r) == CellState::free) REQUIRE(drawn.at(c, r) == CellState::free);
      if (b.layout.at(c, r) == CellState::unknown) REQUIRE(drawn.at(c, r) == CellState::unknown);
    }
  }
  CHECK_THROWS_AS(layout_line_drawing(b, 0.0), parameter_error);
  RobotMapParams bad = RobotMapParams::handheld();
  bad.wall_gap_fraction = 1.5;
  CHECK_THROWS_WITH_AS(make_robot_map(b, bad, 1), doctest::Contains("wall_gap_fraction"), parameter_error);
}

TEST_CASE("invalid generator parameters are rejected with the parameter's name") {
  BuildingParams p;
  p.width_m = -1;
  CHECK_THROWS_WITH_AS(generate_building(p, 1), doctest::Contains("width_m"), parameter_error);
  p = {};
  p.resolution = 0;
  CHECK_THROWS_WITH_AS(generate_building(p, 1), doctest::Contains("resolution"), parameter_error);
  p = {};
  p.wall_thickness_m = 0.01;
  CHECK_THROWS_WITH_AS(generate_building(p, 1), doctest::Contains("wall_thickness_m"), parameter_error);
  p = {};
  p.door_width_m = 5.0;
  CHECK_THROWS_WITH_AS(generate_building(p, 1), doctest::Contains("door_width_m"), parameter_error);
  const auto b = generate_building(BuildingParams{}, 1);
  RobotMapParams rp;
  rp.explored_fraction = 1.5;
  CHECK_THROWS_WITH_AS(make_robot_map(b, rp, 1), doctest::Contains("explored_fraction"), parameter_error);
  rp = {};
  rp.resolution = std::nan("");
  CHECK_THROWS_WITH_AS(make_robot_map(b, rp, 1), doctest::Contains("resolution"), parameter_error);
}

TEST_CASE("buildings from 10 m to 200 m generate") {
  for (double side : {10.0, 50.0, 200.0}) {
    BuildingParams p;
    p.width_m = side;
    p.height_m = side;
    const auto b = generate_building(p, 1);
    CHECK(b.areas.size() >= 3);
    CHECK(b.layout.width() == static_cast<int>(std::ceil((side + 2.0) / 0.05)));
  }
}
