#pragma once
/// \file eval/manifest.hpp
/// Pairs manifests: the JSON format of `shared/pairs.json`, for evaluating a matcher on map pairs
/// with (optional) ground truth. Read with yaml-cpp, which reads JSON.
///
///     {"correct_if": {"max_rotation_error_deg": 3.0, "max_mean_displacement_m": 1.0},
///      "pairs": [{"name": "...", "source": "maps/a.yaml", "destination": "maps/b.yaml",
///                 "ground_truth": {"pixel_transform": [[a, b, tx], [c, d, ty]], ...},
///                 "door_width_m": 1.2, "ambiguous": false, "kind": "...", "note": "...",
///                 "source_resolution": 0.05, "destination_resolution": 0.05,
///                 "allow_reflection": true, "different_buildings": false}]}
///
/// Map paths are relative to the manifest's folder unless absolute. Everything but `name`,
/// `source` and `destination` is optional; `*_resolution` (m/pixel) override what the map's YAML
/// says (needed for bare images). A manifest gives a ground truth for every pair or for none:
/// a pair without one among pairs with one is an error, since a silently unscored pair would
/// skew the correct count. Pairs marked `different_buildings` are the exception: maps that must
/// NOT match (judged correct when rejected), with no ground truth.

#include <areamatch/detail/file.hpp>
#include <areamatch/error.hpp>
#include <areamatch/evaluation.hpp>
#include <areamatch/transform.hpp>

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace areamatch {

struct ManifestPair {
  std::string name;
  std::string kind;
  std::string source;       ///< path as resolved (relative to the manifest's folder)
  std::string destination;
  std::optional<PixelTransform> ground_truth;  ///< source pixel → destination pixel
  std::optional<double> door_width_m;
  std::optional<double> source_resolution;       ///< overrides the source YAML's resolution
  std::optional<double> destination_resolution;
  std::optional<bool> allow_reflection;          ///< overrides the evaluation's default
  bool ambiguous = false;
  bool different_buildings = false;              ///< the maps must not match
};

struct Manifest {
  std::string path;
  CorrectnessThresholds correct_if;
  std::vector<ManifestPair> pairs;
};

namespace detail {

inline std::string resolve_relative(const std::string& base_file, const std::string& path) {
  if (!path.empty() && path[0] == '/') return path;
  const auto slash = base_file.find_last_of('/');
  return slash == std::string::npos ? path : base_file.substr(0, slash + 1) + path;
}

inline double manifest_number(const YAML::Node& node, const std::string& where) {
  try {
    const double value = node.as<double>();
    if (!std::isfinite(value)) throw format_error(where + " must be a finite number");
    return value;
  } catch (const YAML::Exception&) {
    throw format_error(where + " must be a number");
  }
}

inline bool manifest_bool(const YAML::Node& node, const std::string& where) {
  try {
    return node.as<bool>();
  } catch (const YAML::Exception&) {
    throw format_error(where + " must be true or false");
  }
}

inline double manifest_positive(const YAML::Node& node, const std::string& where) {
  const double value = manifest_number(node, where);
  if (!(value > 0.0)) throw format_error(where + " must be positive");
  return value;
}

inline std::string manifest_text(const YAML::Node& node, const std::string& where) {
  if (!node || !node.IsScalar()) throw format_error(where + " must be a string");
  return node.as<std::string>();
}

}  // namespace detail

/// Parses the text of a pairs manifest; `path` names it in messages and map paths are resolved
/// against its folder. Throws `format_error` naming the pair and field when something is wrong
/// (missing or mistyped field, duplicate pair name, a ground truth that is not a 2×3 matrix).
inline Manifest parse_manifest(const std::string& text, const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw format_error(path + ": not valid JSON/YAML: " + e.what());
  }
  Manifest m;
  m.path = path;
  if (!root.IsMap()) throw format_error(path + ": the manifest must be a JSON object with a \"pairs\" array");
  if (const YAML::Node c = root["correct_if"]) {
    if (!c.IsMap()) throw format_error(path + ": correct_if must be an object");
    if (c["max_rotation_error_deg"]) {
      m.correct_if.max_rotation_error_deg = detail::manifest_number(c["max_rotation_error_deg"], path + ": correct_if.max_rotation_error_deg");
    }
    if (c["max_mean_displacement_m"]) {
      m.correct_if.max_mean_displacement_m = detail::manifest_number(c["max_mean_displacement_m"], path + ": correct_if.max_mean_displacement_m");
    }
  }
  const YAML::Node pairs = root["pairs"];
  if (!pairs || !pairs.IsSequence()) throw format_error(path + ": \"pairs\" must be an array");
  std::set<std::string> names;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const YAML::Node p = pairs[i];
    const std::string at = path + ": pair " + std::to_string(i);
    if (!p.IsMap()) throw format_error(at + " must be an object");
    ManifestPair pair;
    pair.name = detail::manifest_text(p["name"], at + ": name");
    const std::string where = path + ": pair '" + pair.name + "'";
    if (!names.insert(pair.name).second) throw format_error(where + ": duplicate pair name");
    if (p["kind"]) pair.kind = detail::manifest_text(p["kind"], where + ": kind");
    pair.source = detail::resolve_relative(path, detail::manifest_text(p["source"], where + ": source"));
    pair.destination = detail::resolve_relative(path, detail::manifest_text(p["destination"], where + ": destination"));
    if (p["door_width_m"]) pair.door_width_m = detail::manifest_positive(p["door_width_m"], where + ": door_width_m");
    if (p["source_resolution"]) {
      pair.source_resolution = detail::manifest_positive(p["source_resolution"], where + ": source_resolution");
    }
    if (p["destination_resolution"]) {
      pair.destination_resolution = detail::manifest_positive(p["destination_resolution"], where + ": destination_resolution");
    }
    if (p["allow_reflection"]) pair.allow_reflection = detail::manifest_bool(p["allow_reflection"], where + ": allow_reflection");
    if (p["ambiguous"]) pair.ambiguous = detail::manifest_bool(p["ambiguous"], where + ": ambiguous");
    if (p["different_buildings"]) {
      pair.different_buildings = detail::manifest_bool(p["different_buildings"], where + ": different_buildings");
    }
    if (const YAML::Node g = p["ground_truth"]) {
      const YAML::Node t = g.IsMap() ? g["pixel_transform"] : YAML::Node();
      if (!t || !t.IsSequence() || t.size() != 2 || !t[0].IsSequence() || !t[1].IsSequence() || t[0].size() != 3 ||
          t[1].size() != 3) {
        throw format_error(where + ": ground_truth.pixel_transform must be [[a, b, tx], [c, d, ty]]");
      }
      PixelTransform m2;
      for (int r = 0; r < 2; ++r)
        for (int c = 0; c < 3; ++c) m2(r, c) = detail::manifest_number(t[r][c], where + ": ground_truth.pixel_transform");
      if (pair.different_buildings) throw format_error(where + ": a pair of different_buildings has no ground_truth");
      pair.ground_truth = m2;
    }
    m.pairs.push_back(std::move(pair));
  }
  if (m.pairs.empty()) throw format_error(path + ": \"pairs\" is empty");
  const ManifestPair* with_truth = nullptr;
  const ManifestPair* without_truth = nullptr;
  for (const ManifestPair& pair : m.pairs) {
    if (pair.different_buildings) continue;
    const ManifestPair*& first = pair.ground_truth ? with_truth : without_truth;
    if (!first) first = &pair;
  }
  if (with_truth && without_truth) {
    throw format_error(path + ": pair '" + without_truth->name + "': ground_truth missing (other pairs have one; give " +
                       "every pair a ground truth or none)");
  }
  return m;
}

