// Merging several maps into one frame: the pose fit, the fusion rule and merge_maps on
// generated buildings with their exact ground truth.
#include "synthetic_cases.hpp"
#include "test_support.hpp"

#include <areamatch/areamatch.hpp>
#include <areamatch/merge.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

using namespace areamatch;

namespace {

Similarity2 pose(double degrees, double x, double y, bool reflected = false) {
  Similarity2 T;
  T.rotation = degrees * pi / 180.0;
  T.translation = {x, y};
  T.reflected = reflected;
  return T;
}

PoseConstraint constraint(std::size_t source, std::size_t dest, const Similarity2& T_dest_source, double weight = 1.0) {
  PoseConstraint c;
  c.source = source;
  c.dest = dest;
  c.T_dest_source = T_dest_source;
  c.anchors = {{0.0, 0.0}, {5.0, 0.0}, {5.0, 4.0}, {0.0, 4.0}};
  c.weight = weight;
  return c;
}

double rotation_error_deg(const Similarity2& a, const Similarity2& b) {
  return std::abs(wrap_angle(a.rotation - b.rotation)) * 180.0 / pi;
}

/// Mean distance between a map's free cells laid by two poses (the rule of shared/tools/score.py,
/// on free cells instead of their edge).
double mean_displacement_m(const OccupancyGrid& grid, const Similarity2& a, const Similarity2& b) {
  double sum = 0.0;
  std::size_t count = 0;
  for (int row = 0; row < grid.height(); row += 7) {
    for (int col = 0; col < grid.width(); col += 7) {
      if (!grid.is_free(col, row)) continue;
      const Eigen::Vector2d p = grid.cell_center(col, row);
      sum += (a * p - b * p).norm();
      ++count;
    }
  }
  return count ? sum / static_cast<double>(count) : 0.0;
}

/// IoU of the merged map's free space and the building's, where the placed maps explored (cells
/// of rooms none of them entered are left out).
double explored_free_iou(const MergeResult& result, const areamatch_test::MergeCase& c) {
  std::set<int> explored;
  for (std::size_t m = 0; m < c.robots.size(); ++m) {
    if (result.maps[m].placed) explored.insert(c.robots[m].explored_areas.begin(), c.robots[m].explored_areas.end());
  }
  const OccupancyGrid& merged = result.merged;
  const Similarity2 layout_from_reference = c.robots[0].T_dest_source;
  const OccupancyGrid& layout = c.building.layout;
  std::size_t both = 0, either = 0;
  for (int row = 0; row < merged.height(); ++row) {
    for (int col = 0; col < merged.width(); ++col) {
      const Eigen::Vector2i cell = layout.world_to_cell(layout_from_reference * merged.cell_center(col, row));
      const int label = layout.contains(cell.x(), cell.y()) ? c.building.labels[layout.index(cell.x(), cell.y())] : -1;
      if (label >= 0 && !explored.count(label)) continue;
      const bool truth_free = label >= 0;
      const bool merged_free = merged.is_free(col, row);
      both += truth_free && merged_free;
      either += truth_free || merged_free;
    }
  }
  return either ? static_cast<double>(both) / static_cast<double>(either) : 0.0;
}

}  // namespace

TEST_CASE("fit_poses recovers exact poses over a loop, reflections included") {
  // Truth: map 0 the reference, map 1 turned and shifted, map 2 mirrored.
  const std::vector<Similarity2> truth = {Similarity2{}, pose(30, 4, -2), pose(-100, -3, 7, true)};
  auto between = [&](std::size_t s, std::size_t d) { return truth[d].inverse() * truth[s]; };
  const std::vector<PoseConstraint> constraints = {constraint(1, 0, between(1, 0)), constraint(2, 1, between(2, 1)),
                                                   constraint(0, 2, between(0, 2))};
  const PoseFit fit = fit_poses(3, 0, constraints, {true, true, true});
  for (std::size_t m = 0; m < 3; ++m) {
    CHECK(bool(fit.placed[m]));
    CHECK(fit.T_reference_map[m].reflected == truth[m].reflected);
    CHECK(rotation_error_deg(fit.T_reference_map[m], truth[m]) < 1e-9);
    CHECK((fit.T_reference_map[m].translation - truth[m].translation).norm() < 1e-9);
    CHECK(fit.T_reference_map[m].scale == 1.0);
  }
  for (double r : fit.residual_m) CHECK(r < 1e-9);
}

