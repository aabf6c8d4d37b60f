// The Python module `areamatch._core`: a thin binding of the public headers for NumPy and ROS 2
// users. Everything the library decides is decided in C++; this file only converts. The GIL is
// released while maps are loaded, segmented, prepared, matched and merged, so Python threads
// run those side by side. Library exceptions become ValueError (bad parameters or file content)
// or OSError (a file that cannot be read or written), with the library's message.

#include <areamatch/areamatch.hpp>
#include <areamatch/synthetic.hpp>
#include <areamatch/io.hpp>
#include <areamatch/io/match_files.hpp>
#include <areamatch/merge.hpp>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/operators.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <initializer_list>
#include <utility>
#include <variant>
#include <vector>

namespace py = pybind11;
namespace am = areamatch;

namespace {

using Origin = std::tuple<double, double, double>;
using DefaultMatcher = am::Matcher<>;
using Prepared = DefaultMatcher::PreparedMap;
using release_gil = py::call_guard<py::gil_scoped_release>;

am::Pose2 to_pose(const Origin& o) { return {std::get<0>(o), std::get<1>(o), std::get<2>(o)}; }
Origin to_tuple(const am::Pose2& p) { return {p.x, p.y, p.yaw}; }

/// An Nx2 array of a ring's (or any range of points') x, y.
template <class Points>
py::array_t<double> points_array(const Points& points) {
  py::array_t<double> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{2}});
  auto view = out.mutable_unchecked<2>();
  py::ssize_t i = 0;
  for (const auto& p : points) {
    view(i, 0) = p.x();
    view(i, 1) = p.y();
    ++i;
  }
  return out;
}

py::object json_loads(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

/// Rejects arrays that are not two-dimensional with a message that says what was given.
void require_2d(const py::array& a, const char* what) {
  if (a.ndim() != 2) {
    throw am::parameter_error(std::string(what) + " must be a two-dimensional array (rows, columns), got " +
                              std::to_string(a.ndim()) + " dimensions");
  }
}

/// A grid from an 8- or 16-bit grey image read as map_server reads its image files.
am::OccupancyGrid grid_from_array(const py::array& a, double resolution, const Origin& origin, double free_thresh,
                                  double occupied_thresh, bool negate) {
  require_2d(a, "the image");
  const auto kind = a.dtype().kind();
  const bool u8 = a.dtype().is(py::dtype::of<std::uint8_t>());
  const bool u16 = a.dtype().is(py::dtype::of<std::uint16_t>());
  if (!u8 && !u16) {
    throw am::parameter_error(std::string("the image must be of dtype uint8 or uint16 (grey values as in a PGM/PNG), got ") +
                              py::str(a.dtype()).cast<std::string>() + (kind == 'b' ? " (use a uint8 image: 0 wall, 254 free, 205 unknown)" : ""));
  }
  am::check_resolution(resolution);
  const auto height = a.shape(0), width = a.shape(1);
  am::check_image_size(width, height, "the image");
  am::GreyImage image(static_cast<int>(width), static_cast<int>(height), u8 ? 255 : 65535);
  if (u8) {
    const auto c = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(a);
    std::copy(c.data(), c.data() + c.size(), image.values.begin());
  } else {
    const auto c = py::array_t<std::uint16_t, py::array::c_style | py::array::forcecast>::ensure(a);
    std::copy(c.data(), c.data() + c.size(), image.values.begin());
  }
  am::OccupancyThresholds thresholds;
  thresholds.free_thresh = free_thresh;
  thresholds.occupied_thresh = occupied_thresh;
  thresholds.negate = negate;
  return am::grid_from_image(image, thresholds, resolution, to_pose(origin));
}

/// A grid from `nav_msgs/OccupancyGrid` data: row 0 of `data` is the row at the origin (the
/// bottom of the image), values −1 unknown and 0–100 occupancy, classified as map_saver does
/// (≥ occupied_thresh·100 occupied, ≤ free_thresh·100 free, unknown between).
am::OccupancyGrid grid_from_occupancy_data(const py::object& data_like, long long width, long long height, double resolution,
                                           const Origin& origin, double free_thresh, double occupied_thresh) {
  if (width <= 0 || height <= 0) {
    throw am::parameter_error("width and height must be positive, got " + std::to_string(width) + "x" + std::to_string(height));
  }
  am::check_image_size(width, height, "the occupancy grid");
  // Lists and array.array('b') (what rclpy hands over) as well as NumPy arrays.
  const py::array data = py::module_::import("numpy").attr("asarray")(data_like);
  const char kind = data.dtype().kind();
  if (kind != 'i' && kind != 'u') {
    throw am::parameter_error("occupancy data must be integers (-1 unknown, 0-100 occupancy), got dtype " +
                              py::str(data.dtype()).cast<std::string>());
  }
  const auto cells = static_cast<py::ssize_t>(width * height);
  if (data.size() != cells) {
    throw am::parameter_error("occupancy data has " + std::to_string(data.size()) + " values, width x height is " +
                              std::to_string(cells));
  }
  if (!(free_thresh >= 0.0 && free_thresh <= occupied_thresh && occupied_thresh <= 1.0)) {
    throw am::parameter_error("thresholds must satisfy 0 <= free_thresh <= occupied_thresh <= 1, got " +
                              std::to_string(free_thresh) + " and " + std::to_string(occupied_thresh));
  }
  // uint8 data is int8 data seen unsigned (255 = −1): rclpy hands the same bytes either way.
  const bool reinterpret_u8 = data.dtype().is(py::dtype::of<std::uint8_t>());
  const auto values = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(data);
  am::OccupancyGrid grid(static_cast<int>(width), static_cast<int>(height), resolution, to_pose(origin));
  const double occupied_at = occupied_thresh * 100.0 - 1e-9, free_at = free_thresh * 100.0 + 1e-9;
  const std::int64_t* v = values.data();
  for (py::ssize_t i = 0; i < cells; ++i) {
    std::int64_t value = v[i];
    if (reinterpret_u8 && value > 127) value -= 256;
    if (value < -1 || value > 100) {
      throw am::parameter_error("occupancy values must be -1 (unknown) or 0-100, got " + std::to_string(value) +
                                " at index " + std::to_string(i));
    }
    const int ros_row = static_cast<int>(i / width), col = static_cast<int>(i % width);
    const int row = static_cast<int>(height) - 1 - ros_row;
    grid.set(col, row, value < 0 ? am::CellState::unknown
                       : value >= occupied_at ? am::CellState::occupied
                       : value <= free_at ? am::CellState::free
                                          : am::CellState::unknown);
  }
  return grid;
}

py::dict occupancy_grid_fields(const am::OccupancyGrid& grid) {
  py::array_t<std::int8_t> data(static_cast<py::ssize_t>(grid.cells().size()));
  std::int8_t* out = data.mutable_data();
  for (int row = 0; row < grid.height(); ++row) {
    for (int col = 0; col < grid.width(); ++col) {
      const am::CellState s = grid.at(col, row);
      out[grid.ros_data_index(col, row)] = s == am::CellState::free ? 0 : s == am::CellState::occupied ? 100 : -1;
    }
  }
  py::dict d;
  d["data"] = data;
  d["width"] = grid.width();
  d["height"] = grid.height();
  d["resolution"] = grid.resolution();
  d["origin"] = to_tuple(grid.origin());
  return d;
}

/// The options of one match, as `areamatch match` takes them.
am::MapPairOptions pair_options(std::optional<double> door_width, std::optional<double> source_door_width,
                                std::optional<double> dest_door_width, bool allow_reflection, bool estimate_scale,
                                std::optional<std::size_t> k, std::optional<double> min_score,
                                std::optional<double> min_agreement, std::optional<double> gate_max_lower_walls,
                                std::optional<double> gate_min_overlap_m2, std::optional<double> min_p_correct, bool paper,
                                unsigned threads,
                                std::array<const char*, 3> names = {"door_width_m", "source_door_width_m", "dest_door_width_m"}) {
  if (door_width && (source_door_width || dest_door_width)) {
    throw am::parameter_error(std::string("give either door_width_m or ") + names[1] + "/" + names[2] + ", not both");
  }
  for (const auto& [value, name] : {std::pair{door_width, names[0]}, std::pair{source_door_width, names[1]},
                                    std::pair{dest_door_width, names[2]}}) {
    if (value) am::detail::require_positive(*value, name);
  }
  if (k && (*k < 1 || *k > 1000)) throw am::parameter_error("k must be in 1..1000, got " + std::to_string(*k));
  am::MapPairOptions o;
  o.source_door_width_m = door_width ? door_width : source_door_width;
  o.dest_door_width_m = door_width ? door_width : dest_door_width;
  o.allow_reflection = allow_reflection;
  o.estimate_scale = estimate_scale;
  // The keywords that stand for settings of the table (as the program's --k, --min-agreement, ...).
  auto add = [&o](const char* name, const std::optional<double>& value) {
    if (value) o.settings.push_back({name, am::detail::format_double(*value)});
  };
  add("k", k ? std::optional<double>(static_cast<double>(*k)) : std::nullopt);
  add("decision.min_score", min_score);
  add("decision.min_agreement", min_agreement);
  add("decision.gate_max_lower_walls", gate_max_lower_walls);
  add("decision.gate_min_overlap_m2", gate_min_overlap_m2);
  add("decision.min_p_correct", min_p_correct);
  o.paper = paper;
  o.threads = threads;
  return o;
}

/// A match with the maps and graphs it was made from (for pictures and the graphs' ids). A source
/// matched as a grid onto a prepared map was segmented inside the match: its graph is made again
/// (by the same segmenter) only when asked for.
struct MatchRun {
  am::MapPairRun run;
  std::optional<am::VoronoiSegmenter> segment_source_on_demand;

  const am::AreaGraph& source_graph() {
    if (segment_source_on_demand) {
      run.source_graph = segment_source_on_demand->segment(run.source);
      segment_source_on_demand.reset();
    }
    return run.source_graph;
  }
};

/// An assessment with the maps and graphs it was made from (for its picture).
struct AssessRun {
  am::MapPairRun run;
  am::MapAssessment assessment;
};


/// A Python callable as the library's progress callback, called with (stage, done, total) and the
/// GIL held; None: no reports. It stays alive for the call it was passed to, whose argument holds
/// it: the callback keeps the bare pointer, since copies of it are made without the GIL.
am::ProgressCallback python_progress(const py::object& callable) {
  if (callable.is_none()) return nullptr;
  PyObject* function = callable.ptr();
  return [function](const am::Progress& p) {
    const py::gil_scoped_acquire gil;
    const py::handle callable_now(function);
    callable_now(std::string(p.stage), p.done, p.total);
  };
}

/// `params={"name": value}` as settings of the table (parameters.hpp): bools as true/false, numbers
/// exactly, lists of numbers comma-joined, text as it is. Called with the GIL released (the
/// bindings' call guard): takes it for the conversion.
std::vector<am::ParameterSetting> settings_from(const py::object& params) {
  const py::gil_scoped_acquire gil;
  std::vector<am::ParameterSetting> settings;
  if (params.is_none()) return settings;
  if (!py::isinstance<py::dict>(params)) throw am::parameter_error("params must be a dict of setting names to values");
  auto text = [](const py::handle& v, const std::string& name) -> std::string {
    if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
    if (py::isinstance<py::int_>(v)) return py::str(v).cast<std::string>();
    if (py::isinstance<py::float_>(v)) return am::detail::format_double(v.cast<double>());
    if (py::isinstance<py::str>(v)) return v.cast<std::string>();
    if (py::hasattr(v, "__float__")) return am::detail::format_double(v.cast<double>());  // numpy's scalars
    throw am::parameter_error("params['" + name + "']: a bool, a number, a list of numbers or text, got " +
                              py::str(py::type::of(v)).cast<std::string>());
  };
  for (const auto& [key, value] : params.cast<py::dict>()) {
    if (!py::isinstance<py::str>(key)) throw am::parameter_error("params: each key is a setting's name (a str)");
    const std::string name = key.cast<std::string>();
    std::string joined;
    if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
      for (const auto& item : value) joined += (joined.empty() ? "" : ",") + text(item, name);
    } else {
      joined = text(value, name);
    }
    settings.push_back({name, joined});
  }
  return settings;
}

