#pragma once
/// \file synthetic/building.hpp
/// `generate_building` draws a layout map: corridors (straight, L, T, loop or a ladder of parallel
/// corridors for large footprints), rooms of varied sizes along both sides of every corridor,
/// one door per room onto its corridor, walls of a given thickness, optional pillars. It returns
/// the map with the rooms' polygons (metres, world frame), the doors and a per-cell label image.
///
/// Deterministic in the seed (same seed, same map, bit for bit, on every platform).

#include "../geometry.hpp"
#include "../grid.hpp"
#include "../detail/random.hpp"
#include "building_params.hpp"
#include "floor_plan.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace areamatch {

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

}  // namespace areamatch