TEST_CASE("fit_poses: a wrong match in a loop stands out, a mirror conflict is flagged, lone maps stay unplaced") {
  const std::vector<Similarity2> truth = {Similarity2{}, pose(90, 10, 0), pose(180, 0, 10), pose(0, 20, 20)};
  auto between = [&](std::size_t s, std::size_t d) { return truth[d].inverse() * truth[s]; };
  std::vector<PoseConstraint> constraints = {constraint(1, 0, between(1, 0), 0.99), constraint(2, 0, between(2, 0), 0.99),
                                             constraint(2, 1, between(2, 1), 0.95),
                                             constraint(1, 2, pose(0, 3, 0) * between(1, 2), 0.9)};  // slid by 3 m
  PoseFit fit = fit_poses(4, 0, constraints, {true, true, true, true});
  CHECK_FALSE(bool(fit.placed[3]));  // map 3 has no constraint
  const auto worst = std::max_element(fit.residual_m.begin(), fit.residual_m.end()) - fit.residual_m.begin();
  CHECK(worst == 3);
  CHECK(fit.residual_m[3] > 1.0);
  fit = fit_poses(4, 0, constraints, {true, true, true, false});
  CHECK(rotation_error_deg(fit.T_reference_map[1], truth[1]) < 1e-9);
  CHECK((fit.T_reference_map[2].translation - truth[2].translation).norm() < 1e-9);

  constraints[2].T_dest_source.reflected = true;  // a mirrored answer against two that are not
  fit = fit_poses(4, 0, constraints, {true, true, true, false});
  CHECK(bool(fit.mirror_conflict[2]));
  CHECK_FALSE(bool(fit.mirror_conflict[0]));
  CHECK(std::isnan(fit.residual_m[2]));

  CHECK_THROWS_AS(fit_poses(4, 4, constraints, {true, true, true, true}), parameter_error);
  CHECK_THROWS_AS(fit_poses(4, 0, constraints, {true}), parameter_error);
}

TEST_CASE("fuse_maps: walls kept where half the maps saw them, free where only free was seen") {
  OccupancyGrid a(10, 10, 0.1, {}, CellState::free), b(10, 10, 0.1, {}, CellState::free);
  a.set(2, 2, CellState::occupied);
  for (int col = 0; col < 10; ++col) b.set(col, 9, CellState::unknown);
  const Similarity2 shift = pose(0, 0.5, 0);  // b lies 5 cells to the right of a
  FuseParams tight;
  tight.margin_m = 0.0;  // no unknown border around what the maps saw
  const OccupancyGrid merged = fuse_maps({&a, &b}, {Similarity2{}, shift}, tight);
  CHECK(merged.width() == 15);
  CHECK(merged.height() == 10);
  CHECK(merged.resolution() == 0.1);
  CHECK(merged.at(2, 2) == CellState::occupied);   // a: wall, b: not there
  CHECK(merged.at(12, 9) == CellState::unknown);   // only b, unknown
  CHECK(merged.at(12, 2) == CellState::free);
  const OccupancyGrid c = fuse_maps({&a, &b, &b}, {Similarity2{}, Similarity2{}, Similarity2{}}, tight);
  CHECK(c.at(2, 2) == CellState::free);  // one wall against two free: outvoted
  CHECK(fuse_maps({&a, &b}, {Similarity2{}, shift}).width() == 35);  // 1 m of unknown on each side by default
  FuseParams coarse;
  coarse.margin_m = -1.0;  // the maps' whole extent
  coarse.resolution = 0.2;
  CHECK(fuse_maps({&a, &b}, {Similarity2{}, shift}, coarse).width() == 8);  // ceil(1.5 / 0.2)
  coarse.wall_share = 0.0;
  CHECK_THROWS_AS(fuse_maps({&a}, {Similarity2{}}, coarse), parameter_error);
  CHECK_THROWS_AS(fuse_maps({&a, &b}, {Similarity2{}}), parameter_error);

  // The unknown margin is cut to margin_m around what the maps saw; cells stay where they were.
  OccupancyGrid scan(100, 80, 0.1, {-2.0, 3.0, 0.0});
  scan.set(40, 30, CellState::free);
  scan.set(60, 50, CellState::occupied);
  FuseParams margin;
  margin.margin_m = 0.5;
  const OccupancyGrid cropped = fuse_maps({&scan}, {Similarity2{}}, margin);
  CHECK(cropped.width() == 31);   // 21 columns seen + 5 on each side
  CHECK(cropped.height() == 31);
  CHECK(cropped.at(5, 5) == CellState::free);
  CHECK(cropped.at(25, 25) == CellState::occupied);
  CHECK((cropped.cell_center(5, 5) - scan.cell_center(40, 30)).norm() < 1e-9);
  margin.margin_m = -1.0;
  CHECK(fuse_maps({&scan}, {Similarity2{}}, margin).width() == 100);
}