/// A default matcher with options, for prepared maps and merging.
struct PyMatcher {
  DefaultMatcher matcher;
  am::MapPairOptions options;
};

/// A merge with its input grids (for the picture).
struct MergeRun {
  am::MergeResult result;
  std::vector<am::OccupancyGrid> grids;
  std::vector<std::string> names;
};

MatchRun match_prepared(const PyMatcher& m, const am::OccupancyGrid* source_grid, const Prepared* source, const Prepared& dest) {
  MatchRun out;
  out.run.result = source ? m.matcher.match(*source, dest) : m.matcher.match(*source_grid, dest);
  if (source) {
    out.run.source = source->grid();
    out.run.source_graph = source->graph();
  } else {
    out.run.source = *source_grid;
    out.segment_source_on_demand = m.matcher.segmenter;
  }
  out.run.dest = dest.grid();
  out.run.dest_graph = dest.graph();
  return out;
}

MergeRun run_merge(const DefaultMatcher& matcher, std::vector<Prepared> maps, std::optional<std::size_t> reference,
                   std::optional<double> resolution, double wall_share, double max_residual, bool until_connected,
                   bool same_side, unsigned threads, std::vector<std::string> names, bool build_merged_map, bool non_rigid,
                   std::optional<double> control_spacing, std::optional<double> bend_length) {
  am::MergeParams params;
  params.non_rigid = non_rigid;
  if (!non_rigid && (control_spacing || bend_length)) {
    throw am::parameter_error("control_spacing_m and bend_length_m shape the warps of non_rigid=True; set non_rigid=True too");
  }
  if (control_spacing) params.warp.control_spacing_m = *control_spacing;
  if (bend_length) params.warp.bend_length_m = *bend_length;
  params.reference = reference.value_or(0);
  if (resolution) {
    am::detail::require_positive(*resolution, "resolution");
    params.fuse.resolution = *resolution;
  }
  params.fuse.wall_share = wall_share;  // checked by merge_maps (FuseParams::validate)
  params.max_residual_m = max_residual;
  params.strategy = until_connected ? am::MergeStrategy::until_connected : am::MergeStrategy::all_pairs;
  params.refine_same_side = same_side;
  params.threads = threads;
  params.names = names;
  params.build_merged_map = build_merged_map;
  MergeRun out;
  out.result = am::merge_maps(matcher, maps, params);
  for (const auto& map : maps) out.grids.push_back(map.grid());
  out.names = std::move(names);
  return out;
}

