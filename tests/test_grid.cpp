// OccupancyGrid frames (pixel ↔ world, ROS origin convention) and Similarity2 / pixel transforms.
#include <areamatch/grid.hpp>
#include <areamatch/transform.hpp>

#include <doctest/doctest.h>

using namespace areamatch;

namespace {
void check_close(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double tol = 1e-9) {
  CHECK((a - b).norm() < tol);
}
}  // namespace

TEST_CASE("grid construction validates its arguments") {
  CHECK_THROWS_AS(OccupancyGrid(0, 5, 0.05), parameter_error);
  CHECK_THROWS_AS(OccupancyGrid(5, -1, 0.05), parameter_error);
  CHECK_THROWS_AS(OccupancyGrid(5, 5, 0.0), parameter_error);
  CHECK_THROWS_AS(OccupancyGrid(5, 5, -0.05), parameter_error);
  CHECK_THROWS_AS(OccupancyGrid(5, 5, std::nan("")), parameter_error);
  CHECK_THROWS_AS(OccupancyGrid(5, 5, 0.05, Pose2{std::nan(""), 0, 0}), parameter_error);
  OccupancyGrid one(1, 1, 0.05);
  CHECK(one.at(0, 0) == CellState::unknown);
  CHECK(one.count().unknown == 1);
}

TEST_CASE("pixel centres follow the ROS origin convention") {
  // 4 × 3 grid, 0.5 m cells, origin at (10, 20), no yaw.
  OccupancyGrid grid(4, 3, 0.5, Pose2{10.0, 20.0, 0.0});
  // The bottom-left pixel is image row 2; its centre is half a cell from the origin.
  check_close(grid.cell_center(0, 2), {10.25, 20.25});
  // The top-left pixel (row 0) is the highest y.
  check_close(grid.cell_center(0, 0), {10.25, 21.25});
  check_close(grid.cell_center(3, 0), {11.75, 21.25});
  // Round trip and rounding to the containing cell.
  check_close(grid.world_to_pixel(grid.pixel_to_world({1.3, 0.7})), {1.3, 0.7});
  CHECK(grid.world_to_cell({10.74, 21.49}) == Eigen::Vector2i(1, 0));
  // ROS message order is bottom row first.
  CHECK(grid.ros_data_index(0, 2) == 0);
  CHECK(grid.ros_data_index(3, 0) == 11);
  CHECK(grid.index(3, 0) == 3);
}

TEST_CASE("a rotated origin rotates the whole image about the origin") {
  OccupancyGrid grid(4, 3, 1.0, Pose2{1.0, 2.0, pi / 2});
  // Lower-left pixel centre (0.5, 0.5) in the map frame, turned by 90°: (-0.5, 0.5).
  check_close(grid.cell_center(0, 2), {0.5, 2.5});
  check_close(grid.world_to_pixel(grid.cell_center(3, 1)), {3.0, 1.0});
}

TEST_CASE("Similarity2 composes, inverts and decomposes") {
  for (bool reflected : {false, true}) {
    Similarity2 a;
    a.rotation = 0.7;
    a.translation = {3.0, -2.0};
    a.scale = 1.3;
    a.reflected = reflected;
    const Eigen::Vector2d p(1.5, -4.0);
    check_close(a.inverse() * (a * p), p);
    const Similarity2 back = Similarity2::from_affine(a.affine());
    CHECK(back.rotation == doctest::Approx(a.rotation));
    CHECK(back.scale == doctest::Approx(a.scale));
    CHECK(back.reflected == reflected);
    Similarity2 b;
    b.rotation = -2.0;
    b.translation = {0.5, 1.0};
    check_close((a * b) * p, a * (b * p));
    CHECK((a * a.inverse()).reflected == false);
  }
  CHECK(wrap_angle(3 * pi) == doctest::Approx(pi));
  CHECK(wrap_angle(-pi) == doctest::Approx(pi));
  CHECK(wrap_angle(0.25) == doctest::Approx(0.25));
}

TEST_CASE("pixel transforms agree with world transforms") {
  OccupancyGrid source(50, 40, 0.04, Pose2{-1.0, 3.0, 0.0});
  OccupancyGrid dest(80, 60, 0.05, Pose2{2.0, -1.0, 0.0});
  Similarity2 T;
  T.rotation = 0.4;
  T.translation = {0.3, 0.9};
  T.reflected = true;
  const PixelTransform px = to_pixel_transform(T, source, dest);
  const Eigen::Vector2d pixel(12.0, 7.0);
  const Eigen::Vector2d via_world = dest.world_to_pixel(T * source.pixel_to_world(pixel));
  check_close(px.leftCols<2>() * pixel + px.col(2), via_world);
  const Similarity2 back = from_pixel_transform(px, source, dest);
  CHECK(back.rotation == doctest::Approx(T.rotation));
  CHECK(back.reflected);
  check_close(back.translation, T.translation);
  // Same building, one map 0.04 m, the other 0.05 m: the pixel transform scales by 0.8.
  CHECK(std::sqrt(std::abs(px.leftCols<2>().determinant())) == doctest::Approx(0.8));
}
