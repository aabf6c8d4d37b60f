// The matcher on synthetic pairs (a fixed set of 100 seeds: every rotation, translation, noise,
// clutter, partial exploration, mirrors), its determinism, its policies and its bad inputs.
#include <areamatch/areamatch.hpp>
#include <areamatch/detail/random.hpp>
#include <areamatch/evaluation.hpp>
#include <areamatch/io/json.hpp>
#include <areamatch/io/match_files.hpp>

#include <doctest/doctest.h>

#include "synthetic_cases.hpp"
#include "test_support.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

using namespace areamatch;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

/// The JSON of a result without its timings, which differ from run to run.
std::string without_timings(const MatchResult& r) {
  const std::string json = match_result_json(r);
  return json.substr(0, json.find("\"timings\""));
}

OccupancyGrid rectangle_room(double width_m, double height_m, double resolution = 0.05) {
  const int w = static_cast<int>(width_m / resolution) + 4, h = static_cast<int>(height_m / resolution) + 4;
  OccupancyGrid grid(w, h, resolution, {}, CellState::occupied);
  for (int r = 2; r < h - 2; ++r)
    for (int c = 2; c < w - 2; ++c) grid.set(c, r, CellState::free);
  return grid;
}

}  // namespace

TEST_CASE("synthetic pairs: at least 95 of 100 correct, accurate when correct") {
  const CorrectnessThresholds thresholds{3.0, 0.5};
  int correct = 0;
  std::vector<double> rotation_errors, displacements;
  const std::uint64_t seeds = areamatch_test::quick_tests() ? 4 : 100;
  for (std::uint64_t seed = 0; seed < seeds; ++seed) {
    const auto c = areamatch_test::synthetic_case(seed);
    Matcher<> matcher;
    matcher.params.allow_reflection = true;
    const MatchResult r = matcher.match(c.robot.grid, c.building.layout);
    const MatchError e = match_error(r.pixel_transform, c.robot.pixel_transform, free_edge_pixels(c.robot.grid),
                                     c.building.layout.resolution());
    if (r.ok && e.correct(thresholds)) {
      ++correct;
      rotation_errors.push_back(e.rotation_error_deg);
      displacements.push_back(e.mean_displacement_m);
    } else {
      MESSAGE("seed " << seed << ": " << (r.ok ? "wrong" : r.reason) << ", rotation error " << e.rotation_error_deg
                      << " deg, displacement " << e.mean_displacement_m << " m");
    }
  }
  MESSAGE(correct << "/" << seeds << " correct; median rotation error " << median(rotation_errors) << " deg, displacement "
                  << median(displacements) << " m");
  CHECK(static_cast<std::uint64_t>(correct) >= seeds - seeds / 20);  // 95 of 100
  CHECK(median(rotation_errors) <= 0.5);
  CHECK(median(displacements) <= 0.10);
}

TEST_CASE("the same pair matched 20 times in one process gives the same JSON, bit for bit") {
  const auto c = areamatch_test::synthetic_case(7);
  Matcher<> matcher;
  matcher.params.allow_reflection = true;
  const std::string first = without_timings(matcher.match(c.robot.grid, c.building.layout));
  for (int i = 0, n = areamatch_test::quick_tests() ? 2 : 19; i < n; ++i) CHECK(without_timings(matcher.match(c.robot.grid, c.building.layout)) == first);
  const PaperMatcher paper;
  const std::string paper_first = without_timings(paper.match(c.robot.grid, c.building.layout));
  CHECK(without_timings(paper.match(c.robot.grid, c.building.layout)) == paper_first);
}

TEST_CASE("any thread count gives the same answer, bit for bit") {
  // MatcherParams::threads spreads segmentation, hypotheses, candidate scores and ICP; each piece
  // writes its own slot, so the result must not depend on the count. Under the sanitizers (quick
  // runs) one building: what they check is the threads' memory use, not more buildings.
  const std::vector<int> seeds = areamatch_test::quick_tests() ? std::vector<int>{13} : std::vector<int>{7, 13, 21};
  for (const int seed : seeds) {
    const auto c = areamatch_test::synthetic_case(seed);
    Matcher<> matcher;
    matcher.params.allow_reflection = true;
    PaperMatcher paper;
    const std::string one = without_timings(matcher.match(c.robot.grid, c.building.layout));
    const std::string paper_one = without_timings(paper.match(c.robot.grid, c.building.layout));
    // A grid onto a prepared map: on threads, the source's cell data is built beside its
    // segmentation, its edge lookup beside the hypotheses, and preparing overlaps the same way.
    const auto layout = matcher.prepare(c.building.layout);
    const std::string onto = without_timings(matcher.match(c.robot.grid, layout));
    CHECK(onto == one);
    for (const unsigned threads : {2u, 3u, 0u}) {
      matcher.params.threads = threads;
      paper.params.threads = threads;
      CHECK(without_timings(matcher.match(c.robot.grid, c.building.layout)) == one);
      CHECK(without_timings(paper.match(c.robot.grid, c.building.layout)) == paper_one);
      CHECK(without_timings(matcher.match(c.robot.grid, layout)) == onto);
      CHECK(without_timings(matcher.match(c.robot.grid, matcher.prepare(c.building.layout))) == onto);
      CHECK(without_timings(matcher.match(matcher.prepare(c.robot.grid), layout)) == onto);
    }
  }
}

TEST_CASE("two maps made side by side: the same answer whichever is made first, errors in map order") {
  // match_side_by_side builds the data of the map made first while the other is still being made.
  // Each order is forced here (the other map waits, at most 5 s, for its turn).
  const auto c = areamatch_test::synthetic_case(13);
  Matcher<> matcher;
  matcher.params.allow_reflection = true;
  const std::string one = without_timings(matcher.match(c.robot.grid, c.building.layout));
  matcher.params.threads = 2;
  for (const std::size_t first : {0u, 1u}) {
    OccupancyGrid grids[2];
    AreaGraph graphs[2];
    std::atomic<bool> first_made{false};
    const MatchResult r = matcher.match_side_by_side(grids[0], graphs[0], grids[1], graphs[1], [&](std::size_t i) {
      if (i != first) {
        const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(5);
        while (!first_made && std::chrono::steady_clock::now() < give_up) std::this_thread::yield();
      }
      grids[i] = i == 0 ? c.robot.grid : c.building.layout;
      graphs[i] = matcher.segmenter.segment(grids[i]);
      if (i == first) first_made = true;
    });
    INFO("map made first: " << first);
    CHECK(without_timings(r) == one);
    CHECK(r.timings.prepare_s > 0.0);
  }
  // Map 0's error before map 1's, and both before the match's (invalid parameters).
  matcher.params.k = 0;
  OccupancyGrid grids[2];
  AreaGraph graphs[2];
  auto failing = [&](std::size_t failing_map) {
    return [&, failing_map](std::size_t i) {
      if (i == failing_map || failing_map == 2) throw io_error("map " + std::to_string(i) + " unreadable");
      grids[i] = c.building.layout;
      graphs[i] = matcher.segmenter.segment(grids[i]);
    };
  };
  CHECK_THROWS_WITH_AS(matcher.match_side_by_side(grids[0], graphs[0], grids[1], graphs[1], failing(2)), "map 0 unreadable", io_error);
  CHECK_THROWS_WITH_AS(matcher.match_side_by_side(grids[0], graphs[0], grids[1], graphs[1], failing(1)), "map 1 unreadable", io_error);
  CHECK_THROWS_AS(matcher.match_side_by_side(grids[0], graphs[0], grids[1], graphs[1], failing(3)), parameter_error);
}

TEST_CASE("bad source grids onto a prepared map fail the same on one thread and on two") {
  // On two threads the source's cells are scanned beside its segmentation: what the segmenter
  // refuses must still be refused with its message, and a map without areas still reported.
  const auto c = areamatch_test::synthetic_case(7);
  for (const unsigned threads : {1u, 2u}) {
    Matcher<> matcher;
    matcher.params.threads = threads;
    const auto layout = matcher.prepare(c.building.layout);
    CHECK_THROWS_WITH_AS(matcher.match(OccupancyGrid{}, layout), "cannot segment an empty grid", parameter_error);
    CHECK_THROWS_WITH_AS(matcher.prepare(OccupancyGrid{}), "cannot segment an empty grid", parameter_error);
    const MatchResult unknown = matcher.match(OccupancyGrid(60, 40, 0.05), layout);
    CHECK_FALSE(unknown.ok);
    CHECK(unknown.reason.find("the source map has no areas") == 0);
    const MatchResult walls = matcher.match(OccupancyGrid(60, 40, 0.05, {}, CellState::occupied), layout);
    CHECK_FALSE(walls.ok);
    CHECK(walls.reason.find("the source map has no areas") == 0);
  }
}