py::dict merged_map_dict(const am::MergedMap& m) {
  py::dict d;
  d["placed"] = m.placed;
  d["reason"] = m.reason;
  d["T_reference_map"] = m.T_reference_map.matrix();
  d["pixel_transform"] = am::PixelTransform(m.pixel_transform);
  d["residual_m"] = m.residual_m;
  if (m.warp) {
    py::dict w;
    w["rigid_median_m"] = m.warp->rigid_median_m;
    w["warped_median_m"] = m.warp->warped_median_m;
    w["rigid_p95_m"] = m.warp->rigid_p95_m;
    w["warped_p95_m"] = m.warp->warped_p95_m;
    w["median_displacement_m"] = m.warp->median_displacement_m;
    w["max_displacement_m"] = m.warp->max_displacement_m;
    d["warp"] = w;
  } else {
    d["warp"] = py::none();
  }
  return d;
}

/// Library exceptions as areamatch.errors' classes (python/areamatch/errors.py: one base,
/// areamatch.Error, each class also a ValueError, OSError or RuntimeError as before). The module
/// is looked up when an error is raised (a dictionary lookup once imported), not held in a static.
void set_library_error(const char* name, const char* message) {
  const py::object type = py::module_::import("areamatch.errors").attr(name);
  PyErr_SetString(type.ptr(), message);
}

void translate_exceptions() {
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const am::format_error& e) {
      set_library_error("FormatError", e.what());
    } catch (const am::io_error& e) {
      set_library_error("IoError", e.what());
    } catch (const am::parameter_error& e) {
      set_library_error("ParameterError", e.what());
    } catch (const am::limit_error& e) {
      set_library_error("LimitError", e.what());
    } catch (const am::error& e) {
      set_library_error("InternalError", e.what());
    }
  });
}

/// Map: an occupancy grid with its frame; load, save, pictures.
void bind_map(py::module_& m) {
  py::class_<am::OccupancyGrid>(m, "Map", "An occupancy grid with its metric frame (ROS map_server conventions).")
      .def_static(
          "from_array",
          [](const py::array& image, double resolution, const Origin& origin, double free_thresh, double occupied_thresh,
             bool negate) { return grid_from_array(image, resolution, origin, free_thresh, occupied_thresh, negate); },
          py::arg("image"), py::arg("resolution"), py::arg("origin") = Origin{0.0, 0.0, 0.0}, py::arg("free_thresh") = 0.196,
          py::arg("occupied_thresh") = 0.65, py::arg("negate") = false,
          "A map from a grey image (uint8 or uint16, rows top to bottom as in the image file), classified as "
          "map_server classifies an image with these thresholds. origin: (x, y, yaw) of the lower-left corner.")
      .def_static("from_occupancy_grid", &grid_from_occupancy_data, py::arg("data"), py::arg("width"), py::arg("height"),
                  py::arg("resolution"), py::arg("origin") = Origin{0.0, 0.0, 0.0}, py::arg("free_thresh") = 0.25,
                  py::arg("occupied_thresh") = 0.65,
                  "A map from nav_msgs/OccupancyGrid fields: data row 0 at the origin (the image's bottom row), -1 "
                  "unknown, 0-100 occupancy (>= 65 occupied, <= 25 free, as map_saver). origin: (x, y, yaw).")
      .def("to_occupancy_grid", &occupancy_grid_fields,
           "The nav_msgs/OccupancyGrid fields as a dict (data: int8, -1/0/100; width; height; resolution; origin): "
           "Map.from_occupancy_grid(**m.to_occupancy_grid()) == m.")
      .def("to_image",
           [](const am::OccupancyGrid& g) {
             const am::GreyImage image = am::image_from_grid(g);
             py::array_t<std::uint8_t> out({g.height(), g.width()});
             std::copy(image.values.begin(), image.values.end(), out.mutable_data());
             return out;
           },
           "The map as map_saver writes it: uint8, 254 free, 0 occupied, 205 unknown, rows top to bottom.")
      .def("save", &am::save_map, py::arg("image_path"), release_gil(),
           "Writes the image (.pgm or .png) and a map_server YAML beside it; returns the YAML's path.")
      .def_property_readonly("width", &am::OccupancyGrid::width)
      .def_property_readonly("height", &am::OccupancyGrid::height)
      .def_property_readonly("resolution", &am::OccupancyGrid::resolution, "metres per cell")
      .def_property_readonly("origin", [](const am::OccupancyGrid& g) { return to_tuple(g.origin()); },
                             "(x, y, yaw) of the lower-left corner of the lower-left cell, metres and radians")
      .def_property_readonly(
          "cells",
          [](py::object self) {
            auto& g = self.cast<am::OccupancyGrid&>();
            static_assert(sizeof(am::CellState) == 1);
            return py::array_t<std::uint8_t>({g.height(), g.width()}, {g.width(), 1},
                                             reinterpret_cast<std::uint8_t*>(g.cells().data()), self);
          },
          "A writable NumPy view (rows, cols) of the cells, image rows top to bottom: FREE 0, OCCUPIED 1, UNKNOWN 2.")
      .def("counts",
           [](const am::OccupancyGrid& g) {
             const auto c = g.count();
             py::dict d;
             d["free"] = c.free;
             d["occupied"] = c.occupied;
             d["unknown"] = c.unknown;
             return d;
           })
      .def("world_from_pixel", [](const am::OccupancyGrid& g) { return Eigen::Matrix3d(g.world_from_pixel().matrix()); },
           "3x3 matrix: pixel (col, row, 1), centres at integers, to world metres (x, y, 1).")
      .def("copy", [](const am::OccupancyGrid& g) { return g; })
      .def(py::self == py::self)
      .def(py::self != py::self)
      .def("__repr__", [](const am::OccupancyGrid& g) {
        return "<areamatch.Map " + std::to_string(g.width()) + "x" + std::to_string(g.height()) + " at " +
               am::detail::format_double(g.resolution()) + " m/cell>";
      });

  m.def(
      "load_map",
      [](const std::filesystem::path& path, std::optional<double> resolution, std::optional<double> free_thresh,
         std::optional<double> occupied_thresh, std::optional<bool> negate) {
        am::LoadOptions o;
        o.resolution = resolution;
        o.free_thresh = free_thresh;
        o.occupied_thresh = occupied_thresh;
        o.negate = negate;
        return am::load_map(path.string(), o);
      },
      py::arg("path"), py::arg("resolution") = py::none(), py::arg("free_thresh") = py::none(),
      py::arg("occupied_thresh") = py::none(), py::arg("negate") = py::none(), release_gil(),
      "Loads a ROS map_server YAML or a bare PNG/PGM (a str or a path-like object; then 0.05 m per pixel and "
      "map_server's thresholds unless given). Keywords override what the YAML says.");

}

