#pragma once
// The fixed set of synthetic match cases used by the matcher test and benchmark: seed n gives a
// building and a robot map of it with every kind of trouble the generator has, drawn from n.
#include <areamatch/detail/random.hpp>
#include <areamatch/synthetic.hpp>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace areamatch_test {

struct SyntheticCase {
  areamatch::SyntheticBuilding building;
  areamatch::RobotMap robot;
  areamatch::RobotMapParams robot_params;
};

inline SyntheticCase synthetic_case(std::uint64_t seed) {
  areamatch::detail::Random random(seed * 7919 + 17);
  areamatch::BuildingParams b;
  b.width_m = random.uniform(18.0, 40.0);
  b.height_m = random.uniform(14.0, 30.0);
  b.pillar_probability = 0.3;
  areamatch::RobotMapParams r;
  r.rotation_rad = random.uniform(-areamatch::pi, areamatch::pi);  // the full circle
  r.translation_m = {random.uniform(-5.0, 5.0), random.uniform(-5.0, 5.0)};
  r.resolution = random.uniform(0.04, 0.06);
  r.mirror = seed % 4 == 3;
  r.wall_noise_m = random.uniform(0.0, 0.03);
  r.wall_bend_m = random.uniform(0.0, 0.1);
  r.max_clutter_per_room = random.integer(0, 3);
  r.explored_fraction = random.uniform(0.7, 1.0);
  r.speckle_per_m2 = random.uniform(0.0, 0.03);
  SyntheticCase c;
  c.building = areamatch::generate_building(b, seed);
  c.robot_params = r;
  c.robot = areamatch::make_robot_map(c.building, r, seed + 1000);
  return c;
}

/// Pair `i` of `areamatch_assess_generated COUNT FIRST_SEED` (tools/assess_generated.cpp,
/// docs/assessment.md): a building of 30-50 x 20-26 m and its robot map turned, noisy (3 cm),
/// cluttered, speckled, bent by 0.2-1.0 m and broken `i % 4` times.
struct DistortedCase {
  areamatch::BuildingParams building_params;
  areamatch::SyntheticBuilding building;
  areamatch::RobotMapParams robot_params;
  areamatch::RobotMap robot;
};

inline DistortedCase distorted_case(std::uint64_t first_seed, int i) {
  const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(i);
  DistortedCase c;
  c.building_params.width_m = 30.0 + 4.0 * (i % 6);
  c.building_params.height_m = 20.0 + 2.0 * (i % 4);
  c.building = areamatch::generate_building(c.building_params, seed);
  areamatch::RobotMapParams& rp = c.robot_params;
  rp.rotation_rad = (37.0 + 53.0 * i) * areamatch::pi / 180.0;
  rp.wall_noise_m = 0.03;
  rp.max_clutter_per_room = 3;
  rp.speckle_per_m2 = 0.02;
  rp.wall_bend_m = 0.2 + 0.2 * (i % 5);
  // Building-wide drift: the sines' wavelength four times the building's longer side, so that a
  // bend of 1 m turns the map by about 2 degrees from one end to the other (shorter ones make a
  // wavy map, strained by 10 % and more, that no set of rigid pieces explains).
  rp.bend_wavelength_m = 4.0 * std::max(c.building_params.width_m, c.building_params.height_m);
  rp.break_count = i % 4;
  c.robot = areamatch::make_robot_map(c.building, rp, seed);
  return c;
}

}  // namespace areamatch_test

namespace areamatch_test {

/// A building with `count` robot maps of it, each exploring 30–60 % of the rooms (and the
/// corridors), turned by any angle and shifted at random; with `mirror_one`, map 1 is a mirror
/// image. `truth[i]` is map i's world → map 0's world (map 0 is the reference).
struct MergeCase {
  areamatch::SyntheticBuilding building;
  std::vector<areamatch::RobotMap> robots;
  std::vector<areamatch::Similarity2> truth;
};

/// `small`: a building of 14-18 m x 10-13 m instead of 24-40 m x 16-28 m (for the sanitizer run).
inline MergeCase merge_case(std::uint64_t seed, std::size_t count, bool mirror_one, bool small = false) {
  areamatch::detail::Random random(seed * 104729 + 3);
  areamatch::BuildingParams b;
  b.width_m = small ? random.uniform(14.0, 18.0) : random.uniform(24.0, 40.0);
  b.height_m = small ? random.uniform(10.0, 13.0) : random.uniform(16.0, 28.0);
  MergeCase c;
  c.building = areamatch::generate_building(b, seed);
  for (std::size_t i = 0; i < count; ++i) {
    areamatch::RobotMapParams r;
    r.rotation_rad = random.uniform(-areamatch::pi, areamatch::pi);
    r.translation_m = {random.uniform(-5.0, 5.0), random.uniform(-5.0, 5.0)};
    r.mirror = mirror_one && i == 1;
    r.wall_noise_m = random.uniform(0.0, 0.02);
    r.max_clutter_per_room = random.integer(0, 2);
    r.explored_fraction = random.uniform(0.3, 0.6);
    r.speckle_per_m2 = random.uniform(0.0, 0.02);
    c.robots.push_back(areamatch::make_robot_map(c.building, r, seed * 1000 + i));
  }
  const areamatch::Similarity2 layout_from_reference = c.robots[0].T_dest_source;
  for (const auto& robot : c.robots) c.truth.push_back(layout_from_reference.inverse() * robot.T_dest_source);
  return c;
}

}  // namespace areamatch_test
