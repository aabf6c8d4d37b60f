#pragma once
/// \file detail/voronoi_circles.hpp
/// Boost.Polygon's segment Voronoi builder with faster circle events for wall outlines.
///
/// Boost computes the circle through a point and tangent to two segments ("pss") from the
/// intersection of the two segment lines, and the circle through two points tangent to a segment
/// ("pps") from the points' bisector. When a point lies on a segment's line both formulas cancel
/// heavily (a short wall piece far from the origin), their error estimate exceeds the 64 ulps
/// Boost accepts, and the event is recomputed in multiprecision: on the shared maps all such pss
/// events and a third of the pps ones were, about half of `construct_voronoi`'s time. Here:
/// - a point that ends one of the segments (`endpoint_circle`, `endpoint_circle_two_points`):
///   the circle from that point directly, with a rounding-error bound derived by hand;
/// - any other pss (`point_segment_segment_circle`) and three segments
///   (`three_segment_circle`): Boost's formulas, but relative to a nearby site, with the
///   cancelling root taken in its conjugate form and the rounding tracked by `ErrorBounded`.
/// If a bound is above `max_ulps` (or the case does not apply) Boost's own computation runs as
/// before. The diagram is Boost's (tests compare the edges, and every circle on robot maps), only
/// events that tie within Boost's tolerance may come out in another order.
///
/// Geometry of `endpoint_circle` (pss), in Boost's orientation (segment 1 runs from site2's
/// point1 to point0, segment 2 from site3's point0 to point1; d1, d2 their directions): the
/// circle's centre c lies on the bisector where the signed distances to the two lines cancel,
/// L1(c) + L2(c) = 0. With the point p on line 1 (L1(p) = 0) the circle touches line 1 at p,
/// so c = p + s·n1 with n1 the unit normal of d1, and L1(c) = s, L2(c) = L2(p) + s·(d̂1·d̂2), hence
///   s = −L2(p) / (1 + d̂1·d̂2),   c = p − cross(d2, p − start2) / D · perp(d1),
///   D = |d1||d2| + d1·d2  (= cross(d1, d2)² / (|d1||d2| − d1·d2) when d1·d2 < 0, no cancellation),
/// radius |s|, and the event's sweep position is c.x + radius. With p on line 2 the roles swap;
/// with p on both the circle is the point itself. (Boost's formula has a double root here, so
/// there is exactly one circle; tests compare both computations on random walls.)

#include <boost/polygon/voronoi.hpp>
#include <boost/version.hpp>

/// Whether the faster circle events are compiled in. They subclass Boost.Polygon's internal
/// predicates (`boost::polygon::detail::voronoi_predicates`), which are not public API: used on
/// the Boost versions whose internals they were written against (tested on 1.81; the predicates'
/// interface is unchanged since Boost 1.52), otherwise the stock builder runs. Define
/// AREAMATCH_FAST_VORONOI_CIRCLES to 0 to force the stock builder, to 1 to force ours.
#ifndef AREAMATCH_FAST_VORONOI_CIRCLES
#if BOOST_VERSION >= 107400 && BOOST_VERSION < 109000
#define AREAMATCH_FAST_VORONOI_CIRCLES 1
#else
#define AREAMATCH_FAST_VORONOI_CIRCLES 0
#endif
#endif

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <initializer_list>
#include <limits>