/// Passage, Area, AreaGraph and segment().
void bind_area_graph(py::module_& m) {
  py::class_<am::Passage>(m, "Passage", "An opening (door or junction) between two areas, metres.")
      .def_readonly("id", &am::Passage::id)
      .def_property_readonly("kind", [](const am::Passage& p) { return std::string(am::to_string(p.kind)); })
      .def_property_readonly("position", [](const am::Passage& p) { return Eigen::Vector2d(p.position); })
      .def_readonly("width_m", &am::Passage::width_m)
      .def_property_readonly("areas", [](const am::Passage& p) { return std::pair{p.area_a, p.area_b}; })
      .def_property_readonly("line", [](const am::Passage& p) { return points_array(std::vector<am::Point2>{p.line.first, p.line.second}); },
                             "2x2 array: the two wall ends across the opening");

  py::class_<am::Area>(m, "Area", "A room or corridor: polygon in metres, world frame.")
      .def_readonly("id", &am::Area::id)
      .def_property_readonly("kind", [](const am::Area& a) { return std::string(am::to_string(a.kind)); })
      .def_property_readonly("polygon", [](const am::Area& a) { return points_array(a.polygon.outer()); },
                             "Nx2 array: the outer ring (closed: the last point repeats the first)")
      .def_property_readonly("holes",
                             [](const am::Area& a) {
                               std::vector<py::array_t<double>> holes;
                               for (const auto& h : a.polygon.inners()) holes.push_back(points_array(h));
                               return holes;
                             })
      .def_property_readonly("convex_hull", [](const am::Area& a) { return points_array(a.convex_hull.outer()); })
      .def_readonly("size_m2", &am::Area::size_m2)
      .def_property_readonly("centroid", [](const am::Area& a) { return Eigen::Vector2d(a.centroid); })
      .def_readonly("max_clearance_m", &am::Area::max_clearance_m)
      .def_readonly("passages", &am::Area::passages);

  py::class_<am::AreaGraph>(m, "AreaGraph", "Areas (rooms, corridors) joined by passages, as `areamatch segment` makes them.")
      .def_readonly("areas", &am::AreaGraph::areas)
      .def_readonly("passages", &am::AreaGraph::passages)
      .def_readonly("covered_fraction", &am::AreaGraph::covered_fraction)
      .def_readonly("reason", &am::AreaGraph::reason, "why there are no areas (empty when there are some)")
      .def("adjacency", &am::AreaGraph::adjacency)
      .def("labels",
           [](const am::AreaGraph& g) {
             py::array_t<std::int32_t> out({g.grid.height, g.grid.width});
             std::copy(g.labels.begin(), g.labels.end(), out.mutable_data());
             return out;
           },
           "int32 image (rows, cols) of area ids, -1 where no area")
      .def("to_json", &am::area_graph_json, "the JSON text of `areamatch segment --json` (and its `--graph` file)")
      .def("to_dict", [](const am::AreaGraph& g) { return json_loads(am::area_graph_json(g)); })
      .def("picture", [](const am::AreaGraph& g, const am::OccupancyGrid& grid) { return am::render_area_graph(grid, g); },
           py::arg("map"), release_gil(), "the areas over the map, as `areamatch segment --png` draws them")
      .def("__len__", [](const am::AreaGraph& g) { return g.areas.size(); })
      .def("__repr__", [](const am::AreaGraph& g) {
        return "<areamatch.AreaGraph " + std::to_string(g.areas.size()) + " areas, " + std::to_string(g.passages.size()) +
               " passages>";
      });

  m.def(
      "segment",
      [](const am::OccupancyGrid& grid, std::optional<double> door_width) {
        if (door_width) am::detail::require_positive(*door_width, "door_width_m");
        return am::detail::segmenter_with_door(am::VoronoiSegmenter{}, door_width).segment(grid);
      },
      py::arg("map"), py::arg("door_width_m") = py::none(), release_gil(),
      "The map's Area Graph (door_width_m: openings narrower than it are doors; default 1.2 m).");

}

/// A number as the JSON of the result gives it: None where that says null (NaN, infinite).
py::object number_or_none(double v) { return std::isfinite(v) ? py::object(py::float_(v)) : py::object(py::none()); }

/// A dict of named numbers, each as the JSON gives it (`number_or_none`), in the order given.
py::dict numbers_dict(std::initializer_list<std::pair<const char*, double>> numbers) {
  py::dict d;
  for (const auto& [name, value] : numbers) d[name] = number_or_none(value);
  return d;
}

/// `Result.evidence`, built from the struct (the keys and values of `areamatch match --json`'s).
py::dict evidence_dict(const am::MatchEvidence& e) {
  return numbers_dict({{"agreement", e.agreement},
                       {"wall_agreement", e.wall_agreement},
                       {"reverse_wall_agreement", e.reverse_wall_agreement},
                       {"forward_wall_agreement", e.forward_wall_agreement},
                       {"free_iou", e.free_iou},
                       {"source_on_dest", e.source_on_dest},
                       {"dest_on_source", e.dest_on_source},
                       {"passage_agreement", e.passage_agreement},
                       {"room_agreement", e.room_agreement},
                       {"overlap_m2", e.overlap_m2},
                       {"turn_margin", e.turn_margin},
                       {"occupied_wall_agreement", e.occupied_wall_agreement}});
}

py::list matched_area_dicts(const am::MatchResult& r) {
  py::list out;
  for (const auto& a : r.matched_areas) {
    py::dict d;
    d["source"] = a.source;
    d["dest"] = a.dest;
    d["overlap"] = number_or_none(a.overlap);
    d["iou"] = number_or_none(a.iou);
    d["local_rotation_deg"] = number_or_none(a.T_dest_source.rotation * 180.0 / am::pi);
    py::list translation;
    translation.append(number_or_none(a.T_dest_source.translation.x()));
    translation.append(number_or_none(a.T_dest_source.translation.y()));
    d["local_translation_m"] = translation;
    d["wall_agreement"] = number_or_none(a.wall_agreement);
    out.append(d);
  }
  return out;
}

py::dict statistics_dict(const am::MatchStatistics& s) {
  py::dict d;
  for (const auto& [name, count] : {std::pair<const char*, std::size_t>{"source_areas", s.source_areas},
                                    {"dest_areas", s.dest_areas}, {"mutual_pairs", s.mutual_pairs},
                                    {"hypotheses", s.hypotheses}, {"clusters", s.clusters}, {"verified", s.verified},
                                    {"refined", s.refined}, {"scales_tried", s.scales_tried},
                                    {"overlay_failures", s.overlay_failures}}) {
    d[name] = count;
  }
  return d;
}

