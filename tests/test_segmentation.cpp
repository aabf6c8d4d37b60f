// The Voronoi segmenter: Boost.Polygon's input contract on nasty shapes, rooms and doors of
// synthetic buildings, valid non-overlapping polygons, determinism, and bad input.
#include <areamatch/areamatch.hpp>
#include <areamatch/synthetic.hpp>
#include <areamatch/detail/random.hpp>
#include <areamatch/detail/compact_voronoi.hpp>
#include <areamatch/detail/voronoi_circles.hpp>
#include <areamatch/segmentation_score.hpp>

#include <doctest/doctest.h>

#include "test_support.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <tuple>
#include <string>
#include <random>
#include <stdexcept>
#include <vector>

using namespace areamatch;

namespace {

/// A grid from text: '#' occupied, '.' free, '?' unknown; 0.1 m cells.
OccupancyGrid grid_from_text(const std::vector<std::string>& rows, double resolution = 0.1) {
  OccupancyGrid g(static_cast<int>(rows.front().size()), static_cast<int>(rows.size()), resolution);
  for (int r = 0; r < g.height(); ++r)
    for (int c = 0; c < g.width(); ++c)
      g.set(c, r, rows[r][c] == '#' ? CellState::occupied : rows[r][c] == '.' ? CellState::free : CellState::unknown);
  return g;
}

/// Checks the boundary at several tolerances; returns how many rings needed repairs in all.
std::size_t check_boundary_contract(const OccupancyGrid& g) {
  std::size_t refined = 0;
  BinarizeParams keep_everything;
  keep_everything.max_speckle_area_m2 = 0.0;
  keep_everything.min_free_area_m2 = 0.0;
  const FreeSpace space = binarize(g, keep_everything);
  for (double tolerance : {0.0, 0.05, 0.1, 0.3}) {
    BoundaryParams params;
    params.simplify_tolerance_m = tolerance;
    const BoundarySegments boundary = trace_boundary(space, g.resolution(), params);
    CHECK(detail::find_conflicts(boundary.segments).empty());
    // Repairs keep the simplification within its tolerance: every corner of the traced outline
    // lies that close to some segment of its ring.
    const detail::TracedRings traced = detail::trace_rings(space);
    REQUIRE(traced.rings.size() == boundary.ring_count);
    std::size_t strays = 0;
    for (std::size_t ring = 0; ring < traced.rings.size(); ++ring)
      for (const LatticePoint& corner : traced.rings[ring]) {
        double nearest = std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < boundary.segments.size(); ++i) {
          if (boundary.ring_of_segment[i] != static_cast<int>(ring)) continue;
          const Eigen::Vector2d a(boundary.segments[i].low().x(), boundary.segments[i].low().y());
          const Eigen::Vector2d b(boundary.segments[i].high().x(), boundary.segments[i].high().y());
          const Eigen::Vector2d p(corner.x, corner.y);
          const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
          nearest = std::min(nearest, (a + t * (b - a) - p).norm());
        }
        strays += nearest > tolerance / g.resolution() + 1e-9;
      }
    CHECK(strays == 0);
    refined += boundary.refined_rings;
    // The Voronoi builder accepts it and the skeleton stays in free space.
    const Skeleton skeleton = build_skeleton(space, boundary, g.resolution());
    for (const auto& branch : skeleton.branches)
      for (const auto& s : skeleton.samples_of(branch))
        CHECK(space.is_free(static_cast<int>(std::floor(s.position.x())), static_cast<int>(std::floor(s.position.y()))));
  }
  return refined;
}

void check_graph_invariants(const AreaGraph& graph) {
  for (const auto& area : graph.areas) {
    std::string reason;
    CHECK_MESSAGE(bg::is_valid(area.polygon, reason), "area ", area.id, ": ", reason);
    CHECK(area.size_m2 > 0.0);
    CHECK(std::is_sorted(area.passages.begin(), area.passages.end()));
  }
  for (const auto& p : graph.passages) {
    CHECK(p.area_a >= 0);
    CHECK(p.area_b > p.area_a);  // two distinct areas, ordered
    CHECK(p.area_b < static_cast<int>(graph.areas.size()));
    CHECK(p.width_m > 0.0);
  }
  // Every labelled cell lies in its area's polygon (so areas cannot overlap).
  OccupancyGrid frame(graph.grid.width, graph.grid.height, graph.grid.resolution, graph.grid.origin);
  std::size_t outside = 0, labelled = 0;
  for (int r = 0; r < frame.height(); r += 3)
    for (int c = 0; c < frame.width(); c += 3) {
      const int l = graph.labels[frame.index(c, r)];
      if (l < 0) continue;
      ++labelled;
      const Eigen::Vector2d p = frame.cell_center(c, r);
      outside += !bg::within(Point2(p.x(), p.y()), graph.areas[l].polygon);
    }
  CHECK(outside == 0);
  CHECK((labelled > 0 || graph.areas.empty()));
}

}  // namespace

TEST_CASE("boundary segments satisfy Boost.Polygon's contract on nasty shapes") {
  SUBCASE("touching corners (free cells meeting diagonally)") {
    check_boundary_contract(grid_from_text({"########", "#..#...#", "#..#...#", "###.####", "#..#...#", "#.#.#..#", "########"}));
  }
  SUBCASE("one-pixel walls and holes") {
    check_boundary_contract(grid_from_text({"##########", "#....#...#", "#.##.#.#.#", "#.##.#...#", "#....#.#.#",
                                            "######...#", "#........#", "##########"}));
  }
  SUBCASE("diagonal staircases") {
    std::vector<std::string> rows(40, std::string(40, '.'));
    for (int i = 0; i < 40; ++i) {
      rows[i][i] = '#';
      rows[i][std::min(39, i + 1)] = '#';
      rows[i][39 - i] = '#';
    }
    rows.front().assign(40, '#');
    rows.back().assign(40, '#');
    check_boundary_contract(grid_from_text(rows, 0.05));
  }
  SUBCASE("isolated single pixels and checkerboards") {
    std::vector<std::string> rows(30, std::string(30, '.'));
    for (int r = 5; r < 25; ++r)
      for (int c = 5; c < 25; ++c)
        if ((r + c) % 2 == 0) rows[r][c] = '#';
    rows[2][2] = '#';
    check_boundary_contract(grid_from_text(rows, 0.05));
  }
  SUBCASE("jagged streaks one cell wide (simplified sides cross: repaired)") {
    // Laser streaks: free one-cell paths wandering from a room into the wall mass.
    detail::Random random(11);
    std::vector<std::string> rows(60, std::string(80, '#'));
    for (int r = 2; r < 20; ++r)
      for (int c = 2; c < 78; ++c) rows[r][c] = '.';
    for (int streak = 0; streak < 8; ++streak) {
      int c = 6 + 9 * streak, r = 20;
      for (int step = 0; step < 60 && r < 58; ++step) {
        rows[r][c] = '.';
        if (random.integer(0, 2) == 0) c = std::clamp(c + (random.integer(0, 1) == 0 ? -1 : 1), 2, 77);
        else ++r;
        rows[r][c] = '.';
      }
    }
    CHECK(check_boundary_contract(grid_from_text(rows, 0.05)) > 0);
  }
  SUBCASE("random blobs") {
    detail::Random random(7);
    for (int trial = 0; trial < 20; ++trial) {
      std::vector<std::string> rows(50, std::string(60, '.'));
      for (int k = 0; k < 300; ++k) rows[random.integer(0, 49)][random.integer(0, 59)] = '#';
      check_boundary_contract(grid_from_text(rows, 0.05));
    }
  }
}

