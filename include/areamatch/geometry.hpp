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

#include <cstddef>

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

namespace detail {

/// The two vertices of a ring farthest apart (the first such pair) and their distance; for a
/// convex hull, its diameter. An empty ring gives two zero points at distance −1.
struct FarthestVertices {
  Eigen::Vector2d a = Eigen::Vector2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  double distance = -1.0;
};

inline FarthestVertices farthest_vertices(const Polygon2& polygon) {
  FarthestVertices best;
  const auto& ring = polygon.outer();
  // Hulls of our areas have tens of vertices: O(h²) is simpler than rotating calipers and as fast.
  for (std::size_t i = 0; i < ring.size(); ++i) {
    for (std::size_t j = i + 1; j < ring.size(); ++j) {
      const double distance = bg::distance(ring[i], ring[j]);
      if (distance > best.distance) best = {to_vector(ring[i]), to_vector(ring[j]), distance};
    }
  }
  return best;
}

}  // namespace detail

}  // namespace areamatch
