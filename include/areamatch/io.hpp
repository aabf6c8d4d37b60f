#pragma once
/// \file io.hpp
/// Loading and saving occupancy grids: PGM, PNG and ROS map_server YAML (`io/map_files.hpp`), and
/// writing results as JSON (`io/json.hpp`) and pictures as SVG (`io/svg.hpp`) (target `areamatch::io`).
///
/// \code
/// areamatch::OccupancyGrid map = areamatch::load_map("maps/office.yaml");     // YAML + its image
/// areamatch::LoadOptions bare;  bare.resolution = 0.05;
/// areamatch::OccupancyGrid plan = areamatch::load_map("plan.png", bare);     // image only
/// areamatch::save_map(map, "out/office.pgm");            // writes out/office.pgm + out/office.yaml
/// \endcode

#include "io/json.hpp"
#include "io/map_files.hpp"
#include "io/svg.hpp"
