#pragma once
/// \file detail/voronoi_circles.hpp
/// Boost.Polygon's segment Voronoi builder with faster circle events for the commonest cases of
/// wall outlines: a point site that is an endpoint of one of the segment sites involved.
///
/// Boost computes the circle through a point and tangent to two segments ("pss") from the
/// intersection of the two segment lines, and the circle through two points tangent to a segment
/// ("pps") from the points' bisector. When a point lies on a segment's line both formulas cancel
/// heavily (a short wall piece far from the origin), their error estimate exceeds the 64 ulps
/// Boost accepts, and the event is recomputed in multiprecision: on the shared maps all such pss
/// events and a third of the pps ones were, about half of `construct_voronoi`'s time. Here the
/// same circles are computed from that point directly, with a rounding-error bound; if the bound
/// is above `max_ulps` (or the case does not apply) Boost's own computation runs as before. The
/// diagram is Boost's (tests compare the edges), only events that tie within Boost's tolerance
/// may come out in another order.
///
/// Geometry of pss, in Boost's orientation (segment 1 runs from site2's point1 to point0, segment 2
/// from site3's point0 to point1; d1, d2 their directions): the circle's centre c lies on the
/// bisector where the signed distances to the two lines cancel, L1(c) + L2(c) = 0. With the
/// point p on line 1 (L1(p) = 0) the circle touches line 1 at p, so c = p + s·n1 with n1 the
/// unit normal of d1, and L1(c) = s, L2(c) = L2(p) + s·(d̂1·d̂2), hence
///   s = −L2(p) / (1 + d̂1·d̂2),   c = p − cross(d2, p − start2) / D · perp(d1),
///   D = |d1||d2| + d1·d2  (= cross(d1, d2)² / (|d1||d2| − d1·d2) when d1·d2 < 0, no cancellation),
/// radius |s|, and the event's sweep position is c.x + radius. With p on line 2 the roles swap;
/// with p on both the circle is the point itself. (Boost's formula has a double root here, so
/// there is exactly one circle; tests compare both computations on random walls.)

#include <boost/polygon/voronoi.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <initializer_list>