#if AREAMATCH_FAST_VORONOI_CIRCLES  // our circle events against Boost's, where they are compiled in
TEST_CASE("corner circle events agree with Boost's own (exact when needed) computation") {
  // detail::endpoint_circle and endpoint_circle_two_points replace Boost's circle events when a
  // point site is an endpoint of a segment site; Boost accepts 64 ulps before it recomputes in
  // multiprecision, so must we.
  using Site = boost::polygon::detail::site_event<int>;
  using Circle = boost::polygon::detail::circle_event<double>;
  using Predicates = boost::polygon::detail::voronoi_predicates<boost::polygon::detail::voronoi_ctype_traits<int>>;
  Predicates::lazy_circle_formation_functor<Site, Circle> boost_formation;
  auto ulps = [](double mine, double theirs) {
    return mine == theirs ? 0.0 : std::abs(mine - theirs) / (std::abs(theirs) * std::numeric_limits<double>::epsilon());
  };
  auto check_close = [&](const Circle& mine, const Circle& theirs, double& worst) {
    worst = std::max({worst, ulps(mine.x(), theirs.x()), ulps(mine.y(), theirs.y()), ulps(mine.lower_x(), theirs.lower_x())});
    CHECK(ulps(mine.x(), theirs.x()) <= 64.0);
    CHECK(ulps(mine.y(), theirs.y()) <= 64.0);
    CHECK(ulps(mine.lower_x(), theirs.lower_x()) <= 64.0);
  };
  detail::Random random(5);
  int point_segment_segment = 0, both_ends = 0, point_point_segment = 0;
  double worst = 0.0;
  for (int trial = 0; trial < 20000; ++trial) {
    const int span = trial % 2 ? 30 : 3000;  // short walls far from the origin are the hard case
    auto coordinate = [&] { return random.integer(0, span); };
    const int px = coordinate(), py = coordinate();
    const Site point(px, py);
    INFO("trial " << trial);
    {  // a point and two segments, the point ending one or both
      Site a(px, py, coordinate(), coordinate());
      const bool shared = random.chance(0.3);
      Site b = shared ? Site(coordinate(), coordinate(), px, py) : Site(coordinate(), coordinate(), coordinate(), coordinate());
      const bool valid = a.point0() != a.point1() && b.point0() != b.point1() &&
                         (shared || (b.point0() != point.point0() && b.point1() != point.point0()));
      if (random.chance(0.5)) std::swap(a, b);  // the point on either segment, either end
      if (random.chance(0.5)) a = Site(a.point1(), a.point0());
      Circle mine, theirs;
      if (valid && detail::endpoint_circle(point, a, b, mine)) {
        boost_formation.pss(point, a, b, 1, theirs);
        ++point_segment_segment;
        both_ends += shared;
        check_close(mine, theirs, worst);
      }
    }
    {  // two points and a segment that one of them ends
      const Site other(coordinate(), coordinate());
      Site segment(px, py, coordinate(), coordinate());
      if (random.chance(0.5)) segment = Site(segment.point1(), segment.point0());
      const bool first = random.chance(0.5);
      const Site& p1 = first ? point : other;
      const Site& p2 = first ? other : point;
      Circle mine, theirs;
      if (other.point0() != point.point0() && segment.point0() != segment.point1() && other.point0() != segment.point0() &&
          other.point0() != segment.point1() && detail::endpoint_circle_two_points(p1, p2, segment, mine)) {
        boost_formation.pps(p1, p2, segment, 3, theirs);
        // Boost's exact recomputation takes the radius as a signed distance, positive on the side
        // the sweep asks about; circles on the other side never arise in a diagram.
        if (theirs.lower_x() >= theirs.x()) {
          ++point_point_segment;
          check_close(mine, theirs, worst);
        }
      }
    }
  }
  MESSAGE("corner circles compared: " << point_segment_segment << " point-segment-segment (" << both_ends
                                      << " at a shared end), " << point_point_segment << " point-point-segment; worst "
                                      << worst << " ulps");
  CHECK(point_segment_segment > 10000);
  CHECK(point_point_segment > 10000);
}

namespace {

/// Counts of the circle events one diagram construction compared, and the worst difference.
struct CircleComparison {
  int point_segment_segment = 0, three_segments = 0, over_64_ulps = 0;
  double worst_ulps = 0.0;
  void record(double ours_x, double ours_y, double ours_lower, double x, double y, double lower) {
    auto ulps = [](double mine, double theirs) {
      return mine == theirs ? 0.0 : std::abs(mine - theirs) / (std::abs(theirs) * std::numeric_limits<double>::epsilon());
    };
    const double u = std::max({ulps(ours_x, x), ulps(ours_y, y), ulps(ours_lower, lower)});
    worst_ulps = std::max(worst_ulps, u);
    over_64_ulps += u > 64.0;
  }
};
CircleComparison* circle_comparison = nullptr;  // the test below sets it around one construction

/// Boost's circle formation, and ours alongside wherever it applies, recorded in `circle_comparison`.
template <class Site, class Circle>
struct ComparingFormation {
  detail::BoostVoronoiPredicates::lazy_circle_formation_functor<Site, Circle> boost_formation;
  void ppp(const Site& a, const Site& b, const Site& c, Circle& circle) { boost_formation.ppp(a, b, c, circle); }
  void pps(const Site& a, const Site& b, const Site& c, int index, Circle& circle) { boost_formation.pps(a, b, c, index, circle); }
  void pss(const Site& a, const Site& b, const Site& c, int index, Circle& circle) {
    boost_formation.pss(a, b, c, index, circle);
    Circle mine;
    if (detail::point_segment_segment_circle(a, b, c, index, mine)) {
      ++circle_comparison->point_segment_segment;
      circle_comparison->record(mine.x(), mine.y(), mine.lower_x(), circle.x(), circle.y(), circle.lower_x());
    }
  }
  void sss(const Site& a, const Site& b, const Site& c, Circle& circle) {
    boost_formation.sss(a, b, c, circle);
    Circle mine;
    if (detail::three_segment_circle(a, b, c, mine)) {
      ++circle_comparison->three_segments;
      circle_comparison->record(mine.x(), mine.y(), mine.lower_x(), circle.x(), circle.y(), circle.lower_x());
    }
  }
};
struct ComparingPredicates : detail::BoostVoronoiPredicates {
  template <class Site, class Circle>
  using circle_formation_predicate = detail::BoostVoronoiPredicates::circle_formation_predicate<
      Site, Circle, detail::BoostVoronoiPredicates::circle_existence_predicate<Site>, ComparingFormation<Site, Circle>>;
};

}  // namespace

