#pragma once
/// \file synthetic/floor_plan.hpp
/// The pieces `generate_building` lays out: rectangles, the corridor system of each layout, rooms
/// placed along a corridor side with their doors.

#include "../geometry.hpp"
#include "../grid.hpp"
#include "../detail/random.hpp"
#include "building_params.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <vector>

namespace areamatch {

namespace detail {

/// Axis-aligned rectangle in metres.
struct Rect {
  double x0, y0, x1, y1;
  double width() const { return x1 - x0; }
  double height() const { return y1 - y0; }
  /// True when the two rectangles come closer than `gap` (touching at exactly `gap` is fine).
  bool closer_than(const Rect& o, double gap) const {
    const double eps = 1e-9;
    return x0 < o.x1 + gap - eps && o.x0 < x1 + gap - eps && y0 < o.y1 + gap - eps && o.y0 < y1 + gap - eps;
  }
  bool inside(const Rect& o) const { return x0 >= o.x0 && y0 >= o.y0 && x1 <= o.x1 && y1 <= o.y1; }
  Rect grown(double d) const { return {x0 - d, y0 - d, x1 + d, y1 + d}; }
  Polygon2 polygon() const { return make_rectangle(x0, y0, x1, y1); }
};

/// Calls fn(col, row) for every cell of `grid` whose centre lies inside `rect` (world frame of a
/// grid with zero yaw).
template <class Fn>
void for_each_cell_in(const OccupancyGrid& grid, const Rect& rect, Fn&& fn) {
  const Eigen::Vector2d a = grid.world_to_pixel({rect.x0, rect.y0});
  const Eigen::Vector2d b = grid.world_to_pixel({rect.x1, rect.y1});
  const int c0 = std::max(0, static_cast<int>(std::ceil(std::min(a.x(), b.x()))));
  const int c1 = std::min(grid.width() - 1, static_cast<int>(std::floor(std::max(a.x(), b.x()))));
  const int r0 = std::max(0, static_cast<int>(std::ceil(std::min(a.y(), b.y()))));
  const int r1 = std::min(grid.height() - 1, static_cast<int>(std::floor(std::max(a.y(), b.y()))));
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c) fn(c, r);
}

/// A corridor: its clear rectangle and which of its long sides may carry rooms.
struct CorridorPiece {
  Rect rect;
  bool horizontal;
};

/// The corridors of a layout over the footprint [0, W] × [0, H].
inline std::vector<CorridorPiece> corridor_pieces(CorridorLayout layout, const BuildingParams& p, Random& random) {
  const double W = p.width_m, H = p.height_m, c = p.corridor_width_m;
  const double depth = 0.5 * (p.min_room_depth_m + p.max_room_depth_m);
  std::vector<CorridorPiece> pieces;
  auto horizontal = [&](double y, double xa, double xb) {
    pieces.push_back({{xa, y, xb, y + c}, true});
  };
  auto vertical = [&](double x, double ya, double yb) {
    pieces.push_back({{x, ya, x + c, yb}, false});
  };
  const double mid_y = std::max(0.0, 0.5 * (H - c));
  switch (layout) {
    case CorridorLayout::straight:
      horizontal(mid_y, 0.0, W);
      break;
    case CorridorLayout::l_shape: {
      const double y = std::min(mid_y, std::max(0.0, depth + p.wall_thickness_m));
      horizontal(y, 0.0, W);
      vertical(std::max(0.0, W - c - depth - p.wall_thickness_m), y, H);
      break;
    }
    case CorridorLayout::t_shape: {
      const double y = std::min(mid_y, std::max(0.0, depth + p.wall_thickness_m));
      horizontal(y, 0.0, W);
      const double x = std::clamp(random.uniform(0.35, 0.65) * W - 0.5 * c, 0.0, std::max(0.0, W - c));
      vertical(x, y, H);
      break;
    }
    case CorridorLayout::loop: {
      const double inset = std::min(depth + p.wall_thickness_m, 0.25 * std::min(W, H));
      const double xa = inset, xb = std::max(inset + 2 * c, W - inset);
      const double ya = inset, yb = std::max(inset + 2 * c, H - inset);
      horizontal(ya, xa, xb);
      horizontal(yb - c, xa, xb);
      vertical(xa, ya, yb);
      vertical(xb - c, ya, yb);
      break;
    }
    case CorridorLayout::ladder:
    case CorridorLayout::automatic: {
      const double band = 2.0 * (depth + p.wall_thickness_m) + c + p.wall_thickness_m;
      const int rungs = std::max(1, static_cast<int>(std::floor(H / band)));
      const double spacing = H / rungs;
      for (int i = 0; i < rungs; ++i) horizontal(std::max(0.0, (i + 0.5) * spacing - 0.5 * c), 0.0, W);
      if (rungs > 1) {
        const double y0 = pieces.front().rect.y0, y1 = pieces.back().rect.y1;
        vertical(0.0, y0, y1);
        vertical(std::max(0.0, W - c), y0, y1);
        if (W > 60.0) vertical(std::max(0.0, 0.5 * W - 0.5 * c), y0, y1);
      }
      break;
    }
  }
  // Keep every corridor inside the footprint.
  for (auto& piece : pieces) {
    piece.rect.x1 = std::min(piece.rect.x1, W);
    piece.rect.y1 = std::min(piece.rect.y1, H);
  }
  return pieces;
}

inline CorridorLayout choose_layout(const BuildingParams& p, Random& random) {
  if (p.layout != CorridorLayout::automatic) return p.layout;
  if (p.width_m > 60.0 && p.height_m > 40.0) return CorridorLayout::ladder;
  const CorridorLayout small[] = {CorridorLayout::straight, CorridorLayout::l_shape, CorridorLayout::t_shape,
                                  CorridorLayout::loop};
  return small[random.integer(0, 3)];
}

/// A room candidate beside a corridor side: the room rectangle, the door rectangle through the
/// wall, and the door's centre line.
struct RoomPlan {
  Rect room;
  Rect door;
  Eigen::Vector2d door_center;
  Eigen::Vector2d jamb_a, jamb_b;
};

/// Lines one side of a corridor with rooms. `side` = +1 places rooms above/right, −1 below/left.
inline void place_rooms_along(const CorridorPiece& corridor, int side, const BuildingParams& p,
                              const Rect& footprint, std::vector<Rect>& occupied,
                              std::vector<RoomPlan>& rooms, Random& random) {
  const double t = p.wall_thickness_m;
  const Rect& c = corridor.rect;
  const double along0 = corridor.horizontal ? c.x0 : c.y0;
  const double along1 = corridor.horizontal ? c.x1 : c.y1;
  const double edge = corridor.horizontal ? (side > 0 ? c.y1 : c.y0) : (side > 0 ? c.x1 : c.x0);
  double cursor = along0;
  while (cursor + p.min_room_width_m <= along1 + 1e-9) {
    const double width = std::min(random.uniform(p.min_room_width_m, p.max_room_width_m), along1 - cursor);
    const double wanted_depth = random.uniform(p.min_room_depth_m, p.max_room_depth_m);
    bool placed = false;
    // Shrink a room that does not fit until it does or gets too shallow.
    for (double depth = wanted_depth; depth >= p.min_room_depth_m - 1e-9; depth -= 0.5) {
      const double near = edge + side * t, far = near + side * depth;
      Rect room = corridor.horizontal ? Rect{cursor, std::min(near, far), cursor + width, std::max(near, far)}
                                      : Rect{std::min(near, far), cursor, std::max(near, far), cursor + width};
      if (!room.inside(footprint)) continue;
      if (std::any_of(occupied.begin(), occupied.end(), [&](const Rect& o) { return room.closer_than(o, t); })) continue;
      // The door: somewhere along the room's corridor side, away from the corners.
      const double slack = width - p.door_width_m - 0.4;
      const double start = cursor + 0.2 + (slack > 0 ? random.uniform(0.0, slack) : 0.5 * (width - p.door_width_m - 0.4));
      const double end = start + p.door_width_m;
      const double wall0 = std::min(edge, edge + side * t), wall1 = std::max(edge, edge + side * t);
      const double wall_mid = 0.5 * (wall0 + wall1);
      RoomPlan plan;
      plan.room = room;
      if (corridor.horizontal) {
        plan.door = {start, wall0, end, wall1};
        plan.jamb_a = {start, wall_mid};
        plan.jamb_b = {end, wall_mid};
      } else {
        plan.door = {wall0, start, wall1, end};
        plan.jamb_a = {wall_mid, start};
        plan.jamb_b = {wall_mid, end};
      }
      plan.door_center = 0.5 * (plan.jamb_a + plan.jamb_b);
      occupied.push_back(room);
      rooms.push_back(plan);
      placed = true;
      break;
    }
    cursor += placed ? width + t : 1.0;
  }
}

}  // namespace detail

}  // namespace areamatch
