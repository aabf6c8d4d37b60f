// The non-rigid warp (warp.hpp): generated bent robot maps, whose exact correspondence is known
// (`RobotMap::true_dest`), laid onto their layouts beyond the rigid answer.
#include <areamatch/areamatch.hpp>
#include <areamatch/synthetic.hpp>
#include <areamatch/warp.hpp>
#include <doctest/doctest.h>
#include "test_support.hpp"

#include <cmath>
#include <vector>

using namespace areamatch;

namespace {

struct BentCase {
  SyntheticBuilding building;
  RobotMap robot;
  MatchResult match;
};

BentCase bent_case(std::uint64_t seed, double bend_m, double wavelength_m, double scale_drift = 0.0) {
  BentCase c{generate_building({}, 900 + seed), {}, {}};
  RobotMapParams rp;
  rp.scale_drift = scale_drift;
  rp.rotation_rad = 0.3 + 1.1 * static_cast<double>(seed);
  rp.wall_bend_m = bend_m;
  rp.bend_wavelength_m = wavelength_m;
  rp.max_clutter_per_room = 3;
  rp.wall_noise_m = 0.03;
  c.robot = make_robot_map(c.building, rp, 1000 + seed);
  Matcher<> matcher;
  matcher.segmenter.params.with_door_width(0.9);
  // The warp is judged here, not the decision: a strongly bent map's right answer is taken
  // whatever the agreement (it is checked against the truth below).
  matcher.params.decision.min_agreement = 0.0;
  matcher.params.decision.gate_max_lower_walls = 2.0;
  const AreaGraph source = matcher.segmenter.segment(c.robot.grid), dest = matcher.segmenter.segment(c.building.layout);
  c.match = matcher.match(c.robot.grid, source, c.building.layout, dest);
  return c;
}

/// Median and 95th percentile of the distance from where `place` puts the robot map's wall points
/// to where they truly belong.
template <class Place>
std::array<double, 2> wall_point_errors(const BentCase& c, Place place) {
  const auto points =
      detail::boundary_points(GridInfo::of(c.robot.grid), detail::wall_edge_cells(c.robot.grid), 0.1);
  std::vector<double> errors;
  for (const auto& p : points) errors.push_back((place(p) - c.robot.true_dest(p)).norm());
  return detail::median_and_p95(errors);
}

}  // namespace

TEST_CASE("the warp undoes a generated building-wide bend that the rigid answer leaves 0.3 m off") {
  const int cases = areamatch_test::quick_tests() ? 2 : 6;
  int judged = 0;
  for (int i = 0; i < cases; ++i) {
    const double bend = 0.6 + 0.1 * (i % 3);
    const BentCase c = bent_case(static_cast<std::uint64_t>(i), bend, 60.0);
    // The right answer, not a turn of it (a building-wide bend turns the best rigid fit by a few degrees).
    REQUIRE(std::abs(wrap_angle(c.match.T_dest_source.rotation - c.robot.T_dest_source.rotation)) < 0.15);
    const WarpResult warp = fit_warp(c.robot.grid, c.building.layout, c.match.T_dest_source);
    const auto rigid = wall_point_errors(c, [&](const Eigen::Vector2d& p) { return c.match.T_dest_source * p; });
    const auto warped = wall_point_errors(c, [&](const Eigen::Vector2d& p) { return warp.field.apply(p); });
    MESSAGE("bend " << bend << " m: rigid " << rigid[0] << " / " << rigid[1] << " m, warp " << warped[0] << " / "
                    << warped[1] << " m (median / 95th percentile)");
    CHECK(warped[0] < 0.5 * rigid[0]);
    CHECK(warped[0] <= 0.05);
    CHECK(warp.warped_median_m < warp.rigid_median_m);
    CHECK(warp.paired_points > 100);
    judged += rigid[0] >= 0.15;
  }
  CHECK(judged >= cases / 2);  // the bends are large enough to matter
}