TEST_CASE("general circle events agree with Boost's own (exact when needed) on robot maps") {
  // detail::point_segment_segment_circle and three_segment_circle replace Boost's circle events
  // for any point-segment-segment and segment-segment-segment circle whose error bound allows;
  // compared here on every such event that turned, noisy, cluttered robot maps raise.
  CircleComparison comparison;
  circle_comparison = &comparison;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    RobotMapParams rp;
    rp.rotation_rad = 0.37 * seed;
    rp.wall_noise_m = 0.03;
    rp.max_clutter_per_room = 3;
    rp.speckle_per_m2 = 0.05;
    const auto robot = make_robot_map(generate_building(BuildingParams{}, seed), rp, seed);
    const BoundarySegments boundary = trace_boundary(binarize(robot.grid), robot.grid.resolution(), BoundaryParams{});
    boost::polygon::voronoi_builder<int, boost::polygon::detail::voronoi_ctype_traits<int>, ComparingPredicates> builder;
    boost::polygon::insert(boundary.segments.begin(), boundary.segments.end(), &builder);
    boost::polygon::voronoi_diagram<double> diagram;
    builder.construct(&diagram);
  }
  circle_comparison = nullptr;
  MESSAGE("circles compared: " << comparison.point_segment_segment << " point-segment-segment, "
                               << comparison.three_segments << " segment-segment-segment; worst "
                               << comparison.worst_ulps << " ulps");
  CHECK(comparison.over_64_ulps == 0);
  CHECK(comparison.point_segment_segment > 1000);
  CHECK(comparison.three_segments > 1000);
}
#endif  // AREAMATCH_FAST_VORONOI_CIRCLES

namespace {

/// A 4 x 3 m walled room with 5–40 random blocks in it: wall outlines for the Voronoi builder.
OccupancyGrid random_blob_room(detail::Random& random) {
  std::vector<std::string> rows(60, std::string(80, '.'));
  for (int c = 0; c < 80; ++c) rows[0][c] = rows[59][c] = '#';
  for (int r = 0; r < 60; ++r) rows[r][0] = rows[r][79] = '#';
  for (int k = random.integer(5, 40); k > 0; --k) {
    const int r = random.integer(1, 55), c = random.integer(1, 75), h = random.integer(1, 4), w = random.integer(1, 4);
    for (int dr = 0; dr < h; ++dr)
      for (int dc = 0; dc < w; ++dc) rows[r + dr][c + dc] = '#';
  }
  return grid_from_text(rows, 0.05);
}

}  // namespace

TEST_CASE("the Voronoi builder with corner circle events gives Boost's diagram") {
  // The same edges as boost::polygon::construct_voronoi on wall outlines (random rooms with
  // blobs): each edge as its two sites and its end points to a micro-cell. The order may differ
  // (events that tie within Boost's tolerance), the diagram may not.
  using Diagram = boost::polygon::voronoi_diagram<double>;
  using Edge = std::tuple<long long, long long, long long, long long, std::size_t, std::size_t>;
  auto edges_of = [](const Diagram& diagram) {
    auto micro = [](double v) { return std::llround(v * 1e6); };
    auto site = [](const Diagram::cell_type* cell) { return cell->source_index() * 4 + cell->source_category(); };
    std::multiset<Edge> edges;
    for (const auto& e : diagram.edges()) {
      const bool finite = e.is_finite();
      edges.insert({finite ? micro(e.vertex0()->x()) : 0, finite ? micro(e.vertex0()->y()) : 0, finite ? micro(e.vertex1()->x()) : 0,
                    finite ? micro(e.vertex1()->y()) : 0, site(e.cell()), site(e.twin()->cell())});
    }
    return edges;
  };
  detail::Random random(31);
  for (int trial = 0; trial < 30; ++trial) {
    const OccupancyGrid g = random_blob_room(random);
    BoundaryParams params;
    params.simplify_tolerance_m = trial % 3 == 0 ? 0.0 : 0.1;
    const BoundarySegments boundary = trace_boundary(binarize(g), g.resolution(), params);
    Diagram theirs, ours;
    boost::polygon::construct_voronoi(boundary.segments.begin(), boundary.segments.end(), &theirs);
    detail::construct_segment_voronoi(boundary.segments.begin(), boundary.segments.end(), &ours);
    INFO("trial " << trial);
    CHECK(ours.vertices().size() == theirs.vertices().size());
    CHECK(edges_of(ours) == edges_of(theirs));
  }
}

TEST_CASE("the compact Voronoi diagram holds Boost's diagram: the same vertices and edges, in order") {
  // detail::CompactVoronoi merges the ends of degenerate edges in a union-find where Boost walks
  // around the vertex; both are filled by the same builder here, so every number is equal.
  using Diagram = boost::polygon::voronoi_diagram<double>;
  std::size_t removed = 0, edges = 0;
  auto compare = [&](const BoundarySegments& boundary) {
    Diagram theirs;
    detail::CompactVoronoi ours;
    detail::construct_segment_voronoi(boundary.segments.begin(), boundary.segments.end(), &theirs);
    detail::construct_segment_voronoi(boundary.segments.begin(), boundary.segments.end(), &ours);
    removed += ours.removed_edges();
    edges += ours.edges().size();
    REQUIRE(ours.vertices().size() == theirs.vertices().size());
    for (std::size_t i = 0; i < ours.vertices().size(); ++i) {
      CHECK(ours.vertices()[i].x == theirs.vertices()[i].x());
      CHECK(ours.vertices()[i].y == theirs.vertices()[i].y());
    }
    REQUIRE(2 * ours.edges().size() == theirs.edges().size());
    const auto* first_vertex = theirs.vertices().data();
    auto index_of = [&](const Diagram::vertex_type* v) {
      return v ? static_cast<std::uint32_t>(v - first_vertex) : detail::CompactVoronoi::no_vertex;
    };
    for (std::size_t i = 0; i < ours.edges().size(); ++i) {
      const detail::CompactVoronoi::Edge& e = ours.edges()[i];
      const Diagram::edge_type& half = theirs.edges()[2 * i];
      REQUIRE(half.twin() == &theirs.edges()[2 * i + 1]);
      CHECK(e.vertex[0] == index_of(half.vertex0()));
      CHECK(e.vertex[1] == index_of(half.vertex1()));
      CHECK(e.primary == half.is_primary());
      CHECK(e.linear == half.is_linear());
      for (int side = 0; side < 2; ++side) {
        const Diagram::cell_type& cell = *theirs.edges()[2 * i + side].cell();
        const detail::CompactVoronoi::Site& site = ours.sites()[e.site[side]];
        CHECK(site.source_index == cell.source_index());
        CHECK(site.category == cell.source_category());
        CHECK(site.contains_point() == cell.contains_point());
      }
    }
  };
  detail::Random random(7);
  for (int trial = 0; trial < 20; ++trial) {  // random rooms with blobs, simplified or not
    const OccupancyGrid g = random_blob_room(random);
    BoundaryParams params;
    params.simplify_tolerance_m = trial % 2 == 0 ? 0.0 : 0.1;
    compare(trace_boundary(binarize(g), g.resolution(), params));
  }
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {  // turned, noisy, cluttered robot maps
    RobotMapParams rp;
    rp.rotation_rad = 0.41 * static_cast<double>(seed);
    rp.wall_noise_m = 0.03;
    rp.max_clutter_per_room = 3;
    const auto robot = make_robot_map(generate_building(BuildingParams{}, seed), rp, seed);
    compare(trace_boundary(binarize(robot.grid), robot.grid.resolution(), BoundaryParams{}));
  }
  MESSAGE(edges << " edges compared, " << removed << " removed for coinciding ends");
  CHECK(removed > 0);  // the merge of coinciding ends was exercised
}