py::dict match_timings_dict(const am::MatchTimings& t) {
  return numbers_dict({{"segment_source_s", t.segment_source_s}, {"segment_dest_s", t.segment_dest_s},
                       {"match_s", t.match_s}, {"total_s", t.total_s}, {"prepare_s", t.prepare_s},
                       {"features_s", t.features_s}, {"hypotheses_s", t.hypotheses_s},
                       {"clustering_s", t.clustering_s}, {"selection_s", t.selection_s}});
}

/// Result, Picture and match().
void bind_match(py::module_& m) {
  py::class_<MatchRun>(m, "Result", "A match of a source map onto a destination map.")
      .def_property_readonly("ok", [](const MatchRun& r) { return r.run.result.ok; })
      .def_property_readonly("reason", [](const MatchRun& r) { return r.run.result.reason; })
      .def_property_readonly("T_dest_source", [](const MatchRun& r) { return r.run.result.T_dest_source.matrix(); },
                             "3x3: source world (x, y, 1) to destination world, metres")
      .def_property_readonly("pixel_transform", [](const MatchRun& r) { return am::PixelTransform(r.run.result.pixel_transform); },
                             "2x3: source pixel (col, row, 1) to destination pixel, as `areamatch match`")
      .def_property_readonly("rotation", [](const MatchRun& r) { return r.run.result.T_dest_source.rotation; }, "radians")
      .def_property_readonly("rotation_deg", [](const MatchRun& r) { return r.run.result.T_dest_source.rotation * 180.0 / am::pi; })
      .def_property_readonly("translation_m", [](const MatchRun& r) { return Eigen::Vector2d(r.run.result.T_dest_source.translation); },
                             "(x, y) metres, in the destination's world frame")
      .def_property_readonly("scale", [](const MatchRun& r) { return r.run.result.T_dest_source.scale; })
      .def_property_readonly("scale_estimated", [](const MatchRun& r) { return r.run.result.scale_estimated; })
      .def_property_readonly("reflected", [](const MatchRun& r) { return r.run.result.T_dest_source.reflected; })
      .def_property_readonly("score", [](const MatchRun& r) { return r.run.result.score; })
      .def_property_readonly("margin", [](const MatchRun& r) { return r.run.result.margin; })
      .def_property_readonly("ambiguous", [](const MatchRun& r) { return r.run.result.ambiguous; })
      .def_property_readonly("p_correct", [](const MatchRun& r) { return r.run.result.p_correct; },
                             "calibrated probability that the transform is right (docs/evaluation.md)")
      // The maps and graphs are the result's own, not copies: each keeps the result alive.
      .def_property_readonly("source_map", [](const MatchRun& r) -> const am::OccupancyGrid& { return r.run.source; },
                             py::return_value_policy::reference_internal)
      .def_property_readonly("dest_map", [](const MatchRun& r) -> const am::OccupancyGrid& { return r.run.dest; },
                             py::return_value_policy::reference_internal)
      .def_property_readonly("source_graph", [](MatchRun& r) -> const am::AreaGraph& { return r.source_graph(); },
                             py::return_value_policy::reference_internal)
      .def_property_readonly("dest_graph", [](const MatchRun& r) -> const am::AreaGraph& { return r.run.dest_graph; },
                             py::return_value_policy::reference_internal)
      // Read from the struct, with the keys and values of `areamatch match --json` (no JSON round trip).
      .def_property_readonly("evidence", [](const MatchRun& r) { return evidence_dict(r.run.result.evidence); },
                             "How much the maps agree under the result (dict).")
      .def_property_readonly("statistics", [](const MatchRun& r) { return statistics_dict(r.run.result.statistics); },
                             "Counts of areas, pairs, hypotheses (dict).")
      .def_property_readonly("timings", [](const MatchRun& r) { return match_timings_dict(r.run.result.timings); },
                             "Seconds per step (dict).")
      .def_property_readonly("rejection",
                             [](const MatchRun& r) -> py::object {
                               if (r.run.result.ok) return py::none();
                               return py::str(am::to_string(r.run.result.rejection));
                             },
                             "What a refusal says of the maps: 'different places', 'not sure' or 'no answer' (None when ok).")
      .def_property_readonly("margin_different", [](const MatchRun& r) { return number_or_none(r.run.result.margin_different); },
                             "Margin over the best clearly different transform.")
      .def_property_readonly("margin_mirrored", [](const MatchRun& r) { return number_or_none(r.run.result.margin_mirrored); },
                             "Margin over the best mirrored transform (None without reflection).")
      .def_property_readonly("_matched_area_dicts", [](const MatchRun& r) { return matched_area_dicts(r.run.result); })
      .def("to_json", [](const MatchRun& r) { return am::match_result_json(r.run.result); },
           "the JSON text of `areamatch match --json`")
      .def("to_dict", [](const MatchRun& r) { return json_loads(am::match_result_json(r.run.result)); })
      .def(
          "picture",
          [](MatchRun& r) { return am::render_match(r.run.source, r.source_graph(), r.run.dest, r.run.dest_graph, r.run.result); },
          release_gil(), "the picture of `areamatch match --png` (RGB image, use numpy.asarray)")
      .def("__repr__", [](const MatchRun& r) {
        const auto& res = r.run.result;
        return std::string("<areamatch.Result ") + (res.ok ? "ok" : "not ok") + ", rotation " +
               am::detail::format_double(std::round(res.T_dest_source.rotation * 18000.0 / am::pi) / 100.0) + " deg, p_correct " +
               am::detail::format_double(std::round(res.p_correct * 1000.0) / 1000.0) + ">";
      });

  py::class_<am::RgbImage>(m, "Picture", py::buffer_protocol(), "An RGB image; numpy.asarray(p) is (rows, cols, 3) uint8.")
      .def_buffer([](am::RgbImage& image) {
        return py::buffer_info(image.rgb.data(), 1, py::format_descriptor<std::uint8_t>::format(), 3,
                               {py::ssize_t(image.height), py::ssize_t(image.width), py::ssize_t(3)},
                               {py::ssize_t(image.width) * 3, py::ssize_t(3), py::ssize_t(1)});
      })
      .def_readonly("width", &am::RgbImage::width)
      .def_readonly("height", &am::RgbImage::height)
      .def("save", [](const am::RgbImage& image, const std::string& path) { am::write_png(path, image); }, py::arg("path"),
           release_gil(), "writes a PNG");

  m.def(
      "match",
      [](const am::OccupancyGrid& source, const am::OccupancyGrid& dest, bool allow_reflection, bool estimate_scale,
         std::optional<double> door_width, std::optional<double> source_door_width, std::optional<double> dest_door_width,
         std::optional<std::size_t> k, std::optional<double> min_score, std::optional<double> min_agreement,
         std::optional<double> gate_max_lower_walls, std::optional<double> gate_min_overlap_m2,
         std::optional<double> min_p_correct, bool paper, unsigned threads, const py::object& progress,
         const py::object& params) {
        auto options = pair_options(door_width, source_door_width, dest_door_width, allow_reflection, estimate_scale, k,
                                     min_score, min_agreement, gate_max_lower_walls, gate_min_overlap_m2, min_p_correct,
                                     paper, threads);
        for (auto& s : settings_from(params)) options.settings.push_back(std::move(s));
        const am::ProgressCallback report = python_progress(progress);
        return MatchRun{am::detail::with_default_matcher(options,
                                                         [&](auto matcher) {
                                                           matcher.progress = report;
                                                           return am::match_grids(matcher, source, dest, options);
                                                         }),
                        std::nullopt};
      },
      py::arg("source"), py::arg("dest"), py::kw_only(), py::arg("allow_reflection") = false, py::arg("estimate_scale") = false,
      py::arg("door_width_m") = py::none(), py::arg("source_door_width_m") = py::none(), py::arg("dest_door_width_m") = py::none(),
      py::arg("k") = py::none(), py::arg("min_score") = py::none(), py::arg("min_agreement") = py::none(),
      py::arg("gate_max_lower_walls") = py::none(), py::arg("gate_min_overlap_m2") = py::none(),
      py::arg("min_p_correct") = py::none(), py::arg("paper") = false, py::arg("threads") = am::default_program_threads,
      py::arg("progress") = py::none(), py::arg("params") = py::none(), release_gil(),
      "Segments both maps and matches source onto dest, as `areamatch match` (same options, same result). "
      "params: any settings by name, {'refinement.gates_m': [2, 1, 0.5], 'rooms.door_width_m': 1.5} "
      "(areamatch.parameters() lists them), applied after the other options, the door widths last. "
      "progress: called with (stage, done, total) at the start of each stage ('load', 'segment', 'prepare', "
      "'select', 'check'; 'scale' per candidate scale); an exception it raises stops the match and is raised here.");

}

