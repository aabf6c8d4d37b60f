#pragma once
// The fixed set of synthetic match cases used by the matcher test and benchmark: seed n gives a
// building and a robot map of it with every kind of trouble the generator has, drawn from n.
#include <areamatch/detail/random.hpp>
#include <areamatch/synthetic.hpp>

#include <cstdint>

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

}  // namespace areamatch_test