TEST_CASE("segmentation is the same with Boost's stock Voronoi builder") {
  // SkeletonParams::fast_circle_events off: boost::polygon::construct_voronoi, as on a Boost
  // version the faster circle events are not compiled for (AREAMATCH_FAST_VORONOI_CIRCLES).
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const auto building = generate_building({}, seed);
    RobotMapParams rp;
    rp.rotation_rad = 0.3 * static_cast<double>(seed);
    rp.max_clutter_per_room = 3;
    const RobotMap robot = make_robot_map(building, rp, seed + 10);
    for (const OccupancyGrid* grid : {&building.layout, &robot.grid}) {
      VoronoiSegmenter fast, stock;
      stock.params.skeleton.fast_circle_events = false;
      const AreaGraph a = fast.segment(*grid), b = stock.segment(*grid);
      INFO("seed " << seed);
      CHECK(a.labels == b.labels);
      REQUIRE(a.passages.size() == b.passages.size());
      // Circle events within a few ulps of Boost's: the same passages up to the last bits.
      for (std::size_t i = 0; i < a.passages.size(); ++i) {
        CHECK((a.passages[i].position - b.passages[i].position).norm() < 1e-9);
        CHECK(a.passages[i].width_m == doctest::Approx(b.passages[i].width_m).epsilon(1e-9));
      }
    }
  }
}

TEST_CASE("synthetic buildings: every room is one area, every door one passage near it") {
  const CorridorLayout layouts[] = {CorridorLayout::straight, CorridorLayout::l_shape, CorridorLayout::t_shape,
                                    CorridorLayout::loop};
  std::size_t rooms = 0, rooms_found = 0, doors = 0, doors_found = 0;
  for (CorridorLayout layout : layouts) {
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
      BuildingParams params;
      params.layout = layout;
      params.width_m = 30;
      params.height_m = 22;
      const auto building = generate_building(params, seed);
      const AreaGraph graph = VoronoiSegmenter{}.segment(building.layout);
      INFO("layout " << static_cast<int>(layout) << " seed " << seed);
      check_graph_invariants(graph);
      // Each room: one area holds ≥ 95 % of it and is ≥ 95 % inside it.
      const SegmentationScore score = score_segmentation(graph.labels, building.labels, 1);
      CHECK(score.recall > 0.95);
      for (const auto& area : building.areas) {
        if (area.corridor) continue;
        ++rooms;
        std::map<int, std::size_t> votes;
        std::size_t size = 0;
        for (std::size_t i = 0; i < building.labels.size(); ++i) {
          if (building.labels[i] != area.id) continue;
          ++size;
          if (graph.labels[i] >= 0) ++votes[graph.labels[i]];
        }
        std::size_t best = 0;
        int best_area = -1;
        for (const auto& [a, v] : votes)
          if (v > best) best = v, best_area = a;
        std::size_t best_size = 0;
        for (int l : graph.labels) best_size += l == best_area;
        rooms_found += best >= 0.95 * size && best >= 0.95 * best_size;
      }
      for (const auto& door : building.doors) {
        ++doors;
        std::size_t near = 0;
        for (const auto& p : graph.passages) near += (p.position - door.position).norm() <= 0.3;
        doors_found += near == 1;
      }
    }
  }
  MESSAGE("rooms found as one area: " << rooms_found << "/" << rooms << ", doors with one passage within 0.3 m: "
                                      << doors_found << "/" << doors);
  CHECK(rooms_found == rooms);
  CHECK(doors_found == doors);
}

TEST_CASE("byte scans find and count the same bytes as a plain loop") {
  detail::Random random(8);
  for (int trial = 0; trial < 2000; ++trial) {
    const int n = random.integer(0, 70);
    std::vector<std::uint8_t> row(static_cast<std::size_t>(n) + 1);
    const bool long_runs = trial % 2 == 0;
    for (auto& b : row) b = static_cast<std::uint8_t>(long_runs ? (random.chance(0.05) ? 1 : 0) : random.integer(0, 2));
    const int from = random.integer(0, n), to = random.integer(from, n);
    const auto value = static_cast<std::uint8_t>(random.integer(0, 2));
    int equal = from, not_equal = from;
    while (equal < to && row[equal] != value) ++equal;
    while (not_equal < to && row[not_equal] == value) ++not_equal;
    CHECK(detail::find_byte_equal(row.data(), from, to, value) == equal);
    CHECK(detail::find_byte_not_equal(row.data(), from, to, value) == not_equal);
    CHECK(detail::count_byte_equal(row.data() + from, static_cast<std::size_t>(to - from), value) ==
          static_cast<std::size_t>(std::count(row.begin() + from, row.begin() + to, value)));
  }
}

TEST_CASE("value scans find the same cells as a plain loop, for bytes and 16- and 32-bit labels") {
  // Values near the working labels' states (negative) and region ids, including 0x7FFF and
  // values whose halves look alike, so that a lane test that leaked across lanes would show.
  detail::Random random(18);
  const std::int16_t values16[] = {-4, -3, -2, -1, 0, 1, 255, 256, 0x7FFF, -0x8000};
  auto check = [&](auto sample) {
    using T = decltype(sample);
    for (int trial = 0; trial < 2000; ++trial) {
      const int n = random.integer(0, 70);
      std::vector<T> row(static_cast<std::size_t>(n) + 1);
      const bool long_runs = trial % 2 == 0;
      for (auto& v : row) v = static_cast<T>(values16[long_runs ? (random.chance(0.05) ? 4 : 0) : random.integer(0, 9)]);
      const int from = random.integer(0, n), to = random.integer(from, n);
      const auto value = static_cast<T>(values16[random.integer(0, 9)]);
      int equal = from, not_equal = from;
      while (equal < to && row[equal] != value) ++equal;
      while (not_equal < to && row[not_equal] == value) ++not_equal;
      CHECK(detail::find_value(row.data(), from, to, value, true) == equal);
      CHECK(detail::find_value(row.data(), from, to, value, false) == not_equal);
    }
  };
  check(std::uint8_t{});
  check(std::int16_t{});
  check(std::int32_t{});
}

TEST_CASE("speckles: small blobs go by area, and by size with max_speckle_size_m") {
  // 0.1 m cells. A 4x4 blob (0.16 m^2, 0.4 m across), a 1x3 dot (0.03 m^2) and a free-standing
  // wall 20 cells long (0.2 m^2, 2 m across) in a room.
  std::vector<std::string> rows(16, std::string(30, '.'));
  rows.front() = rows.back() = std::string(30, '#');
  for (auto& row : rows) row.front() = row.back() = '#';
  for (int r = 4; r < 8; ++r) rows[r].replace(5, 4, "####");
  rows[10].replace(5, 3, "###");
  for (int r = 12; r < 14; ++r) rows[r].replace(5, 20, std::string(20, '#'));
  const OccupancyGrid g = grid_from_text(rows);
  auto free_at = [&](const FreeSpace& space, int col, int row) { return space.is_free(col - space.offset_col, row - space.offset_row); };

  const FreeSpace by_area = binarize(g);  // defaults: area only (0.05 m^2)
  CHECK(free_at(by_area, 6, 10));         // the dot is erased
  CHECK_FALSE(free_at(by_area, 6, 5));    // the blob is not
  CHECK_FALSE(free_at(by_area, 10, 12));  // nor the wall

  BinarizeParams by_size;
  by_size.max_speckle_size_m = 0.5;
  const FreeSpace sized = binarize(g, by_size);
  CHECK(free_at(sized, 6, 10));
  CHECK(free_at(sized, 6, 5));            // 0.4 m across: erased
  CHECK_FALSE(free_at(sized, 10, 12));    // 2 m long: a wall, kept
  CHECK_FALSE(free_at(sized, 0, 5));      // the outer walls touch the border: kept

  by_size.max_speckle_size_m = -0.1;
  CHECK_THROWS_AS(binarize(g, by_size), parameter_error);
}