TEST_CASE("a map matched against itself gives the identity") {
  const auto building = generate_building({}, 3);
  const MatchResult r = Matcher<>{}.match(building.layout, building.layout);
  REQUIRE(r.ok);
  CHECK(std::abs(r.T_dest_source.rotation) < 1e-3);
  INFO("translation " << r.T_dest_source.translation.transpose());
  CHECK(r.T_dest_source.translation.norm() < 0.05);
  CHECK_FALSE(r.T_dest_source.reflected);
  CHECK(r.matched_areas.size() == r.statistics.source_areas);
}

namespace {
/// A small mirrored pair: `areamatch generate --seed 5 --width 20 --height 14 --rotation 75 --mirror`.
std::pair<SyntheticBuilding, RobotMap> small_mirrored_pair() {
  BuildingParams small;
  small.width_m = 20;
  small.height_m = 14;
  SyntheticBuilding building = generate_building(small, 5);
  RobotMapParams params;
  params.rotation_rad = 75.0 * pi / 180.0;
  params.mirror = true;
  params.wall_noise_m = 0.03;
  params.max_clutter_per_room = 3;
  params.speckle_per_m2 = 0.02;
  RobotMap robot = make_robot_map(building, params, 5);
  return {std::move(building), std::move(robot)};
}
}  // namespace

TEST_CASE("the paper preset: right on a pair it can get, a half turn where the whole map is needed") {
  // The paper's matching as written loses most real pairs to half turns and mirrors
  // (docs/evaluation.md, docs/algorithm.md). This small mirrored pair it gets right...
  const auto pair = small_mirrored_pair();  // (no structured binding: clang will not capture one in INFO)
  const SyntheticBuilding& building = pair.first;
  const RobotMap& robot = pair.second;
  MatcherParams paper = MatcherParams::paper();
  paper.allow_reflection = true;
  const MatchResult r = PaperMatcher{paper}.match(robot.grid, building.layout);
  CHECK(r.statistics.mutual_pairs > 0);
  REQUIRE(r.ok);
  const MatchError e = match_error(r.pixel_transform, robot.pixel_transform, free_edge_pixels(robot.grid),
                                   building.layout.resolution());
  INFO("rotation error " << e.rotation_error_deg << " deg, displacement " << e.mean_displacement_m << " m");
  CHECK(e.correct({3.0, 0.5}));
  CHECK(std::isnan(r.evidence.turn_margin));  // no refinement, no turn check

  // ... while on a clean 30 x 20 m building its Σ OP prefers the half turn, which our default
  // selection (the whole map's walls) does not.
  const auto larger = generate_building({}, 5);
  RobotMapParams turned;
  turned.rotation_rad = 0.6;
  const auto clean = make_robot_map(larger, turned, 5);
  const MatchResult half = PaperMatcher{}.match(clean.grid, larger.layout);
  const MatchResult ours = Matcher<>{}.match(clean.grid, larger.layout);
  const auto edges = free_edge_pixels(clean.grid);
  const double resolution = larger.layout.resolution();
  CHECK(match_error(half.pixel_transform, clean.pixel_transform, edges, resolution).rotation_error_deg > 170.0);
  REQUIRE(ours.ok);
  CHECK(match_error(ours.pixel_transform, clean.pixel_transform, edges, resolution).correct({3.0, 0.5}));
}

TEST_CASE("progress: each stage reported in order on the calling thread; the answer unchanged; a throw cancels") {
  const auto pair = small_mirrored_pair();
  const OccupancyGrid& robot = pair.second.grid;
  const OccupancyGrid& layout = pair.first.layout;
  MatcherParams params;
  params.allow_reflection = true;
  const Matcher<> quiet(params);
  Matcher<> reporting(params);
  std::vector<std::string> stages;
  const auto caller = std::this_thread::get_id();
  bool other_thread = false;
  reporting.progress = [&](const Progress& p) {
    stages.emplace_back(p.stage);
    other_thread = other_thread || std::this_thread::get_id() != caller;
  };
  const MatchResult expected = quiet.match(robot, layout);
  const MatchResult reported = reporting.match(robot, layout);
  CHECK(stages == std::vector<std::string>{"segment", "prepare", "select", "check"});
  CHECK_FALSE(other_thread);
  CHECK(reported.ok == expected.ok);
  CHECK(reported.T_dest_source.rotation == expected.T_dest_source.rotation);
  CHECK(reported.T_dest_source.translation == expected.T_dest_source.translation);
  CHECK(reported.p_correct == expected.p_correct);

  // Onto a prepared map: no "segment" of the destination, the source's still.
  stages.clear();
  const auto prepared = reporting.prepare(layout);
  CHECK(reporting.match(robot, prepared).p_correct == expected.p_correct);
  CHECK(stages == std::vector<std::string>{"segment", "prepare", "select", "check"});

  // A callback that throws stops the match; the exception reaches the caller.
  reporting.progress = [](const Progress& p) {
    if (p.stage == "select") throw std::runtime_error("cancelled");
  };
  CHECK_THROWS_WITH_AS(reporting.match(robot, layout), "cancelled", std::runtime_error);
}

TEST_CASE("maps without areas give a clear not-ok result, never a crash") {
  const OccupancyGrid walls(50, 50, 0.05, {}, CellState::occupied);
  const auto building = generate_building({}, 1);
  for (const auto& [source, dest] : {std::pair{walls, building.layout}, std::pair{building.layout, walls}}) {
    const MatchResult r = Matcher<>{}.match(source, dest);
    CHECK_FALSE(r.ok);
    CHECK(r.reason.find("no areas") != std::string::npos);
    const MatchResult p = PaperMatcher{}.match(source, dest);
    CHECK_FALSE(p.ok);
  }
}

TEST_CASE("one-area maps and maps without passages: the room onto itself, its half turn flagged") {
  const OccupancyGrid a = rectangle_room(6.0, 4.0), b = rectangle_room(6.0, 4.0);
  const MatchResult r = Matcher<>{}.match(a, b);
  CHECK(r.statistics.source_areas == 1);
  // A bare rectangle lies on itself as well turned by 180°: either is right, and the result
  // must say that the other scores as well.
  REQUIRE(r.ok);
  const double turn = std::abs(wrap_angle(r.T_dest_source.rotation));
  CHECK((turn < 0.01 || std::abs(turn - pi) < 0.01));
  CHECK(r.score > 0.95);
  CHECK(r.ambiguous);
  CHECK(r.evidence.turn_margin < 0.05);
  // The paper's preset has no rejection rule: it lays a 6 x 4 m room on a 3 x 9 m one, centred.
  const OccupancyGrid c = rectangle_room(3.0, 9.0);
  const MatchResult p = PaperMatcher{}.match(a, c);
  REQUIRE(p.ok);
  const Eigen::Vector2d a_centre(3.1, 2.1), c_centre(1.6, 4.6);  // two border cells of wall around each
  CHECK((p.T_dest_source * a_centre - c_centre).norm() < 0.5);
}

TEST_CASE("maps of different buildings do not crash and score lower than the true pair") {
  const auto one = generate_building({}, 11);
  BuildingParams other_params;
  other_params.width_m = 22.0;
  other_params.height_m = 26.0;
  const auto other = generate_building(other_params, 12);
  Matcher<> matcher;
  matcher.params.allow_reflection = true;
  const MatchResult wrong = matcher.match(one.layout, other.layout);
  const MatchResult right = matcher.match(one.layout, one.layout);
  CHECK(right.ok);
  CHECK(wrong.score < right.score);
  // ... and they are rejected, with the reason and the evidence.
  CHECK_FALSE(wrong.ok);
  CHECK(wrong.rejection != Rejection::none);
  CHECK(wrong.rejection != Rejection::no_answer);
  CHECK(wrong.reason.find(wrong.rejection == Rejection::different_places ? "different places: " : "not sure: ") == 0);
  CHECK(wrong.evidence.agreement < matcher.params.decision.min_agreement);
  CHECK(wrong.p_correct < 0.5);
  CHECK(right.p_correct > 0.5);
  CHECK(right.evidence.agreement > 0.95);
  CHECK(right.evidence.reverse_wall_agreement > 0.95);
  CHECK(right.evidence.free_iou > 0.95);
}

