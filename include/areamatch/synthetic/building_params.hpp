#pragma once
/// \file synthetic/building_params.hpp
/// What `generate_building` is asked for (`BuildingParams`) and gives (`SyntheticBuilding`).

#include "../error.hpp"
#include "../geometry.hpp"
#include "../grid.hpp"
#include "../image.hpp"

#include <Eigen/Core>

#include <string>
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

}  // namespace areamatch