/// Maps grouped into buildings: maps joined by a pair of one building are one building
/// (transitively). Maps are numbered in the order they are first named.
class BuildingGroups {
 public:
  /// The map's number (a new one when the map is new: its own building).
  std::size_t add(const std::string& map) {
    const auto [it, added] = index_.emplace(map, parent_.size());
    if (added) {
      parent_.push_back(parent_.size());
      maps_.push_back(map);
    }
    return it->second;
  }
  /// Puts two maps into one building.
  void join(const std::string& a, const std::string& b) {
    const std::size_t ra = find(add(a)), rb = find(add(b));
    if (ra != rb) parent_[std::max(ra, rb)] = std::min(ra, rb);
  }
  /// The building of map number `i`: the number of its building's first-named map.
  std::size_t find(std::size_t i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  std::size_t building(const std::string& map) { return find(add(map)); }
  const std::string& map(std::size_t i) const { return maps_[i]; }
  std::size_t size() const { return maps_.size(); }

 private:
  std::map<std::string, std::size_t> index_;
  std::vector<std::size_t> parent_;
  std::vector<std::string> maps_;
};

/// Pairs of maps that must not match, made from a manifest's pairs: maps joined by a pair (of
/// the same building) form one building, and every two maps of different buildings make a pair
/// marked `different_buildings` (each unordered combination once, reflection allowed). A map
/// keeps the resolution and door width of the first pair that names it.
inline std::vector<ManifestPair> cross_building_pairs(const Manifest& m) {
  struct MapEntry {
    std::string path;
    std::optional<double> resolution, door_width_m;
    std::string stem;
  };
  std::vector<MapEntry> maps;
  BuildingGroups buildings;
  auto add = [&](const std::string& path, const std::optional<double>& resolution, const std::optional<double>& door) {
    const std::size_t i = buildings.add(path);
    if (i < maps.size()) return i;
    // The name: the path relative to the manifest's folder, without its extension.
    const std::string folder = detail::resolve_relative(m.path, "");
    std::string stem = path.compare(0, folder.size(), folder) == 0 ? path.substr(folder.size()) : path;
    const auto dot = stem.find_last_of('.');
    if (dot != std::string::npos && dot > 0 && stem.find('/', dot) == std::string::npos) stem.resize(dot);
    maps.push_back({path, resolution, door, stem});
    return i;
  };
  for (const ManifestPair& pair : m.pairs) {
    if (pair.different_buildings) continue;
    add(pair.source, pair.source_resolution, pair.door_width_m);
    add(pair.destination, pair.destination_resolution, pair.door_width_m);
    buildings.join(pair.source, pair.destination);
  }
  std::vector<ManifestPair> out;
  for (std::size_t i = 0; i < maps.size(); ++i) {
    for (std::size_t j = i + 1; j < maps.size(); ++j) {
      if (buildings.find(i) == buildings.find(j)) continue;
      ManifestPair pair;
      pair.name = maps[i].stem + " x " + maps[j].stem;
      pair.kind = "different_buildings";
      pair.source = maps[i].path;
      pair.destination = maps[j].path;
      pair.source_resolution = maps[i].resolution;
      pair.destination_resolution = maps[j].resolution;
      if (maps[i].door_width_m && maps[j].door_width_m && *maps[i].door_width_m == *maps[j].door_width_m) {
        pair.door_width_m = maps[i].door_width_m;
      }
      pair.allow_reflection = true;
      pair.different_buildings = true;
      out.push_back(std::move(pair));
    }
  }
  return out;
}

/// Reads a pairs manifest (at most 64 MiB). Throws `io_error` when the file cannot be read and
/// `format_error` as `parse_manifest` does.
inline Manifest load_manifest(const std::string& path) {
  std::vector<unsigned char> bytes;
  try {
    bytes = detail::read_file_bytes(path, std::size_t(64) << 20);
  } catch (const format_error& e) {
    throw format_error(std::string("manifest ") + e.what());
  } catch (const io_error& e) {
    throw io_error(std::string("cannot read manifest ") + e.what());
  }
  return parse_manifest(std::string(bytes.begin(), bytes.end()), path);
}

/// Throws `io_error` naming the pair and field when a pair's source or destination file does
/// not exist or cannot be opened, so that a long evaluation does not stop half-way on a typo.
inline void check_manifest_files(const Manifest& m) {
  for (const ManifestPair& pair : m.pairs) {
    for (const auto& [field, file] : {std::pair{"source", &pair.source}, std::pair{"destination", &pair.destination}}) {
      std::error_code ec;
      const bool exists = std::filesystem::exists(*file, ec);
      std::ifstream in(*file, std::ios::binary);
      if (!exists || !in || !std::filesystem::is_regular_file(*file, ec)) {
        throw io_error(m.path + ": pair '" + pair.name + "': " + field + " " + *file +
                       (exists ? " is not a readable file" : " does not exist"));
      }
    }
  }
}

}  // namespace areamatch