TEST_CASE("different synthetic buildings are rejected, their true pairs accepted") {
  // Robot maps (rotated, mirrored, noisy) of 12 buildings, each against its own layout and the
  // next building's layout.
  const int buildings = areamatch_test::quick_tests() ? 3 : 12;
  int accepted = 0, rejected = 0;
  std::vector<SyntheticBuilding> layouts;
  std::vector<RobotMap> robots;
  for (int i = 0; i < buildings; ++i) {
    // Out of the calibration sets' seeds (test_support.hpp): the decision has not seen them.
    const std::uint64_t seed = areamatch_test::test_seed_base + 300 + static_cast<std::uint64_t>(i);
    REQUIRE(!areamatch_test::calibration_seed(seed));
    layouts.push_back(generate_building({}, seed));
    RobotMapParams rp;
    rp.rotation_rad = 0.7 * i;
    rp.mirror = i % 2 == 1;
    robots.push_back(make_robot_map(layouts.back(), rp, seed + 100));
  }
  Matcher<> matcher;
  matcher.params.allow_reflection = true;
  for (int i = 0; i < buildings; ++i) {
    const MatchResult same = matcher.match(robots[i].grid, layouts[i].layout);
    const MatchResult other = matcher.match(robots[i].grid, layouts[(i + 1) % buildings].layout);
    MESSAGE("building " << i << ": same agreement " << same.evidence.agreement << ", other "
                        << other.evidence.agreement);
    accepted += same.ok;
    rejected += !other.ok;
    if (!other.ok) CHECK(other.reason.find("min_agreement") != std::string::npos);
  }
  CHECK(accepted == buildings);
  CHECK(rejected == buildings);
}

TEST_CASE("generated hand-held scans onto line-drawn layouts: right and accepted; another building's refused") {
  const int cases = areamatch_test::quick_tests() ? 2 : 6;
  const CorrectnessThresholds thresholds{3.0, 0.5};
  Matcher<> matcher;
  // The drawn doorways are 0.1 m wider than the built ones (the walls thinned from 0.15 to 0.05 m).
  matcher.segmenter.params.with_door_width(1.0);
  std::vector<OccupancyGrid> layouts;
  int right = 0, other_refused = 0;
  for (int i = 0; i < cases; ++i) {
    BuildingParams bp;
    bp.resolution = 0.025;
    if (areamatch_test::quick_tests()) {  // 0.02 m scans: smaller buildings under the sanitizers
      bp.width_m = 20.0;
      bp.height_m = 14.0;
    }
    auto building = generate_building(bp, 900 + static_cast<std::uint64_t>(i));
    RobotMapParams rp = RobotMapParams::handheld();
    rp.rotation_rad = 2.1 * i - 3.0;
    const RobotMap scan = make_robot_map(building, rp, 950 + static_cast<std::uint64_t>(i));
    layouts.push_back(layout_line_drawing(building, 0.05));
    const MatchResult r = matcher.match(scan.grid, layouts.back());
    const MatchError e = match_error(r.pixel_transform, scan.pixel_transform, free_edge_pixels(scan.grid), bp.resolution);
    MESSAGE("scan " << i << ": " << (r.ok ? "ok" : r.reason) << ", rotation error " << e.rotation_error_deg
                    << " deg, displacement " << e.mean_displacement_m << " m, p_correct " << r.p_correct);
    right += r.ok && e.correct(thresholds);
    if (i > 0) {
      const MatchResult other = matcher.match(scan.grid, layouts[static_cast<std::size_t>(i - 1)]);
      other_refused += !other.ok;
    }
  }
  CHECK(right == cases);
  CHECK(other_refused == cases - 1);
}

TEST_CASE("partial maps both ways: a 40 %-explored robot map onto its layout, and the layout onto it") {
  const int cases = areamatch_test::quick_tests() ? 2 : 8;
  int robot_onto_layout = 0, layout_onto_robot = 0;
  for (int i = 0; i < cases; ++i) {
    const auto building = generate_building({}, 900 + static_cast<std::uint64_t>(i));
    RobotMapParams rp;
    rp.rotation_rad = 0.8 * i - 3.0;
    rp.explored_fraction = 0.4;
    const auto robot = make_robot_map(building, rp, 950 + static_cast<std::uint64_t>(i));
    Matcher<> matcher;
    matcher.segmenter.params.with_door_width(0.9);
    const MatchResult forward = matcher.match(robot.grid, building.layout);
    const MatchResult backward = matcher.match(building.layout, robot.grid);
    const Similarity2 truth_back = robot.T_dest_source.inverse();
    auto close = [](const Similarity2& a, const Similarity2& b) {
      return std::abs(wrap_angle(a.rotation - b.rotation)) < 2.0 * pi / 180.0 && (a.translation - b.translation).norm() < 0.3;
    };
    MESSAGE("case " << i << ": agreement " << forward.evidence.agreement << " / " << backward.evidence.agreement);
    robot_onto_layout += forward.ok && close(forward.T_dest_source, robot.T_dest_source);
    layout_onto_robot += backward.ok && close(backward.T_dest_source, truth_back);
  }
  CHECK(robot_onto_layout == cases);
  CHECK(layout_onto_robot == cases);
}

TEST_CASE("room correspondences on bent robot maps: right rooms, local transforms that fit better") {
  // A smoothly bent robot map (SLAM drift): every corresponding pair must name the right room;
  // the truth is the layout's room under the area's centroid (the bend moves it < 0.5 m).
  const int cases = areamatch_test::quick_tests() ? 2 : 8;
  std::size_t pairs = 0, right = 0, moved = 0;
  for (int i = 0; i < cases; ++i) {
    const std::uint64_t seed = areamatch_test::test_seed_base + 500 + static_cast<std::uint64_t>(i);  // out of calibration
    const auto building = generate_building({}, seed);
    RobotMapParams rp;
    rp.rotation_rad = 0.4 + 0.9 * i;
    rp.wall_bend_m = 0.4;
    const auto robot = make_robot_map(building, rp, seed + 100);
    Matcher<> matcher;
    matcher.segmenter.params.with_door_width(0.9);
    const AreaGraph source = matcher.segmenter.segment(robot.grid);
    const AreaGraph dest = matcher.segmenter.segment(building.layout);
    const MatchResult r = matcher.match(robot.grid, source, building.layout, dest);
    REQUIRE_MESSAGE(r.ok, r.reason);
    // The public overload, from the grid and the rasters and lookup a matcher builds, gives the
    // matcher's own correspondences.
    const auto source_data = detail::build_map_data(robot.grid, source, matcher.features, matcher.params, false);
    const auto dest_data = detail::build_map_data(building.layout, dest, matcher.features, matcher.params, true);
    const std::vector<MatchedAreaPair> again =
        area_correspondences(robot.grid, source, dest, source_data.fine(), dest_data.fine(), dest_data.lookup,
                             r.T_dest_source, matcher.params.correspondences);
    REQUIRE(again.size() == r.matched_areas.size());
    for (std::size_t k = 0; k < again.size(); ++k) {
      const MatchedAreaPair &a = again[k], &b = r.matched_areas[k];
      CHECK(a.source == b.source);
      CHECK(a.dest == b.dest);
      CHECK(a.overlap == b.overlap);
      CHECK(a.iou == b.iou);
      CHECK(a.T_dest_source.translation == b.T_dest_source.translation);
      CHECK(a.T_dest_source.rotation == b.T_dest_source.rotation);
      CHECK((a.wall_agreement == b.wall_agreement || (std::isnan(a.wall_agreement) && std::isnan(b.wall_agreement))));
    }
    auto truth_room = [&](const Eigen::Vector2d& world) {
      const Eigen::Vector2d px = building.layout.pixel_from_world() * world;
      const int col = static_cast<int>(std::lround(px.x())), row = static_cast<int>(std::lround(px.y()));
      if (col < 0 || row < 0 || col >= building.layout.width() || row >= building.layout.height()) return -1;
      return building.labels[static_cast<std::size_t>(row) * static_cast<std::size_t>(building.layout.width()) +
                             static_cast<std::size_t>(col)];
    };
    for (const MatchedAreaPair& p : r.matched_areas) {
      const int from = truth_room(robot.T_dest_source * source.areas[static_cast<std::size_t>(p.source)].centroid);
      const int to = truth_room(dest.areas[static_cast<std::size_t>(p.dest)].centroid);
      if (from < 0 || to < 0) continue;  // a centroid outside every room (an L-shaped corridor)
      ++pairs;
      right += from == to;
      if (!(p.T_dest_source.translation - r.T_dest_source.translation).isZero(1e-12)) {
        ++moved;
        CHECK(p.wall_agreement >= 0.0);
      }
      CHECK(p.iou > 0.0);
      CHECK(p.iou <= 1.0);
      CHECK(p.overlap >= matcher.params.correspondences.min_overlap);
    }
  }
  MESSAGE(right << " of " << pairs << " room pairs right; " << moved << " with their own transform");
  CHECK(pairs > 0);
  CHECK(right >= pairs * 95 / 100);
  CHECK(moved > 0);
}

