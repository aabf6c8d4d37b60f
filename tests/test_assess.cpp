// Map assessment (assess.hpp): generated robot maps whose exact truth is known — bends, broken
// pieces, explored share — assessed against their layouts; refusals and bad parameters.
#include <areamatch/areamatch.hpp>
#include <areamatch/synthetic.hpp>
#include <areamatch/io/json.hpp>
#include <doctest/doctest.h>
#include "synthetic_cases.hpp"
#include "test_support.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

using namespace areamatch;

namespace {

struct AssessCase {
  SyntheticBuilding building;
  RobotMap robot;
  AreaGraph map_graph, reference_graph;
  MatchResult match;
};

/// A building and its robot map, each segmented, the map matched onto the building's layout.
AssessCase assess_case(SyntheticBuilding building, RobotMap robot) {
  AssessCase c{std::move(building), std::move(robot), {}, {}, {}};
  const Matcher<> matcher;
  c.map_graph = matcher.segmenter.segment(c.robot.grid);
  c.reference_graph = matcher.segmenter.segment(c.building.layout);
  c.match = matcher.match(c.robot.grid, c.map_graph, c.building.layout, c.reference_graph);
  return c;
}

AssessCase assess_case(std::uint64_t seed, const RobotMapParams& rp) {
  SyntheticBuilding building = generate_building({}, seed);
  RobotMap robot = make_robot_map(building, rp, seed + 1);
  return assess_case(std::move(building), std::move(robot));
}

/// Pair `index` of `areamatch_assess_generated 60 FIRST_SEED` (tools/assess_generated.cpp): its case,
/// assessed as the layout's building (a broken map may be rejected).
std::pair<AssessCase, MapAssessment> assess_distorted(std::uint64_t first_seed, int index) {
  areamatch_test::DistortedCase pair = areamatch_test::distorted_case(first_seed, index);
  AssessCase c = assess_case(std::move(pair.building), std::move(pair.robot));
  AssessParams params;
  params.assume_same_building = true;
  MapAssessment a = assess_match(c.robot.grid, c.map_graph, c.building.layout, c.reference_graph, c.match, params);
  return {std::move(c), std::move(a)};
}

/// The 95th percentile of the warp's error at the map's wall points, against the generator's truth.
double warp_error_p95(const AssessCase& c, const MapAssessment& a) {
  std::vector<double> errors;
  for (const Eigen::Vector2d& p : detail::wall_points(c.robot.grid, 0.1)) errors.push_back((a.warp.field.apply(p) - c.robot.true_dest(p)).norm());
  std::sort(errors.begin(), errors.end());
  return errors.empty() ? 0.0 : errors[errors.size() * 95 / 100];
}

RobotMapParams plain_robot(double rotation_rad) {
  RobotMapParams rp;
  rp.rotation_rad = rotation_rad;
  rp.wall_noise_m = 0.02;
  rp.max_clutter_per_room = 2;
  return rp;
}

}  // namespace

TEST_CASE("an undistorted generated map: walls in place both ways, one piece, coverage and topology as built") {
  RobotMapParams rp = plain_robot(0.7);
  rp.explored_fraction = 0.6;
  const AssessCase c = assess_case(1201, rp);
  REQUIRE(c.match.ok);
  const MapAssessment a = assess_match(c.robot.grid, c.map_graph, c.building.layout, c.reference_graph, c.match);
  REQUIRE(a.ok);
  CHECK_FALSE(a.decision_overridden);
  CHECK(a.rigid_walls.map_to_reference.median_m < 0.05);
  CHECK(a.rigid_walls.reference_to_map.median_m < 0.05);
  CHECK(a.rigid_walls.reference_to_map.within_tolerance > 0.9);
  CHECK(a.warp.median_displacement_m < 0.05);
  CHECK(a.brokenness.pieces.size() == 1);
  CHECK(a.brokenness.broken_pieces() == 0);
  CHECK(a.area_displacement.size() == c.map_graph.areas.size());
  // 60 % of the rooms explored (and the corridors): clearly less than all, clearly more than half the rooms' share.
  CHECK(a.coverage.explored_share > 0.4);
  CHECK(a.coverage.explored_share < 0.95);
  CHECK(a.coverage.found + a.coverage.partly_found + a.coverage.missed == c.reference_graph.areas.size());
  CHECK(a.coverage.missed > 0);
  CHECK(a.topology.map_passages > 0);
  CHECK(a.topology.share() > 0.8);
  // Each reference area the robot entered is found; each it never entered is not.
  const Similarity2 back = c.robot.T_dest_source.inverse();
  for (const auto& r : a.coverage.reference_areas) {
    if (r.state != AreaFound::found) continue;
    const Eigen::Vector2i cell = c.robot.grid.world_to_cell(back * c.reference_graph.areas[static_cast<std::size_t>(r.area)].centroid);
    if (c.robot.grid.contains(cell.x(), cell.y())) CHECK(c.robot.grid.at(cell.x(), cell.y()) != CellState::unknown);
  }
}

