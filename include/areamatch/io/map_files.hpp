#pragma once
/// \file io/map_files.hpp
/// Loading and saving occupancy grids: PGM, PNG and ROS map_server YAML. `<areamatch/io.hpp>`
/// includes it with the JSON and SVG writers; a program that only reads and writes maps includes
/// this alone (under a third of the compile: the writers pull in every result type).

#include "../detail/file.hpp"
#include "../error.hpp"
#include "../grid.hpp"
#include "../image.hpp"
#include "pgm.hpp"
#include "png.hpp"
#include "ros_yaml.hpp"

#include <optional>
#include <string>

namespace areamatch {

/// Overrides for what a YAML says (or, for a bare image, what map_server would assume).
struct LoadOptions {
  std::optional<double> resolution;       ///< m/pixel; a bare image defaults to 0.05
  std::optional<double> free_thresh;      ///< default 0.196 for a bare image
  std::optional<double> occupied_thresh;  ///< default 0.65 for a bare image
  std::optional<bool> negate;             ///< default false for a bare image
};

/// A loaded map with where it came from.
struct LoadedMap {
  OccupancyGrid grid;
  GreyImage image;                   ///< the image as read (grey, with alpha if any)
  std::string image_path;
  std::string yaml_path;             ///< empty when a bare image was loaded
  OccupancyThresholds thresholds;    ///< what classified the cells
};

/// Default resolution of a bare image (the Bormann et al. dataset's and most SLAM maps').
inline constexpr double default_resolution = 0.05;

/// Decodes a PNG or PGM image from a file, recognised by its content (not its extension).
inline GreyImage read_image(const std::string& path) {
  const auto bytes = detail::read_file_bytes(path);
  if (looks_like_png(bytes)) return decode_png(bytes, path);
  if (looks_like_pgm(bytes)) return decode_pgm(bytes, path);
  throw format_error(path + ": not a PNG or PGM image");
}

/// Writes a PNG or PGM, chosen by the extension (.png, .pgm). RGB images only as PNG.
inline void write_image(const std::string& path, const GreyImage& image) {
  const std::string ext = detail::lowercase_extension(path);
  if (ext == "png") write_png(path, image);
  else if (ext == "pgm") write_pgm(path, image);
  else throw parameter_error(path + ": unsupported image extension (use .png or .pgm)");
}

/// Loads a map from a map_server YAML (.yaml/.yml) or a bare PNG/PGM image, applying `options`
/// over the YAML's values. Throws `io_error`/`format_error`/`parameter_error` with the file name.
inline LoadedMap load_map_with_image(const std::string& path, const LoadOptions& options = {}) {
  LoadedMap loaded;
  const std::string ext = detail::lowercase_extension(path);
  double resolution = default_resolution;
  Pose2 origin{};
  if (ext == "yaml" || ext == "yml") {
    MapYaml meta = read_map_yaml(path);
    loaded.yaml_path = path;
    loaded.image_path = meta.image_path;
    loaded.thresholds = meta.thresholds;
    resolution = meta.resolution;
    origin = meta.origin;
  } else {
    loaded.image_path = path;
  }
  if (options.resolution) resolution = *options.resolution;
  if (options.free_thresh) loaded.thresholds.free_thresh = *options.free_thresh;
  if (options.occupied_thresh) loaded.thresholds.occupied_thresh = *options.occupied_thresh;
  if (options.negate) loaded.thresholds.negate = *options.negate;
  check_resolution(resolution, path + ": resolution");
  loaded.thresholds.validate();

  try {
    loaded.image = read_image(loaded.image_path);
  } catch (const io_error& e) {
    if (loaded.yaml_path.empty()) throw;
    // Say which YAML pointed at the unreadable image.
    if (dynamic_cast<const format_error*>(&e)) throw format_error(std::string(e.what()) + " (image of " + path + ")");
    throw io_error(std::string(e.what()) + " (image of " + path + ")");
  }
  check_extent(loaded.image.width, loaded.image.height, resolution, path);
  loaded.grid = grid_from_image(loaded.image, loaded.thresholds, resolution, origin);
  return loaded;
}

/// The grid only; see `load_map_with_image`.
inline OccupancyGrid load_map(const std::string& path, const LoadOptions& options = {}) {
  return load_map_with_image(path, options).grid;
}

/// Saves `grid` as map_saver does (free 254, occupied 0, unknown 205) to `image_path` (.pgm or
/// .png) and writes a map_server YAML beside it (same name, .yaml). Returns the YAML's path.
/// Loading the YAML gives back `grid` exactly.
inline std::string save_map(const OccupancyGrid& grid, const std::string& image_path) {
  write_image(image_path, image_from_grid(grid));
  const std::string name = detail::file_name(image_path);
  const auto dot = name.find_last_of('.');
  const std::string yaml_path = detail::parent_folder(image_path) + name.substr(0, dot) + ".yaml";
  MapYaml meta;
  meta.image = name;
  meta.resolution = grid.resolution();
  meta.origin = grid.origin();
  detail::write_file_text(yaml_path, map_yaml_text(meta));
  return yaml_path;
}

}  // namespace areamatch
