// Hostile inputs (docs/hostile-inputs.md): every row of the table there is checked here or in
// the test named in the table. The rule: a clear `areamatch::error` or a not-ok result with a
// reason, never a crash, a hang, an unbounded allocation or a silent wrong answer.
#include <areamatch/areamatch.hpp>
#include <areamatch/synthetic.hpp>
#include <areamatch/io.hpp>

#include <doctest/doctest.h>

#include "test_support.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include <sys/resource.h>

using namespace areamatch;

namespace {

OccupancyGrid filled(int width, int height, CellState state) { return OccupancyGrid(width, height, 0.05, {}, state); }

/// The header of a PNG claiming the given size, with no pixel data.
std::vector<unsigned char> png_header_only(std::uint32_t width, std::uint32_t height) {
  std::vector<unsigned char> bytes = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R'};
  for (std::uint32_t v : {width, height})
    for (int shift = 24; shift >= 0; shift -= 8) bytes.push_back(static_cast<unsigned char>(v >> shift));
  for (unsigned char b : {8, 0, 0, 0, 0}) bytes.push_back(b);                 // 8-bit grey
  for (int i = 0; i < 4; ++i) bytes.push_back(0);                             // CRC (wrong on purpose)
  return bytes;
}

}  // namespace

TEST_CASE("huge images are refused from their header, before any pixel memory is allocated") {
  CHECK_THROWS_AS(decode_png(png_header_only(30000, 10), "wide.png"), format_error);       // > max_image_side
  CHECK_THROWS_AS(decode_png(png_header_only(15000, 15000), "big.png"), limit_error);      // > max_grid_cells
  const std::string pgm = "P5 15000 15000 255\n";
  CHECK_THROWS_AS(decode_pgm(std::vector<unsigned char>(pgm.begin(), pgm.end()), "big.pgm"), limit_error);
  // A grid built in code is checked by the segmenter.
  static_assert(14200LL * 14200 > max_grid_cells);
  const OccupancyGrid too_big(14200, 14200, 0.05, {}, CellState::occupied);
  CHECK_THROWS_WITH_AS(VoronoiSegmenter{}.segment(too_big), doctest::Contains("max_grid_cells"), limit_error);
}

TEST_CASE("tiny, empty, all-wall and all-unknown maps give no areas and a reason") {
  for (const auto& grid : {filled(1, 1, CellState::free), filled(1, 1, CellState::occupied), filled(3, 2, CellState::free),
                           filled(50, 40, CellState::occupied), filled(50, 40, CellState::unknown)}) {
    const AreaGraph graph = VoronoiSegmenter{}.segment(grid);
    CHECK(graph.areas.empty());
    CHECK_FALSE(graph.reason.empty());
  }
  const auto building = generate_building({}, 2);
  for (const auto& empty : {filled(50, 40, CellState::occupied), filled(1, 1, CellState::free)}) {
    const MatchResult r = Matcher<>{}.match(building.layout, empty);
    CHECK_FALSE(r.ok);
    CHECK(r.reason.find("no areas") != std::string::npos);
  }
}

TEST_CASE("NaN, infinite, zero and negative parameters are refused with the parameter named") {
  const double bad[] = {std::nan(""), std::numeric_limits<double>::infinity(), 0.0, -1.0};
  const auto grid = generate_building({}, 1).layout;
  for (double v : bad) {
    CAPTURE(v);
    VoronoiSegmenter segmenter;
    segmenter.params.with_door_width(v);
    CHECK_THROWS_WITH_AS(segmenter.segment(grid), doctest::Contains("door width"), parameter_error);
    CHECK_THROWS_AS(OccupancyGrid(10, 10, v), parameter_error);
    LoadOptions options;
    options.resolution = v;
    CHECK_THROWS_AS(load_map("any.png", options), parameter_error);
  }
  for (double v : {std::nan(""), -0.5}) {
    Matcher<> matcher;
    matcher.params.decision.min_score = v;
    CHECK_THROWS_WITH_AS(matcher.match(grid, grid), doctest::Contains("min_score"), parameter_error);
    VoronoiSegmenter segmenter;
    segmenter.params.areas.min_area_m2 = v;
    CHECK_THROWS_WITH_AS(segmenter.segment(grid), doctest::Contains("min_area_m2"), parameter_error);
  }
  Matcher<> matcher;
  matcher.params.k = 0;
  CHECK_THROWS_WITH_AS(matcher.match(grid, grid), doctest::Contains("k must be"), parameter_error);
  CHECK_THROWS_AS(OccupancyGrid(0, 10, 0.05), parameter_error);
  CHECK_THROWS_AS(OccupancyGrid(-5, 10, 0.05), parameter_error);
  CHECK_THROWS_AS(OccupancyGrid(10, 10, 0.05, Pose2{std::nan(""), 0.0, 0.0}), parameter_error);
}