TEST_CASE("binarize: unknown cells are obstacles unless unknown_is_free; the mask is the free cells' box") {
  // 0.1 m cells: a room of free cells (rows 2-9), an unknown band beside it (rows 2-9, columns
  // 40-59, more than 32 cells wide so the band spans a whole block of the row kernel), walls.
  std::vector<std::string> rows(12, std::string(64, '#'));
  for (int r = 2; r < 10; ++r) {
    rows[r].replace(2, 38, std::string(38, '.'));
    rows[r].replace(40, 20, std::string(20, '?'));
  }
  const OccupancyGrid g = grid_from_text(rows);
  BinarizeParams keep_everything;
  keep_everything.max_speckle_area_m2 = 0.0;
  keep_everything.min_free_area_m2 = 0.0;
  const FreeSpace known = binarize(g, keep_everything);
  CHECK(known.offset_col == 1);
  CHECK(known.offset_row == 1);
  CHECK(known.width == 38 + 2);
  CHECK(known.height == 8 + 2);
  CHECK(known.count() == 38u * 8u);
  keep_everything.unknown_is_free = true;
  const FreeSpace with_unknown = binarize(g, keep_everything);
  CHECK(with_unknown.width == 58 + 2);
  CHECK(with_unknown.count() == 58u * 8u);
  CHECK(with_unknown.is_free(59 - with_unknown.offset_col, 9 - with_unknown.offset_row));
  CHECK_FALSE(with_unknown.is_free(60 - with_unknown.offset_col, 9 - with_unknown.offset_row));
}

TEST_CASE("erode_mask keeps the cells with no outside cell closer than the distance") {
  // Masks that touch the grid's edges, rows with nothing in them, and rows wider than the
  // 8-byte steps of the row scans.
  detail::Random random(91);
  // The last trials are taller than a band of rows (`erosion_band_rows`), so bands meet.
  for (int trial = 0; trial < 46; ++trial) {
    const int W = trial < 40 ? random.integer(1, 70) : random.integer(1, 12);
    const int H = trial < 40 ? random.integer(1, 30) : random.integer(detail::erosion_band_rows, 3 * detail::erosion_band_rows);
    std::vector<std::uint8_t> mask(static_cast<std::size_t>(W) * H, 0);
    const double density = random.uniform(0.5, 1.0);
    for (int r = 0; r < H; ++r) {
      if (random.chance(0.2)) continue;  // an empty row
      const int from = random.integer(0, W - 1), to = random.integer(from + 1, W);
      for (int c = from; c < to; ++c) mask[static_cast<std::size_t>(r) * W + c] = random.chance(density);
    }
    for (double distance : {0.5, 1.0, 1.5, 2.0, 2.3, 4.5, 5.0}) {
      const std::vector<std::uint8_t> core = detail::erode_mask(mask, W, H, distance);
      const int reach = static_cast<int>(std::ceil(distance));
      for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c) {
          bool expected = mask[static_cast<std::size_t>(r) * W + c] != 0;
          for (int dr = -reach; dr <= reach && expected; ++dr)
            for (int dc = -reach; dc <= reach && expected; ++dc) {
              if (dc * dc + dr * dr >= distance * distance) continue;
              const int cc = c + dc, rr = r + dr;
              expected = cc >= 0 && rr >= 0 && cc < W && rr < H && mask[static_cast<std::size_t>(rr) * W + cc] != 0;
            }
          INFO("trial " << trial << " (" << W << "x" << H << ") distance " << distance << " cell " << c << "," << r);
          CHECK((core[static_cast<std::size_t>(r) * W + c] != 0) == expected);
        }
    }
  }
}

TEST_CASE("open_free_space is the opening by a disc, on its fast path and its general one") {
  detail::Random random(77);
  for (int trial = 0; trial < 20; ++trial) {
    FreeSpace space;
    space.width = random.integer(3, 40);
    space.height = random.integer(3, 40);
    space.free.assign(static_cast<std::size_t>(space.width) * space.height, 0);
    for (int r = 1; r + 1 < space.height; ++r)  // free cells never on the border
      for (int c = 1; c + 1 < space.width; ++c) space.free[static_cast<std::size_t>(r) * space.width + c] = random.chance(0.8);
    for (double radius : {0.5, 1.0, 1.2, 1.5, 2.3}) {
      // By definition: a disc centred on a cell fits when every cell within `radius` of it
      // (centre to centre) is free; the opening keeps the free cells some fitting disc covers.
      const int reach = static_cast<int>(std::ceil(radius));
      auto within = [&](int dc, int dr) { return dc * dc + dr * dr <= radius * radius; };
      auto fits = [&](int c, int r) {
        for (int dr = -reach; dr <= reach; ++dr)
          for (int dc = -reach; dc <= reach; ++dc)
            if (within(dc, dr) && !space.is_free(c + dc, r + dr)) return false;
        return true;
      };
      const FreeSpace opened = open_free_space(space, radius);
      for (int r = 0; r < space.height; ++r)
        for (int c = 0; c < space.width; ++c) {
          bool covered = false;
          for (int dr = -reach; dr <= reach && !covered; ++dr)
            for (int dc = -reach; dc <= reach && !covered; ++dc) covered = within(dc, dr) && fits(c + dc, r + dr);
          INFO("trial " << trial << " radius " << radius << " cell " << c << "," << r);
          CHECK(opened.is_free(c, r) == (space.is_free(c, r) && covered));
        }
    }
  }
}

TEST_CASE("min_traced_width_m keeps laser streaks out of the Voronoi input, not out of the map") {
  // A 4 x 3 m room (0.05 m cells) with a door-free wall pierced by thin streaks into the unknown.
  std::vector<std::string> rows(70, std::string(120, '?'));
  for (int r = 5; r < 67; ++r) rows[r].replace(5, 82, "#" + std::string(80, '.') + "#");
  rows[5].replace(5, 82, std::string(82, '#'));
  rows[66].replace(5, 82, std::string(82, '#'));
  for (int k = 0; k < 8; ++k) {  // one-cell streaks out through the right wall, 10 to 17 cells long
    const int r = 10 + 6 * k;
    for (int c = 86; c < 87 + 10 + k; ++c) rows.at(r).at(c) = '.';
  }
  const OccupancyGrid g = grid_from_text(rows, 0.05);
  VoronoiSegmenter plain, filtered;
  filtered.params.boundary.min_traced_width_m = 0.1;
  const auto a = plain.segment_with_details(g), b = filtered.segment_with_details(g);
  CHECK(b.boundary_segments < a.boundary_segments);
  REQUIRE(a.graph.areas.size() == 1);
  REQUIRE(b.graph.areas.size() == 1);
  CHECK(b.graph.areas[0].size_m2 == doctest::Approx(a.graph.areas[0].size_m2).epsilon(0.01));
  check_graph_invariants(b.graph);
  filtered.params.boundary.min_traced_width_m = -0.1;
  CHECK_THROWS_AS(filtered.segment(g), parameter_error);
}

TEST_CASE("a door exactly as wide as the door width is a passage") {
  // The door width is the widest opening that still separates: drawn at exactly W on the grid,
  // a door measures up to one cell more, which the parameter's slack absorbs.
  for (double door : {0.8, 0.9, 1.0}) {
    for (double resolution : {0.04, 0.05}) {
      BuildingParams params;
      params.door_width_m = door;
      params.resolution = resolution;
      const auto building = generate_building(params, 3);
      VoronoiSegmenter segmenter;
      segmenter.params.with_door_width(door);
      const AreaGraph graph = segmenter.segment(building.layout);
      INFO("door " << door << " m, cells " << resolution << " m");
      std::size_t found = 0;
      for (const auto& d : building.doors) {
        for (const auto& p : graph.passages) found += (p.position - d.position).norm() <= 0.3;
      }
      CHECK(found == building.doors.size());
    }
  }
}