TEST_CASE("correspondence labels: destination id + 1 on the source's cells, 0 elsewhere") {
  AreaGraph g;
  g.areas.resize(3);
  g.labels = {-1, 0, 0, 1, 2, 2};
  std::vector<MatchedAreaPair> pairs(2);
  pairs[0].source = 0;
  pairs[0].dest = 5;
  pairs[1].source = 2;
  pairs[1].dest = 7;
  CHECK(correspondence_labels(g, pairs) == std::vector<int>{0, 6, 6, 0, 8, 8});
}

TEST_CASE("estimate_scale: robot maps whose resolution is wrong by 0.5x to 2x") {
  // The robot map is made at 0.05 m but claims another resolution; the true scale (true
  // resolution / given) must come back within 2 %, with the transform right.
  // Quick runs (the sanitizer build): one scale, and candidates in [1.4, 2] only.
  const bool quick = areamatch_test::quick_tests();
  const std::vector<double> true_scales = quick ? std::vector<double>{1.8}
                                                : std::vector<double>{0.5, 0.62, 0.8, 1.13, 1.45, 2.0};
  int index = 0;
  for (double truth : true_scales) {
    const auto building = generate_building({}, 700 + static_cast<std::uint64_t>(index));
    RobotMapParams rp;
    rp.rotation_rad = 1.1 * index - 2.0;
    rp.mirror = index % 2 == 1;
    RobotMap robot = make_robot_map(building, rp, 800 + static_cast<std::uint64_t>(index));
    ++index;
    robot.grid.set_resolution(robot.grid.resolution() / truth);
    Matcher<> matcher;
    matcher.params.allow_reflection = true;
    matcher.params.estimate_scale = true;
    if (quick) matcher.params.scale.min_scale = 1.4;
    matcher.segmenter.params.with_door_width(0.9);
    const MatchResult r = matcher.match(robot.grid, building.layout);
    INFO("true scale " << truth << ": " << r.reason << " scale " << r.T_dest_source.scale);
    REQUIRE(r.ok);
    CHECK(r.scale_estimated);
    CHECK(std::abs(r.T_dest_source.scale / truth - 1.0) < 0.02);
    const auto pixel_error = match_error(r.pixel_transform, robot.pixel_transform, free_edge_pixels(robot.grid), 0.05);
    CHECK(pixel_error.rotation_error_deg < 1.0);
    CHECK(pixel_error.mean_displacement_m < 0.3);
    CHECK(pixel_error.scale_error < 0.02);
  }
}

TEST_CASE("estimate_scale: refused with graphs or without refinement; no hypothesis gives a clear not-ok") {
  const auto building = generate_building({}, 3);
  Matcher<> matcher;
  matcher.params.estimate_scale = true;
  const AreaGraph g = matcher.segmenter.segment(building.layout);
  CHECK_THROWS_WITH_AS(matcher.match(building.layout, g, building.layout, g), doctest::Contains("estimate_scale"),
                       parameter_error);
  matcher.params.refine = false;
  CHECK_THROWS_WITH_AS(matcher.match(building.layout, building.layout), doctest::Contains("needs refine"), parameter_error);
  matcher.params.refine = true;
  matcher.params.scale.min_scale = 2.0;
  matcher.params.scale.max_scale = 1.0;
  CHECK_THROWS_AS(matcher.match(building.layout, building.layout), parameter_error);
  matcher.params.scale = ScaleParams{};
  matcher.params.scale.finalists = 0;
  CHECK_THROWS_WITH_AS(matcher.match(building.layout, building.layout), doctest::Contains("finalists"), parameter_error);
  // Nothing to match: every candidate scale fails, and the result says so.
  matcher.params.scale = ScaleParams{};
  OccupancyGrid walls(40, 40, 0.05, {}, CellState::occupied);
  const MatchResult none = matcher.match(walls, building.layout);
  CHECK_FALSE(none.ok);
  CHECK(none.reason.find("scale could not be estimated") != std::string::npos);
  CHECK(none.statistics.scales_tried == scale_candidates(ScaleParams{}).size() + 1);  // and the fallback run
}

TEST_CASE("scale candidates cover the range evenly in log scale") {
  const std::vector<double> c = scale_candidates(ScaleParams{});
  REQUIRE(c.size() == 17);
  CHECK(c.front() == doctest::Approx(0.5));
  CHECK(c.back() == doctest::Approx(2.0));
  CHECK(c[8] == doctest::Approx(1.0));
  ScaleParams odd;
  odd.min_scale = 0.8;
  odd.max_scale = 1.0;
  odd.candidates_per_doubling = 2;
  CHECK(scale_candidates(odd) == std::vector<double>{0.8, 1.0});
}

TEST_CASE("bad parameters are refused with a message") {
  const auto building = generate_building({}, 2);
  Matcher<> matcher;
  matcher.params.k = 0;
  CHECK_THROWS_AS(matcher.match(building.layout, building.layout), parameter_error);
  matcher.params = {};
  matcher.params.coarse_cell_m = -1.0;
  CHECK_THROWS_AS(matcher.match(building.layout, building.layout), parameter_error);
  matcher.params = {};
  matcher.params.hypotheses.min_area_overlap = 2.0;
  CHECK_THROWS_AS(matcher.match(building.layout, building.layout), parameter_error);
  struct Bad {
    std::array<double, 3> values{0.5, 0.5, 0.5};
  };
  Matcher<VoronoiSegmenter, PaperFeatures, Bad> bad_weights;
  CHECK_THROWS_AS(bad_weights.match(building.layout, building.layout), parameter_error);
  BuildingParams small;
  small.width_m = 12.0;
  const auto other = generate_building(small, 4);
  const AreaGraph graph = VoronoiSegmenter{}.segment(building.layout);
  CHECK_THROWS_AS(Matcher<>{}.match(other.layout, graph, building.layout, graph), parameter_error);
}

TEST_CASE("policy concepts: the library's policies conform, other types do not") {
  // Checked when the test runs (a failing trait is reported by name); the compile-fail tests
  // (tests/compile_fail) check the messages a wrong policy gets.
  CHECK(is_feature_v<AreaSize>);
  CHECK(is_feature_v<PassageDistances>);
  CHECK(is_feature_v<HullDiameter>);
  CHECK(feature_has_segments_v<HullDiameter>);
  CHECK_FALSE(feature_has_segments_v<AreaSize>);
  CHECK(is_weights_v<PaperWeights, 3>);
  CHECK_FALSE(is_weights_v<PaperWeights, 4>);
  CHECK(is_clusterer_v<AngularClusterer>);
  CHECK(is_clusterer_v<PoseClusterer>);
  CHECK(is_selection_v<WholeMapSelection>);
  CHECK(is_selection_v<LargestClusterSelection>);
  CHECK_FALSE(is_clusterer_v<int>);
  CHECK_FALSE(is_feature_v<int>);
  CHECK_FALSE(is_selection_v<int>);
  CHECK(is_segmenter_v<VoronoiSegmenter>);
  CHECK_FALSE(is_segmenter_v<int>);
}