TEST_CASE("typos no building has: a resolution of 1e300 or 1e-9, a door width of 1e308, refused naming the limit") {
  CHECK_THROWS_WITH_AS(OccupancyGrid(100, 100, 1e300), doctest::Contains("max_map_extent_m"), parameter_error);
  CHECK_THROWS_WITH_AS(OccupancyGrid(100, 100, 1e-9), doctest::Contains("min_resolution_m"), parameter_error);
  CHECK_NOTHROW(OccupancyGrid(39000, 100, 0.05));  // 1.95 km: under the widest map taken
  OccupancyGrid grid(100, 100, 0.05);
  CHECK_THROWS_WITH_AS(grid.set_resolution(30.0), doctest::Contains("max_map_extent_m"), parameter_error);
  CHECK(grid.resolution() == 0.05);
  LoadOptions options;
  options.resolution = 1e-9;
  CHECK_THROWS_WITH_AS(load_map("typo.png", options), doctest::Contains("typo.png: resolution 1e-09"), parameter_error);
  VoronoiSegmenter segmenter;
  segmenter.params.with_door_width(1e308);
  CHECK_THROWS_WITH_AS(segmenter.segment(generate_building({}, 1).layout), doctest::Contains("up to 20"), parameter_error);
}

TEST_CASE("resource limits: too many Voronoi sites or areas is a limit_error naming the limit") {
  const auto building = generate_building({}, 4);
  VoronoiSegmenter segmenter;
  segmenter.params.boundary.max_segments = 10;
  CHECK_THROWS_WITH_AS(segmenter.segment(building.layout), doctest::Contains("max_segments"), limit_error);
  Matcher<> matcher;
  matcher.params.max_areas = 3;
  CHECK_THROWS_WITH_AS(matcher.match(building.layout, building.layout), doctest::Contains("max_areas"), limit_error);
}

TEST_CASE("a map against one 100 times its area: an answer or a clear refusal, in bounded time") {
  BuildingParams small, large;
  small.width_m = 6;
  small.height_m = 5;
  large.width_m = 60;
  large.height_m = 50;
  const auto a = generate_building(small, 5), b = generate_building(large, 5);
  for (const auto& [source, dest] : {std::pair{&a.layout, &b.layout}, std::pair{&b.layout, &a.layout}}) {
    const auto start = std::chrono::steady_clock::now();
    const MatchResult r = Matcher<>{}.match(*source, *dest);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    CHECK((r.ok || !r.reason.empty()));
    if (r.ok) CHECK(std::isfinite(r.score));
    // A guard against runaway work (the work is bounded by the areas: a few hundred
    // hypotheses per area pair), not a speed target: it takes well under a second in Release.
    MESSAGE("matched in " << seconds << " s: " << r.statistics.hypotheses << " hypotheses, " << r.statistics.clusters
                          << " clusters");
    CHECK(seconds < (areamatch_test::quick_tests() ? 120.0 : 30.0));
    CHECK(r.statistics.verified <= Matcher<>{}.selection.params.verify_candidates);
    CHECK(r.statistics.refined <= Matcher<>{}.selection.params.refine_candidates + 1);
  }
}

TEST_CASE("memory stays bounded: segmenting a 4040 x 4040-cell map peaks under 1 GB") {
  // docs/reliability.md: ~23 bytes per cell. Skipped in the sanitizer run, whose shadow memory
  // and unoptimised code make the number meaningless there.
  if (areamatch_test::quick_tests()) return;
  BuildingParams params;
  params.width_m = 200;
  params.height_m = 200;
  const auto building = generate_building(params, 1);
  REQUIRE(static_cast<long long>(building.layout.width()) * building.layout.height() >= 16'000'000);
  const AreaGraph graph = VoronoiSegmenter{}.segment(building.layout);
  CHECK(graph.areas.size() > 1000);
  rusage usage{};
  REQUIRE(::getrusage(RUSAGE_SELF, &usage) == 0);
  const double peak_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
  MESSAGE("peak RSS " << peak_mb << " MB for " << building.layout.width() << " x " << building.layout.height() << " cells");
  CHECK(peak_mb < 1024.0);
}