TEST_CASE("robot maps with furniture and noise: rooms still found (tolerance 10 %)") {
  std::size_t rooms = 0, rooms_found = 0;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const auto building = generate_building(BuildingParams{}, seed);
    RobotMapParams rp;
    rp.rotation_rad = 0.4 * seed;
    rp.wall_noise_m = 0.03;
    rp.max_clutter_per_room = 2;
    rp.speckle_per_m2 = 0.02;
    const auto robot = make_robot_map(building, rp, seed);
    const AreaGraph graph = VoronoiSegmenter{}.segment(robot.grid);
    check_graph_invariants(graph);
    // Map each room's centre into the robot map: the area there must be mostly that room.
    for (const auto& area : building.areas) {
      if (area.corridor) continue;
      ++rooms;
      Point2 centre(0.0, 0.0);
      bg::centroid(area.polygon, centre);
      const Eigen::Vector2d p = robot.T_dest_source.inverse() * to_vector(centre);
      const Eigen::Vector2i cell = robot.grid.world_to_cell(p);
      if (!robot.grid.contains(cell.x(), cell.y())) continue;
      const int label = graph.labels[robot.grid.index(cell.x(), cell.y())];
      if (label < 0) continue;
      const double ratio = graph.areas[label].size_m2 / area.size_m2;
      rooms_found += ratio > 0.6 && ratio < 1.25;
    }
  }
  MESSAGE("rooms found in robot maps: " << rooms_found << "/" << rooms);
  CHECK(rooms_found >= 0.9 * rooms);
}

TEST_CASE("with split_at_junctions, corridors are split where they meet, as in the paper") {
  for (std::uint64_t seed : {2u, 3u}) {
    BuildingParams params;
    params.layout = CorridorLayout::t_shape;
    params.width_m = 30;
    params.height_m = 22;
    const auto building = generate_building(params, seed);
    VoronoiSegmenter segmenter;
    segmenter.params.rooms.split_at_junctions = true;
    const AreaGraph graph = segmenter.segment(building.layout);
    check_graph_invariants(graph);
    // The corridor system (ground-truth area 0) is now at least three areas, each a real share.
    std::map<int, std::size_t> pieces;
    std::size_t corridor_cells = 0;
    for (std::size_t i = 0; i < building.labels.size(); ++i) {
      if (building.labels[i] != 0) continue;
      ++corridor_cells;
      if (graph.labels[i] >= 0) ++pieces[graph.labels[i]];
    }
    int big_pieces = 0;
    for (const auto& [area, cells] : pieces) big_pieces += cells >= 0.1 * corridor_cells;
    CHECK(big_pieces >= 3);
    // …joined by junction passages at one point.
    std::vector<Eigen::Vector2d> junctions;
    for (const auto& p : graph.passages)
      if (p.kind == PassageKind::junction) junctions.push_back(p.position);
    REQUIRE(junctions.size() >= 2);
    for (const auto& j : junctions) CHECK((j - junctions.front()).norm() < 1e-9);
    // Rooms are untouched: the same rooms are found as without splitting.
    CHECK(score_segmentation(graph.labels, building.labels, 1).recall > 0.9);
  }
  // Off (the default), the corridor system stays one area.
  BuildingParams params;
  params.layout = CorridorLayout::t_shape;
  const auto building = generate_building(params, 2);
  for (const auto& p : VoronoiSegmenter{}.segment(building.layout).passages) CHECK(p.kind == PassageKind::door);
}

TEST_CASE("segmentation is deterministic") {
  const auto building = generate_building(BuildingParams{}, 11);
  RobotMapParams rp;
  rp.rotation_rad = 0.7;
  rp.wall_noise_m = 0.03;
  rp.max_clutter_per_room = 3;
  const auto robot = make_robot_map(building, rp, 11);
  const AreaGraph a = VoronoiSegmenter{}.segment(robot.grid);
  const AreaGraph b = VoronoiSegmenter{}.segment(robot.grid);
  CHECK(a.labels == b.labels);
  REQUIRE(a.passages.size() == b.passages.size());
  for (std::size_t i = 0; i < a.passages.size(); ++i) {
    CHECK(a.passages[i].position == b.passages[i].position);
    CHECK(a.passages[i].width_m == b.passages[i].width_m);
  }
}

TEST_CASE("degenerate maps give an empty graph or one area, never a crash") {
  const VoronoiSegmenter segmenter;
  const AreaGraph tiny = segmenter.segment(OccupancyGrid(1, 1, 0.05, {}, CellState::free));
  CHECK(tiny.areas.empty());
  CHECK(tiny.reason.find("only specks") != std::string::npos);  // one cell is below the crumb size
  CHECK(segmenter.segment(OccupancyGrid(1, 1, 0.05, {}, CellState::occupied)).areas.empty());
  const AreaGraph walls = segmenter.segment(OccupancyGrid(50, 40, 0.05, {}, CellState::occupied));
  CHECK(walls.areas.empty());
  CHECK(walls.reason == "the map has no free cells");
  CHECK(segmenter.segment(OccupancyGrid(50, 40, 0.05, {}, CellState::unknown)).areas.empty());
  // All free: one area, the whole map.
  const AreaGraph all_free = segmenter.segment(OccupancyGrid(60, 40, 0.05, {}, CellState::free));
  REQUIRE(all_free.areas.size() == 1);
  CHECK(all_free.reason.empty());
  CHECK(all_free.areas[0].size_m2 == doctest::Approx(60 * 40 * 0.05 * 0.05));
  CHECK(all_free.covered_fraction == doctest::Approx(1.0));
  // Free space too thin to pass (one-cell corridors): no areas.
  std::vector<std::string> rows(20, std::string(140, '#'));
  for (int r = 2; r < 18; r += 2) rows[r].replace(1, 138, std::string(138, '.'));
  const AreaGraph thin = segmenter.segment(grid_from_text(rows, 0.05));
  CHECK(thin.areas.empty());
  CHECK(thin.reason.find("wide enough to pass") != std::string::npos);
  // Bad parameters are named.
  VoronoiSegmenter bad;
  bad.params.rooms.door_width_m = -1.0;
  CHECK_THROWS_WITH_AS(bad.segment(OccupancyGrid(10, 10, 0.05, {}, CellState::free)), doctest::Contains("door width"),
                       parameter_error);
}

TEST_CASE("random maps never crash and always give valid polygons") {
  detail::Random random(2024);
  const VoronoiSegmenter segmenter;
  for (int trial = 0, trials = areamatch_test::quick_tests() ? 25 : 200; trial < trials; ++trial) {
    const int w = random.integer(20, 90), h = random.integer(20, 90);
    OccupancyGrid g(w, h, 0.05, {}, CellState::free);
    for (int k = random.integer(0, 12); k > 0; --k) {  // random walls
      const bool horizontal = random.chance(0.5);
      const int at = random.integer(0, horizontal ? h - 1 : w - 1);
      const int from = random.integer(0, horizontal ? w - 1 : h - 1), length = random.integer(1, 60);
      for (int i = from; i < std::min(from + length, horizontal ? w : h); ++i)
        g.set(horizontal ? i : at, horizontal ? at : i, CellState::occupied);
    }
    for (int k = random.integer(0, 30); k > 0; --k) {  // blobs and unknown patches
      const int c = random.integer(0, w - 1), r = random.integer(0, h - 1), s = random.integer(0, 4);
      const CellState state = random.chance(0.3) ? CellState::unknown : CellState::occupied;
      for (int dr = 0; dr <= s; ++dr)
        for (int dc = 0; dc <= s; ++dc)
          if (g.contains(c + dc, r + dr)) g.set(c + dc, r + dr, state);
    }
    INFO("trial " << trial);
    AreaGraph graph;
    CHECK_NOTHROW(graph = segmenter.segment(g));
    check_graph_invariants(graph);
  }
}