TEST_CASE("merge_maps places N robot maps of generated buildings (N = 2, 5, 10, one mirrored)") {
  const bool quick = areamatch_test::quick_tests();
  MatcherParams params;
  params.allow_reflection = true;
  const Matcher<> matcher(params);
  for (std::size_t n : quick ? std::vector<std::size_t>{2, 3} : std::vector<std::size_t>{2, 5, 10}) {
    const int buildings = quick ? 1 : 20;
    int all_right = 0, maps_right = 0, maps_total = 0, maps_wrong = 0;
    double min_iou = 1.0;
    for (int b = 0; b < buildings; ++b) {
      const auto c = areamatch_test::merge_case(static_cast<std::uint64_t>(1000 * n + b), n, /*mirror_one=*/true, quick);
      std::vector<Matcher<>::PreparedMap> maps;
      for (const auto& robot : c.robots) maps.push_back(matcher.prepare(robot.grid));
      const MergeResult merged = merge_maps(matcher, maps);
      bool right = merged.ok;
      for (std::size_t m = 0; m < n; ++m) {
        const MergedMap& out = merged.maps[m];
        const bool ok = out.placed && out.T_reference_map.reflected == c.truth[m].reflected &&
                        rotation_error_deg(out.T_reference_map, c.truth[m]) <= 0.5 &&
                        mean_displacement_m(c.robots[m].grid, out.T_reference_map, c.truth[m]) <= 0.1;
        if (!ok) {
          MESSAGE("N " << n << " building " << b << " map " << m << ": placed " << out.placed << " " << out.reason
                       << " rot err " << rotation_error_deg(out.T_reference_map, c.truth[m]) << " disp "
                       << mean_displacement_m(c.robots[m].grid, out.T_reference_map, c.truth[m]));
        }
        // Placed wrongly by shared/tools/score.py's rule (3°, 1 m): the error a user must never get.
        maps_wrong += out.placed && (out.T_reference_map.reflected != c.truth[m].reflected ||
                                     rotation_error_deg(out.T_reference_map, c.truth[m]) > 3.0 ||
                                     mean_displacement_m(c.robots[m].grid, out.T_reference_map, c.truth[m]) > 1.0);
        right = right && ok;
        maps_right += ok;
        ++maps_total;
      }
      all_right += right;
      const double iou = explored_free_iou(merged, c);
      min_iou = std::min(min_iou, iou);
      if (iou < 0.9) MESSAGE("N " << n << " building " << b << ": explored free-space IoU " << iou);
    }
    MESSAGE("N = " << n << ": " << all_right << " / " << buildings << " buildings with every map right, " << maps_right
                   << " / " << maps_total << " maps, " << maps_wrong << " placed wrongly; lowest explored free-space IoU "
                   << min_iou);
    CHECK(maps_wrong == 0);
    // 95 % of the buildings with every map within 0.5° and 0.1 m. N = 2 reaches 19 / 20: one
    // pair of partial maps (building 16) overlaps too little, and its right mirrored transform
    // loses to a wrong one that is then rejected (not placed).
    CHECK(all_right >= 0.95 * buildings);
    CHECK(min_iou >= 0.9);
  }
}