TEST_CASE("features and pairing follow the paper's formulas") {
  CHECK(relative_difference(0.0, 0.0) == 0.0);
  CHECK(relative_difference(0.0, 2.0) == 1.0);
  CHECK(relative_difference(2.0, 4.0) == doctest::Approx(0.5));
  CHECK(AreaSize{}.cost(4.0, 16.0) == doctest::Approx(0.5));  // |2 − 4| / 4
  Eigen::MatrixXd cost(3, 3);
  cost << 0.1, 0.5, 0.9,
          0.5, 0.1, 0.2,
          0.9, 0.2, 0.3;
  const auto one = mutual_nearest_pairs(cost, 1);
  REQUIRE(one.size() == 2);  // (0,0) and (1,1); row 2 prefers column 1, which prefers row 1
  CHECK(one[0].source == 0);
  CHECK(one[1].source == 1);
  CHECK(mutual_nearest_pairs(cost, 3).size() == 9);
}

namespace {
/// A user feature without a bound key: the pairing must compare it everywhere.
struct PassageCount {
  using descriptor_type = double;
  descriptor_type describe(const AreaGraph&, const Area& area) const { return static_cast<double>(area.passages.size()); }
  double cost(double a, double b) const { return relative_difference(a, b); }
};

/// Random descriptors of `count` areas, coarsely rounded so that many costs tie.
template <class Set>
typename Set::descriptors_type random_descriptors(detail::Random& random, std::size_t count) {
  typename Set::descriptors_type out;
  auto rounded = [&](double low, double high) { return std::round(random.uniform(low, high) * 2.0) / 2.0; };
  auto segment = [&](double length) { return AreaSegment{Eigen::Vector2d::Zero(), Eigen::Vector2d(length, 0.0)}; };
  for (std::size_t i = 0; i < count; ++i) {
    std::get<0>(out).push_back(rounded(0.0, 60.0));
    PassageDistances::descriptor_type passages;
    const int k = random.integer(0, 4);
    for (int p = 0; p < k * (k - 1) / 2; ++p) passages.lengths.push_back(rounded(0.5, 12.0));
    std::sort(passages.lengths.begin(), passages.lengths.end());
    for (double length : passages.lengths) passages.pairs.push_back(segment(length));
    passages.hull_diameter = segment(rounded(0.0, 15.0));
    std::get<1>(out).push_back(passages);
    std::get<2>(out).push_back(passages.hull_diameter);
    if constexpr (Set::size == 4) std::get<3>(out).push_back(static_cast<double>(random.integer(0, 3)));
  }
  return out;
}

template <class Set, std::size_t N>
void check_pruned_pairing(const Set& features, const std::array<double, N>& weights, std::uint64_t seed) {
  detail::Random random(seed);
  const std::size_t rows = static_cast<std::size_t>(random.integer(1, 120)), cols = static_cast<std::size_t>(random.integer(1, 120));
  const auto source = random_descriptors<Set>(random, rows), dest = random_descriptors<Set>(random, cols);
  for (std::size_t k : {std::size_t{1}, std::size_t{3}, std::size_t{10}, std::size_t{200}}) {
    const auto full = mutual_nearest_pairs(weighted_cost(features.costs(source, dest), weights), k);
    for (unsigned threads : {1u, 2u}) {
      const auto pruned = mutual_nearest_pairs(features, source, dest, weights, k, threads);
      REQUIRE(pruned.size() == full.size());
      for (std::size_t p = 0; p < full.size(); ++p) {
        CHECK(pruned[p].source == full[p].source);
        CHECK(pruned[p].dest == full[p].dest);
        CHECK(pruned[p].cost == full[p].cost);  // bit for bit
      }
    }
  }
}
}  // namespace

TEST_CASE("mutual pairs searched along the bound keys: exactly the full cost matrix's, bit for bit") {
  // Keys prune the search; the pairs, their order and their costs must not change. Ties are
  // frequent (rounded descriptors), k runs past the area counts, and a keyless user feature,
  // weights of zero and a key-only set are all covered.
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    CAPTURE(seed);
    check_pruned_pairing(PaperFeatures{}, PaperWeights{}.values, seed);
    check_pruned_pairing(PaperFeatures{}, std::array<double, 3>{0.0, 1.0, 0.0}, seed);
    check_pruned_pairing(PaperFeatures{}, std::array<double, 3>{0.5, 0.0, 0.5}, seed);
    check_pruned_pairing(FeatureSet<AreaSize, PassageDistances, HullDiameter, PassageCount>{},
                         std::array<double, 4>{0.1, 0.1, 0.5, 0.3}, seed);
  }
  CHECK(feature_has_bound_key_v<AreaSize>);
  CHECK(feature_has_bound_key_v<HullDiameter>);
  CHECK_FALSE(feature_has_bound_key_v<PassageDistances>);
  CHECK_FALSE(feature_has_bound_key_v<PassageCount>);
  CHECK_THROWS_AS(mutual_nearest_pairs(PaperFeatures{}, {}, {}, PaperWeights{}.values, 0), parameter_error);
  CHECK_THROWS_AS(mutual_nearest_pairs(PaperFeatures{}, {}, {}, std::array<double, 3>{0.5, 0.5, 0.5}, 3), parameter_error);
  CHECK(mutual_nearest_pairs(PaperFeatures{}, {}, {}, PaperWeights{}.values, 3).empty());
}

TEST_CASE("pose clustering: its binned leader search gives exactly a linear scan's clusters") {
  // PoseClusterer compares each hypothesis only with the leaders in neighbouring (rotation,
  // translation) bins; a linear scan compares it with every leader, earliest first. Clumps of
  // near-duplicates around a few poses (as many area pairs give), across the ±π seam and both
  // sides of the mirror, with tolerances and bin edges in between.
  detail::Random random(17);
  std::vector<Hypothesis> hypotheses;
  for (int centre = 0; centre < 30; ++centre) {
    const double rotation = random.uniform(-pi, pi);
    const Eigen::Vector2d translation(random.uniform(-20.0, 20.0), random.uniform(-20.0, 20.0));
    const bool reflected = random.uniform() < 0.3;
    for (int k = random.integer(1, 40); k > 0; --k) {
      Hypothesis h;
      h.T_dest_source.rotation = wrap_angle(rotation + random.uniform(-0.1, 0.1));
      h.T_dest_source.translation = translation + Eigen::Vector2d(random.uniform(-1.5, 1.5), random.uniform(-1.5, 1.5));
      h.T_dest_source.reflected = reflected;
      h.area_overlap = std::round(random.uniform(0.5, 1.0) * 20.0) / 20.0;  // ties, broken by cost
      h.pair_cost = random.uniform();
      hypotheses.push_back(h);
    }
  }
  // Poses exactly on bin edges and tolerances apart (multiples of 0.5 m and of 3°, ±π).
  for (int k = -4; k <= 4; ++k) {
    for (double degrees : {-180.0, -3.0, 0.0, 3.0, 6.0, 180.0}) {
      Hypothesis h;
      h.T_dest_source.rotation = degrees * pi / 180.0;
      h.T_dest_source.translation = Eigen::Vector2d(0.5 * k, -0.5 * (k % 3));
      h.area_overlap = 0.5 + 0.05 * ((k + 4) % 3);
      h.pair_cost = 0.01 * (k + 4) + degrees / 1000.0;
      hypotheses.push_back(h);
    }
  }
  for (const auto& tolerances : {std::pair{3.0 * pi / 180.0, 1.0}, std::pair{0.05, 0.3}, std::pair{2.5, 4.0},
                                 std::pair{3.0 * pi / 180.0, 0.5}, std::pair{4.0, 0.25}}) {
    const double rotation = tolerances.first, translation = tolerances.second;  // (lambdas below capture them)
    PoseClusterer clusterer;
    clusterer.params.rotation_rad = rotation;
    clusterer.params.translation_m = translation;
    const std::vector<Cluster> binned = clusterer.cluster(hypotheses);

    const std::vector<int> order = detail::by_overlap(hypotheses);
    std::vector<Cluster> linear;
    for (int i : order) {
      const Similarity2& T = hypotheses[static_cast<std::size_t>(i)].T_dest_source;
      auto joins = [&](const Cluster& c) {
        const Similarity2& L = hypotheses[static_cast<std::size_t>(c.members.front())].T_dest_source;
        return L.reflected == T.reflected && std::abs(wrap_angle(L.rotation - T.rotation)) <= rotation &&
               (L.translation - T.translation).norm() <= translation;
      };
      const auto it = std::find_if(linear.begin(), linear.end(), joins);
      if (it == linear.end()) linear.push_back({{i}, T.rotation, 0.0});
      else it->members.push_back(i);
    }
    detail::finish_clusters(hypotheses, order, linear);
    std::stable_sort(linear.begin(), linear.end(), [](const Cluster& a, const Cluster& b) { return a.total_overlap > b.total_overlap; });

    INFO("tolerances " << rotation << " rad, " << translation << " m: " << binned.size() << " clusters");
    REQUIRE(binned.size() == linear.size());
    CHECK(binned.size() > 1);
    CHECK(binned.size() < hypotheses.size());
    for (std::size_t c = 0; c < binned.size(); ++c) CHECK(binned[c].members == linear[c].members);
  }
}