TEST_CASE("a broken generated map: the broken piece is found with its turn") {
  const int cases = areamatch_test::quick_tests() ? 1 : 3;
  for (int i = 0; i < cases; ++i) {
    RobotMapParams rp = plain_robot(0.4 + 1.3 * i);
    rp.break_count = 1;
    rp.break_min_rotation_rad = rp.break_max_rotation_rad = (4.0 + 2.0 * i) * pi / 180.0;
    const AssessCase c = assess_case(1300 + static_cast<std::uint64_t>(i), rp);
    REQUIRE(c.robot.breaks.size() == 1);
    AssessParams params;
    params.assume_same_building = true;  // a broken map may be rejected; it is this building
    const MapAssessment a = assess_match(c.robot.grid, c.map_graph, c.building.layout, c.reference_graph, c.match, params);
    REQUIRE(a.ok);
    REQUIRE(a.brokenness.pieces.size() == 2);
    const double true_turn = std::abs(c.robot.breaks.front().motion.rotation);
    CHECK(std::abs(std::abs(a.brokenness.pieces[1].rotation_rad) - true_turn) < 0.5 * pi / 180.0);
    // The pieces lie on either side of the cut.
    const Eigen::Vector2d& normal = c.robot.breaks.front().normal;
    const auto side_of = [&](const RigidPiece& p) {
      const Eigen::Vector2d q = c.robot.T_dest_source * p.centroid;
      return (q - c.robot.breaks.front().point).dot(normal) > 0.0;
    };
    CHECK(side_of(a.brokenness.pieces[0]) != side_of(a.brokenness.pieces[1]));
    // Each piece has its own warp, so the walls beside the cut land where they belong too (one
    // smooth field blended the two sides over a control cell there).
    REQUIRE(a.warp.field.piece_fields().size() == 2);
    const double p95 = warp_error_p95(c, a);
    MESSAGE("warp error at the walls, 95th percentile: " << p95 << " m");
    CHECK(p95 < 0.15);
  }
}

TEST_CASE("breaks that add up are not merged into one piece") {
  // Three cuts of 8 degrees each: the far pieces turn 16-24 degrees from the near one, more than a
  // tile's fit could turn from the whole map's before 2026-12-06 (this map was then one piece).
  // Each tile is now measured from the neighbour it started from, and a tile across a cut is
  // fitted again from turned starts (AssessParams::piece_retry_turns_rad).
  RobotMapParams rp = plain_robot(0.9);
  rp.break_count = 3;
  rp.break_min_rotation_rad = rp.break_max_rotation_rad = 8.0 * pi / 180.0;
  const AssessCase c = assess_case(1322, rp);
  REQUIRE(c.robot.breaks.size() == 3);
  AssessParams params;
  params.assume_same_building = true;
  const MapAssessment a = assess_match(c.robot.grid, c.map_graph, c.building.layout, c.reference_graph, c.match, params);
  REQUIRE(a.ok);
  MESSAGE("pieces found: " << a.brokenness.pieces.size() << " of 4");
  CHECK(a.brokenness.pieces.size() >= 2);
  double widest = 0.0;
  for (const RigidPiece& piece : a.brokenness.pieces) widest = std::max(widest, std::abs(piece.rotation_rad));
  CHECK(widest > 10.0 * pi / 180.0);  // a piece beyond the first cut is found
}