TEST_CASE("generated scale drift: its truth is exact, and the warp takes out what the rigid answer leaves") {
  // The truth: a drift of 3 % moves points along the building's longer side by rate s² / 2L.
  const SyntheticBuilding building = generate_building({}, 905);
  RobotMapParams rp;
  rp.scale_drift = 0.03;
  const RobotMap drifted = make_robot_map(building, rp, 77);
  rp.scale_drift = 0.0;
  const RobotMap plain = make_robot_map(building, rp, 77);
  CHECK(drifted.T_dest_source.translation == plain.T_dest_source.translation);
  const double length = std::max(building.params.width_m, building.params.height_m);
  const Eigen::Vector2d far_end = drifted.drift.axis * length;
  CHECK((drifted.smooth(far_end) - far_end).norm() == doctest::Approx(0.015 * length));
  CHECK((drifted.smooth_inverse(drifted.smooth(far_end)) - far_end).norm() < 1e-6);
  CHECK(drifted.grid != plain.grid);
  rp.scale_drift = 0.5;
  CHECK_THROWS_AS(make_robot_map(building, rp, 77), parameter_error);

  const BentCase c = bent_case(5, 0.0, 60.0, 0.03);
  REQUIRE(std::abs(wrap_angle(c.match.T_dest_source.rotation - c.robot.T_dest_source.rotation)) < 0.15);
  const WarpResult warp = fit_warp(c.robot.grid, c.building.layout, c.match.T_dest_source);
  const auto rigid = wall_point_errors(c, [&](const Eigen::Vector2d& p) { return c.match.T_dest_source * p; });
  const auto warped = wall_point_errors(c, [&](const Eigen::Vector2d& p) { return warp.field.apply(p); });
  MESSAGE("scale drift 3 %: rigid " << rigid[0] << " / " << rigid[1] << " m, warp " << warped[0] << " / " << warped[1]
                                    << " m (median / 95th percentile)");
  CHECK(warped[0] < 0.5 * rigid[0]);
  CHECK(warped[0] <= 0.05);
}

TEST_CASE("the warp's inverse returns points, and a map resampled through it lies on the destination") {
  const BentCase c = bent_case(1, 0.5, 40.0);
  const WarpResult warp = fit_warp(c.robot.grid, c.building.layout, c.match.T_dest_source);
  const auto points = detail::boundary_points(GridInfo::of(c.robot.grid), detail::wall_edge_cells(c.robot.grid), 0.5);
  REQUIRE(points.size() > 50);
  double worst = 0.0;
  for (const auto& p : points) worst = std::max(worst, (warp.field.inverse(warp.field.apply(p)) - p).norm());
  CHECK(worst < 1e-5);

  const OccupancyGrid onto = resample_through(c.robot.grid, warp.field, GridInfo::of(c.building.layout));
  CHECK(onto.width() == c.building.layout.width());
  CHECK(onto.height() == c.building.layout.height());
  // Free cells of the resampled map on the layout's free cells: more with the warp than rigidly.
  auto free_on_free = [&](const OccupancyGrid& g) {
    std::size_t on = 0, all = 0;
    for (int row = 0; row < g.height(); ++row) {
      for (int col = 0; col < g.width(); ++col) {
        if (g.at(col, row) != CellState::free) continue;
        ++all;
        on += c.building.layout.at(col, row) == CellState::free;
      }
    }
    return static_cast<double>(on) / static_cast<double>(std::max<std::size_t>(all, 1));
  };
  const WarpField rigid_only(c.match.T_dest_source, warp.field.origin(), warp.field.spacing(), warp.field.columns(),
                             warp.field.rows());
  const double rigid_share = free_on_free(resample_through(c.robot.grid, rigid_only, GridInfo::of(c.building.layout)));
  const double warp_share = free_on_free(onto);
  MESSAGE("free on free: rigid " << rigid_share << ", warp " << warp_share);
  CHECK(warp_share > rigid_share);
}

TEST_CASE("the warp is deterministic and bad parameters are refused") {
  const BentCase c = bent_case(2, 0.4, 30.0);
  const WarpResult a = fit_warp(c.robot.grid, c.building.layout, c.match.T_dest_source);
  const WarpResult b = fit_warp(c.robot.grid, c.building.layout, c.match.T_dest_source);
  REQUIRE(a.field.node_count() == b.field.node_count());
  for (std::size_t k = 0; k < a.field.node_count(); ++k) {
    CHECK(a.field.node_displacement(k).x() == b.field.node_displacement(k).x());
    CHECK(a.field.node_displacement(k).y() == b.field.node_displacement(k).y());
  }

  WarpParams bad;
  bad.control_spacing_m = 0.0;
  CHECK_THROWS_AS(fit_warp(c.robot.grid, c.building.layout, c.match.T_dest_source, bad), parameter_error);
  bad = {};
  bad.gates_m.clear();
  CHECK_THROWS_AS(fit_warp(c.robot.grid, c.building.layout, c.match.T_dest_source, bad), parameter_error);
  bad = {};
  bad.keep_fraction = 1.5;
  CHECK_THROWS_AS(fit_warp(c.robot.grid, c.building.layout, c.match.T_dest_source, bad), parameter_error);
  bad = {};
  bad.bend_length_m = -1.0;
  CHECK_THROWS_AS(fit_warp(c.robot.grid, c.building.layout, c.match.T_dest_source, bad), parameter_error);
  bad = {};
  bad.control_spacing_m = 1e-4;  // a grid of billions of nodes: refused before it is allocated
  CHECK_THROWS_AS(fit_warp(c.robot.grid, c.building.layout, c.match.T_dest_source, bad), parameter_error);
}