TEST_CASE("angular clustering does not depend on the hypotheses' order") {
  std::vector<Hypothesis> hypotheses;
  for (double degrees : {10.0, 11.0, 12.5, 100.0, 101.0, -179.0, 179.5, 10.5}) {
    Hypothesis h;
    h.T_dest_source.rotation = degrees * pi / 180.0;
    h.area_overlap = 0.5 + 0.01 * degrees / 180.0;
    hypotheses.push_back(h);
  }
  const auto clusters = AngularClusterer{}.cluster(hypotheses);
  REQUIRE(clusters.size() == 3);
  CHECK(clusters[0].members.size() == 4);              // 10, 10.5, 11, 12.5 degrees
  CHECK(clusters[1].members.size() == 2);
  std::vector<Hypothesis> reversed(hypotheses.rbegin(), hypotheses.rend());
  const auto again = AngularClusterer{}.cluster(reversed);
  REQUIRE(again.size() == clusters.size());
  for (std::size_t i = 0; i < again.size(); ++i) {
    CHECK(again[i].members.size() == clusters[i].members.size());
    CHECK(again[i].rotation == doctest::Approx(clusters[i].rotation));
  }
}

namespace {

/// Boundary points of a corridor (walls at y = 0 and y = 1.2, x in [0, 30]) with room dividers
/// every 3 m above it (x = 3, 6, ..., 27; y in [1.2, 4]), 0.05 m apart.
std::vector<Eigen::Vector2d> corridor_with_dividers() {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i <= 600; ++i) {
    points.emplace_back(0.05 * i, 0.0);
    points.emplace_back(0.05 * i, 1.2);
  }
  for (int k = 1; k <= 9; ++k)
    for (int j = 1; j <= 56; ++j) points.emplace_back(3.0 * k, 1.2 + 0.05 * j);
  return points;
}

}  // namespace

TEST_CASE("boundary normals lie across the walls") {
  std::vector<Eigen::Vector2d> line;
  const Eigen::Vector2d along(std::cos(0.5), std::sin(0.5));
  for (int i = 0; i < 100; ++i) line.push_back(0.05 * i * along);
  const BoundaryLookup lookup(line, 0.1, 1.0, 0.2);
  REQUIRE(lookup.has_normals());
  for (const auto& p : line) CHECK(std::abs(lookup.normal_at(lookup.nearest(p)).dot(along)) < 1e-9);
  CHECK_FALSE(BoundaryLookup(line, 0.1, 1.0).has_normals());
}

TEST_CASE("point-to-line ICP pins a map sliding along a corridor to its room dividers") {
  const auto dest_points = corridor_with_dividers();
  // The robot saw the middle of the corridor only; its map starts 0.45 m along and 0.1 m across.
  std::vector<Eigen::Vector2d> source;
  for (const auto& p : dest_points)
    if (p.x() > 5.0 && p.x() < 25.0) source.push_back(p);
  const BoundaryLookup dest(dest_points, 0.1, 2.0, 0.2);
  Similarity2 start;
  start.translation = Eigen::Vector2d(0.45, 0.1);
  start.rotation = 0.01;
  RefineParams params;
  const Similarity2 line_fit = refine_icp(source, dest, start, params);
  CHECK(line_fit.translation.norm() < 0.01);
  CHECK(std::abs(line_fit.rotation) < 1e-3);
  params.point_to_line = false;
  const Similarity2 point_fit = refine_icp(source, dest, start, params);
  MESSAGE("point-to-point ends " << point_fit.translation.norm() << " m off, point-to-line " << line_fit.translation.norm() << " m");
  CHECK(line_fit.translation.norm() <= point_fit.translation.norm());
}
namespace {

/// A corridor (y 0.5–2 m) under a wall 0.2 m thick and a room as long above it (y 2.2–6 m), 0.05 m
/// cells; the room free when `room_entered`, else walled in (another map's robot never went in).
OccupancyGrid corridor_and_room(bool room_entered) {
  OccupancyGrid grid(240, 140, 0.05, {}, CellState::unknown);
  for (int row = 0; row < grid.height(); ++row) {
    for (int col = 0; col < grid.width(); ++col) {
      const Eigen::Vector2d p = grid.cell_center(col, row);
      const bool inside = p.x() > 0.5 && p.x() < 11.5 && p.y() > 0.3 && p.y() < 6.2;
      if (!inside) continue;
      const bool corridor = p.x() > 0.7 && p.x() < 11.3 && p.y() > 0.5 && p.y() < 2.0;
      const bool room = p.x() > 0.7 && p.x() < 11.3 && p.y() > 2.2 && p.y() < 6.0;
      grid.set(col, row, corridor || (room && room_entered) ? CellState::free : CellState::occupied);
    }
  }
  return grid;
}

/// World centres of the free cells with a 4-neighbour that is not free.
std::vector<Eigen::Vector2d> free_edge_points(const OccupancyGrid& grid) {
  std::vector<Eigen::Vector2d> points;
  auto free = [&](int col, int row) { return grid.contains(col, row) && grid.is_free(col, row); };
  for (int row = 0; row < grid.height(); ++row) {
    for (int col = 0; col < grid.width(); ++col) {
      if (free(col, row) && !(free(col - 1, row) && free(col + 1, row) && free(col, row - 1) && free(col, row + 1))) {
        points.push_back(grid.cell_center(col, row));
      }
    }
  }
  return points;
}

}  // namespace

TEST_CASE("counting wall inliers may stop early only below what it was told is enough") {
  // The candidates' first ranking stops counting one that cannot reach the worst kept count
  // (WholeMapSelection); a count that reaches `enough` must be the full count.
  detail::Random random(31);
  std::vector<Eigen::Vector2d> walls, points;
  for (int i = 0; i < 400; ++i) walls.emplace_back(random.uniform(0.0, 20.0), std::floor(random.uniform(0.0, 5.0)) * 3.0);
  for (int i = 0; i < 300; ++i) points.emplace_back(random.uniform(0.0, 20.0), std::floor(random.uniform(0.0, 5.0)) * 3.0 + random.uniform(-0.8, 0.8));
  const BoundaryLookup lookup(walls, 0.1, 2.0);
  for (int t = 0; t < 40; ++t) {
    const Similarity2 T{random.uniform(-0.2, 0.2), Eigen::Vector2d(random.uniform(-1.0, 1.0), random.uniform(-1.0, 1.0)), 1.0, false};
    const std::size_t full = lookup.count_within(points, T, 0.5);
    CHECK(full == static_cast<std::size_t>(std::lround(boundary_inlier_fraction(points, lookup, T, 0.5) * 300.0)));
    for (const std::size_t enough : {std::size_t{1}, full / 2, full, full + 1, full + 40, std::size_t{300}}) {
      const std::size_t counted = lookup.count_within(points, T, 0.5, enough);
      if (full >= enough) CHECK(counted == full);
      else CHECK(counted < enough);
    }
  }
}