TEST_CASE("merge_maps reports its own stages: every match counted, then the poses and the fused map") {
  MatcherParams params;
  params.allow_reflection = true;
  Matcher<> matcher(params);
  const auto c = areamatch_test::merge_case(3001, 3, /*mirror_one=*/true, true);
  std::vector<Matcher<>::PreparedMap> maps;
  for (const auto& robot : c.robots) maps.push_back(matcher.prepare(robot.grid));
  const MergeResult expected = merge_maps(matcher, maps);
  std::vector<std::string> stages;
  std::vector<std::size_t> counted;
  matcher.progress = [&](const Progress& p) {  // never two calls at once: no lock needed here
    stages.emplace_back(p.stage);
    if (p.stage == "match") {
      CHECK(p.total == 3);  // three maps: three pairs
      counted.push_back(p.done);
    }
  };
  const MergeResult reported = merge_maps(matcher, maps);
  CHECK(counted == std::vector<std::size_t>{0, 1, 2, 3});
  REQUIRE(stages.size() == 6);
  CHECK(stages[4] == "poses");
  CHECK(stages[5] == "fuse");
  REQUIRE(reported.maps.size() == expected.maps.size());
  for (std::size_t m = 0; m < expected.maps.size(); ++m) {
    CHECK(reported.maps[m].placed == expected.maps[m].placed);
    CHECK(reported.maps[m].T_reference_map.translation == expected.maps[m].T_reference_map.translation);
  }
}

TEST_CASE("merge_maps: the same-side refinement places two partial maps that entered rooms on opposite sides") {
  // Generated building 1 of N = 2: map 1 (mirrored) entered rooms across the corridor from map 0's,
  // and the matcher's nearest-point ICP pulls their sides of the corridor walls together.
  const auto c = areamatch_test::merge_case(2001, 2, /*mirror_one=*/true);
  MatcherParams params;
  params.allow_reflection = true;
  const Matcher<> matcher(params);
  const std::vector<Matcher<>::PreparedMap> maps{matcher.prepare(c.robots[0].grid), matcher.prepare(c.robots[1].grid)};
  MergeParams merge_params;
  merge_params.build_merged_map = false;
  const MergeResult refined = merge_maps(matcher, maps, merge_params);
  merge_params.refine_same_side = false;
  const MergeResult unrefined = merge_maps(matcher, maps, merge_params);
  REQUIRE(refined.maps[1].placed);
  REQUIRE(unrefined.maps[1].placed);
  const double with = mean_displacement_m(c.robots[1].grid, refined.maps[1].T_reference_map, c.truth[1]);
  const double without = mean_displacement_m(c.robots[1].grid, unrefined.maps[1].T_reference_map, c.truth[1]);
  MESSAGE("map 1 off by " << with << " m refined, " << without << " m unrefined");
  CHECK(with < 0.02);
  CHECK(without > 0.1);
  CHECK(refined.timings.refine_s > 0.0);
  CHECK(unrefined.timings.refine_s == 0.0);
}

TEST_CASE("merge_maps: a map of another building is reported as not placed and the others are unaffected") {
  const Matcher<> matcher;
  const bool quick = areamatch_test::quick_tests();
  const int buildings = quick ? 1 : 5;
  for (int b = 0; b < buildings; ++b) {
    const auto c = areamatch_test::merge_case(static_cast<std::uint64_t>(7000 + b), quick ? 2 : 4, /*mirror_one=*/false, quick);
    const auto other = areamatch_test::merge_case(static_cast<std::uint64_t>(8000 + b), 1, false, quick);
    std::vector<Matcher<>::PreparedMap> maps;
    for (const auto& robot : c.robots) maps.push_back(matcher.prepare(robot.grid));
    const MergeResult alone = merge_maps(matcher, maps);
    maps.push_back(matcher.prepare(other.robots[0].grid));
    MergeParams params;
    params.names.clear();
    for (std::size_t m = 0; m + 1 < maps.size(); ++m) params.names.push_back("map " + std::to_string(m));
    params.names.push_back("stranger");
    const MergeResult with_stranger = merge_maps(matcher, maps, params);
    CHECK_FALSE(with_stranger.ok);
    const std::size_t stranger = maps.size() - 1;
    CHECK_FALSE(with_stranger.maps[stranger].placed);
    CHECK(with_stranger.maps[stranger].reason.find("no accepted match") != std::string::npos);
    CHECK(with_stranger.maps[stranger].reason.find("was rejected: ") != std::string::npos);
    for (std::size_t m = 0; m < stranger; ++m) {
      CHECK(with_stranger.maps[m].placed == alone.maps[m].placed);
      CHECK(with_stranger.maps[m].T_reference_map.rotation == alone.maps[m].T_reference_map.rotation);
      CHECK(with_stranger.maps[m].T_reference_map.translation == alone.maps[m].T_reference_map.translation);
    }
    CHECK(with_stranger.merged == alone.merged);
  }
}