/// The settings table (parameters.hpp) with typed values: the default matcher's, or the paper's.
py::list parameter_list(bool paper) {
  py::list out;
  auto add = [&out](const am::ParameterInfo& info, const auto& field) {
    py::dict row;
    row["name"] = info.name;
    row["value"] = py::cast(field);
    row["meaning"] = info.meaning;
    row["of"] = am::detail::parameter_owner(info.name);
    row["shapes_map_data"] = info.shapes_map_data;
    out.append(row);
  };
  const am::PaperMatcher paper_matcher;
  const DefaultMatcher default_matcher;
  if (paper) am::for_each_parameter(paper_matcher, add);
  else am::for_each_parameter(default_matcher, add);
  return out;
}

/// Matcher: prepare, match, merge.
void bind_matcher(py::module_& m) {
  m.def("parameters", &parameter_list, py::kw_only(), py::arg("paper") = false,
        "Every setting that params= takes, as `areamatch parameters` lists them: dicts of name, value (the default; "
        "the paper's with paper=True), meaning, of ('segmenter' or 'matcher') and shapes_map_data.");
  py::class_<PyMatcher>(m, "Matcher", "The default matcher with options, for prepared maps and merging.")
      .def(py::init([](std::optional<double> door_width, bool allow_reflection, std::optional<std::size_t> k,
                       std::optional<double> min_score, std::optional<double> min_agreement,
                       std::optional<double> gate_max_lower_walls, std::optional<double> gate_min_overlap_m2,
                       std::optional<double> min_p_correct, unsigned threads, const py::object& params) {
             PyMatcher p;
             p.options = pair_options(door_width, std::nullopt, std::nullopt, allow_reflection, false, k, min_score,
                                      min_agreement, gate_max_lower_walls, gate_min_overlap_m2, min_p_correct, false, threads);
             for (auto& s : settings_from(params)) p.options.settings.push_back(std::move(s));
             p.matcher = am::detail::configured_matcher(DefaultMatcher{}, p.options);
             p.matcher.segmenter = am::detail::segmenter_with_door(p.matcher.segmenter, door_width);
             return p;
           }),
           py::kw_only(), py::arg("door_width_m") = py::none(), py::arg("allow_reflection") = false, py::arg("k") = py::none(),
           py::arg("min_score") = py::none(), py::arg("min_agreement") = py::none(),
           py::arg("gate_max_lower_walls") = py::none(), py::arg("gate_min_overlap_m2") = py::none(),
           py::arg("min_p_correct") = py::none(), py::arg("threads") = am::default_program_threads,
           py::arg("params") = py::none())
      .def("prepare", [](const PyMatcher& p, const am::OccupancyGrid& grid) { return p.matcher.prepare(grid); }, py::arg("map"),
           release_gil(), "Segments the map and builds its match data once.")
      .def(
          "prepare_all",
          [](const PyMatcher& p, const std::vector<am::OccupancyGrid>& grids, unsigned threads) {
            std::vector<Prepared> out(grids.size());
            am::detail::for_each_index(grids.size(), threads, [&](std::size_t i) { out[i] = p.matcher.prepare(grids[i]); });
            return out;
          },
          py::arg("maps"), py::arg("threads") = am::default_program_threads, release_gil(),
          "prepare() of every map, `threads` at a time (the same maps for any count; errors: the first map's)")
      .def("match", [](const PyMatcher& p, const Prepared& source, const Prepared& dest) { return match_prepared(p, nullptr, &source, dest); },
           py::arg("source"), py::arg("dest"), release_gil())
      .def("match", [](const PyMatcher& p, const am::OccupancyGrid& source, const Prepared& dest) { return match_prepared(p, &source, nullptr, dest); },
           py::arg("source"), py::arg("dest"), release_gil(),
           "Matches a map (or a prepared map) onto a prepared map: the same result as match(source, dest.map).")
      .def("match", [](const PyMatcher& p, const am::OccupancyGrid& source, const am::OccupancyGrid& dest) { return MatchRun{am::match_grids(source, dest, p.options), std::nullopt}; },
           py::arg("source"), py::arg("dest"), release_gil())
      .def(
          "merge",
          [](const PyMatcher& p, std::vector<Prepared> maps, std::optional<std::size_t> reference, std::optional<double> resolution,
             double wall_share, double max_residual, bool until_connected, bool same_side, unsigned threads,
             std::vector<std::string> names, bool build_merged_map, bool non_rigid, std::optional<double> control_spacing,
             std::optional<double> bend_length) {
            return run_merge(p.matcher, std::move(maps), reference, resolution, wall_share, max_residual, until_connected,
                             same_side, threads, std::move(names), build_merged_map, non_rigid, control_spacing, bend_length);
          },
          py::arg("maps"), py::kw_only(), py::arg("reference") = py::none(), py::arg("resolution") = py::none(),
          py::arg("wall_share") = 0.5, py::arg("max_residual_m") = 1.0, py::arg("until_connected") = false,
          py::arg("same_side") = true, py::arg("threads") = am::default_program_threads, py::arg("names") = std::vector<std::string>{}, py::arg("build_merged_map") = true,
          py::arg("non_rigid") = false, py::arg("control_spacing_m") = py::none(), py::arg("bend_length_m") = py::none(),
          release_gil(), "Places prepared maps in the frame of maps[reference] and fuses them (as `areamatch merge`).");

}