TEST_CASE("cross-modal consistency: a robot map and its layout segment alike") {
  // Identical label images under the identity transform agree perfectly; shifted far, not at all.
  std::vector<int> labels(100 * 40, -1);
  for (int r = 0; r < 40; ++r)
    for (int c = 0; c < 100; ++c) labels[static_cast<std::size_t>(r) * 100 + c] = c / 25;  // four 25 × 40 areas
  PixelTransform identity;
  identity << 1, 0, 0, 0, 1, 0;
  CHECK(segmentation_consistency(labels, 100, 40, labels, 100, 40, identity) == doctest::Approx(1.0));
  PixelTransform shifted = identity;
  shifted(0, 2) = 13.0;  // more than half an area's width: IoU of the best match < 0.5
  CHECK(segmentation_consistency(labels, 100, 40, labels, 100, 40, shifted) == doctest::Approx(0.0));

  // A turned, noisy, furnished robot map and its layout, through the generator's ground truth.
  const auto building = generate_building(BuildingParams{}, 6);
  RobotMapParams rp;
  rp.rotation_rad = 2.1;
  rp.resolution = 0.04;
  rp.wall_noise_m = 0.03;
  rp.max_clutter_per_room = 2;
  const auto robot = make_robot_map(building, rp, 6);
  const AreaGraph source = VoronoiSegmenter{}.segment(robot.grid);
  const AreaGraph dest = VoronoiSegmenter{}.segment(building.layout);
  const double share = segmentation_consistency(source.labels, robot.grid.width(), robot.grid.height(), dest.labels,
                                                building.layout.width(), building.layout.height(), robot.pixel_transform);
  MESSAGE("synthetic robot map vs layout consistency: " << share);
  CHECK(share >= 0.9);
}

TEST_CASE("room scores agree with the definition of segscore.py") {
  // Rooms 0 and 1 of 300 cells. Area 0 covers room 0 and half of room 1; area 1 the other half
  // of room 1 and 100 cells outside every room; area 2 (50 cells) is too small to count.
  std::vector<int> rooms(900, -1), labels(900, -1);
  for (int i = 0; i < 300; ++i) rooms[i] = 0;
  for (int i = 300; i < 600; ++i) rooms[i] = 1;
  for (int i = 0; i < 450; ++i) labels[i] = 0;
  for (int i = 450; i < 700; ++i) labels[i] = 1;
  for (int i = 700; i < 750; ++i) labels[i] = 2;
  const SegmentationScore s = score_segmentation(labels, rooms);
  CHECK(s.rooms == 2);
  CHECK(s.areas == 2);
  CHECK(s.recall == doctest::Approx((1.0 + 0.5) / 2));
  CHECK(s.precision == doctest::Approx((300.0 / 450 + 150.0 / 250) / 2));
}

TEST_CASE("the free end of a pruned spur joins the region its spur led into") {
  std::size_t lone_nodes = 0;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    RobotMapParams rp;
    rp.wall_noise_m = 0.03;
    rp.max_clutter_per_room = 2;
    const auto robot = make_robot_map(generate_building(BuildingParams{}, seed), rp, seed);
    const SegmentationDetails d = VoronoiSegmenter{}.segment_with_details(robot.grid);
    // Lone nodes: every branch pruned. Each takes a region some of its pruned branches' other
    // ends (or theirs, in turn) have; no region is made of one lone sample.
    std::vector<int> samples_of_region(d.rooms.region_count(), 0);
    for (int region : d.rooms.region_of_sample) {
      REQUIRE(region >= 0);
      ++samples_of_region[region];
    }
    for (std::size_t j = 0; j < d.skeleton.nodes.size(); ++j) {
      if (d.skeleton.degree(static_cast<int>(j)) != 0) continue;
      ++lone_nodes;
      CHECK(samples_of_region[d.rooms.region_of_sample[j]] > 1);
    }
  }
  MESSAGE("lone nodes: " << lone_nodes);
  CHECK(lone_nodes > 0);  // the case is exercised
}

TEST_CASE("parameters the segmenter derives from another stage are refused, not silently ignored") {
  const auto building = generate_building({}, 3);
  VoronoiSegmenter derived_keep;
  derived_keep.params.skeleton.keep_clearance_m = 1.0;  // VoronoiSegmenter sets it from the door width
  CHECK_THROWS_WITH_AS(derived_keep.segment(building.layout), doctest::Contains("door width"), parameter_error);
  VoronoiSegmenter derived_clearance;
  derived_clearance.params.areas.min_clearance_m = 0.4;  // ... and this from SkeletonParams::min_clearance_m
  CHECK_THROWS_WITH_AS(derived_clearance.segment(building.layout), doctest::Contains("SkeletonParams::min_clearance_m"),
                       parameter_error);
  VoronoiSegmenter agreeing;  // set to what the segmenter derives: accepted, the same graph
  agreeing.params.skeleton.min_clearance_m = 0.3;
  agreeing.params.areas.min_clearance_m = 0.3;
  VoronoiSegmenter skeleton_only;
  skeleton_only.params.skeleton.min_clearance_m = 0.3;
  CHECK(agreeing.segment(building.layout).areas.size() == skeleton_only.segment(building.layout).areas.size());
}