TEST_CASE("a tile's fit that slid a wall period along does not start the warp") {
  // In-sample regression pin: pair 5 of `areamatch_assess_generated 60 6300`, broken once under a
  // 0.2 m bend. Both pieces' fits are right, but a few tiles of like rooms fitted 2-6 m along, and
  // the warp, started from them, stayed there: its 95th percentile error was 4.0 m (the rigid
  // answer's 3.9 m) until a tile's fit started the warp only near its piece's
  // (AssessParams::piece_start_max_offset_m); 0.03 m since.
  const auto [c, a] = assess_distorted(6300, 5);
  REQUIRE(c.robot.breaks.size() == 1);
  REQUIRE(a.ok);
  REQUIRE(a.brokenness.pieces.size() == 2);
  CHECK(warp_error_p95(c, a) < 0.15);
}

TEST_CASE("a bent broken piece's turn is the rigid fit of its warped walls") {
  // In-sample regression pin: pair 25 of `areamatch_assess_generated 60 4300`, broken once under a
  // 0.2 m bend. The tiles' ICP fits lean to the walls they agree with best: the piece's turn was
  // 0.76 degrees off its break's before each piece's fit became the least-squares fit of its
  // warped walls (fit_pieces_to_warp, 2026-12-07); 0.24 since.
  const auto [c, a] = assess_distorted(4300, 25);
  REQUIRE(c.robot.breaks.size() == 1);
  REQUIRE(a.ok);
  REQUIRE(a.brokenness.pieces.size() == 2);
  const double error = std::abs(std::abs(a.brokenness.pieces[1].rotation_rad) - std::abs(c.robot.breaks.front().motion.rotation));
  MESSAGE("turn error: " << error * 180.0 / pi << " degrees");
  CHECK(error < 0.5 * pi / 180.0);
}

TEST_CASE("a piece is fitted from each of its tiles' own fits, not its first tile's alone") {
  // In-sample regression pin: pair 38 of `areamatch_assess_generated 60 4300`, broken twice under a
  // 0.8 m bend. One piece's fit, started from its first tile's, converged 1.5 degrees off and slid
  // along the corridor; the warp followed it, 3.3 m off at the 95th percentile, until a piece's fit
  // tried each of its tiles' fits as a start (detail::fit_tile_group, 2026-12-07); 0.034 m since.
  const auto [c, a] = assess_distorted(4300, 38);
  REQUIRE(c.robot.breaks.size() == 2);
  REQUIRE(a.ok);
  CHECK(a.brokenness.pieces.size() == 3);
  CHECK(warp_error_p95(c, a) < 0.15);
}