TEST_CASE("merge_maps: bad input is refused, maps without areas are reported, results are deterministic") {
  const Matcher<> matcher;
  const auto c = areamatch_test::merge_case(42, 2, false, areamatch_test::quick_tests());
  std::vector<Matcher<>::PreparedMap> maps{matcher.prepare(c.robots[0].grid)};
  CHECK_THROWS_AS(merge_maps(matcher, maps), parameter_error);  // one map
  maps.push_back(matcher.prepare(c.robots[1].grid));
  MergeParams params;
  params.reference = 2;
  CHECK_THROWS_AS(merge_maps(matcher, maps, params), parameter_error);
  params.reference = 1;
  params.names = {"only one name"};
  CHECK_THROWS_AS(merge_maps(matcher, maps, params), parameter_error);
  params.names.clear();
  params.max_residual_m = 0.0;
  CHECK_THROWS_AS(merge_maps(matcher, maps, params), parameter_error);

  // An all-unknown map has no areas: not placed, with the segmenter's reason.
  maps.push_back(matcher.prepare(OccupancyGrid(200, 200, 0.05)));
  const MergeResult result = merge_maps(matcher, maps);
  CHECK_FALSE(result.maps[2].placed);
  CHECK(result.maps[2].reason.find("no areas") != std::string::npos);
  // Its picture: the merged map, then a legend naming each map's colour, the unplaced one said so.
  std::vector<const OccupancyGrid*> grids;
  for (const auto& map : maps) grids.push_back(&map.grid());
  const RgbImage picture = render_merge(result, grids, {"plan", "robot", "blank"});
  CHECK(picture.width >= result.merged.width());
  CHECK(picture.height > result.merged.height());
  auto count_colour = [&](const Rgb& c, int from_row, int to_row) {
    int n = 0;
    for (int r = from_row; r < to_row; ++r)
      for (int col = 0; col < picture.width; ++col) {
        const std::uint8_t* p = &picture.rgb[(static_cast<std::size_t>(r) * picture.width + col) * 3];
        n += p[0] == c[0] && p[1] == c[1] && p[2] == c[2];
      }
    return n;
  };
  // Each placed map's walls are drawn in its colour (the robot's over the plan's), and its swatch
  // is in the legend.
  CHECK(count_colour(map_color(1), 0, result.merged.height()) > 1000);
  for (int m = 0; m < 2; ++m) CHECK(count_colour(map_color(m), result.merged.height(), picture.height) > 0);
  CHECK(count_colour(map_color(2), result.merged.height(), picture.height) == 0);  // not placed: grey
  const MergeResult again = merge_maps(matcher, maps);
  for (std::size_t m = 0; m < 3; ++m) {
    CHECK(again.maps[m].placed == result.maps[m].placed);
    CHECK(again.maps[m].T_reference_map.translation == result.maps[m].T_reference_map.translation);
  }
  CHECK(again.merged == result.merged);
  MergeParams threaded;
  threaded.threads = 3;
  const MergeResult on_threads = merge_maps(matcher, maps, threaded);
  for (std::size_t m = 0; m < 3; ++m) {
    CHECK(on_threads.maps[m].reason == result.maps[m].reason);
    CHECK(on_threads.maps[m].T_reference_map.rotation == result.maps[m].T_reference_map.rotation);
    CHECK(on_threads.maps[m].T_reference_map.translation == result.maps[m].T_reference_map.translation);
  }
  CHECK(on_threads.merged == result.merged);

  // The reference's frame is the merged frame: merging onto map 1 places map 1 at the identity.
  params = MergeParams{};
  params.reference = 1;
  const MergeResult onto_second = merge_maps(matcher, maps, params);
  CHECK(onto_second.reference == 1);
  CHECK(onto_second.maps[1].T_reference_map.rotation == 0.0);
  CHECK(onto_second.maps[1].T_reference_map.translation.norm() == 0.0);
}

