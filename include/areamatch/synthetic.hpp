#pragma once
/// \file synthetic.hpp
/// Umbrella header of the generator: synthetic floor plans with exact ground truth, for tests,
/// demos, benchmarks and calibration. Not part of the matcher's API (<areamatch/areamatch.hpp>
/// leaves it out); the simulated laser SLAM of a generated or any floor plan is <areamatch/simulate.hpp>.
///
///   synthetic/building.hpp      `generate_building`: corridors, rooms, doors, walls, pillars
///   synthetic/line_drawing.hpp  `layout_line_drawing`: the layout with thin walls
///   synthetic/robot_map.hpp     `make_robot_map`: what a robot's SLAM would make of a building
///
/// Everything is deterministic in the seed (same seed, same map, bit for bit, on every platform).

#include "synthetic/building.hpp"
#include "synthetic/line_drawing.hpp"
#include "synthetic/robot_map.hpp"
