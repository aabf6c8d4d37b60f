#pragma once
/// \file image.hpp
/// Plain images (grey with optional alpha, and RGB) and the map_server rule that turns a grey image
/// into an `OccupancyGrid`. No file formats here: those live in the `areamatch::io` target.

#include "error.hpp"
#include "grid.hpp"

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace areamatch {

/// Largest accepted image side in pixels (a 20000 × 20000 map at 0.05 m is 1 km²). Loaders check
/// it before allocating, so a corrupt header cannot ask for gigabytes.
inline constexpr int max_image_side = 20000;

/// Largest accepted map in cells (e.g. 14 000 × 14 000; 500 000 m² at 0.05 m: a 400 × 300 m
/// floor turned by 37° needs 96 M). Matching a pair peaks at about 6 bytes per cell of the two
/// maps (measured with the CLI: 567–587 MiB for the 400 × 300 m generated pair's 97 M cells,
/// docs/performance.md), so a pair at this size needs about 2.5 GB; the limit keeps a corrupt or
/// absurd header from asking for more.
inline constexpr long long max_grid_cells = 200'000'000;

/// Throws `format_error` naming `what` unless 1 ≤ width, height ≤ max_image_side, and
/// `limit_error` when width · height > max_grid_cells — before any pixel memory is allocated.
inline void check_image_size(long long width, long long height, const std::string& what) {
  if (width <= 0 || height <= 0) {
    throw format_error(what + ": image has zero size (" + std::to_string(width) + "x" +
                       std::to_string(height) + ")");
  }
  if (width > max_image_side || height > max_image_side) {
    throw format_error(what + ": image is " + std::to_string(width) + "x" + std::to_string(height) +
                       ", larger than the limit of " + std::to_string(max_image_side) +
                       " pixels per side");
  }
  if (width * height > max_grid_cells) {
    throw limit_error(what + ": image is " + std::to_string(width) + "x" + std::to_string(height) + " = " +
                      std::to_string(width * height) + " cells, more than the limit of " +
                      std::to_string(max_grid_cells) + " (areamatch::max_grid_cells); crop or downsample the map");
  }
}

/// A single-channel image with 8- or 16-bit values (colour images are averaged to grey when read),
/// plus the alpha channel when the file had one. Row 0 is the top row.
struct GreyImage {
  int width = 0;
  int height = 0;
  int max_value = 255;                ///< 255 (8-bit), 65535 (16-bit) or a PGM maxval
  std::vector<std::uint16_t> values;  ///< width·height values, row-major
  std::vector<std::uint16_t> alpha;   ///< empty, or width·height values in [0, max_value]

  GreyImage() = default;
  GreyImage(int w, int h, int max, std::uint16_t fill = 0)
      : width(w), height(h), max_value(max), values(static_cast<std::size_t>(w) * h, fill) {}

  std::uint16_t at(int col, int row) const { return values[static_cast<std::size_t>(row) * width + col]; }
  std::uint16_t& at(int col, int row) { return values[static_cast<std::size_t>(row) * width + col]; }
  bool has_alpha() const { return !alpha.empty(); }
  /// The value reduced to 8 bits, round(v · 255 / max_value): map_server (and OpenCV-based tools)
  /// judge every image on this 0–255 scale.
  int value8(std::size_t i) const {
    if (max_value == 255) return values[i];
    // Integer round-half-up, the same as lround of the quotient for these non-negative values,
    // without a floating-point call per pixel (it was 6 % of loading a 16-bit map).
    const long long v = values[i], m = max_value;
    return static_cast<int>((2 * 255 * v + m) / (2 * m));
  }
  friend bool operator==(const GreyImage& a, const GreyImage& b) {
    return a.width == b.width && a.height == b.height && a.max_value == b.max_value &&
           a.values == b.values && a.alpha == b.alpha;
  }
};

/// An 8-bit RGB image (pictures of maps and matches). Row 0 is the top row.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< 3·width·height bytes

  RgbImage() = default;
  RgbImage(int w, int h, std::uint8_t r = 255, std::uint8_t g = 255, std::uint8_t b = 255)
      : width(w), height(h) {
    rgb.reserve(static_cast<std::size_t>(w) * h * 3);
    for (std::size_t i = 0; i < static_cast<std::size_t>(w) * h; ++i) {
      rgb.push_back(r);
      rgb.push_back(g);
      rgb.push_back(b);
    }
  }
  void set(int col, int row, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    std::uint8_t* p = &rgb[(static_cast<std::size_t>(row) * width + col) * 3];
    p[0] = r;
    p[1] = g;
    p[2] = b;
  }
};