TEST_CASE("merge_maps until_connected: fewer matches, measured against all pairs (N = 10)") {
  MatcherParams matcher_params;
  matcher_params.allow_reflection = true;
  const Matcher<> matcher(matcher_params);
  const bool quick = areamatch_test::quick_tests();
  const int buildings = quick ? 1 : 20;
  const std::size_t n = quick ? 4 : 10;
  int all_right = 0, maps_wrong = 0;
  std::size_t matches = 0;
  for (int b = 0; b < buildings; ++b) {
    const auto c = areamatch_test::merge_case(static_cast<std::uint64_t>(1000 * 10 + b), n, /*mirror_one=*/true, quick);
    std::vector<Matcher<>::PreparedMap> maps;
    for (const auto& robot : c.robots) maps.push_back(matcher.prepare(robot.grid));
    MergeParams params;
    params.strategy = MergeStrategy::until_connected;
    params.build_merged_map = false;
    const MergeResult merged = merge_maps(matcher, maps, params);
    CHECK(merged.merged.empty());
    matches += merged.edges.size();
    bool right = merged.ok;
    for (std::size_t m = 0; m < c.robots.size(); ++m) {
      const MergedMap& out = merged.maps[m];
      const double rotation = rotation_error_deg(out.T_reference_map, c.truth[m]);
      const double displacement = mean_displacement_m(c.robots[m].grid, out.T_reference_map, c.truth[m]);
      right = right && out.placed && rotation <= 0.5 && displacement <= 0.1;
      maps_wrong += out.placed && (out.T_reference_map.reflected != c.truth[m].reflected || rotation > 3.0 || displacement > 1.0);
    }
    all_right += right;
  }
  const std::size_t all_pairs = n * (n - 1) / 2 * static_cast<std::size_t>(buildings);
  MESSAGE("until_connected, N = " << n << ": " << all_right << " / " << buildings << " buildings with every map right, "
                                   << maps_wrong << " maps placed wrongly, " << matches << " matches (all pairs: " << all_pairs
                                   << ")");
  // Measured: 180 matches instead of 900, 18 / 20 buildings right, and 2 of the 200 maps placed
  // wrongly — accepted wrong matches that no loop checks (all pairs: 0 wrong, above); since the
  // agreement gate needs walls that disagree (2026-12-03), 182 matches and 0 placed wrongly. No
  // loop checks a match still: all_pairs is the default, until_connected for when time matters more.
  if (quick) {  // one small building: the code runs (its rates mean nothing on one sample)
    CHECK(matches <= all_pairs);
    return;
  }
  CHECK(matches <= 0.25 * all_pairs);
  CHECK(all_right >= 0.85 * buildings);
  CHECK(maps_wrong <= 0.02 * n * buildings);
}

namespace {

/// A free room with walls drawn as occupied columns at the given metres from its left edge (each
/// a cell wide, full height), the rest free; 0.05 m cells.
OccupancyGrid room_with_walls(const std::vector<double>& walls_m) {
  OccupancyGrid grid(120, 60, 0.05);
  for (int row = 0; row < grid.height(); ++row) {
    for (int col = 0; col < grid.width(); ++col) grid.set(col, row, CellState::free);
  }
  for (const double x : walls_m) {
    const int col = static_cast<int>(std::lround(x / 0.05));
    for (int row = 0; row < grid.height(); ++row) grid.set(col, row, CellState::occupied);
  }
  return grid;
}

}  // namespace