namespace areamatch::detail {

namespace bpd = boost::polygon::detail;
/// Boost.Polygon's default predicates for int32 input, which the functors below fall back to.
using BoostVoronoiPredicates = bpd::voronoi_predicates<bpd::voronoi_ctype_traits<bpd::int32>>;

/// Whether `p` is one of the end points of segment site `segment`.
template <class Site, class Point>
bool ends_at(const Site& segment, const Point& p) {
  return p == segment.point0() || p == segment.point1();
}

/// The circle centred at p + k·normal with radius |k|·|normal| (p, normal integers), as a
/// Boost circle event (centre, and the sweep position centre.x + radius), if its rounding error
/// is provably within `max_ulps` of every coordinate. `k` may carry up to 5 epsilon of error.
template <class Circle>
bool circle_from_offset(double px, double py, double k, double normal_x, double normal_y, double normal_length,
                        Circle& circle) {
  // Boost accepts 64 ulps (in units of machine epsilon) before recomputing exactly; stay within half.
  constexpr double max_ulps = 32.0;
  const double offset_x = k * normal_x, offset_y = k * normal_y;
  const double cx = px + offset_x, cy = py + offset_y;
  const double radius = std::abs(k) * normal_length;
  const double lower_x = cx + radius;
  // Rounding, in units of epsilon: the offsets carry ≤ 5.5, the radius ≤ 6.5 (normal_length a
  // square root of an integer: ≤ 1), each sum 0.5 more; bounded by 8 per term plus 1 for the
  // final rounding.
  const double error_x = 8.0 * std::abs(offset_x) + std::abs(cx);
  const double error_y = 8.0 * std::abs(offset_y) + std::abs(cy);
  const double error_lower = error_x + 8.0 * radius + std::abs(lower_x);
  auto within = [&](double error, double value) { return error <= max_ulps * std::abs(value); };
  if (!within(error_x, cx) || !within(error_y, cy) || !within(error_lower, lower_x)) return false;
  circle = Circle(cx, cy, lower_x);
  return true;
}

/// Coordinates below 2^26 keep every integer product below here within int64 and exactly
/// representable sums; larger inputs take Boost's route.
template <class Point>
bool small_coordinates(std::initializer_list<Point> points) {
  constexpr long long limit = 1LL << 26;
  for (const auto& q : points)
    if (std::llabs(q.x()) >= limit || std::llabs(q.y()) >= limit) return false;
  return true;
}

/// The circle through point site `point`, tangent to segment sites `segment1` and `segment2`
/// (Boost's pss roles), when the point is an endpoint of one or both segments and the result is
/// provably accurate (see the file comment). Returns false otherwise.
template <class Site, class Circle>
bool endpoint_circle(const Site& point, const Site& segment1, const Site& segment2, Circle& circle) {
  const auto& p = point.point0();
  const bool on1 = ends_at(segment1, p);
  const bool on2 = ends_at(segment2, p);
  if (!on1 && !on2) return false;
  const double px = p.x(), py = p.y();
  if (on1 && on2) {  // both segments end at p: the circle is p itself
    circle = Circle(px, py, px);
    return true;
  }
  if (!small_coordinates({p, segment1.point0(), segment1.point1(), segment2.point0(), segment2.point1()})) return false;
  using ll = long long;
  const ll d1x = ll{segment1.point0().x()} - segment1.point1().x(), d1y = ll{segment1.point0().y()} - segment1.point1().y();
  const ll d2x = ll{segment2.point1().x()} - segment2.point0().x(), d2y = ll{segment2.point1().y()} - segment2.point0().y();
  const ll dot = d1x * d2x + d1y * d2y;
  const ll cross = d1x * d2y - d1y * d2x;
  const double length1_sq = static_cast<double>(d1x * d1x + d1y * d1y);
  const double length2_sq = static_cast<double>(d2x * d2x + d2y * d2y);
  const double lengths = std::sqrt(length1_sq * length2_sq);
  // D carries ≤ 3.75 epsilon, the quotient below ≤ 4.75.
  const double D = dot >= 0 ? lengths + static_cast<double>(dot)
                            : static_cast<double>(cross) * static_cast<double>(cross) / (lengths - static_cast<double>(dot));
  if (!(D > 0.0)) return false;  // antiparallel: Boost's parallel-segment case
  if (on1) {  // distance of p from line 2 (times |d2|); the centre lies on line 1's normal at p
    const ll numerator = d2x * (ll{p.y()} - segment2.point0().y()) - d2y * (ll{p.x()} - segment2.point0().x());
    return circle_from_offset(px, py, -static_cast<double>(numerator) / D, static_cast<double>(-d1y), static_cast<double>(d1x),
                              std::sqrt(length1_sq), circle);
  }
  const ll numerator = d1x * (ll{p.y()} - segment1.point1().y()) - d1y * (ll{p.x()} - segment1.point1().x());
  return circle_from_offset(px, py, -static_cast<double>(numerator) / D, static_cast<double>(-d2y), static_cast<double>(d2x),
                            std::sqrt(length2_sq), circle);
}

/// The circle through point sites `point1`, `point2` tangent to segment site `segment` (Boost's
/// pps roles), when one of the points is an endpoint of the segment: the circle touches the
/// segment's line there, so its centre is e + k·perp(d) with e that endpoint, d the segment's
/// direction and k = |o − e|² / (2·cross(d, o − e)) for the other point o (one circle: Boost's
/// two solutions coincide). Returns false when that does not apply or is not provably accurate.
template <class Site, class Circle>
bool endpoint_circle_two_points(const Site& point1, const Site& point2, const Site& segment, Circle& circle) {
  const auto& a = point1.point0();
  const auto& b = point2.point0();
  const bool a_on = ends_at(segment, a);
  const bool b_on = ends_at(segment, b);
  if (a_on == b_on) return false;
  if (!small_coordinates({a, b, segment.point0(), segment.point1()})) return false;
  const auto& e = a_on ? a : b;
  const auto& o = a_on ? b : a;
  using ll = long long;
  const ll dx = ll{segment.point1().x()} - segment.point0().x(), dy = ll{segment.point1().y()} - segment.point0().y();
  const ll vx = ll{o.x()} - e.x(), vy = ll{o.y()} - e.y();
  const ll cross = dx * vy - dy * vx;
  if (cross == 0) return false;  // both points on the line
  // k carries ≤ 1.5 epsilon.
  const double k = static_cast<double>(vx * vx + vy * vy) / (2.0 * static_cast<double>(cross));
  return circle_from_offset(static_cast<double>(e.x()), static_cast<double>(e.y()), k, static_cast<double>(-dy),
                            static_cast<double>(dx), std::sqrt(static_cast<double>(dx * dx + dy * dy)), circle);
}

/// Boost's lazy circle formation with `endpoint_circle` (pss) and `endpoint_circle_two_points`
/// (pps) tried first.
template <class Site, class Circle>
struct EndpointCircleFormation {
  typename BoostVoronoiPredicates::template lazy_circle_formation_functor<Site, Circle> boost_formation;

  void ppp(const Site& a, const Site& b, const Site& c, Circle& circle) { boost_formation.ppp(a, b, c, circle); }
  void pps(const Site& a, const Site& b, const Site& c, int index, Circle& circle) {
    if (!endpoint_circle_two_points(a, b, c, circle)) boost_formation.pps(a, b, c, index, circle);
  }
  void sss(const Site& a, const Site& b, const Site& c, Circle& circle) { boost_formation.sss(a, b, c, circle); }
  void pss(const Site& a, const Site& b, const Site& c, int index, Circle& circle) {
    if (!endpoint_circle(a, b, c, circle)) boost_formation.pss(a, b, c, index, circle);
  }
};

/// Boost's predicates with `EndpointCircleFormation` as the circle formation functor.
struct EndpointCirclePredicates : BoostVoronoiPredicates {
  template <class Site, class Circle>
  using circle_formation_predicate = typename BoostVoronoiPredicates::template circle_formation_predicate<
      Site, Circle, typename BoostVoronoiPredicates::template circle_existence_predicate<Site>, EndpointCircleFormation<Site, Circle>>;
};

/// `boost::polygon::construct_voronoi` for segments, with the faster circle events.
template <class SegmentIterator, class Diagram>
void construct_segment_voronoi(SegmentIterator first, SegmentIterator last, Diagram* diagram) {
  boost::polygon::voronoi_builder<bpd::int32, bpd::voronoi_ctype_traits<bpd::int32>, EndpointCirclePredicates> builder;
  boost::polygon::insert(first, last, &builder);
  builder.construct(diagram);
}

}  // namespace areamatch::detail
