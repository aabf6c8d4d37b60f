#pragma once
/// \file io/ros_yaml.hpp
/// ROS map_server map metadata (the YAML beside a map image), read with yaml-cpp.
///
///     image: map.pgm            # required; relative to the YAML's folder unless absolute
///     resolution: 0.05          # required; metres per pixel, positive
///     origin: [x, y, yaw]       # required; world pose of the lower-left pixel's corner
///     negate: 0                 # optional; 0/1 or false/true
///     occupied_thresh: 0.65     # optional; in [0, 1]
///     free_thresh: 0.196        # optional; in [0, 1], ≤ occupied_thresh
///     mode: trinary             # optional; trinary | scale | raw

#include "../detail/file.hpp"
#include "../detail/format.hpp"
#include "../error.hpp"
#include "../grid.hpp"
#include "../image.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <string>

namespace areamatch {

/// The content of a map_server YAML.
struct MapYaml {
  std::string image;       ///< as written in the file
  std::string image_path;  ///< `image` resolved against the YAML's folder
  double resolution = 0.05;
  Pose2 origin{};
  OccupancyThresholds thresholds{};
};

namespace detail {

template <class T>
T yaml_value(const YAML::Node& node, const std::string& key, const std::string& path, const char* expected) {
  try {
    return node[key].as<T>();
  } catch (const YAML::Exception&) {
    throw format_error(path + ": '" + key + "' must be " + expected);
  }
}

inline std::string yaml_quote(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace detail

/// Parses and checks the text of a map_server YAML; `path` names it in messages and relative
/// image paths are resolved against its folder. Throws `format_error` (naming the file and the
/// key) when a key is missing or invalid.
inline MapYaml parse_map_yaml(const std::string& text, const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw format_error(path + ": not valid YAML (" + e.msg + ")");
  }
  if (!root.IsMap()) throw format_error(path + ": expected a YAML mapping of map_server keys");
  for (const char* key : {"image", "resolution", "origin"}) {
    if (!root[key]) throw format_error(path + ": missing required key '" + key + "'");
  }
  MapYaml meta;
  meta.image = detail::yaml_value<std::string>(root, "image", path, "a file name");
  if (meta.image.empty()) throw format_error(path + ": 'image' is empty");
  meta.image_path = meta.image.front() == '/' ? meta.image : detail::parent_folder(path) + meta.image;

  meta.resolution = detail::yaml_value<double>(root, "resolution", path, "a number");
  if (!(std::isfinite(meta.resolution) && meta.resolution > 0.0)) {
    throw format_error(path + ": 'resolution' must be a positive finite number of metres per pixel, got " +
                       detail::format_double(meta.resolution));
  }
  const YAML::Node origin = root["origin"];
  if (!origin.IsSequence() || origin.size() != 3) {
    throw format_error(path + ": 'origin' must be a list [x, y, yaw]");
  }
  try {
    meta.origin = {origin[0].as<double>(), origin[1].as<double>(), origin[2].as<double>()};
  } catch (const YAML::Exception&) {
    throw format_error(path + ": 'origin' must hold three numbers [x, y, yaw]");
  }
  if (!std::isfinite(meta.origin.x) || !std::isfinite(meta.origin.y) || !std::isfinite(meta.origin.yaw)) {
    throw format_error(path + ": 'origin' must be finite");
  }

  OccupancyThresholds& t = meta.thresholds;
  if (root["negate"]) {
    try {
      t.negate = root["negate"].as<int>() != 0;
    } catch (const YAML::Exception&) {
      t.negate = detail::yaml_value<bool>(root, "negate", path, "0, 1, true or false");
    }
  }
  if (root["occupied_thresh"]) t.occupied_thresh = detail::yaml_value<double>(root, "occupied_thresh", path, "a number");
  if (root["free_thresh"]) t.free_thresh = detail::yaml_value<double>(root, "free_thresh", path, "a number");
  if (root["mode"]) {
    const auto mode = detail::yaml_value<std::string>(root, "mode", path, "trinary, scale or raw");
    if (mode == "trinary") t.mode = ThresholdMode::trinary;
    else if (mode == "scale") t.mode = ThresholdMode::scale;
    else if (mode == "raw") t.mode = ThresholdMode::raw;
    else throw format_error(path + ": 'mode' must be trinary, scale or raw, got '" + mode + "'");
  }
  try {
    t.validate();
  } catch (const parameter_error& e) {
    throw format_error(path + ": " + e.what());
  }
  return meta;
}

/// Reads and checks a map_server YAML (at most 1 MiB). Throws `io_error` when the file cannot be
/// read and `format_error` (naming the file and the key) when a key is missing or invalid.
inline MapYaml read_map_yaml(const std::string& path) {
  const auto bytes = detail::read_file_bytes(path, std::size_t(1) << 20);
  return parse_map_yaml(std::string(bytes.begin(), bytes.end()), path);
}

/// The YAML text for `meta` (numbers written so that they read back exactly).
inline std::string map_yaml_text(const MapYaml& meta) {
  using detail::format_double;
  const auto& t = meta.thresholds;
  const char* mode = t.mode == ThresholdMode::trinary ? "trinary" : t.mode == ThresholdMode::scale ? "scale" : "raw";
  return "image: " + detail::yaml_quote(meta.image) + "\n" +
         "resolution: " + format_double(meta.resolution) + "\n" +
         "origin: [" + format_double(meta.origin.x) + ", " + format_double(meta.origin.y) + ", " +
         format_double(meta.origin.yaw) + "]\n" +
         "negate: " + (t.negate ? "1" : "0") + "\n" +
         "occupied_thresh: " + format_double(t.occupied_thresh) + "\n" +
         "free_thresh: " + format_double(t.free_thresh) + "\n" +
         "mode: " + mode + "\n";
}

}  // namespace areamatch
