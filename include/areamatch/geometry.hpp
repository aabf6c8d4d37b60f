#pragma once
/// \file geometry.hpp
/// The Boost.Geometry types areamatch uses for areas, rooms and overlaps. Coordinates are metres
/// in a map's world frame (x right, y up). Polygons are clockwise and closed (Boost.Geometry's
/// default); call `boost::geometry::correct` after building one by hand.

// GCC 12 reports false "may be used uninitialized" warnings deep inside Boost.Geometry's overlay
// code; they are Boost's, not ours, so they are silenced for these includes only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <boost/geometry.hpp>
#include <boost/geometry/geometries/point_xy.hpp>
#include <boost/geometry/geometries/polygon.hpp>
#include <boost/geometry/geometries/multi_polygon.hpp>
#include <boost/geometry/geometries/segment.hpp>
#include <boost/geometry/geometries/box.hpp>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

#include <Eigen/Core>

namespace areamatch {

namespace bg = boost::geometry;

using Point2 = bg::model::d2::point_xy<double>;
using Polygon2 = bg::model::polygon<Point2>;
using MultiPolygon2 = bg::model::multi_polygon<Polygon2>;
using Segment2 = bg::model::segment<Point2>;
using Box2 = bg::model::box<Point2>;

inline Point2 to_point(const Eigen::Vector2d& v) { return {v.x(), v.y()}; }
inline Eigen::Vector2d to_vector(const Point2& p) { return {p.x(), p.y()}; }

/// An axis-aligned rectangle [min_x, max_x] × [min_y, max_y] as a valid (corrected) polygon.
inline Polygon2 make_rectangle(double min_x, double min_y, double max_x, double max_y) {
  Polygon2 polygon;
  auto& ring = polygon.outer();
  ring = {{min_x, min_y}, {min_x, max_y}, {max_x, max_y}, {max_x, min_y}, {min_x, min_y}};
  bg::correct(polygon);
  return polygon;
}

}  // namespace areamatch