TEST_CASE("pieces whose warped fits agree where they meet are one piece") {
  // Before the warp a bend can split one side of a break into two pieces whose tile fits disagree
  // a little; fitted on their warped walls they agree, and detail::join_agreeing_pieces joins them
  // (on generated pair 13 of `areamatch_assess_generated 60 4300`: 3 pieces before 2026-12-07, 2
  // since, in the Release build). Here three tiles in a row, three pieces: the first two moved
  // alike (0.3 degrees apart), the third turned 4 degrees.
  Brokenness b;
  b.tile_m = 6.0;
  b.tile_columns = 3;
  b.tile_rows = 1;
  b.piece_of_tile = {0, 1, 2};
  b.tile_fit.assign(3, Similarity2{});
  b.piece_of_area = {0, 1, 2, 2};
  const double degree = pi / 180.0;
  const Similarity2 turned_by[3] = {Similarity2{0.0, {1.0, 2.0}}, Similarity2{0.3 * degree, {1.0, 2.0}},
                                    Similarity2{4.0 * degree, {1.0, 2.0}}};
  std::vector<std::vector<Eigen::Vector2d>> from(3), to(3);
  for (int k = 0; k < 3; ++k) {
    RigidPiece piece;
    piece.areas = k < 2 ? std::vector<int>{k} : std::vector<int>{2, 3};
    piece.size_m2 = k < 2 ? 30.0 : 40.0;
    piece.centroid = Eigen::Vector2d(6.0 * k + 3.0, 3.0);
    piece.T_reference_map = turned_by[k];
    b.pieces.push_back(piece);
    for (int i = 0; i <= 60; ++i) {  // a wall along the tile's bottom and one along its top
      for (const double y : {0.5, 5.5}) {
        const Eigen::Vector2d p(6.0 * k + 0.1 * i, y);
        from[static_cast<std::size_t>(k)].push_back(p);
        to[static_cast<std::size_t>(k)].push_back(turned_by[k] * p);
      }
    }
  }
  // The pieces largest first: the 40 m² one, then the two of 30 m².
  std::swap(b.pieces[0], b.pieces[2]);
  std::swap(from[0], from[2]);
  std::swap(to[0], to[2]);
  b.piece_of_tile = {2, 1, 0};
  b.piece_of_area = {2, 1, 0, 0};
  AssessParams params;
  detail::join_agreeing_pieces(b, from, to, params);
  REQUIRE(b.pieces.size() == 2);
  // The joined piece (60 m²) is now the main one; its fit lies between its two parts'.
  CHECK(b.pieces[0].size_m2 == doctest::Approx(60.0));
  CHECK(b.pieces[0].areas == std::vector<int>{0, 1});
  CHECK(b.pieces[0].T_reference_map.rotation > 0.0);
  CHECK(b.pieces[0].T_reference_map.rotation < 0.3 * degree);
  CHECK(b.pieces[1].areas == std::vector<int>{2, 3});
  CHECK(b.pieces[1].T_reference_map.rotation == doctest::Approx(4.0 * degree));
  CHECK(b.piece_of_tile == std::vector<int>{0, 0, 1});
  CHECK(b.piece_of_area == std::vector<int>{0, 0, 1, 1});
  REQUIRE(from.size() == 2);
  CHECK(from[0].size() == 2 * 122);
  // Fits 2 degrees apart (beyond piece_rotation_tolerance_rad) stay apart.
  Brokenness apart;
  apart.tile_m = 6.0;
  apart.tile_columns = 2;
  apart.tile_rows = 1;
  apart.piece_of_tile = {0, 1};
  apart.piece_of_area = {0, 1};
  apart.pieces.resize(2);
  apart.pieces[1].T_reference_map.rotation = 2.0 * degree;
  std::vector<std::vector<Eigen::Vector2d>> no_walls(2), no_places(2);
  detail::join_agreeing_pieces(apart, no_walls, no_places, params);
  CHECK(apart.pieces.size() == 2);
}

TEST_CASE("tiles whose fits scatter gather into their piece instead of joining the large one next door") {
  // In-sample regression pin: pair 15 of `areamatch_assess_generated 60 6300`, a map broken three
  // times under a 0.2 m bend. Its tiles' own fits scatter by a degree or so, so
  // one piece's tiles formed groups too small to count, and each joined the large piece next door:
  // 3 pieces found before 2026-12-07, the true 4 since small groups gather first.
  const auto [c, a] = assess_distorted(6300, 15);
  REQUIRE(c.robot.breaks.size() == 3);
  REQUIRE(a.ok);
  CHECK(a.brokenness.pieces.size() == 4);
}

TEST_CASE("the generator's broken pieces: truth and random stream") {
  RobotMapParams rp = plain_robot(0.5);
  const SyntheticBuilding building = generate_building({}, 1400);
  const RobotMap plain = make_robot_map(building, rp, 7);
  rp.break_count = 2;
  const RobotMap broken = make_robot_map(building, rp, 7);
  REQUIRE(broken.breaks.size() == 2);
  for (const auto& b : broken.breaks) {
    const double turn = std::abs(b.motion.rotation) * 180.0 / pi;
    CHECK(turn >= 2.0);
    CHECK(turn <= 10.0);
  }
  // The cuts split the building's longer side in three.
  CHECK(broken.piece_motion(0).rotation == 0.0);
  CHECK(broken.piece_motion(2).rotation == doctest::Approx(broken.breaks[0].motion.rotation + broken.breaks[1].motion.rotation));
  // Without breaks nothing is drawn: the same map as before breaks existed.
  rp.break_count = 0;
  CHECK(make_robot_map(building, rp, 7).grid.cells() == plain.grid.cells());
  rp.break_count = -1;
  CHECK_THROWS_AS(make_robot_map(building, rp, 7), parameter_error);
}

