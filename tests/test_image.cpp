// The map_server thresholding rule and the PGM/PNG codecs, in memory.
#include <areamatch/image.hpp>
#include <areamatch/io/pgm.hpp>
#include <areamatch/io/png.hpp>

#include <doctest/doctest.h>

#include <string>
#include <vector>

using namespace areamatch;

namespace {
std::vector<unsigned char> bytes_of(const std::string& s) { return {s.begin(), s.end()}; }
}  // namespace

TEST_CASE("map_server trinary rule with strict comparisons") {
  OccupancyThresholds t;  // 0.65 / 0.196
  CHECK(t.classify(254, false) == CellState::free);
  CHECK(t.classify(0, false) == CellState::occupied);
  // 205 → p = 0.19608: just above free_thresh, so unknown (map_saver's unknown grey).
  CHECK(t.classify(205, false) == CellState::unknown);
  // 206 → p = 0.1922 < 0.196: free.
  CHECK(t.classify(206, false) == CellState::free);
  // p exactly at a threshold is neither free nor occupied: (255 − v)/255 = 0.65 has no integer v,
  // but the dataset's free_thresh 0.06 puts grey 240 (p = 0.0588) free and 239 (p = 0.0627) not.
  OccupancyThresholds dataset{0.065, 0.06, false, ThresholdMode::trinary};
  CHECK(dataset.classify(240, false) == CellState::free);
  CHECK(dataset.classify(239, false) == CellState::unknown);
  CHECK(dataset.classify(238, false) == CellState::occupied);
}

TEST_CASE("negate, scale and raw modes") {
  OccupancyThresholds negate;
  negate.negate = true;
  CHECK(negate.classify(0, false) == CellState::free);
  CHECK(negate.classify(255, false) == CellState::occupied);
  OccupancyThresholds scale;
  scale.mode = ThresholdMode::scale;
  CHECK(scale.classify(254, true) == CellState::unknown);  // transparent
  CHECK(scale.classify(254, false) == CellState::free);
  OccupancyThresholds trinary;
  CHECK(trinary.classify(254, true) == CellState::free);  // trinary ignores alpha
  OccupancyThresholds raw;
  raw.mode = ThresholdMode::raw;
  CHECK(raw.classify(0, false) == CellState::free);
  CHECK(raw.classify(100, false) == CellState::occupied);
  CHECK(raw.classify(50, false) == CellState::unknown);
  CHECK(raw.classify(255, false) == CellState::unknown);
}

TEST_CASE("thresholds are validated") {
  OccupancyThresholds t;
  t.occupied_thresh = 1.5;
  CHECK_THROWS_AS(t.validate(), parameter_error);
  t = {};
  t.free_thresh = -0.1;
  CHECK_THROWS_AS(t.validate(), parameter_error);
  t = {};
  t.free_thresh = 0.8;
  CHECK_THROWS_AS(t.validate(), parameter_error);
  t = {};
  t.free_thresh = std::nan("");
  CHECK_THROWS_AS(t.validate(), parameter_error);
}

TEST_CASE("grid → image → grid is lossless") {
  OccupancyGrid grid(7, 5, 0.1);
  grid.set(0, 0, CellState::free);
  grid.set(6, 4, CellState::occupied);
  grid.set(3, 2, CellState::free);
  const OccupancyGrid back = grid_from_image(image_from_grid(grid), OccupancyThresholds{}, 0.1);
  CHECK(back == grid);
}