TEST_CASE("label images: runs in chunks, read and written like a plain array of ints") {
  LabelImage labels(6, -1);
  CHECK(labels.size() == 6);
  labels.fill(1, 3, 7);
  labels.set(5, 32767);
  labels.set(4, 40000);
  CHECK(labels.to_vector() == std::vector<int>{-1, 7, 7, -1, 40000, 32767});
  std::vector<int> read;
  for (int label : labels) read.push_back(label);
  CHECK(read == labels.to_vector());
  CHECK_THROWS_AS(labels.fill(2, 7, 0), std::out_of_range);

  const LabelImage a{-1, 0, 2}, b(std::vector<int>{-1, 0, 2});
  LabelImage rewritten = a;
  rewritten.assign(3, 0);
  rewritten.set(0, -1);
  rewritten.set(2, 2);
  CHECK(a == b);
  CHECK(a == rewritten);  // equal by value, however it was written
  CHECK(a != LabelImage{-1, 0, 3});
  CHECK(a != LabelImage{-1, 0});
  CHECK(LabelImage().empty());
  CHECK(LabelImage().begin() == LabelImage().end());
  LabelImage counted;
  counted.assign(5, 3);  // a count and a value, not an iterator pair
  CHECK(counted.to_vector() == std::vector<int>(5, 3));

  // Random writes across chunk borders against a plain array; the image stays canonical (equal
  // to one built from the array) and its runs are the array's.
  std::mt19937 random(11);
  for (const std::size_t size : {std::size_t{1}, std::size_t{63}, std::size_t{64}, std::size_t{65}, std::size_t{1000}}) {
    std::vector<int> plain(size, -1);
    LabelImage image(size, -1);
    for (int step = 0; step < 300; ++step) {
      std::size_t first = random() % size, last = random() % (size + 1);
      if (first > last) std::swap(first, last);
      if (step % 3 == 0) last = std::min(size, first + 1);
      const int value = static_cast<int>(random() % 5) - 1;
      std::fill(plain.begin() + static_cast<std::ptrdiff_t>(first), plain.begin() + static_cast<std::ptrdiff_t>(last), value);
      image.fill(first, last, value);
      if (step % 50 == 0 || step == 299) {
        REQUIRE(image.to_vector() == plain);
        CHECK(image == LabelImage(plain));
        for (std::size_t i = 0; i < size; ++i) REQUIRE(image[i] == plain[i]);
        std::vector<int> from_runs;
        std::size_t previous_end = 0;
        int previous_label = 0;
        image.for_each_run([&](std::size_t begin, std::size_t end, int label) {
          CHECK(begin == previous_end);
          CHECK((begin == 0 || label != previous_label));  // stretches as long as they can be
          from_runs.insert(from_runs.end(), end - begin, label);
          previous_end = end;
          previous_label = label;
        });
        CHECK(from_runs == plain);
        const std::size_t from = size / 3, to = size - size / 4;
        std::vector<int> part;
        image.for_each_run(from, to, [&](std::size_t begin, std::size_t end, int label) { part.insert(part.end(), end - begin, label); });
        CHECK(part == std::vector<int>(plain.begin() + static_cast<std::ptrdiff_t>(from), plain.begin() + static_cast<std::ptrdiff_t>(to)));
      }
    }
    LabelImage appended;
    for (std::size_t i = 0; i < size;) {
      std::size_t end = i + 1;
      while (end < size && plain[end] == plain[i]) ++end;
      appended.append(end - i, plain[i]);
      i = end;
    }
    CHECK(appended == image);
  }
}

TEST_CASE("a segmentation's labels take a small part of a byte a cell, the same with its details or without") {
  const auto building = generate_building({}, 3);
  const VoronoiSegmenter segmenter;
  const AreaGraph graph = segmenter.segment(building.layout);
  REQUIRE(!graph.areas.empty());
  CHECK(graph.labels.size() == building.layout.cells().size());
  CHECK(graph.labels.memory_bytes() < graph.labels.size() / 4);
  CHECK(graph.labels == segmenter.segment_with_details(building.layout).graph.labels);
  CHECK_FALSE(segmenter.segment_with_details(building.layout).skeleton.branches.empty());
}

TEST_CASE("the skeleton's samples: one array in branch order; rooms found the same when the graph takes them over") {
  const auto building = generate_building({}, 5);
  const double res = building.layout.resolution();
  const FreeSpace space = binarize(building.layout);
  const BoundarySegments boundary = trace_boundary(space, res);
  Skeleton skeleton = build_skeleton(space, boundary, res);
  REQUIRE(skeleton.branches.size() > 10);
  std::size_t next = 0;
  for (const SkeletonBranch& branch : skeleton.branches) {
    CHECK(branch.first_sample == next);  // branch after branch, no gaps
    CHECK(branch.sample_count >= 2);
    next += branch.sample_count;
    double length = 0.0;
    const SkeletonSamples samples = skeleton.samples_of(branch);
    for (std::size_t i = 1; i < samples.size(); ++i) length += (samples[i].position - samples[i - 1].position).norm();
    CHECK(length == branch.length);
  }
  CHECK(next == skeleton.samples.size());

  const RoomParams params;
  const RoomDetection copied = detect_rooms(skeleton, res, params);
  const std::size_t node_count = skeleton.nodes.size();
  const RoomDetection taken = detail::detect_rooms_taking_samples(skeleton, res, params);
  CHECK(skeleton.samples.empty());
  CHECK(skeleton.nodes.size() == node_count);
  for (const SkeletonBranch& branch : skeleton.branches) CHECK(skeleton.samples_of(branch).empty());
  REQUIRE(taken.graph.samples.size() == copied.graph.samples.size());
  for (std::size_t s = 0; s < copied.graph.samples.size(); ++s) {
    const SkeletonSample& a = copied.graph.samples[s];
    const SkeletonSample& b = taken.graph.samples[s];
    CHECK(a.position == b.position);
    CHECK(a.clearance == b.clearance);
    CHECK(a.foot_a == b.foot_a);
    CHECK(a.foot_b == b.foot_b);
    const auto na = copied.graph.neighbours(static_cast<int>(s)), nb = taken.graph.neighbours(static_cast<int>(s));
    CHECK(std::vector<int>(na.begin(), na.end()) == std::vector<int>(nb.begin(), nb.end()));
  }
  CHECK(taken.region_of_sample == copied.region_of_sample);
  CHECK(taken.region_is_room == copied.region_is_room);
  REQUIRE(taken.passages.size() == copied.passages.size());
  for (std::size_t p = 0; p < copied.passages.size(); ++p) {
    CHECK(taken.passages[p].sample == copied.passages[p].sample);
    CHECK(taken.passages[p].line_a == copied.passages[p].line_a);
    CHECK(taken.passages[p].line_b == copied.passages[p].line_b);
  }
}

TEST_CASE("free space held as its runs: the same cells, and the same skeleton as from the mask") {
  detail::Random random(48);
  for (int trial = 0; trial < 200; ++trial) {
    const int W = random.integer(1, 40), H = random.integer(1, 20);
    std::vector<std::uint8_t> mask(static_cast<std::size_t>(W) * H);
    for (auto& cell : mask) cell = static_cast<std::uint8_t>(random.chance(0.6) ? random.integer(1, 3) : 0);
    const detail::RowRuns runs = detail::nonzero_runs(mask, W, H);
    std::size_t cells = 0;
    for (const detail::CellRun& run : runs.runs) {
      CHECK(run.begin < run.end);
      cells += static_cast<std::size_t>(run.end - run.begin);
    }
    CHECK(cells == static_cast<std::size_t>(std::count_if(mask.begin(), mask.end(), [](std::uint8_t b) { return b != 0; })));
    for (int r = -1; r <= H; ++r)
      for (int c = -1; c <= W; ++c) {
        const bool inside = c >= 0 && r >= 0 && c < W && r < H && mask[static_cast<std::size_t>(r) * W + c] != 0;
        CHECK(runs.contains(c, r) == inside);
      }
  }
  // The segmenter builds its skeleton from the runs once the boundary is traced.
  RobotMapParams rp;
  rp.rotation_rad = 0.7;
  rp.max_clutter_per_room = 2;
  const auto robot = make_robot_map(generate_building(BuildingParams{}, 6), rp, 6);
  const double res = robot.grid.resolution();
  const FreeSpace space = binarize(robot.grid);
  const BoundarySegments boundary = trace_boundary(space, res);
  const detail::RowRuns runs = detail::nonzero_runs(space.free, space.width, space.height);
  const Skeleton from_mask = build_skeleton(space, boundary, res);
  const Skeleton from_runs = detail::skeleton_of([&](int c, int r) { return runs.contains(c, r); },
                                                 Eigen::Vector2d(space.offset_col, space.offset_row), boundary, res, {});
  REQUIRE(from_mask.samples.size() > 100);
  REQUIRE(from_runs.samples.size() == from_mask.samples.size());
  for (std::size_t s = 0; s < from_mask.samples.size(); ++s) CHECK(from_runs.samples[s].position == from_mask.samples[s].position);
  CHECK(from_runs.branches.size() == from_mask.branches.size());
  CHECK(from_runs.voronoi_edges == from_mask.voronoi_edges);
}