TEST_CASE("a map that cannot be placed is not assessed against a guess, unless the caller says it is the building") {
  const AssessCase c = assess_case(1500, plain_robot(0.2));
  const SyntheticBuilding other = generate_building({}, 1501);
  const Matcher<> matcher;
  const AreaGraph other_graph = matcher.segmenter.segment(other.layout);
  const MatchResult wrong = matcher.match(c.robot.grid, c.map_graph, other.layout, other_graph);
  REQUIRE_FALSE(wrong.ok);
  const MapAssessment refused = assess_match(c.robot.grid, c.map_graph, other.layout, other_graph, wrong);
  CHECK_FALSE(refused.ok);
  CHECK(refused.reason.find("could not be placed") != std::string::npos);
  CHECK(assessment_json(refused).find("\"ok\": false") != std::string::npos);
  if (!wrong.matched_areas.empty()) {
    AssessParams params;
    params.assume_same_building = true;
    const MapAssessment forced = assess_match(c.robot.grid, c.map_graph, other.layout, other_graph, wrong, params);
    CHECK(forced.ok);
    CHECK(forced.decision_overridden);
  }
  // A graph that is not the map's segmentation is refused.
  CHECK_THROWS_AS(assess_match(c.robot.grid, c.reference_graph, c.building.layout, c.reference_graph, c.match), parameter_error);
}

TEST_CASE("an assessment is deterministic and its JSON and picture hold every part") {
  const AssessCase c = assess_case(1600, plain_robot(1.1));
  REQUIRE(c.match.ok);
  const MapAssessment a = assess_match(c.robot.grid, c.map_graph, c.building.layout, c.reference_graph, c.match);
  const MapAssessment b = assess_match(c.robot.grid, c.map_graph, c.building.layout, c.reference_graph, c.match);
  auto without_timings = [](std::string json) { return json.substr(0, json.find("\"timings\"")); };
  CHECK(without_timings(assessment_json(a)) == without_timings(assessment_json(b)));
  const std::string json = assessment_json(a);
  for (const char* key : {"\"rigid_walls\"", "\"warped_walls\"", "\"map_to_reference\"", "\"reference_to_map\"", "\"area_displacement\"",
                          "\"brokenness\"", "\"pieces\"", "\"coverage\"", "\"reference_areas\"", "\"topology\"", "\"warp\""}) {
    CHECK_MESSAGE(json.find(key) != std::string::npos, key);
  }
  const RgbImage picture = render_assessment(c.robot.grid, c.map_graph, c.building.layout, a);
  CHECK(picture.width >= c.building.layout.width());
  CHECK(picture.height > c.building.layout.height());  // the legend below
}

TEST_CASE("bad assessment parameters are refused by name") {
  auto refused = [](auto change, const char* name) {
    AssessParams p;
    change(p);
    try {
      p.validate();
      FAIL("accepted bad " << name);
    } catch (const parameter_error& e) {
      CHECK(std::string(e.what()).find(name) != std::string::npos);
    }
  };
  refused([](AssessParams& p) { p.wall_distance_cap_m = 0.0; }, "wall_distance_cap_m");
  refused([](AssessParams& p) { p.wall_tolerance_m = -1.0; }, "wall_tolerance_m");
  refused([](AssessParams& p) { p.piece_tile_m = 0.0; }, "piece_tile_m");
  refused([](AssessParams& p) { p.found_share = 1.5; }, "found_share");
  refused([](AssessParams& p) { p.partly_found_share = 0.8; }, "partly_found_share");
  refused([](AssessParams& p) { p.sample_cell_m = std::nan(""); }, "sample_cell_m");
  refused([](AssessParams& p) { p.warp.bend_length_m = 0.0; }, "bend_length_m");
  refused([](AssessParams& p) { p.piece_retry_turns_rad = {0.1, std::nan("")}; }, "piece_retry_turns_rad");
  refused([](AssessParams& p) { p.piece_start_max_offset_m = -1.0; }, "piece_start_max_offset_m");
  refused([](AssessParams& p) { p.piece_refit_rounds = -1; }, "piece_refit_rounds");
  refused([](AssessParams& p) { p.piece_fit_starts = 0; }, "piece_fit_starts");
  refused([](AssessParams& p) { p.warp.piece_label_cell_m = 0.0; }, "piece_label_cell_m");
  refused([](AssessParams& p) { p.warp.piece_boundary_m = -0.5; }, "piece_boundary_m");
}
