// Map files: ROS YAML variants, PGM/PNG round trips, and every bad input a user can hand us.
#include <areamatch/io.hpp>
#include <areamatch/synthetic.hpp>

#include <doctest/doctest.h>

#include "test_support.hpp"

#include <string>

using namespace areamatch;
using areamatch_test::temp_dir;
using areamatch_test::write_bytes;

namespace {

std::string dir() { return temp_dir(); }

/// A 4 × 3 grey map: top row free, middle unknown, bottom occupied.
void write_small_pgm(const std::string& path) {
  write_bytes(path, std::string("P5 4 3 255\n") + std::string(4, '\xfe') + std::string(4, '\xcd') + std::string(4, '\x00'));
}

std::string yaml_with(const std::string& name, const std::string& body) {
  const std::string path = dir() + "/" + name;
  write_bytes(path, body);
  return path;
}

template <class Exception>
std::string error_of(const std::string& path, const LoadOptions& options = {}) {
  try {
    load_map(path, options);
  } catch (const Exception& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("wrong exception type: ") + e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("YAML: relative image path, origin, thresholds, negate, mode") {
  write_small_pgm(dir() + "/small.pgm");
  const auto path = yaml_with("small.yaml",
                              "image: small.pgm\nresolution: 0.1\norigin: [1.5, -2.0, 0.0]\nnegate: 0\n"
                              "occupied_thresh: 0.65\nfree_thresh: 0.196\nmode: trinary\n");
  const LoadedMap loaded = load_map_with_image(path);
  const OccupancyGrid& grid = loaded.grid;
  CHECK(grid.width() == 4);
  CHECK(grid.height() == 3);
  CHECK(grid.resolution() == 0.1);
  CHECK(grid.origin().x == 1.5);
  CHECK(grid.origin().y == -2.0);
  CHECK(grid.at(0, 0) == CellState::free);
  CHECK(grid.at(0, 1) == CellState::unknown);
  CHECK(grid.at(0, 2) == CellState::occupied);
  CHECK(loaded.image_path == dir() + "/small.pgm");

  // negate: true flips free and occupied; the defaults apply to absent keys.
  const auto negated = yaml_with("negated.yaml", "image: small.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: true\n");
  const OccupancyGrid flipped = load_map(negated);
  CHECK(flipped.at(0, 0) == CellState::occupied);
  CHECK(flipped.at(0, 2) == CellState::free);

  // An absolute image path is used as is.
  const auto absolute = yaml_with("absolute.yaml", "image: " + dir() + "/small.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n");
  CHECK(load_map(absolute).width() == 4);

  // Overrides beat the YAML.
  LoadOptions options;
  options.resolution = 0.25;
  options.free_thresh = 0.0;  // nothing is free any more
  const OccupancyGrid overridden = load_map(path, options);
  CHECK(overridden.resolution() == 0.25);
  CHECK(overridden.count().free == 0);
}

TEST_CASE("a bare image gets map_server's defaults and the caller's resolution") {
  write_small_pgm(dir() + "/bare.pgm");
  const OccupancyGrid grid = load_map(dir() + "/bare.pgm");
  CHECK(grid.resolution() == default_resolution);
  CHECK(grid.count().free == 4);
  CHECK(grid.count().unknown == 4);
  LoadOptions options;
  options.resolution = 0.02;
  CHECK(load_map(dir() + "/bare.pgm", options).resolution() == 0.02);
}

TEST_CASE("save and load round-trip a generated map exactly (PGM and PNG)") {
  BuildingParams params;
  params.width_m = 12;
  params.height_m = 9;
  OccupancyGrid grid = generate_building(params, 3).layout;
  grid.set_origin(Pose2{-3.25, 7.125, 0.1});
  grid.set_resolution(0.0437);
  for (const char* ext : {"pgm", "png", "PNG"}) {
    const std::string yaml = save_map(grid, dir() + "/roundtrip_" + std::string(ext) + "." + ext);
    const OccupancyGrid back = load_map(yaml);
    CHECK(back == grid);
  }
  CHECK_THROWS_AS(save_map(grid, dir() + "/roundtrip.bmp"), parameter_error);
}

TEST_CASE("bad files give clear errors that name the file") {
  const std::string d = dir();
  CHECK(error_of<io_error>(d + "/does_not_exist.yaml").find("does_not_exist.yaml: cannot open") != std::string::npos);
  CHECK(error_of<io_error>(d).find("is a directory") != std::string::npos);
  write_bytes(d + "/empty.png", "");
  CHECK(error_of<format_error>(d + "/empty.png").find("empty.png: file is empty") != std::string::npos);
  write_bytes(d + "/truncated.pgm", "P5 10 10 255\nabc");
  CHECK(error_of<format_error>(d + "/truncated.pgm").find("truncated PGM") != std::string::npos);
  write_bytes(d + "/corrupt.png", std::string("\x89PNG\r\n\x1a\n", 8) + std::string(100, 'x'));
  CHECK(error_of<format_error>(d + "/corrupt.png").find("corrupt.png: corrupt PNG") != std::string::npos);
  write_bytes(d + "/maxval.pgm", "P5 1 1 70000\nxx");
  CHECK(error_of<format_error>(d + "/maxval.pgm").find("unsupported PGM maxval 70000") != std::string::npos);
  write_bytes(d + "/zero.pgm", "P5 0 0 255\n");
  CHECK(error_of<format_error>(d + "/zero.pgm").find("zero size") != std::string::npos);
  write_bytes(d + "/huge.pgm", "P5 20001 20001 255\n");
  CHECK(error_of<format_error>(d + "/huge.pgm").find("larger than the limit") != std::string::npos);
  write_bytes(d + "/text.png", "hello");
  CHECK(error_of<format_error>(d + "/text.png").find("not a PNG or PGM") != std::string::npos);
}

TEST_CASE("bad YAMLs give clear errors that name the file and the key") {
  write_small_pgm(dir() + "/ok.pgm");
  auto check_yaml = [](const std::string& name, const std::string& body, const std::string& expected) {
    const auto path = yaml_with(name, body);
    const std::string message = error_of<format_error>(path);
    INFO(name << ": " << message);
    CHECK(message.find(name) != std::string::npos);
    CHECK(message.find(expected) != std::string::npos);
  };
  check_yaml("no_resolution.yaml", "image: ok.pgm\norigin: [0, 0, 0]\n", "missing required key 'resolution'");
  check_yaml("no_image.yaml", "resolution: 0.05\norigin: [0, 0, 0]\n", "missing required key 'image'");
  check_yaml("no_origin.yaml", "image: ok.pgm\nresolution: 0.05\n", "missing required key 'origin'");
  check_yaml("zero_res.yaml", "image: ok.pgm\nresolution: 0\norigin: [0, 0, 0]\n", "'resolution' must be a positive");
  check_yaml("negative_res.yaml", "image: ok.pgm\nresolution: -0.05\norigin: [0, 0, 0]\n", "'resolution' must be a positive");
  check_yaml("nan_res.yaml", "image: ok.pgm\nresolution: .nan\norigin: [0, 0, 0]\n", "'resolution' must be a positive");
  check_yaml("text_res.yaml", "image: ok.pgm\nresolution: fine\norigin: [0, 0, 0]\n", "'resolution' must be a number");
  check_yaml("short_origin.yaml", "image: ok.pgm\nresolution: 0.05\norigin: [0, 0]\n", "'origin' must be a list");
  check_yaml("text_origin.yaml", "image: ok.pgm\nresolution: 0.05\norigin: [a, 0, 0]\n", "three numbers");
  check_yaml("occ_range.yaml", "image: ok.pgm\nresolution: 0.05\norigin: [0, 0, 0]\noccupied_thresh: 1.2\n", "occupied_thresh must be in [0, 1]");
  check_yaml("free_range.yaml", "image: ok.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nfree_thresh: -0.5\n", "free_thresh must be in [0, 1]");
  check_yaml("bad_mode.yaml", "image: ok.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nmode: fancy\n", "'mode' must be trinary, scale or raw");
  check_yaml("bad_negate.yaml", "image: ok.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: maybe\n", "'negate' must be");
  check_yaml("not_yaml.yaml", "image: [unclosed\n", "not valid YAML");
  check_yaml("list.yaml", "- a\n- b\n", "expected a YAML mapping");
  // The image a YAML names is missing: the error names both files.
  const auto missing = yaml_with("missing_image.yaml", "image: nowhere.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n");
  const std::string message = error_of<io_error>(missing);
  CHECK(message.find("nowhere.pgm") != std::string::npos);
  CHECK(message.find("missing_image.yaml") != std::string::npos);
}

TEST_CASE("bad overrides are parameter errors") {
  write_small_pgm(dir() + "/ok2.pgm");
  LoadOptions options;
  options.resolution = 0.0;
  CHECK(error_of<parameter_error>(dir() + "/ok2.pgm", options).find("resolution") != std::string::npos);
  options.resolution = -1.0;
  CHECK(error_of<parameter_error>(dir() + "/ok2.pgm", options).find("resolution") != std::string::npos);
  options = {};
  options.occupied_thresh = 2.0;
  CHECK(error_of<parameter_error>(dir() + "/ok2.pgm", options).find("occupied_thresh") != std::string::npos);
}

TEST_CASE("an SVG overlay embeds the destination and places the source walls exactly") {
  BuildingParams params;
  params.width_m = 10;
  params.height_m = 8;
  const auto building = generate_building(params, 5);
  RobotMapParams robot_params;
  robot_params.rotation_rad = 0.5;
  const auto robot = make_robot_map(building, robot_params, 5);
  const std::string svg = overlay_svg(building.layout, robot.grid, robot.T_dest_source);
  CHECK(svg.rfind("<svg", 0) == 0);
  CHECK(svg.find("data:image/png;base64,") != std::string::npos);
  CHECK(svg.find("<g transform=\"matrix(") != std::string::npos);
  CHECK(svg.find("</svg>") != std::string::npos);
}