TEST_CASE("a map without walls warps rigidly and says so") {
  OccupancyGrid empty(40, 40, 0.05, {}, CellState::unknown);
  const BentCase c = bent_case(3, 0.3, 30.0);
  const WarpResult w = fit_warp(empty, c.building.layout, Similarity2{});
  CHECK(w.paired_points == 0);
  CHECK(w.source_wall_points == 0);
  const Eigen::Vector2d p(0.7, 0.9);
  CHECK((w.field.apply(p) - p).norm() == 0.0);
}

TEST_CASE("a broken map's warp: each point moves with its piece's field, and a gap between pieces has no preimage") {
  // Two pieces split at x = 0: the left one stays, the right one is moved 0.5 m to the right, so
  // that the destination strip 0 < x < 0.5 m is a gap no source point reaches.
  const Similarity2 rigid{0.0, Eigen::Vector2d(1.0, 2.0)};
  WarpField left(rigid, Eigen::Vector2d(-10.0, -10.0), 1.0, 21, 21), right = left;
  for (std::size_t k = 0; k < right.node_count(); ++k) right.node_displacement(k) = Eigen::Vector2d(0.5, 0.0);
  PieceLabels labels;
  labels.origin = Eigen::Vector2d(-10.0, -10.0);
  labels.cell_m = 0.5;
  labels.columns = labels.rows = 40;
  for (int r = 0; r < labels.rows; ++r) {
    for (int col = 0; col < labels.columns; ++col) labels.labels.push_back(col < 20 ? 0 : 1);
  }
  CHECK(labels.count() == 2);
  CHECK(labels.at(Eigen::Vector2d(-0.1, 3.0)) == 0);
  CHECK(labels.at(Eigen::Vector2d(0.1, 3.0)) == 1);
  CHECK(labels.at(Eigen::Vector2d(50.0, 50.0)) == 1);  // beyond the raster: the nearest cell's
  WarpField field(rigid);
  CHECK_THROWS_AS(field.set_pieces(labels, {left}), parameter_error);  // a label without its field
  field.set_pieces(labels, {left, right});
  CHECK_FALSE(field.is_rigid());
  const Eigen::Vector2d a(-0.2, 1.0), b(0.2, 1.0);
  CHECK((field.apply(a) - (rigid * a)).norm() < 1e-12);
  CHECK((field.apply(b) - (rigid * b + Eigen::Vector2d(0.5, 0.0))).norm() < 1e-12);
  for (const Eigen::Vector2d& p : {a, b}) {
    const auto x = field.preimage(field.apply(p));
    REQUIRE(x.has_value());
    CHECK((*x - p).norm() < 1e-6);
    CHECK((field.inverse(field.apply(p)) - p).norm() < 1e-6);
  }
  // In the gap: no preimage; `inverse` gives a point the warp takes within the gap's width of it,
  // and a map resampled through the warp is unknown there.
  const Eigen::Vector2d in_gap = rigid * Eigen::Vector2d(0.25, 1.0);
  CHECK_FALSE(field.preimage(in_gap).has_value());
  CHECK((field.apply(field.inverse(in_gap)) - in_gap).norm() <= 0.5 + 1e-9);
  OccupancyGrid source(40, 40, 0.5, Pose2{-10.0, -10.0, 0.0}, CellState::free);
  const OccupancyGrid resampled = resample_through(source, field, GridInfo::of(source));
  const Eigen::Vector2i gap_cell = resampled.world_to_cell(Eigen::Vector2d(1.25, 3.0));   // x 0.25 before the rigid shift
  const Eigen::Vector2i kept_cell = resampled.world_to_cell(Eigen::Vector2d(0.25, 3.0));  // x -0.75: the left piece
  CHECK(resampled.at(gap_cell.x(), gap_cell.y()) == CellState::unknown);
  CHECK(resampled.at(kept_cell.x(), kept_cell.y()) == CellState::free);
}