/// How map_server interprets pixel values (the YAML keys of the same names).
enum class ThresholdMode { trinary, scale, raw };

/// map_server's thresholds. With p = (255 − v)/255 (or v/255 when `negate`), v the 8-bit value:
/// occupied if p > occupied_thresh, free if p < free_thresh, otherwise unknown — strict comparisons,
/// as map_server makes them, so ROS's unknown grey 205 (p = 0.19608) stays unknown at 0.196.
/// `scale` gives the same three states (its intermediate probabilities have no place in a
/// three-state grid) and also makes fully transparent pixels unknown. `raw` reads v itself as an
/// occupancy percentage: v ≤ 100 is thresholded as p = v/100, anything above is unknown.
struct OccupancyThresholds {
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  bool negate = false;
  ThresholdMode mode = ThresholdMode::trinary;

  /// Throws `parameter_error` unless both thresholds are in [0, 1] and free ≤ occupied.
  void validate() const {
    auto in_unit = [](double v) { return std::isfinite(v) && v >= 0.0 && v <= 1.0; };
    if (!in_unit(occupied_thresh)) {
      throw parameter_error("occupied_thresh must be in [0, 1], got " + std::to_string(occupied_thresh));
    }
    if (!in_unit(free_thresh)) {
      throw parameter_error("free_thresh must be in [0, 1], got " + std::to_string(free_thresh));
    }
    if (free_thresh > occupied_thresh) {
      throw parameter_error("free_thresh (" + std::to_string(free_thresh) +
                            ") must not exceed occupied_thresh (" + std::to_string(occupied_thresh) + ")");
    }
  }

  CellState classify(int value8, bool transparent) const {
    if (mode == ThresholdMode::raw) {
      if (value8 > 100) return CellState::unknown;
      return classify_probability(value8 / 100.0);
    }
    if (mode == ThresholdMode::scale && transparent) return CellState::unknown;
    const double p = negate ? value8 / 255.0 : (255.0 - value8) / 255.0;
    return classify_probability(p);
  }

 private:
  CellState classify_probability(double p) const {
    if (p > occupied_thresh) return CellState::occupied;
    if (p < free_thresh) return CellState::free;
    return CellState::unknown;
  }
};

/// Applies map_server's rule to every pixel of `image`.
inline OccupancyGrid grid_from_image(const GreyImage& image, const OccupancyThresholds& thresholds,
                                     double resolution, const Pose2& origin = {}) {
  thresholds.validate();
  OccupancyGrid grid(image.width, image.height, resolution, origin);
  // Every pixel is judged on its 8-bit value: one table lookup per pixel.
  CellState opaque[256], transparent[256];
  for (int v = 0; v < 256; ++v) {
    opaque[v] = thresholds.classify(v, false);
    transparent[v] = thresholds.classify(v, true);
  }
  auto& cells = grid.cells();
  const bool eight_bit = image.max_value == 255;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const int v = eight_bit ? image.values[i] : image.value8(i);
    cells[i] = image.has_alpha() && image.alpha[i] == 0 ? transparent[v] : opaque[v];
  }
  return grid;
}

/// The grey values map_saver writes: free 254, occupied 0, unknown 205. With the default
/// thresholds `grid_from_image(image_from_grid(g))` gives back `g` exactly.
inline GreyImage image_from_grid(const OccupancyGrid& grid) {
  GreyImage image(grid.width(), grid.height(), 255);
  const auto& cells = grid.cells();
  for (std::size_t i = 0; i < cells.size(); ++i) {
    image.values[i] = cells[i] == CellState::free ? 254 : cells[i] == CellState::occupied ? 0 : 205;
  }
  return image;
}

}  // namespace areamatch