namespace areamatch::detail {

#if AREAMATCH_FAST_VORONOI_CIRCLES
namespace bpd = boost::polygon::detail;
/// Boost.Polygon's default predicates for int32 input, which the functors below fall back to.
using BoostVoronoiPredicates = bpd::voronoi_predicates<bpd::voronoi_ctype_traits<bpd::int32>>;

/// Whether `p` is one of the end points of segment site `segment`.
template <class Site, class Point>
bool ends_at(const Site& segment, const Point& p) {
  return p == segment.point0() || p == segment.point1();
}

/// The error every circle computed here is proven within, in units of machine epsilon relative to
/// each coordinate: Boost accepts 64 before recomputing exactly; we stay within half.
constexpr double max_ulps = 32.0;

/// The circle centred at p + k·normal with radius |k|·|normal| (p, normal integers), as a
/// Boost circle event (centre, and the sweep position centre.x + radius), if its rounding error
/// is provably within `max_ulps` of every coordinate. `k` may carry up to 5 epsilon of error.
template <class Circle>
bool circle_from_offset(double px, double py, double k, double normal_x, double normal_y, double normal_length,
                        Circle& circle) {
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

/// A double with a bound on its absolute error, carried through + − × ÷ √ (each adds one
/// rounding, counted as epsilon·|result|: twice the round-to-nearest bound). Boost's
/// `robust_fpt` carries relative errors, which overstate a small, rounded term that is then added
/// to a large exact one — the case of circles computed relative to a nearby site below.
struct ErrorBounded {
  double value = 0.0;
  double error = 0.0;

  static constexpr double epsilon = std::numeric_limits<double>::epsilon();
  /// An integer (exact up to 2^53).
  static ErrorBounded of(long long v) {
    const double d = static_cast<double>(v);
    return {d, std::llabs(v) < (1LL << 53) ? 0.0 : std::abs(d) * epsilon};
  }
  static ErrorBounded rounded(double v, double error) { return {v, error + std::abs(v) * epsilon}; }
  ErrorBounded operator-() const { return {-value, error}; }
  friend ErrorBounded operator+(ErrorBounded a, ErrorBounded b) { return rounded(a.value + b.value, a.error + b.error); }
  friend ErrorBounded operator-(ErrorBounded a, ErrorBounded b) { return rounded(a.value - b.value, a.error + b.error); }
  friend ErrorBounded operator*(ErrorBounded a, ErrorBounded b) {
    return rounded(a.value * b.value, std::abs(a.value) * b.error + std::abs(b.value) * a.error + a.error * b.error);
  }
  /// Needs |b.value| > b.error: divisors below are far from zero by construction, or checked
  /// with `divisor_safe()`.
  friend ErrorBounded operator/(ErrorBounded a, ErrorBounded b) {
    const double q = a.value / b.value;
    return rounded(q, (a.error + std::abs(q) * b.error) / (std::abs(b.value) - b.error));
  }
  bool divisor_safe() const { return std::abs(value) > 2.0 * error; }
  ErrorBounded abs() const { return {std::abs(value), error}; }
  /// Of a value known to be ≥ 0 (callers check `value - error >= 0`).
  ErrorBounded sqrt() const {
    const double root = std::sqrt(value);
    return rounded(root, error / (root + std::sqrt(std::max(value - error, 0.0))));
  }
  bool within_ulps(double ulps) const { return error <= ulps * epsilon * std::abs(value); }
};

/// The circle through point site `point` tangent to segment sites `segment1`, `segment2` (Boost's
/// pss roles) for non-parallel segments, as Boost's lazy formula computes it but relative to the
/// point: with the point at the origin, the lines' intersection I, the bisector u = d1·|d2| + d2·|d1|
/// (Boost's d1, d2) and A = |d1||d2| + d1·d2, the centre is I + t·u with
/// A²t² + 2(u·I)t + |I|² = 0. Boost takes t = (−u·I ± √det) / A² (det = 2·A·or1·or2 from exact
/// cross products, sign by `point_index`); where those two terms would cancel, the same root is
/// |I|² / (−u·I ∓ √det). The point's coordinates are added last, exactly. Boost's formula in
/// absolute coordinates cancels when the point is near the lines' intersection (wall corners,
/// two walls a pixel apart), which sent such events to multiprecision. Returns false when the
/// case does not apply or the result is not provably within `max_ulps`.
template <class Site, class Circle>
bool point_segment_segment_circle(const Site& point, const Site& segment1, const Site& segment2, int point_index,
                                  Circle& circle) {
  const auto& p = point.point0();
  // Boost's orientation: segment 1 from point1 to point0, segment 2 from point0 to point1.
  const auto& start1 = segment1.point1();
  const auto& end1 = segment1.point0();
  const auto& start2 = segment2.point0();
  const auto& end2 = segment2.point1();
  if (!small_coordinates({p, start1, end1, start2, end2})) return false;
  using ll = long long;
  using E = ErrorBounded;
  const ll e1x = ll{end1.x()} - p.x(), e1y = ll{end1.y()} - p.y();
  const ll e2x = ll{end2.x()} - p.x(), e2y = ll{end2.y()} - p.y();
  const ll a1 = ll{end1.x()} - start1.x(), b1 = ll{end1.y()} - start1.y();
  const ll a2 = ll{end2.x()} - start2.x(), b2 = ll{end2.y()} - start2.y();
  const ll orientation = b1 * a2 - a1 * b2;
  if (orientation == 0) return false;  // parallel: Boost's own case
  const E length1 = E::of(a1 * a1 + b1 * b1).sqrt(), length2 = E::of(a2 * a2 + b2 * b2).sqrt();
  const ll dot = a1 * a2 + b1 * b2;
  const E lengths = length1 * length2;
  // A without cancellation: for d1·d2 < 0, |d1||d2| + d1·d2 = cross² / (|d1||d2| − d1·d2).
  const E A = dot >= 0 ? E::of(dot) + lengths : E::of(orientation) * E::of(orientation) / (lengths - E::of(dot));
  // Cross products of each direction with its end point (relative to the point): exact.
  const ll or1 = b1 * e1x - a1 * e1y;
  const ll or2 = a2 * e2y - b2 * e2x;
  const E det = E{2.0, 0.0} * A * E::of(or1) * E::of(or2);
  if (!(det.value - det.error >= 0.0)) return false;
  const E root = det.sqrt();
  const E ix = (E::of(a2) * E::of(or1) + E::of(a1) * E::of(or2)) / E::of(orientation);
  const E iy = (E::of(b1) * E::of(or2) + E::of(b2) * E::of(or1)) / E::of(orientation);
  const E ux = E::of(a1) * length2 + E::of(a2) * length1;
  const E uy = E::of(b1) * length2 + E::of(b2) * length1;
  const E w = -(ix * ux + iy * uy);
  const bool plus = point_index == 2;
  E t;
  if ((w.value >= 0.0) == plus) {
    t = (plus ? w + root : w - root) / (A * A);
  } else {
    const E conjugate = plus ? w - root : w + root;
    if (!conjugate.divisor_safe()) return false;
    t = (ix * ix + iy * iy) / conjugate;
  }
  const E cx = E::of(p.x()) + (ix + t * ux);
  const E cy = E::of(p.y()) + (iy + t * uy);
  const E lower_x = cx + t.abs() * E::of(std::llabs(orientation));
  if (!cx.within_ulps(max_ulps) || !cy.within_ulps(max_ulps) || !lower_x.within_ulps(max_ulps)) return false;
  circle = Circle(cx.value, cy.value, lower_x.value);
  return true;
}

/// The circle tangent to segment sites `site1`, `site2`, `site3` (Boost's sss), by Boost's lazy
/// formula (the centre and radius as ratios of sums over the three lines, each line as
/// a·y − b·x = c), but with coordinates relative to an end point of the middle segment, so the
/// lines' constants c are small and the sums cancel far less; the origin is added back last.
/// Returns false when the result is not provably within `max_ulps`.
template <class Site, class Circle>
bool three_segment_circle(const Site& site1, const Site& site2, const Site& site3, Circle& circle) {
  if (!small_coordinates({site1.point0(), site1.point1(), site2.point0(), site2.point1(), site3.point0(), site3.point1()}))
    return false;
  using ll = long long;
  using E = ErrorBounded;
  const ll ox = site2.x0(), oy = site2.y0();
  struct Line {
    ll a, b, c;
    E length;
  };
  auto line = [&](const Site& s) {
    const ll x0 = ll{s.x0()} - ox, y0 = ll{s.y0()} - oy, x1 = ll{s.x1()} - ox, y1 = ll{s.y1()} - oy;
    const ll a = x1 - x0, b = y1 - y0;
    return Line{a, b, x0 * y1 - y0 * x1, E::of(a * a + b * b).sqrt()};
  };
  const Line l1 = line(site1), l2 = line(site2), l3 = line(site3);
  const ll cross12 = l1.a * l2.b - l1.b * l2.a, cross23 = l2.a * l3.b - l2.b * l3.a, cross31 = l3.a * l1.b - l3.b * l1.a;
  const E denom = E::of(cross12) * l3.length + E::of(cross23) * l1.length + E::of(cross31) * l2.length;
  if (!denom.divisor_safe()) return false;
  const E r = -(E::of(cross12) * E::of(l3.c) + E::of(cross23) * E::of(l1.c) + E::of(cross31) * E::of(l2.c));
  // a_i·c_j − a_j·c_i in the frame: products up to 2^82, so as bounded doubles.
  auto pair_term = [](ll ai, ll cj, ll aj, ll ci) { return E::of(ai) * E::of(cj) - E::of(aj) * E::of(ci); };
  const E cx = pair_term(l1.a, l2.c, l2.a, l1.c) * l3.length + pair_term(l2.a, l3.c, l3.a, l2.c) * l1.length +
               pair_term(l3.a, l1.c, l1.a, l3.c) * l2.length;
  const E cy = pair_term(l1.b, l2.c, l2.b, l1.c) * l3.length + pair_term(l2.b, l3.c, l3.b, l2.c) * l1.length +
               pair_term(l3.b, l1.c, l1.b, l3.c) * l2.length;
  const E centre_x = E::of(ox) + cx / denom;
  const E centre_y = E::of(oy) + cy / denom;
  const E lower_x = E::of(ox) + (cx + r) / denom;
  if (!centre_x.within_ulps(max_ulps) || !centre_y.within_ulps(max_ulps) || !lower_x.within_ulps(max_ulps)) return false;
  circle = Circle(centre_x.value, centre_y.value, lower_x.value);
  return true;
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
  void sss(const Site& a, const Site& b, const Site& c, Circle& circle) {
    if (!three_segment_circle(a, b, c, circle)) boost_formation.sss(a, b, c, circle);
  }
  void pss(const Site& a, const Site& b, const Site& c, int index, Circle& circle) {
    if (!endpoint_circle(a, b, c, circle) && !point_segment_segment_circle(a, b, c, index, circle)) boost_formation.pss(a, b, c, index, circle);
  }
};

/// Boost's predicates with `EndpointCircleFormation` as the circle formation functor.
struct EndpointCirclePredicates : BoostVoronoiPredicates {
  template <class Site, class Circle>
  using circle_formation_predicate = typename BoostVoronoiPredicates::template circle_formation_predicate<
      Site, Circle, typename BoostVoronoiPredicates::template circle_existence_predicate<Site>, EndpointCircleFormation<Site, Circle>>;
};

#endif  // AREAMATCH_FAST_VORONOI_CIRCLES

/// `boost::polygon::construct_voronoi` for segments, with the faster circle events when
/// `fast_circles` and they are compiled in (the same diagram either way, vertices equal up to a
/// few ulps; tests compare them).
template <class SegmentIterator, class Diagram>
void construct_segment_voronoi(SegmentIterator first, SegmentIterator last, Diagram* diagram, bool fast_circles = true) {
#if AREAMATCH_FAST_VORONOI_CIRCLES
  if (fast_circles) {
    boost::polygon::voronoi_builder<bpd::int32, bpd::voronoi_ctype_traits<bpd::int32>, EndpointCirclePredicates> builder;
    boost::polygon::insert(first, last, &builder);
    builder.construct(diagram);
    return;
  }
#endif
  (void)fast_circles;
  boost::polygon::construct_voronoi(first, last, diagram);
}

}  // namespace areamatch::detail