/// MergeResult's members (the class is declared before Matcher, whose merge returns it).
void bind_merge_result(py::class_<MergeRun>& merge_result) {
  merge_result.def_property_readonly("ok", [](const MergeRun& r) { return r.result.ok; }, "every map placed")
      .def_property_readonly("reference", [](const MergeRun& r) { return r.result.reference; })
      .def_property_readonly("maps",
                             [](const MergeRun& r) {
                               py::list out;
                               for (const auto& map : r.result.maps) out.append(merged_map_dict(map));
                               return out;
                             },
                             "per map: placed, reason, T_reference_map (3x3), pixel_transform (2x3), residual_m, warp (non_rigid: its wall figures, else None)")
      .def_property_readonly("double_walls",
                             [](const MergeRun& r) {
                               py::dict d;
                               d["wall_cells"] = r.result.double_walls.wall_cells;
                               d["doubled_cells"] = r.result.double_walls.doubled_cells;
                               d["share"] = r.result.double_walls.share();
                               return d;
                             },
                             "the merged map's wall cells and the doubled ones (merge/double_walls.hpp)")
      .def_property_readonly("merged", [](const MergeRun& r) -> const am::OccupancyGrid& { return r.result.merged; },
                             py::return_value_policy::reference_internal, "the fused Map (reference frame; keeps the result alive)")
      .def_property_readonly("edges",
                             [](const MergeRun& r) {
                               py::list out;
                               for (const auto& e : r.result.edges) {
                                 py::dict d;
                                 d["from"] = am::merge_map_name(r.names, e.source);
                                 d["to"] = am::merge_map_name(r.names, e.dest);
                                 d["ok"] = e.match.ok;
                                 d["p_correct"] = number_or_none(e.match.p_correct);
                                 d["agreement"] = number_or_none(e.match.evidence.agreement);
                                 d["used"] = e.used;
                                 d["residual_m"] = number_or_none(e.residual_m);
                                 if (!e.used) d["note"] = e.note;
                                 out.append(d);
                               }
                               return out;
                             },
                             "Every pairwise match run: from, to, ok, p_correct, agreement, used, residual_m, note.")
      .def_property_readonly("timings",
                             [](const MergeRun& r) {
                               const am::MergeTimings& t = r.result.timings;
                               return numbers_dict({{"matching_s", t.matching_s}, {"refine_s", t.refine_s},
                                                    {"fit_s", t.fit_s}, {"warp_s", t.warp_s}, {"fuse_s", t.fuse_s},
                                                    {"merge_s", t.total_s}});
                             },
                             "Seconds per step (dict).")
      .def("edge_results",
           [](const MergeRun& r) {
             std::vector<std::tuple<std::size_t, std::size_t, MatchRun>> out;
             for (const auto& e : r.result.edges) {
               MatchRun run;
               run.run.result = e.match;
               run.run.source = r.grids[e.source];
               run.run.dest = r.grids[e.dest];
               out.emplace_back(e.source, e.dest, std::move(run));
             }
             return out;
           },
           "(source index, dest index, Result) of every pairwise match run")
      .def("to_json", [](const MergeRun& r) { return am::merge_result_json(r.result, r.names); },
           "the JSON text of `areamatch merge --json` (names: as given, else \"map i\")")
      .def("to_dict", [](const MergeRun& r) { return json_loads(am::merge_result_json(r.result, r.names)); })
      .def(
          "picture",
          [](const MergeRun& r) {
            std::vector<const am::OccupancyGrid*> grids;
            for (const auto& g : r.grids) grids.push_back(&g);
            if (r.result.merged.empty()) throw am::parameter_error("no merged map was built");
            return am::render_merge(r.result, grids, r.names);
          },
          release_gil(), "the picture of `areamatch merge --png` (each map's walls in its colour, a legend with `names`)")
      .def("__repr__", [](const MergeRun& r) {
        std::size_t placed = 0;
        for (const auto& map : r.result.maps) placed += map.placed;
        std::string text = "<areamatch.MergeResult " + std::string(r.result.ok ? "ok" : "not ok") + ", " + std::to_string(placed) +
                           " of " + std::to_string(r.result.maps.size()) + " maps placed";
        if (!r.result.merged.empty()) {
          text += ", merged " + std::to_string(r.result.merged.width()) + "x" + std::to_string(r.result.merged.height()) +
                  ", doubled walls " + am::detail::format_fixed(100.0 * r.result.double_walls.share(), 1) + " %";
        }
        return text + ">";
      });

}

/// Assessment and assess().
void bind_assess(py::module_& m) {
  py::class_<AssessRun>(m, "Assessment", "A map assessed against a reference (docs/assessment.md).")
      .def_property_readonly("ok", [](const AssessRun& a) { return a.assessment.ok; })
      .def_property_readonly("reason", [](const AssessRun& a) { return a.assessment.reason; })
      .def_property_readonly("decision_overridden", [](const AssessRun& a) { return a.assessment.decision_overridden; },
                             "the match was rejected and assessed all the same (same_building=True)")
      .def_property_readonly("broken_pieces", [](const AssessRun& a) { return a.assessment.brokenness.broken_pieces(); })
      .def_property_readonly("explored_share", [](const AssessRun& a) { return a.assessment.coverage.explored_share; },
                             "share of the reference's rooms and corridors the map explored")
      .def("warp_points",
           [](const AssessRun& a, const Eigen::Matrix<double, Eigen::Dynamic, 2>& pixels) {
             if (!a.assessment.ok) throw am::parameter_error("the map was not placed: " + a.assessment.reason);
             const Eigen::Affine2d to_world = a.run.source.world_from_pixel(), to_pixel = a.run.dest.pixel_from_world();
             Eigen::Matrix<double, Eigen::Dynamic, 2> out(pixels.rows(), 2);
             for (Eigen::Index i = 0; i < pixels.rows(); ++i) {
               out.row(i) = (to_pixel * a.assessment.warp.field.apply(to_world * Eigen::Vector2d(pixels.row(i).transpose()))).transpose();
             }
             return out;
           },
           py::arg("pixels"), "map pixels (n x 2: col, row) to reference pixels through the warp, as `areamatch warp --points`")
      .def("to_json", [](const AssessRun& a) { return am::assessment_json(a.assessment); },
           "the JSON text of `areamatch assess --json`")
      .def("to_dict", [](const AssessRun& a) { return json_loads(am::assessment_json(a.assessment)); })
      .def(
          "picture",
          [](const AssessRun& a, double error_scale) {
            am::detail::require_positive(error_scale, "error_scale_m");
            return am::render_assessment(a.run.source, a.run.source_graph, a.run.dest, a.assessment, error_scale);
          },
          py::arg("error_scale_m") = 0.5, release_gil(), "the picture of `areamatch assess --png`")
      .def("__repr__", [](const AssessRun& a) {
        const auto& r = a.assessment;
        if (!r.ok) return std::string("<areamatch.Assessment not placed>");
        return "<areamatch.Assessment walls " +
               am::detail::format_double(std::round(r.rigid_walls.map_to_reference.median_m * 1000.0) / 1000.0) +
               " m off (median), " + std::to_string(r.brokenness.broken_pieces()) + " broken pieces, explored " +
               am::detail::format_double(std::round(r.coverage.explored_share * 1000.0) / 10.0) + " %>";
      });

  m.def(
      "assess",
      [](const am::OccupancyGrid& map, const am::OccupancyGrid& reference, bool same_building, bool allow_reflection,
         std::optional<double> door_width, std::optional<double> map_door_width, std::optional<double> reference_door_width,
         std::optional<double> min_agreement, std::optional<double> min_p_correct, std::optional<double> control_spacing,
         std::optional<double> bend_length) {
        const auto options = pair_options(door_width, map_door_width, reference_door_width, allow_reflection, false, std::nullopt,
                                           std::nullopt, min_agreement, std::nullopt, std::nullopt, min_p_correct, false, 1,
                                           {"door_width_m", "map_door_width_m", "reference_door_width_m"});
        am::AssessParams params;
        params.assume_same_building = same_building;
        if (control_spacing) params.warp.control_spacing_m = *control_spacing;
        if (bend_length) params.warp.bend_length_m = *bend_length;
        params.validate();
        AssessRun out{am::match_grids(map, reference, options), {}};
        out.assessment = am::assess_match(out.run.source, out.run.source_graph, out.run.dest, out.run.dest_graph, out.run.result, params);
        out.assessment.timings.match_s = out.run.result.timings.total_s;
        out.assessment.timings.total_s += out.run.result.timings.total_s;
        return out;
      },
      py::arg("map"), py::arg("reference"), py::kw_only(), py::arg("same_building") = false, py::arg("allow_reflection") = false,
      py::arg("door_width_m") = py::none(), py::arg("map_door_width_m") = py::none(), py::arg("reference_door_width_m") = py::none(),
      py::arg("min_agreement") = py::none(), py::arg("min_p_correct") = py::none(), py::arg("control_spacing_m") = py::none(),
      py::arg("bend_length_m") = py::none(), release_gil(),
      "Assesses map against reference as `areamatch assess` (same options, same numbers): wall error both ways, the warp's "
      "displacement, broken pieces, coverage, topology. A map that cannot be placed gives ok False with the reason, unless "
      "same_building.");

}

