#pragma once
/// \file detail/voronoi_circles.hpp
/// Boost.Polygon's segment Voronoi builder with a faster circle event for the commonest case of
/// wall outlines: a corner point and two segments, the point being an endpoint of one or both.
///
/// Boost computes the circle through a point and tangent to two segments ("pss") from the
/// intersection of the two segment lines. When the point lies on one of the lines that formula
/// cancels heavily (a short wall piece far from the origin) and its error estimate exceeds the
/// 64 ulps Boost accepts, so it recomputes the event in multiprecision: on the shared maps every
/// such event did, about half of `construct_voronoi`'s time. Here the same circle is computed
/// from the point directly, with a rounding-error bound; if the bound is above `max_ulps` (or
/// the case does not apply) Boost's own computation runs as before.
///
/// Geometry, in Boost's orientation (segment 1 runs from site2's point1 to point0, segment 2
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

namespace areamatch::detail {

namespace bpd = boost::polygon::detail;

/// The circle through point site `point`, tangent to segment sites `segment1` and `segment2`
/// (Boost's pss roles), when the point is an endpoint of one or both segments and the result is
/// provably within `max_ulps` relative rounding error. Returns false otherwise.
template <class Site, class Circle>
bool endpoint_circle(const Site& point, const Site& segment1, const Site& segment2, Circle& circle) {
  // Boost accepts 64 ulps (in units of machine epsilon) before recomputing exactly; stay within half.
  constexpr double max_ulps = 32.0;
  const auto& p = point.point0();
  const bool on1 = p == segment1.point0() || p == segment1.point1();
  const bool on2 = p == segment2.point0() || p == segment2.point1();
  if (!on1 && !on2) return false;
  const double px = p.x(), py = p.y();
  if (on1 && on2) {  // both segments end at p: the circle is p itself
    circle = Circle(px, py, px);
    return true;
  }
  // Coordinates below 2^26 keep every product below exact-integer range of int64 (and of the
  // bound below); larger inputs take Boost's route.
  constexpr long long limit = 1LL << 26;
  for (const auto& q : {p, segment1.point0(), segment1.point1(), segment2.point0(), segment2.point1()}) {
    if (std::llabs(q.x()) >= limit || std::llabs(q.y()) >= limit) return false;
  }
  using ll = long long;
  const ll d1x = ll{segment1.point0().x()} - segment1.point1().x(), d1y = ll{segment1.point0().y()} - segment1.point1().y();
  const ll d2x = ll{segment2.point1().x()} - segment2.point0().x(), d2y = ll{segment2.point1().y()} - segment2.point0().y();
  const ll dot = d1x * d2x + d1y * d2y;
  const ll cross = d1x * d2y - d1y * d2x;
  const double length1_sq = static_cast<double>(d1x * d1x + d1y * d1y);
  const double length2_sq = static_cast<double>(d2x * d2x + d2y * d2y);
  const double lengths = std::sqrt(length1_sq * length2_sq);
  const double D = dot >= 0 ? lengths + static_cast<double>(dot)
                            : static_cast<double>(cross) * static_cast<double>(cross) / (lengths - static_cast<double>(dot));
  if (!(D > 0.0)) return false;  // antiparallel: Boost's parallel-segment case
  ll offset_numerator, normal_x, normal_y;
  double normal_length;
  if (on1) {  // distance of p from line 2 (times |d2|); the centre lies on line 1's normal at p
    offset_numerator = d2x * (ll{p.y()} - segment2.point0().y()) - d2y * (ll{p.x()} - segment2.point0().x());
    normal_x = -d1y, normal_y = d1x;
    normal_length = std::sqrt(length1_sq);
  } else {
    offset_numerator = d1x * (ll{p.y()} - segment1.point1().y()) - d1y * (ll{p.x()} - segment1.point1().x());
    normal_x = -d2y, normal_y = d2x;
    normal_length = std::sqrt(length2_sq);
  }
  const double k = static_cast<double>(offset_numerator) / D;
  const double offset_x = k * static_cast<double>(normal_x), offset_y = k * static_cast<double>(normal_y);
  const double cx = px - offset_x, cy = py - offset_y;
  const double radius = std::abs(k) * normal_length;
  const double lower_x = cx + radius;
  // Rounding, in units of epsilon: D carries ≤ 3.75, k ≤ 4.75, the offsets ≤ 5.25, the radius
  // ≤ 6.25, each sum 0.5 more; bounded here by 8 per term plus 1 for the final rounding.
  const double error_x = 8.0 * std::abs(offset_x) + std::abs(cx);
  const double error_y = 8.0 * std::abs(offset_y) + std::abs(cy);
  const double error_lower = error_x + 8.0 * radius + std::abs(lower_x);
  auto within = [&](double error, double value) { return error <= max_ulps * std::abs(value); };
  if (!within(error_x, cx) || !within(error_y, cy) || !within(error_lower, lower_x)) return false;
  circle = Circle(cx, cy, lower_x);
  return true;
}

/// Boost's lazy circle formation with `endpoint_circle` tried first for point–segment–segment.
template <class Site, class Circle>
struct EndpointCircleFormation {
  using ctype_traits = bpd::voronoi_ctype_traits<bpd::int32>;
  typename bpd::voronoi_predicates<ctype_traits>::template lazy_circle_formation_functor<Site, Circle> boost_formation;

  void ppp(const Site& a, const Site& b, const Site& c, Circle& circle) { boost_formation.ppp(a, b, c, circle); }
  void pps(const Site& a, const Site& b, const Site& c, int index, Circle& circle) {
    boost_formation.pps(a, b, c, index, circle);
  }
  void sss(const Site& a, const Site& b, const Site& c, Circle& circle) { boost_formation.sss(a, b, c, circle); }
  void pss(const Site& a, const Site& b, const Site& c, int index, Circle& circle) {
    if (!endpoint_circle(a, b, c, circle)) boost_formation.pss(a, b, c, index, circle);
  }
};

/// Boost's predicates with `EndpointCircleFormation` as the circle formation functor.
struct EndpointCirclePredicates : bpd::voronoi_predicates<bpd::voronoi_ctype_traits<bpd::int32>> {
  using boost_predicates = bpd::voronoi_predicates<bpd::voronoi_ctype_traits<bpd::int32>>;
  template <class Site, class Circle>
  using circle_formation_predicate =
      typename boost_predicates::template circle_formation_predicate<Site, Circle,
                                                                     typename boost_predicates::template circle_existence_predicate<Site>,
                                                                     EndpointCircleFormation<Site, Circle>>;
};

/// `boost::polygon::construct_voronoi` for segments, with the faster circle events.
template <class SegmentIterator, class Diagram>
void construct_segment_voronoi(SegmentIterator first, SegmentIterator last, Diagram* diagram) {
  boost::polygon::voronoi_builder<bpd::int32, bpd::voronoi_ctype_traits<bpd::int32>, EndpointCirclePredicates> builder;
  boost::polygon::insert(first, last, &builder);
  builder.construct(diagram);
}

}  // namespace areamatch::detail