TEST_CASE("ICP pairs a wall's face only with a face looking the same way") {
  // The source entered the room, the destination did not: the room's floor-side face lies 0.2 m
  // above the corridor's ceiling-side face, and pairing the two would pull the map across the wall.
  const OccupancyGrid source_grid = corridor_and_room(true), dest_grid = corridor_and_room(false);
  const std::vector<Eigen::Vector2d> source = free_edge_points(source_grid);
  BoundaryLookup dest(free_edge_points(dest_grid), 0.1, 2.0, 0.2);
  RefineParams params;
  params.same_side_only = true;
  dest.set_sides(detail::free_sides(dest_grid, dest.points(), params.free_side_radius_m));
  const std::vector<Eigen::Vector2d> sides = detail::free_sides(source_grid, source, params.free_side_radius_m);
  // Sides point into the free space: up on the corridor's floor, down on its ceiling.
  auto side_near = [&](const Eigen::Vector2d& p) {
    std::size_t best = 0;
    for (std::size_t i = 0; i < source.size(); ++i) {
      if ((source[i] - p).norm() < (source[best] - p).norm()) best = i;
    }
    return sides[best];
  };
  CHECK(side_near({5.0, 0.52}).y() > 0.9);
  CHECK(side_near({5.0, 2.23}).y() > 0.9);  // the room's floor
  CHECK(dest.side_at(dest.nearest({5.0, 1.98})).y() < -0.9);
  Similarity2 start;
  start.translation = Eigen::Vector2d(0.12, 0.15);
  start.rotation = 0.01;
  const Similarity2 same_side = refine_icp(source, dest, start, params, &sides);
  params.same_side_only = false;
  const Similarity2 any_side = refine_icp(source, dest, start, params, &sides);
  MESSAGE("same side only: " << same_side.translation.norm() << " m off; any side: " << any_side.translation.norm() << " m off");
  CHECK(same_side.translation.norm() < 0.01);
  CHECK(std::abs(same_side.rotation) < 1e-3);
  CHECK(any_side.translation.norm() > 0.05);
  CHECK_THROWS_AS(dest.set_sides({}), parameter_error);
}

TEST_CASE("prepared maps: the same results as matching the grids, bit for bit; a mismatched matcher refuses them") {
  const auto c = areamatch_test::synthetic_case(11);
  Matcher<> matcher;
  matcher.params.allow_reflection = true;
  const auto source = matcher.prepare(c.robot.grid);
  const auto dest = matcher.prepare(c.building.layout);
  const std::string expected = without_timings(matcher.match(c.robot.grid, c.building.layout));
  const MatchResult prepared = matcher.match(source, dest);
  CHECK(without_timings(prepared) == expected);
  CHECK(prepared.timings.prepare_s == 0.0);
  CHECK(without_timings(matcher.match(c.robot.grid, dest)) == expected);
  CHECK(without_timings(matcher.match(source, dest)) == expected);  // reused: unchanged
  CHECK(source.graph().areas.size() == prepared.statistics.source_areas);
  CHECK(dest.grid() == c.building.layout);

  const PaperMatcher paper;
  CHECK(without_timings(paper.match(paper.prepare(c.robot.grid), paper.prepare(c.building.layout))) ==
        without_timings(paper.match(c.robot.grid, c.building.layout)));

  // The source's scale unknown: onto a prepared destination as onto its grid.
  Matcher<> scaled = matcher;
  scaled.params.estimate_scale = true;
  if (!areamatch_test::quick_tests()) {
    CHECK(without_timings(scaled.match(c.robot.grid, dest)) == without_timings(scaled.match(c.robot.grid, c.building.layout)));
  }
  CHECK_THROWS_WITH_AS(scaled.match(source, dest), doctest::Contains("estimate_scale"), parameter_error);

  Matcher<> other = matcher;
  other.params.coarse_cell_m *= 2.0;
  CHECK_THROWS_WITH_AS(other.match(source, dest), doctest::Contains("prepared by a matcher with another coarse_cell_m"),
                       parameter_error);
  other = matcher;
  other.params.decision.min_agreement = 0.5;  // the decision is not part of a prepared map
  CHECK_NOTHROW(other.match(source, dest));

  // A map without areas prepares, and matching it says why it cannot.
  const OccupancyGrid walls(40, 40, 0.05, {}, CellState::occupied);
  const auto empty = matcher.prepare(walls);
  const MatchResult none = matcher.match(source, empty);
  CHECK_FALSE(none.ok);
  CHECK(none.reason.find("no areas") != std::string::npos);
}

TEST_CASE("the raster overlap estimates the exact polygon overlap (the paper's OP)") {
  // The default hypotheses filter on OP counted on 0.25 m rasters from at most 128 cells
  // (raster_area_overlap); the paper's preset intersects the polygons with Boost.Geometry
  // (exact_area_overlap). Same areas, same transforms: the estimate must follow the exact value.
  const auto building = generate_building({}, 8);
  const AreaGraph graph = VoronoiSegmenter{}.segment(building.layout);
  REQUIRE(graph.areas.size() > 5);
  const AreaRaster raster = make_area_raster(graph, MatcherParams{}.coarse_cell_m);
  detail::Random random(9);
  double worst = 0.0, total = 0.0;
  int compared = 0, filter_disagreements = 0;
  for (int trial = 0; trial < 20; ++trial) {
    Similarity2 T;
    T.rotation = random.uniform(-0.1, 0.1);
    T.translation = Eigen::Vector2d(random.uniform(-1.5, 1.5), random.uniform(-1.5, 1.5));
    for (std::size_t i = 0; i < graph.areas.size(); ++i) {
      for (std::size_t j = 0; j < graph.areas.size(); ++j) {
        const std::optional<double> exact = detail::exact_area_overlap(graph.areas[i], graph.areas[j], T);
        REQUIRE(exact.has_value());
        const double estimate = raster_area_overlap(raster, raster, static_cast<int>(i), static_cast<int>(j),
                                                    graph.areas[i].size_m2, graph.areas[j].size_m2, T);
        if (*exact == 0.0 && estimate == 0.0) continue;
        const double error = std::abs(estimate - *exact);
        worst = std::max(worst, error);
        total += error;
        ++compared;
        // Where it matters, at the filter's 0.5, the two must not disagree by much.
        if (std::abs(*exact - 0.5) > 0.1) filter_disagreements += (estimate >= 0.5) != (*exact >= 0.5);
      }
    }
  }
  REQUIRE(compared > 100);
  MESSAGE(compared << " overlapping area pairs: mean error " << total / compared << ", worst " << worst
                   << "; filter decisions differing away from 0.5: " << filter_disagreements);
  // Measured: mean 0.027; the worst, up to 0.29, are a large corridor (1235 cells) against a
  // small room: 128 evenly spread corridor cells, of which only ~10 land in the room. Sampling
  // the smaller of the two areas would fix that (a known weakness; it would change the default
  // matcher's hypotheses, so it waits for a recalibration). Two of the 1058 filter decisions
  // away from 0.5 differ.
  CHECK(total / compared < 0.05);
  CHECK(worst < 0.35);
  CHECK(filter_disagreements <= compared / 100);
}

namespace {
/// The smallest selection policy (match/verification/selection.hpp's example): the best cluster's best member.
struct FirstClusterSelection {
  Selected select(const SelectionInputs& in, MatchStatistics&) const {
    Selected out;
    if (in.clusters.empty()) return out;
    const int best = in.clusters.front().members.front();
    out.finalists.push_back({in.hypotheses[static_cast<std::size_t>(best)].T_dest_source, 0.0});
    return out;
  }
};
}  // namespace