/// The _synthetic submodule (areamatch.synthetic).
void bind_synthetic(py::module_& m) {
  auto synthetic = m.def_submodule("_synthetic", "synthetic buildings and robot maps (areamatch.synthetic)");
  py::class_<am::SyntheticBuilding>(synthetic, "SyntheticBuilding", "A generated floor: its layout map and rooms.")
      .def_readonly("layout", &am::SyntheticBuilding::layout)
      .def_property_readonly("area_count", [](const am::SyntheticBuilding& b) { return b.areas.size(); },
                             "rooms + 1 (area 0 is the corridor system)")
      .def("labels",
           [](const am::SyntheticBuilding& b) {
             py::array_t<std::int32_t> out({b.layout.height(), b.layout.width()});
             std::copy(b.labels.begin(), b.labels.end(), out.mutable_data());
             return out;
           },
           "int32 image of the true area ids of the layout's cells, -1 elsewhere");
  synthetic.def(
      "generate_building",
      [](std::uint64_t seed, double width_m, double height_m, double door_width_m, double resolution, bool unknown_outside) {
        am::BuildingParams p;
        p.width_m = width_m;
        p.height_m = height_m;
        p.door_width_m = door_width_m;
        p.resolution = resolution;
        p.unknown_outside = unknown_outside;
        return am::generate_building(p, seed);
      },
      py::arg("seed"), py::kw_only(), py::arg("width_m") = 30.0, py::arg("height_m") = 20.0, py::arg("door_width_m") = 0.9,
      py::arg("resolution") = 0.05, py::arg("unknown_outside") = true, release_gil(),
      "A floor of rooms along corridors; the same seed gives the same building.");
  py::class_<am::RobotMap>(synthetic, "RobotMap", "A robot's map of a synthetic building with its true transform.")
      .def_readonly("map", &am::RobotMap::grid)
      .def_property_readonly("T_dest_source", [](const am::RobotMap& r) { return r.T_dest_source.matrix(); },
                             "3x3: robot-map world to layout world (the truth)")
      .def_property_readonly("pixel_transform", [](const am::RobotMap& r) { return am::PixelTransform(r.pixel_transform); })
      .def_readonly("explored_areas", &am::RobotMap::explored_areas);
  synthetic.def(
      "make_robot_map",
      [](const am::SyntheticBuilding& building, std::uint64_t seed, double rotation_rad, std::pair<double, double> translation_m,
         bool mirror, double explored_fraction, double wall_noise_m, double wall_bend_m, int max_clutter_per_room,
         std::optional<double> resolution, bool handheld) {
        am::RobotMapParams p = handheld ? am::RobotMapParams::handheld() : am::RobotMapParams{};
        p.rotation_rad = rotation_rad;
        p.translation_m = Eigen::Vector2d(translation_m.first, translation_m.second);
        p.mirror = mirror;
        if (!handheld) {
          p.explored_fraction = explored_fraction;
          p.wall_noise_m = wall_noise_m;
          p.wall_bend_m = wall_bend_m;
          p.max_clutter_per_room = max_clutter_per_room;
        }
        if (resolution) p.resolution = *resolution;
        return am::make_robot_map(building, p, seed);
      },
      py::arg("building"), py::arg("seed"), py::kw_only(), py::arg("rotation_rad") = 0.0,
      py::arg("translation_m") = std::pair{0.0, 0.0}, py::arg("mirror") = false, py::arg("explored_fraction") = 1.0,
      py::arg("wall_noise_m") = 0.0, py::arg("wall_bend_m") = 0.0, py::arg("max_clutter_per_room") = 0,
      py::arg("resolution") = py::none(), py::arg("handheld") = false, release_gil(),
      "A robot map of `building` turned, shifted (and mirrored), exploring a share of its rooms; handheld=True: "
      "the hand-held scan style (RobotMapParams::handheld, the other noise keywords ignored).");
}

}  // namespace

PYBIND11_MODULE(_core, m) {

  m.doc() = "areamatch: align 2D occupancy-grid maps of one building and say which room is which";
  m.attr("__version__") = am::version_string;
  m.attr("DEFAULT_THREADS") = am::default_program_threads;  // as the `areamatch` program
  m.attr("FREE") = static_cast<int>(am::CellState::free);
  m.attr("OCCUPIED") = static_cast<int>(am::CellState::occupied);
  m.attr("UNKNOWN") = static_cast<int>(am::CellState::unknown);
  translate_exceptions();

  bind_map(m);
  bind_area_graph(m);
  bind_match(m);
  py::class_<Prepared>(m, "PreparedMap", "A map segmented and made ready for any number of matches (Matcher.prepare).")
      .def_property_readonly("map", &Prepared::grid)
      .def_property_readonly("graph", &Prepared::graph);

  // Declared before Matcher so that Matcher.merge's signature names it (not the C++ type).
  py::class_<MergeRun> merge_result(m, "MergeResult", "Several maps placed in one frame, with the merged map.");
  bind_matcher(m);
  bind_merge_result(merge_result);
  bind_assess(m);
  bind_synthetic(m);
}