TEST_CASE("PGM P5 and P2, 8 and 16 bit") {
  const auto p5 = decode_pgm(bytes_of(std::string("P5\n# a comment\n3 2\n255\n") + std::string("\x00\x7f\xfe\x01\x02\x03", 6)), "p5");
  CHECK(p5.width == 3);
  CHECK(p5.height == 2);
  CHECK(p5.at(2, 0) == 254);
  CHECK(p5.at(0, 1) == 1);
  const auto p2 = decode_pgm(bytes_of("P2 2 2 15\n0 15\n# mid-data comment\n7 8\n"), "p2");
  CHECK(p2.max_value == 15);
  CHECK(p2.at(1, 0) == 15);
  CHECK(p2.value8(1) == 255);
  CHECK(p2.value8(2) == 119);  // round(7·255/15)
  const auto wide = decode_pgm(bytes_of(std::string("P5 2 1 65535\n") + std::string("\xff\xff\x01\x00", 4)), "p5-16");
  CHECK(wide.at(0, 0) == 65535);
  CHECK(wide.at(1, 0) == 256);
  CHECK(decode_pgm(encode_pgm(wide), "again") == wide);
  CHECK(decode_pgm(encode_pgm(p5), "again") == p5);
}

TEST_CASE("bad PGMs give format errors naming the problem") {
  auto message = [](const std::string& text) {
    try {
      decode_pgm(bytes_of(text), "bad.pgm");
    } catch (const format_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(message("P5 3 2 255\n\x01\x02").find("truncated") != std::string::npos);
  CHECK(message("P5 3 2 70000\n").find("maxval") != std::string::npos);
  CHECK(message("P5 3 2 0\n").find("maxval") != std::string::npos);
  CHECK(message("P5 0 2 255\n").find("zero size") != std::string::npos);
  CHECK(message("P5 30000 2 255\n").find("limit") != std::string::npos);
  CHECK(message("P2 2 1 10\n3 11\n").find("exceeds maxval") != std::string::npos);
  CHECK(message("P2 2 1 10\n3").find("truncated") != std::string::npos);
  CHECK(message("P5 x 2 255\n").find("width") != std::string::npos);
  CHECK(message("P6 1 1 255\n\x01\x01\x01").find("not a PGM") != std::string::npos);
  CHECK(message("P5 99999999999 1 255\n").find("too large") != std::string::npos);
}

TEST_CASE("PNG encode/decode round trips: 8-bit, 16-bit grey and RGB") {
  GreyImage grey(5, 3, 255);
  for (std::size_t i = 0; i < grey.values.size(); ++i) grey.values[i] = static_cast<std::uint16_t>(i * 17);
  CHECK(decode_png(encode_png(grey), "grey") == grey);
  GreyImage labels(4, 4, 65535);
  for (std::size_t i = 0; i < labels.values.size(); ++i) labels.values[i] = static_cast<std::uint16_t>(i * 4000);
  CHECK(decode_png(encode_png(labels), "labels") == labels);
  RgbImage rgb(3, 2);
  rgb.set(0, 0, 30, 60, 90);  // averages to 60
  const GreyImage from_rgb = decode_png(encode_png(rgb), "rgb");
  CHECK(from_rgb.at(0, 0) == 60);
  CHECK(from_rgb.at(1, 1) == 255);
  CHECK_FALSE(from_rgb.has_alpha());
}

TEST_CASE("corrupt PNGs give format errors") {
  GreyImage grey(20, 20, 255, 100);
  auto png = encode_png(grey);
  CHECK_THROWS_AS(decode_png(bytes_of("\x89PNG\r\n\x1a\nrubbish"), "bad.png"), format_error);
  auto truncated = png;
  truncated.resize(png.size() / 2);
  CHECK_THROWS_AS(decode_png(truncated, "half.png"), format_error);
  auto flipped = png;
  flipped[png.size() / 2] ^= 0xff;  // damage the compressed data
  flipped[png.size() / 2 + 1] ^= 0xff;
  try {
    const GreyImage damaged = decode_png(flipped, "flipped.png");
    CHECK(damaged.width == 20);  // stb may decode damaged data without noticing; it must not crash
  } catch (const format_error&) {
  }
  CHECK_THROWS_WITH_AS(decode_png(bytes_of("GIF89a"), "x.gif"), doctest::Contains("not a PNG"), format_error);
}