TEST_CASE("every clusterer with every selection, through the same synthetic cases") {
  // The two clusterers (PoseClusterer, AngularClusterer) and the selections (WholeMapSelection,
  // LargestClusterSelection, and one of our own) compose freely: every composition runs,
  // deterministically. The default (PoseClusterer + whole map) is right on every case. Measured
  // on the 8 cases: AngularClusterer + whole map 4 (a cluster per rotation keeps one candidate
  // per rotation, whatever its translation: the whole-map check needs pose clusters),
  // PoseClusterer + largest cluster 8 (our hypotheses and pose clusters carry the paper's
  // selection here), AngularClusterer + largest cluster 5 (the paper's clustering).
  static_assert(is_selection_v<FirstClusterSelection> && !is_selection_v<PoseClusterer>);
  const CorrectnessThresholds thresholds{3.0, 0.5};
  // Quick runs (the sanitizer build): every composition still runs, twice, on one case; the
  // counts are the Release run's to check.
  const std::uint64_t cases = areamatch_test::quick_tests() ? 1 : 8;
  auto run = [&](auto matcher) {
    matcher.params.allow_reflection = true;
    int right = 0;
    for (std::uint64_t seed = 200; seed < 200 + cases; ++seed) {
      const auto c = areamatch_test::synthetic_case(seed);
      const MatchResult r = matcher.match(c.robot.grid, c.building.layout);
      const MatchResult again = matcher.match(c.robot.grid, c.building.layout);
      CHECK(without_timings(again) == without_timings(r));  // deterministic in every composition
      CHECK(r.statistics.clusters > 0);
      CHECK(std::isfinite(r.T_dest_source.rotation));
      const MatchError e = match_error(r.pixel_transform, c.robot.pixel_transform, free_edge_pixels(c.robot.grid),
                                       c.building.layout.resolution());
      right += r.ok && e.correct(thresholds);
    }
    return right;
  };
  using Features = PaperFeatures;
  using Weights = PaperWeights;
  using AngularWhole = Matcher<VoronoiSegmenter, Features, Weights, AngularClusterer, WholeMapSelection>;
  using PoseLargest = Matcher<VoronoiSegmenter, Features, Weights, PoseClusterer, LargestClusterSelection>;
  using AngularLargest = Matcher<VoronoiSegmenter, Features, Weights, AngularClusterer, LargestClusterSelection>;
  using PoseFirst = Matcher<VoronoiSegmenter, Features, Weights, PoseClusterer, FirstClusterSelection>;
  const int pose_whole = run(Matcher<>{});
  const int angular_whole = run(AngularWhole{});
  const int pose_largest = run(PoseLargest{});
  const int angular_largest = run(AngularLargest{});
  const int pose_first = run(PoseFirst{});
  MESSAGE("right of " << cases << ": pose + whole map " << pose_whole << ", angular + whole map " << angular_whole
                      << ", pose + largest cluster " << pose_largest << ", angular + largest cluster " << angular_largest
                      << ", pose + first cluster (ours) " << pose_first);
  CHECK(pose_whole == static_cast<int>(cases));
  CHECK(pose_largest >= 1);
  CHECK(pose_first >= 1);
  // The angular compositions are right on about half the cases, and which half depends on the
  // compiler (clang 14 -O1: 3 and 4 of 8 against GCC's 4 and 5): on the quick mode's one case
  // none may be right, so their counts are checked on the full eight only.
  if (!areamatch_test::quick_tests()) {
    CHECK(angular_whole >= 1);
    CHECK(angular_largest >= 1);
  }
}

TEST_CASE("a rejected match's picture says so in a red band above it; an accepted one has none") {
  const OccupancyGrid layout = generate_building({}, 3).layout;
  const AreaGraph graph = VoronoiSegmenter{}.segment(layout);
  MatchResult result;
  result.ok = true;
  const RgbImage accepted = render_match(layout, graph, layout, graph, result);
  result.ok = false;
  result.reason = "the maps agree too little under the best transform to be the same building: agreement 0.747 < "
                  "min_agreement 0.835 (the destination's walls near the source's free space explained: 0.810)";
  const RgbImage rejected = render_match(layout, graph, layout, graph, result);
  CHECK(rejected.width == accepted.width);
  const int band = rejected.height - accepted.height;
  REQUIRE(band > 0);
  auto pixel = [](const RgbImage& image, int c, int r) {
    const std::uint8_t* p = &image.rgb[(static_cast<std::size_t>(r) * image.width + c) * 3];
    return std::array<int, 3>{p[0], p[1], p[2]};
  };
  CHECK(pixel(rejected, 0, 0) == std::array<int, 3>{190, 30, 30});
  int letters = 0;
  for (int r = 0; r < band; ++r) {
    for (int c = 0; c < rejected.width; ++c) letters += pixel(rejected, c, r) == std::array<int, 3>{255, 255, 255};
  }
  CHECK(letters > 100);
  bool same_below = true;
  for (int r = 0; r < accepted.height && same_below; ++r) {
    for (int c = 0; c < accepted.width; ++c) same_below = same_below && pixel(rejected, c, r + band) == pixel(accepted, c, r);
  }
  CHECK(same_below);
  // A picture too narrow for the reason: cut, never past the edge.
  const RgbImage narrow = with_rejection_banner(RgbImage(30, 10), result.reason);
  CHECK(narrow.width == 30);
  CHECK(narrow.height > 10);
}

TEST_CASE("a refusal says 'different places' only when the evidence is against, else 'not sure'") {
  const MatcherParams params;
  MatchResult result;
  result.score = 0.6;
  result.margin = 0.2;
  result.evidence.agreement = 0.7;  // below min_agreement
  result.evidence.forward_wall_agreement = 0.5;
  result.evidence.reverse_wall_agreement = 0.8;
  result.evidence.overlap_m2 = 300.0;
  // A right answer the evidence does not carry (Intel's: agreement 0.77, p_correct 0.04): not sure,
  // and nothing says the maps are of different buildings.
  result.p_correct = 0.04;
  detail::Refusal r = detail::refusal(result, params.decision, true);
  CHECK(r.kind == Rejection::not_sure);
  CHECK(r.reason.find("not sure: ") == 0);
  CHECK(r.reason.find("same building") == std::string::npos);
  CHECK(r.reason.find("different places") == std::string::npos);
  CHECK(r.reason.find("it may be another building, or this one mapped too differently") != std::string::npos);
  // The model all but sure it is wrong: different places.
  result.p_correct = 0.5 * params.decision.different_places_p;
  r = detail::refusal(result, params.decision, true);
  CHECK(r.kind == Rejection::different_places);
  CHECK(r.reason.find("different places: ") == 0);
  CHECK(r.reason.find("< different_places_p") != std::string::npos);
  // A whole-map score below min_score: different places, whatever the model.
  result.p_correct = 0.5;
  result.score = 0.5 * params.decision.min_score;
  r = detail::refusal(result, params.decision, true);
  CHECK(r.kind == Rejection::different_places);
  result.score = 0.6;
  // The maps agree but the gate is closed (walls agree both ways) and the model is not sure: not sure.
  result.evidence.agreement = 0.9;
  result.evidence.forward_wall_agreement = result.evidence.reverse_wall_agreement = 0.9;
  r = detail::refusal(result, params.decision, true);
  CHECK(r.kind == Rejection::not_sure);
  CHECK(r.reason.find("not sure: the maps agree") == 0);
  // A close rival: not sure, even with a model that would accept.
  MatcherParams strict = params;
  strict.decision.min_margin = 0.05;
  result.p_correct = 0.99;
  result.margin = 0.01;
  r = detail::refusal(result, strict.decision, true);
  CHECK(r.kind == Rejection::not_sure);
  CHECK(r.reason.find("not sure: ambiguous") == 0);
  // Accepted: no refusal.
  result.margin = 0.2;
  r = detail::refusal(result, strict.decision, true);
  CHECK(r.reason.empty());
  CHECK(r.kind == Rejection::none);
  // No answer at all: a map without areas.
  const OccupancyGrid walls(60, 40, 0.05, {}, CellState::occupied);
  const MatchResult empty = Matcher<>{}.match(walls, walls);
  CHECK_FALSE(empty.ok);
  CHECK(empty.rejection == Rejection::no_answer);
  CHECK(to_string(Rejection::not_sure) == std::string("not sure"));
}

TEST_CASE("match_grids keeps a matcher's own settings where the options leave them unset") {
  // apply_match_options used to write allow_reflection and threads whatever the options said,
  // so a matcher's own allow_reflection was silently turned off (issue 45, item 1).
  const auto pair = small_mirrored_pair();  // (no structured binding: clang will not capture one in INFO)
  const SyntheticBuilding& building = pair.first;
  const RobotMap& robot = pair.second;
  Matcher<> mine;
  mine.params.allow_reflection = true;
  mine.params.threads = 2;
  const MapPairRun kept = match_grids(mine, robot.grid, building.layout);
  CHECK(kept.result.ok);
  CHECK(kept.result.T_dest_source.reflected);
  MapPairOptions off;
  off.allow_reflection = false;  // set: it wins over the matcher's
  const MapPairRun overridden = match_grids(mine, robot.grid, building.layout, off);
  CHECK_FALSE(overridden.result.T_dest_source.reflected);
  MatcherParams applied = mine.params;
  detail::apply_match_options(applied, MapPairOptions{});
  CHECK(applied.allow_reflection);
  CHECK(applied.threads == 2u);
  // Settings by name patch the matcher; what they do not name stays the matcher's own.
  MapPairOptions patch;
  patch.settings = {{"k", "4"}, {"decision.min_agreement", "0.9"}, {"selection.verify_candidates", "20"}};
  const Matcher<> patched = detail::configured_matcher(mine, patch);
  CHECK(patched.params.k == 4);
  CHECK(patched.params.decision.min_agreement == 0.9);
  CHECK(patched.selection.params.verify_candidates == 20);
  CHECK(patched.params.allow_reflection);
  CHECK(patched.params.threads == 2u);
}