TEST_CASE("count_double_walls: a wall 0.1-0.4 m beside a parallel wall across free space is doubled, a corridor is not") {
  const DoubleWalls single = count_double_walls(room_with_walls({2.0}));
  CHECK(single.wall_cells == 60);
  CHECK(single.doubled_cells == 0);
  const DoubleWalls doubled = count_double_walls(room_with_walls({2.0, 2.25}));  // 0.2 m of free space between
  CHECK(doubled.wall_cells == 120);
  CHECK(doubled.doubled_cells == 120);
  CHECK(doubled.share() == doctest::Approx(1.0));
  CHECK(doubled.doubled.size() == 120);
  CHECK(count_double_walls(room_with_walls({2.0, 3.0})).doubled_cells == 0);   // a 0.95 m corridor
  CHECK(count_double_walls(room_with_walls({2.0, 2.05})).doubled_cells == 0);  // one thick wall
  CHECK(count_double_walls(room_with_walls({2.0, 2.1})).doubled_cells == 0);   // one cell between: rasterisation
  // A perpendicular wall across the look is not a parallel one.
  OccupancyGrid corner = room_with_walls({2.0});
  for (int col = 41; col < 100; ++col) corner.set(col, 30, CellState::occupied);
  const DoubleWalls cornered = count_double_walls(corner);
  CHECK(cornered.doubled_cells == 0);
  // Unknown between the walls ends the look.
  OccupancyGrid behind = room_with_walls({2.0, 2.25});
  for (int row = 0; row < behind.height(); ++row) {
    for (int col = 41; col < 45; ++col) behind.set(col, row, CellState::unknown);
  }
  CHECK(count_double_walls(behind).doubled_cells == 0);
  DoubleWallParams bad;
  bad.min_gap_m = 0.5;
  CHECK_THROWS_AS(count_double_walls(room_with_walls({2.0}), bad), parameter_error);
}

TEST_CASE("merge_maps non_rigid: bent maps bent onto the layout leave fewer doubled walls than their rigid poses") {
  const bool quick = areamatch_test::quick_tests();
  const Matcher<> matcher;
  std::size_t rigid_doubled = 0, warped_doubled = 0;
  for (std::uint64_t seed : quick ? std::vector<std::uint64_t>{7} : std::vector<std::uint64_t>{7, 8, 9}) {
    areamatch::BuildingParams b;
    b.width_m = 30.0;
    b.height_m = 20.0;
    const SyntheticBuilding building = generate_building(b, seed);
    std::vector<Matcher<>::PreparedMap> maps{matcher.prepare(building.layout)};
    for (int i = 0; i < 2; ++i) {
      RobotMapParams r;
      r.rotation_rad = 0.4 + i;
      r.wall_bend_m = 0.4;
      r.explored_fraction = 0.8;
      maps.push_back(matcher.prepare(make_robot_map(building, r, seed * 10 + static_cast<std::uint64_t>(i)).grid));
    }
    MergeParams params;  // the layout (map 0) is the reference
    const MergeResult rigid = merge_maps(matcher, maps, params);
    params.non_rigid = true;
    const MergeResult warped = merge_maps(matcher, maps, params);
    REQUIRE(rigid.ok);
    REQUIRE(warped.ok);
    CHECK_FALSE(rigid.maps[1].warp.has_value());
    CHECK_FALSE(warped.maps[0].warp.has_value());  // the reference is not warped
    for (std::size_t m = 1; m < maps.size(); ++m) {
      REQUIRE(warped.maps[m].warp.has_value());
      const WarpResult& w = *warped.maps[m].warp;
      MESSAGE("seed " << seed << " map " << m << ": walls " << w.rigid_median_m << " -> " << w.warped_median_m << " m off the layout's");
      CHECK(w.warped_median_m < w.rigid_median_m);
      // Same poses: the warp only bends what the pose fit placed.
      CHECK(warped.maps[m].T_reference_map.translation == rigid.maps[m].T_reference_map.translation);
    }
    MESSAGE("seed " << seed << ": doubled wall cells " << rigid.double_walls.doubled_cells << " rigid, "
                    << warped.double_walls.doubled_cells << " non-rigid (of " << rigid.double_walls.wall_cells << ", "
                    << warped.double_walls.wall_cells << ")");
    rigid_doubled += rigid.double_walls.doubled_cells;
    warped_doubled += warped.double_walls.doubled_cells;
    CHECK(warped.timings.warp_s > 0.0);
    // Deterministic, on any thread count.
    params.threads = 3;
    const MergeResult threaded = merge_maps(matcher, maps, params);
    CHECK(threaded.merged == warped.merged);
    CHECK(threaded.double_walls.doubled_cells == warped.double_walls.doubled_cells);
  }
  CHECK(warped_doubled < rigid_doubled);
  MergeParams bad;
  bad.non_rigid = true;
  bad.warp.control_spacing_m = 0.0;
  const std::vector<Matcher<>::PreparedMap> two{matcher.prepare(room_with_walls({2.0})), matcher.prepare(room_with_walls({2.0}))};
  CHECK_THROWS_AS(merge_maps(matcher, two, bad), parameter_error);
}
