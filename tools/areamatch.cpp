// The areamatch command-line program: a thin user of the public headers.
//
//   areamatch info MAP            size, resolution, origin and cell fractions of a map
//   areamatch segment MAP         the map's Area Graph, with pictures, labels and JSON
//   areamatch match SOURCE DEST   the transform between two maps, with a picture and JSON
//   areamatch warp SOURCE DEST    a smooth warp beyond the rigid transform; carries points across
//   areamatch assess MAP REF      map evaluation: wall error, local error, brokenness, coverage, topology
//   areamatch merge MAP MAP...    several maps in one frame, fused into one map
//   areamatch eval MANIFEST       every pair of a manifest, scored against its ground truth
//   areamatch generate OUTDIR     a synthetic layout + robot map pair with ground truth
//
// Exit status: 0 success, 1 no acceptable result (matching), 2 bad input or usage.
#include "eval/calibrate.hpp"
#include "eval/eval_report.hpp"
#include "cli_args.hpp"
#include "progress_line.hpp"

#include <areamatch/areamatch.hpp>
#include <areamatch/detail/format.hpp>
#include <areamatch/io.hpp>
#include <areamatch/io/match_files.hpp>
#include <areamatch/merge.hpp>
#include <areamatch/simulate.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <new>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace {

using areamatch::detail::format_double;
using areamatch::detail::format_fixed;
using areamatch_cli::Args;
using areamatch_cli::assign_buildings;
using areamatch_cli::CalibrationRow;
using areamatch_cli::choose_rule;
using areamatch_cli::DecisionCounts;
using areamatch_cli::leave_one_building_out;
using areamatch_cli::nested_rule_cv;
using areamatch_cli::percent;
using areamatch_cli::read_calibration_rows;
using areamatch_cli::reliability;
using areamatch_cli::reliability_svg;
using areamatch_cli::Rule;
using areamatch_cli::ReliabilityBin;
using areamatch_cli::UsageError;

const std::set<std::string> kMapFlags = {"negate", "help"};
const std::set<std::string> kMapOptions = {"resolution", "free-thresh", "occupied-thresh"};

const char* kMapOptionsHelp =
    "Map options (a ROS YAML gives these; the flags override it; a bare image uses map_server's defaults):\n"
    "  --resolution R        metres per pixel (default for a bare image: 0.05)\n"
    "  --free-thresh P       free if occupancy probability p < P (default 0.196)\n"
    "  --occupied-thresh P   occupied if p > P (default 0.65)\n"
    "  --negate              p = v/255 instead of (255 - v)/255\n";

std::set<std::string> merged(std::set<std::string> a, const std::set<std::string>& b) {
  a.insert(b.begin(), b.end());
  return a;
}

areamatch::LoadOptions load_options(const Args& args) {
  areamatch::LoadOptions options;
  options.resolution = args.number("resolution", /*positive=*/true);
  options.free_thresh = args.fraction("free-thresh");
  options.occupied_thresh = args.fraction("occupied-thresh");
  if (args.flag("negate")) options.negate = true;
  return options;
}

/// What a bare PNG/PGM (no YAML) is read with because nothing said otherwise: resolution, origin,
/// thresholds. Empty for a YAML, whose values are the map's own.
std::vector<std::string> assumed_defaults(const std::string& path, const areamatch::LoadOptions& options) {
  const std::string ext = areamatch::detail::lowercase_extension(path);
  if (ext == "yaml" || ext == "yml") return {};
  std::vector<std::string> assumed;
  if (!options.resolution) assumed.push_back("resolution");
  assumed.push_back("origin");
  if (!options.free_thresh || !options.occupied_thresh || !options.negate) assumed.push_back("thresholds");
  return assumed;
}

/// Says on stderr which defaults a bare image is read with (a map matched at a wrong scale
/// fails silently otherwise). `resolution_flag` names the option that sets its resolution.
/// Makes the folders the output files named by `names` go into, before any work: a missing folder
/// is created, one that cannot be is a usage error naming the option — not a failure after the work.
void make_output_folders(const Args& args, std::initializer_list<const char*> names) {
  for (const char* name : names) {
    const auto path = args.text(name);
    if (!path) continue;
    const std::filesystem::path folder = std::filesystem::path(*path).parent_path();
    if (folder.empty()) continue;
    std::error_code ec;
    std::filesystem::create_directories(folder, ec);
    if (ec || !std::filesystem::is_directory(folder)) {
      throw UsageError("--" + std::string(name) + " " + *path + ": cannot make its folder " + folder.string() +
                       (ec ? " (" + ec.message() + ")" : std::string()));
    }
  }
}

/// Whether `path` starts as a PNG or a PGM does: a file that does not is reported by the loader
/// alone, without a note on what would have been assumed for it.
bool starts_like_an_image(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[4] = {0, 0, 0, 0};
  in.read(head, 4);
  const bool png = head[0] == '\x89' && head[1] == 'P' && head[2] == 'N' && head[3] == 'G';
  const bool pgm = head[0] == 'P' && (head[1] == '2' || head[1] == '5');
  return png || pgm;
}

void note_assumed_defaults(const std::string& path, const areamatch::LoadOptions& options, const std::string& resolution_flag) {
  const auto assumed = assumed_defaults(path, options);
  if (assumed.empty() || !starts_like_an_image(path)) return;
  std::string what;
  for (const auto& a : assumed) {
    const std::string part = a == "resolution"  ? "0.05 m per pixel"
                             : a == "origin"    ? "origin (0, 0, 0)"
                                                : "map_server's thresholds (occupied if p > 0.65, free if p < 0.196)";
    what += (what.empty() ? "" : ", ") + part;
  }
  std::cerr << "areamatch: " << path << " has no YAML: assuming " << what << " (give its map_server YAML"
            << (resolution_flag.empty() ? std::string() : ", or " + resolution_flag + " M,") << " to say otherwise)\n";
}

// ---------------------------------------------------------------------------------------- info

const char* kInfoHelp =
    "usage: areamatch info MAP [--json] [map options]\n"
    "Prints a map's size, resolution, origin and the fractions of free, occupied and unknown cells.\n"
    "MAP is a ROS map_server YAML, a PNG or a PGM.\n";

int run_info(const std::vector<std::string>& tokens) {
  const Args args(tokens, merged(kMapFlags, {"json"}), kMapOptions);
  if (args.flag("help")) {
    std::cout << kInfoHelp << kMapOptionsHelp;
    return 0;
  }
  args.expect_positional(1, "MAP");
  const auto options = load_options(args);
  const auto loaded = areamatch::load_map_with_image(args.positional()[0], options);
  const auto assumed = assumed_defaults(args.positional()[0], options);
  const auto is_assumed = [&](const char* what) { return std::find(assumed.begin(), assumed.end(), what) != assumed.end(); };
  const auto mark = [&](const char* what) { return is_assumed(what) ? std::string(" (assumed: no YAML)") : std::string(); };
  const auto& g = loaded.grid;
  const auto counts = g.count();
  const double total = static_cast<double>(counts.total());
  const auto percent = [&](std::size_t n) { return format_fixed(100.0 * n / total, 2); };
  const auto& t = loaded.thresholds;
  if (args.flag("json")) {
    std::cout << "{\"map\": " << areamatch::detail::json_quote(args.positional()[0]) << ", \"image\": " << areamatch::detail::json_quote(loaded.image_path)
              << ", \"width\": " << g.width() << ", \"height\": " << g.height()
              << ", \"resolution\": " << format_double(g.resolution()) << ", \"origin\": [" << format_double(g.origin().x)
              << ", " << format_double(g.origin().y) << ", " << format_double(g.origin().yaw) << "]"
              << ", \"free_cells\": " << counts.free << ", \"occupied_cells\": " << counts.occupied
              << ", \"unknown_cells\": " << counts.unknown << ", \"assumed\": [";
    for (std::size_t i = 0; i < assumed.size(); ++i) std::cout << (i ? ", " : "") << areamatch::detail::json_quote(assumed[i]);
    std::cout << "]}\n";
    return 0;
  }
  std::cout << "map:        " << args.positional()[0] << "\n"
            << "image:      " << loaded.image_path << " (" << (loaded.image.max_value > 255 ? 16 : 8) << "-bit"
            << (loaded.image.has_alpha() ? ", with alpha" : "") << ")\n"
            << "size:       " << g.width() << " x " << g.height() << " cells ("
            << format_fixed(g.width() * g.resolution(), 2) << " x " << format_fixed(g.height() * g.resolution(), 2) << " m)\n"
            << "resolution: " << format_double(g.resolution()) << " m/cell" << mark("resolution") << "\n"
            << "origin:     x " << format_double(g.origin().x) << " m, y " << format_double(g.origin().y) << " m, yaw "
            << format_double(g.origin().yaw) << " rad" << mark("origin") << "\n"
            << "free:       " << percent(counts.free) << " % (" << counts.free << " cells, "
            << format_fixed(counts.free * g.resolution() * g.resolution(), 1) << " m^2)\n"
            << "occupied:   " << percent(counts.occupied) << " % (" << counts.occupied << " cells)\n"
            << "unknown:    " << percent(counts.unknown) << " % (" << counts.unknown << " cells)\n"
            << "thresholds: occupied if p > " << format_double(t.occupied_thresh) << ", free if p < "
            << format_double(t.free_thresh) << (t.negate ? ", negated" : "") << mark("thresholds") << "\n";
  return 0;
}

// ------------------------------------------------------------------------------------ generate

std::string matrix_json(const areamatch::PixelTransform& m) {
  return "[[" + format_double(m(0, 0)) + ", " + format_double(m(0, 1)) + ", " + format_double(m(0, 2)) + "], [" +
         format_double(m(1, 0)) + ", " + format_double(m(1, 1)) + ", " + format_double(m(1, 2)) + "]]";
}

const char* kLidarOptionsHelp =
    "Laser-SLAM options (areamatch simulate, areamatch generate --style lidar; docs/synthetic.md):\n"
    "  --beams N              beams per scan (default 541)\n"
    "  --fov DEG              field of view, centred on the direction of travel (default 270)\n"
    "  --range M              maximum range in metres (default 15)\n"
    "  --range-noise M        standard deviation of each range in metres (default 0.02)\n"
    "  --dropout P            share of beams that return nothing (default 0.02)\n"
    "  --furniture D          furniture blobs per square metre of free space (default 0.05)\n"
    "  --glass S              share of the outer walls' 1 m panes that rays pass through (default 0.15)\n"
    "  --people N             people near the robot in each scan (default 2)\n"
    "  --explored F           share of the waypoints visited, those nearest the start, 0..1 (default 1)\n"
    "  --bend M               largest drift left after the loop closure, metres (default 0.3)\n"
    "  --plan-error M         the building as built differs from the plan by a smooth warp of up to\n"
    "                         M metres, as a schematic plan does (default 0: the plan is exact)\n"
    "  --break P              chance of a broken piece: the path turned by 3 degrees and shifted by\n"
    "                         0.2 m from some scan on, as after a wrong loop closure (default 0)\n"
    "  --robot-resolution R   the SLAM map's metres per cell (default 0.05)\n"
    "  --rotation DEG         the map's turn (default: golden-angle steps over a set, 37 for one)\n"
    "  --mirror               the map is a mirror image\n"
    "  --binary               unknown written as occupied (free against non-free only), as the\n"
    "                         room-segmentation dataset's SLAM maps are\n";

/// The laser-SLAM options `generate` has only with --style lidar, and all of them (`generate`
/// shares --explored, --robot-resolution and --rotation with its other styles).
const std::set<std::string> kLidarOwnOptions = {"beams", "fov",    "range", "range-noise", "dropout",
                                                "furniture", "glass", "people", "bend", "plan-error", "break"};
const std::set<std::string> kLidarOptions = merged(kLidarOwnOptions, {"explored", "robot-resolution", "rotation"});

/// A set's turn of map `seed` in degrees: golden-angle steps over a set (`count` given), else 37.
double default_turn_deg(std::uint64_t seed, bool in_a_set) {
  return in_a_set ? std::fmod(137.5 * static_cast<double>(seed), 360.0) : 37.0;
}

areamatch::LidarSlamParams lidar_params_from(const Args& args) {
  areamatch::LidarSlamParams p;
  p.beams = static_cast<int>(args.integer("beams", 1, 100000).value_or(p.beams));
  if (const auto fov = args.number("fov", true)) {
    if (*fov > 360.0) throw UsageError("--fov must be at most 360 degrees, got " + format_double(*fov));
    p.field_of_view_rad = *fov * areamatch::pi / 180.0;
  }
  p.max_range_m = args.number("range", true).value_or(p.max_range_m);
  p.range_noise_m = args.number("range-noise", false, true).value_or(p.range_noise_m);
  p.dropout = args.number("dropout", false, true).value_or(p.dropout);
  p.furniture_per_m2 = args.number("furniture", false, true).value_or(p.furniture_per_m2);
  p.glass_share = args.number("glass", false, true).value_or(p.glass_share);
  p.people = static_cast<int>(args.integer("people", 0, 1000).value_or(p.people));
  p.explored_fraction = args.number("explored", true).value_or(p.explored_fraction);
  p.bend_m = args.number("bend", false, true).value_or(p.bend_m);
  p.plan_error_m = args.number("plan-error", false, true).value_or(p.plan_error_m);
  p.break_probability = args.number("break", false, true).value_or(p.break_probability);
  p.resolution_m = args.number("robot-resolution", true).value_or(p.resolution_m);
  p.mirror = args.flag("mirror");
  p.binary = args.flag("binary");
  try {
    p.validate();
  } catch (const areamatch::parameter_error& e) {
    throw UsageError(std::string("a laser-SLAM option is out of range: ") + e.what() + " (see --help)");
  }
  return p;
}

/// The manifest entry of a simulated map `source` onto `destination` (paths as the manifest writes them).
std::string simulated_entry(const std::string& name, const std::string& source, const std::string& destination,
                            const areamatch::SimulatedSlamMap& map, double scale, std::optional<double> door_width_m) {
  std::ostringstream entry;
  entry << "  {\n   \"name\": \"" << name << "\",\n   \"kind\": \"synthetic_lidar\",\n"
        << "   \"source\": \"" << source << "\",\n   \"destination\": \"" << destination << "\",\n";
  if (door_width_m) entry << "   \"door_width_m\": " << format_double(*door_width_m) << ",\n";
  entry << "   \"note\": \"simulated laser-SLAM map: " << map.scans << " scans, " << map.furniture << " furniture blobs, bend "
        << format_fixed(map.bend_m, 2) << " m" << (map.broken ? ", a broken piece" : "") << "\",\n"
        << "   \"ground_truth\": {\"pixel_transform\": " << matrix_json(map.pixel_transform)
        << ", \"scale\": " << format_double(scale) << ", \"reflected\": " << (map.T_dest_source.reflected ? "true" : "false")
        << "}\n  }";
  return entry.str();
}

std::string manifest_of(const std::vector<std::string>& entries, const std::string& description, double max_displacement_m) {
  std::ostringstream manifest;
  manifest << "{\n \"description\": \"" << description << " pixel_transform maps a source pixel (col, row) to a destination pixel.\",\n"
           << " \"correct_if\": {\"max_rotation_error_deg\": 3.0, \"max_mean_displacement_m\": " << format_double(max_displacement_m)
           << "},\n \"pairs\": [\n";
  for (std::size_t i = 0; i < entries.size(); ++i) manifest << entries[i] << (i + 1 < entries.size() ? ",\n" : "\n");
  manifest << " ]\n}\n";
  return manifest.str();
}

const char* kGenerateHelp =
    "usage: areamatch generate OUTDIR [options]\n"
    "Writes a synthetic building and a degraded, turned 'robot map' of it with the exact ground truth:\n"
    "  OUTDIR/layout.pgm + .yaml        the floor-plan layout (destination)\n"
    "  OUTDIR/robot.png + .yaml         the robot map (source)\n"
    "  OUTDIR/layout_labels.png         16-bit room labels of the layout (area id + 1, 0 = none)\n"
    "  OUTDIR/pairs.json                a manifest in the format of pairs.json, with ground truth\n"
    "  OUTDIR/overlay.png, overlay.svg  the robot map's walls laid over the layout by the ground truth\n"
    "Options:\n"
    "  --seed N               random seed (default 1); same seed, same files\n"
    "  --width M, --height M  building footprint in metres (default 30 x 20)\n"
    "  --layout KIND          auto | straight | l | t | loop | ladder (default auto)\n"
    "  --door-width M         door width in metres (default 0.9)\n"
    "  --rotation DEG         robot map turn in degrees (default 37)\n"
    "  --mirror               the robot map is a mirror image\n"
    "  --robot-resolution R   robot map metres per cell (default 0.05)\n"
    "  --noise M              wall jitter, standard deviation in metres (default 0.03)\n"
    "  --clutter N            up to N furniture blobs per room (default 3)\n"
    "  --explored F           share of rooms explored, 0..1 (default 1)\n"
    "  --speckles D           speckles per square metre of free space (default 0.02)\n"
    "  --style S              robot (default: a laser SLAM map) or handheld: a hand-held depth-sensor scan\n"
    "                         of part of the floor (0.02 m cells, thin ragged walls seen from one side with\n"
    "                         gaps, closed doors, furniture, 40 % of the rooms near one start, 0.3 m drift)\n"
    "                         onto a line-drawn layout (0.025 m cells, 0.05 m lines); the options above\n"
    "                         still override (docs/synthetic.md); or lidar: a simulated laser-SLAM map of\n"
    "                         the building (the options below; --noise, --clutter, --speckles do not apply)\n";

areamatch::CorridorLayout parse_layout(const std::string& name) {
  static const std::map<std::string, areamatch::CorridorLayout> kinds = {
      {"auto", areamatch::CorridorLayout::automatic}, {"straight", areamatch::CorridorLayout::straight},
      {"l", areamatch::CorridorLayout::l_shape},      {"t", areamatch::CorridorLayout::t_shape},
      {"loop", areamatch::CorridorLayout::loop},      {"ladder", areamatch::CorridorLayout::ladder}};
  const auto it = kinds.find(name);
  if (it == kinds.end()) throw UsageError("--layout must be auto, straight, l, t, loop or ladder, got '" + name + "'");
  return it->second;
}


/// Writes one synthetic pair into `out` and returns its manifest entry (paths relative to
/// `out`'s parent when `prefix` names `out`, else to `out`).
std::string generate_pair(const std::string& out, const std::string& prefix, std::uint64_t seed,
                          const areamatch::BuildingParams& building_params, const areamatch::RobotMapParams& robot_params,
                          double layout_line_width_m, const areamatch::LidarSlamParams* lidar = nullptr) {
  auto building = areamatch::generate_building(building_params, seed);
  areamatch::RobotMap robot;
  if (lidar) {  // --style lidar: rays through the building as built
    auto simulated = areamatch::simulate_lidar_slam(building.layout, *lidar, seed);
    robot.grid = std::move(simulated.grid);
    robot.T_dest_source = simulated.T_dest_source;
    robot.pixel_transform = simulated.pixel_transform;
  } else {
    robot = areamatch::make_robot_map(building, robot_params, seed);
  }
  // A line-drawn floor plan (hand-held style): walls as thin lines, drawn after the scan was made
  // from the building as built.
  // Thinning the walls also shortens each wall end by half the thickness it loses, so the drawn
  // doorways are that much wider than the built ones: the segmenter's door width follows.
  double door_width_m = building_params.door_width_m;
  if (layout_line_width_m > 0.0) {
    building.layout = areamatch::layout_line_drawing(building, layout_line_width_m);
    door_width_m += building_params.wall_thickness_m - layout_line_width_m;
  }

  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) throw areamatch::io_error(out + ": cannot create folder (" + ec.message() + ")");
  areamatch::save_map(building.layout, out + "/layout.pgm");
  areamatch::save_map(robot.grid, out + "/robot.png");
  areamatch::GreyImage labels(building.layout.width(), building.layout.height(), 65535);
  for (std::size_t i = 0; i < labels.values.size(); ++i) labels.values[i] = static_cast<std::uint16_t>(building.labels[i] + 1);
  areamatch::write_png(out + "/layout_labels.png", labels);
  areamatch::write_png(out + "/overlay.png", areamatch::render_overlay(building.layout, robot.grid, robot.T_dest_source));
  areamatch::write_text_file(out + "/overlay.svg", areamatch::overlay_svg(building.layout, robot.grid, robot.T_dest_source));

  std::cout << "wrote " << out << ": layout " << building.layout.width() << "x" << building.layout.height() << " ("
            << building.areas.size() << " areas, " << building.doors.size() << " doors), robot map "
            << robot.grid.width() << "x" << robot.grid.height() << "\n";
  std::ostringstream entry;
  entry << "  {\n   \"name\": \"synthetic_" << seed << "\",\n   \"kind\": \"" << (lidar ? "synthetic_lidar" : "synthetic") << "\",\n"
        << "   \"source\": \"" << prefix << "robot.yaml\",\n   \"destination\": \"" << prefix << "layout.yaml\",\n"
        << "   \"door_width_m\": " << format_double(door_width_m) << ",\n"
        << "   \"ground_truth\": {\"pixel_transform\": " << matrix_json(robot.pixel_transform)
        << ", \"scale\": " << format_double((lidar ? lidar->resolution_m : robot_params.resolution) / building_params.resolution)
        << ", \"reflected\": " << (robot.T_dest_source.reflected ? "true" : "false") << "}\n  }";
  return entry.str();
}

/// A door width option: positive, and no wider than a door or junction can be
/// (`RoomParams::max_door_width_m`): 1e308 is a typo, not a setting.
std::optional<double> door_width(const Args& args, const std::string& name) {
  const auto width = args.number(name, true);
  if (width && *width > areamatch::RoomParams::max_door_width_m) {
    throw UsageError("--" + name + " must be at most " + areamatch::detail::format_fixed(areamatch::RoomParams::max_door_width_m, 0) +
                     " m (a door or junction, not a hall), got " + *args.text(name));
  }
  return width;
}

int run_generate(const std::vector<std::string>& tokens) {
  const Args args(tokens, {"mirror", "binary", "help"},
                  merged(kLidarOptions, {"seed", "count", "width", "height", "layout", "door-width", "rotation", "robot-resolution",
                                         "noise", "clutter", "explored", "speckles", "style"}));
  if (args.flag("help")) {
    std::cout << kGenerateHelp << kLidarOptionsHelp;
    return 0;
  }
  args.expect_positional(1, "OUTDIR");
  const std::string out = args.positional()[0];
  const auto first_seed = static_cast<std::uint64_t>(args.integer("seed", 0, 1LL << 62).value_or(1));
  const auto count = args.integer("count", 1, 10000);

  const std::string style = args.text("style").value_or("robot");
  if (style != "robot" && style != "handheld" && style != "lidar") {
    throw UsageError("--style must be robot, handheld or lidar, got '" + style + "'");
  }
  const bool handheld = style == "handheld";
  std::optional<areamatch::LidarSlamParams> lidar;
  if (style == "lidar") {
    lidar = lidar_params_from(args);
  } else {
    for (const std::string& name : kLidarOwnOptions) {
      if (args.text(name)) throw UsageError("--" + name + " is a laser-SLAM option: it needs --style lidar");
    }
  }
  areamatch::BuildingParams building_params;
  if (handheld) building_params.resolution = 0.025;  // the hand-held layouts: 0.013-0.025 m per pixel
  const double layout_line_width_m = handheld ? 0.05 : 0.0;
  building_params.width_m = args.number("width", true).value_or(30.0);
  building_params.height_m = args.number("height", true).value_or(20.0);
  building_params.door_width_m = door_width(args, "door-width").value_or(0.9);
  building_params.layout = parse_layout(args.text("layout").value_or("auto"));
  areamatch::RobotMapParams robot_params;
  if (handheld) {
    robot_params = areamatch::RobotMapParams::handheld();
  } else {
    robot_params.wall_noise_m = 0.03;
    robot_params.max_clutter_per_room = 3;
    robot_params.speckle_per_m2 = 0.02;
  }
  const auto rotation_deg = args.number("rotation");
  robot_params.mirror = args.flag("mirror");
  robot_params.resolution = args.number("robot-resolution", true).value_or(robot_params.resolution);
  robot_params.wall_noise_m = args.number("noise", false, true).value_or(robot_params.wall_noise_m);
  robot_params.max_clutter_per_room =
      static_cast<int>(args.integer("clutter", 0, 100).value_or(robot_params.max_clutter_per_room));
  robot_params.explored_fraction = args.number("explored", false, true).value_or(robot_params.explored_fraction);
  robot_params.speckle_per_m2 = args.number("speckles", false, true).value_or(robot_params.speckle_per_m2);

  std::vector<std::string> entries;
  for (std::uint64_t seed = first_seed; seed < first_seed + static_cast<std::uint64_t>(count.value_or(1)); ++seed) {
    // A set turns each robot map differently (golden-angle steps) unless --rotation is given.
    const double deg = rotation_deg ? *rotation_deg : default_turn_deg(seed, count.has_value());
    robot_params.rotation_rad = deg * areamatch::pi / 180.0;
    if (lidar) lidar->rotation_rad = robot_params.rotation_rad;
    const std::string folder = "pair_" + std::to_string(seed);
    const areamatch::LidarSlamParams* simulated = lidar ? &*lidar : nullptr;
    entries.push_back(count ? generate_pair(out + "/" + folder, folder + "/", seed, building_params, robot_params, layout_line_width_m, simulated)
                            : generate_pair(out, "", seed, building_params, robot_params, layout_line_width_m, simulated));
  }
  areamatch::write_text_file(out + "/pairs.json", manifest_of(entries, "Synthetic pairs written by 'areamatch generate'.", 0.5));
  std::cout << "ground truth of " << entries.size() << " pair(s) in " << out << "/pairs.json\n";
  return 0;
}

// ------------------------------------------------------------------------------------ simulate

const char* kSimulateHelp =
    "usage: areamatch simulate PLAN OUTDIR [options] [map options]\n"
    "Simulates what a robot with a 2D laser scanner maps driving through a floor plan (any map:\n"
    "free space, walls, unknown or outside): furniture and people the rays meet, glass in outer walls,\n"
    "odometry drift with an imperfect loop closure, log-odds integration into a ROS trinary map. Writes\n"
    "  OUTDIR/slam_<seed>.png + .yaml   each simulated SLAM map (source)\n"
    "  OUTDIR/pairs.json                a manifest onto PLAN (destination) with the exact ground truth\n"
    "Options:\n"
    "  --seed N               random seed of the first map (default 1); same seed, same map\n"
    "  --count N              maps, one per seed from --seed (default 1)\n"
    "  --door-width M         the door width the manifest gives the pairs (default: none)\n";

int run_simulate(const std::vector<std::string>& tokens) {
  const Args args(tokens, merged(kMapFlags, {"mirror", "binary"}), merged(merged(kMapOptions, kLidarOptions), {"seed", "count", "door-width"}));
  if (args.flag("help")) {
    std::cout << kSimulateHelp << kLidarOptionsHelp << kMapOptionsHelp;
    return 0;
  }
  args.expect_positional(2, "PLAN OUTDIR");
  const std::string plan_path = args.positional()[0], out = args.positional()[1];
  auto params = lidar_params_from(args);
  const auto first_seed = static_cast<std::uint64_t>(args.integer("seed", 0, 1LL << 62).value_or(1));
  const auto count = args.integer("count", 1, 10000);
  const auto door = door_width(args, "door-width");
  const auto rotation_deg = args.number("rotation");
  const auto options = load_options(args);
  note_assumed_defaults(plan_path, options, "--resolution");
  const areamatch::OccupancyGrid plan = areamatch::load_map(plan_path, options);
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) throw areamatch::io_error(out + ": cannot create folder (" + ec.message() + ")");
  const std::string destination = std::filesystem::absolute(plan_path).lexically_normal().string();
  std::vector<std::string> entries;
  for (std::uint64_t seed = first_seed; seed < first_seed + static_cast<std::uint64_t>(count.value_or(1)); ++seed) {
    const double deg = rotation_deg ? *rotation_deg : default_turn_deg(seed, count.has_value());
    params.rotation_rad = deg * areamatch::pi / 180.0;
    const areamatch::SimulatedSlamMap map = areamatch::simulate_lidar_slam(plan, params, seed);
    const std::string name = "slam_" + std::to_string(seed);
    areamatch::save_map(map.grid, out + "/" + name + ".png");
    std::cout << "wrote " << out << "/" << name << ".png: " << map.grid.width() << "x" << map.grid.height() << ", " << map.scans
              << " scans, bend " << format_fixed(map.bend_m, 2) << " m" << (map.broken ? ", broken piece" : "") << "\n";
    entries.push_back(simulated_entry(std::filesystem::path(plan_path).stem().string() + "_" + name, name + ".yaml", destination,
                                      map, params.resolution_m / plan.resolution(), door));
  }
  areamatch::write_text_file(out + "/pairs.json",
                             manifest_of(entries, "Simulated laser-SLAM maps written by 'areamatch simulate'.", 1.0));
  std::cout << "ground truth of " << entries.size() << " pair(s) in " << out << "/pairs.json\n";
  return 0;
}

// ------------------------------------------------------------------------------------- segment

const char* kSegmentHelp =
    "usage: areamatch segment MAP [options] [map options]\n"
    "Splits a map into areas (rooms, corridors) joined by passages (doors): its Area Graph.\n"
    "Prints one summary line; exit status 1 when the map has no areas.\n"
    "Options:\n"
    "  --door-width M     widest opening that still separates two areas, metres, plus one cell of slack\n"
    "                     (default 1.2: openings up to 1.25 m at 0.05 m cells)\n"
    "  --min-area M2      areas smaller than this merge into a neighbour (default 1.0 m^2)\n"
    "  --room-margin M    a room must be this much wider than a door somewhere (default 0.05 m)\n"
    "  --simplify M       how far simplified walls may stray from the pixel boundary (default 0.1 m)\n"
    "  --speckle-area M2  obstacle blobs up to this area are erased (default 0.05 m^2)\n"
    "  --speckle-size M   obstacle blobs that fit in an M x M box are erased too (default 0: off)\n"
    "  --min-traced-width M  free space no wider than this (laser streaks) is not traced (default 0)\n"
    "  --png OUT.png      picture: areas in colours, passages as lines with a dot sized by width\n"
    "  --svg OUT.svg      the same as SVG (passages as vectors)\n"
    "  --show-skeleton    draw the Voronoi skeleton in the pictures\n"
    "  --labels OUT.png   16-bit label image the size of the map: area id + 1 per pixel, 0 = none\n"
    "  --graph OUT.json   write the graph: areas (polygons in metres, world frame), passages, map frame\n"
    "  --json             print the graph as exactly one JSON object on stdout (no summary line)\n";

/// The settings that the shorthand options of `args` stand for (`--k 5` is `k=5`), each checked
/// here with a message naming the option; the shorthands a command does not take are absent.
std::vector<areamatch::ParameterSetting> shorthand_settings(const Args& args) {
  std::vector<areamatch::ParameterSetting> settings;
  auto add = [&](const char* name, const std::optional<double>& value) {
    if (value) settings.push_back({name, format_double(*value)});
  };
  add("k", args.integer("k", 1, 1000));
  add("decision.min_score", args.fraction("min-score"));
  add("decision.min_agreement", args.fraction("min-agreement"));
  add("decision.gate_max_lower_walls", args.number("gate-max-lower-walls", false, true));
  add("decision.gate_min_overlap_m2", args.number("gate-min-overlap", false, true));
  add("decision.min_p_correct", args.fraction("min-p-correct"));
  return settings;
}

/// The shorthand options' settings, then the `--set NAME=VALUE` ones in order (names and values
/// are checked where they are applied).
std::vector<areamatch::ParameterSetting> settings_from(const Args& args) {
  std::vector<areamatch::ParameterSetting> settings = shorthand_settings(args);
  for (const std::string& given : args.all("set")) {
    const auto eq = given.find('=');
    if (eq == std::string::npos || eq == 0) throw UsageError("--set takes NAME=VALUE, got '" + given + "'");
    settings.push_back({given.substr(0, eq), given.substr(eq + 1)});
  }
  return settings;
}

const char* kSetHelp =
    "  --set NAME=VALUE        any setting by name, e.g. --set refinement.gates_m=2,1,0.5 (repeatable;\n"
    "                          applied after the other options, the door widths last): see areamatch parameters\n";

areamatch::VoronoiSegmenter segmenter_from(const Args& args, const std::string& door_option = "door-width") {
  areamatch::VoronoiSegmenter segmenter;
  if (const auto area = args.number("min-area", false, true)) segmenter.params.areas.min_area_m2 = *area;
  if (const auto margin = args.number("room-margin", false, true)) segmenter.params.rooms.room_margin_m = *margin;
  if (const auto tolerance = args.number("simplify", false, true)) segmenter.params.boundary.simplify_tolerance_m = *tolerance;
  if (const auto speckle = args.number("speckle-area", false, true)) segmenter.params.binarize.max_speckle_area_m2 = *speckle;
  if (const auto size = args.number("speckle-size", false, true)) segmenter.params.binarize.max_speckle_size_m = *size;
  if (const auto width = args.number("min-traced-width", false, true)) segmenter.params.boundary.min_traced_width_m = *width;
  // The segmenter's settings of the table; a matching one is named as such, an unknown one with
  // the nearest known name (set_parameters' message).
  areamatch::Matcher<> matcher;
  matcher.segmenter = segmenter;
  for (const auto& setting : settings_from(args)) {
    areamatch::set_parameters(matcher, {setting});
    if (!areamatch::parameter_is_segmenters(setting.name)) {
      throw UsageError("--set " + setting.name + ": a matching setting; this command takes the segmenter's (areamatch parameters)");
    }
  }
  segmenter = matcher.segmenter;
  if (const auto door = door_width(args, door_option)) segmenter.params.with_door_width(*door);
  return segmenter;
}

areamatch::GreyImage label_image(const areamatch::AreaGraph& graph) {
  areamatch::GreyImage labels(graph.grid.width, graph.grid.height, 65535);
  graph.labels.for_each_run([&](std::size_t first, std::size_t last, int label) {
    std::fill(labels.values.begin() + static_cast<std::ptrdiff_t>(first), labels.values.begin() + static_cast<std::ptrdiff_t>(last),
              static_cast<std::uint16_t>(std::min(label + 1, 65535)));
  });
  return labels;
}

int run_segment(const std::vector<std::string>& tokens) {
  const Args args(tokens, merged(kMapFlags, {"show-skeleton", "json"}),
                  merged(kMapOptions, {"door-width", "min-area", "room-margin", "simplify", "speckle-area", "speckle-size",
                                       "min-traced-width", "png", "svg", "labels", "graph", "set"}));
  if (args.flag("help")) {
    std::cout << kSegmentHelp << kSetHelp << kMapOptionsHelp;
    return 0;
  }
  make_output_folders(args, {"png", "svg", "labels", "graph"});
  // `--json` was once `--json OUT.json`; as everywhere else it is now a flag (stdout).
  if (args.flag("json") && args.positional().size() == 2) {
    for (const std::string& given : args.positional()) {
      if (std::filesystem::path(given).extension() == ".json") {
        throw UsageError("--json prints the graph on stdout and takes no file; write it to a file with --graph " + given);
      }
    }
  }
  args.expect_positional(1, "MAP");
  const auto segmenter = segmenter_from(args);
  const auto options = load_options(args);
  note_assumed_defaults(args.positional()[0], options, "--resolution");
  const auto grid = areamatch::load_map(args.positional()[0], options);
  const auto details = segmenter.segment_with_details(grid);
  const auto& graph = details.graph;
  const auto& t = details.timings;
  if (const auto png = args.text("png")) {
    areamatch::write_png(*png, areamatch::render_area_graph(grid, graph, {}, args.flag("show-skeleton") ? &details.skeleton : nullptr));
  }
  if (const auto svg = args.text("svg")) {
    areamatch::write_text_file(*svg, areamatch::area_graph_svg(grid, graph, args.flag("show-skeleton") ? &details.skeleton : nullptr));
  }
  if (const auto labels = args.text("labels")) areamatch::write_png(*labels, label_image(graph));
  if (const auto file = args.text("graph")) areamatch::write_text_file(*file, areamatch::area_graph_json(graph));
  if (args.flag("json")) {
    std::cout << areamatch::area_graph_json(graph) << "\n";
  } else {
    std::cout << "areas " << graph.areas.size() << ", passages " << graph.passages.size() << ", covered "
            << format_fixed(100.0 * graph.covered_fraction, 1) << " % of free space, " << format_fixed(1000.0 * t.total_s, 1)
            << " ms (binarize " << format_fixed(1000.0 * t.binarize_s, 1) << ", boundary " << format_fixed(1000.0 * t.boundary_s, 1)
            << " [" << details.boundary_segments << " segments], skeleton " << format_fixed(1000.0 * t.skeleton_s, 1)
            << ", rooms " << format_fixed(1000.0 * t.rooms_s, 1) << ", areas " << format_fixed(1000.0 * t.areas_s, 1) << ")\n";
  }
  if (graph.areas.empty()) {
    std::cerr << "areamatch segment: " << args.positional()[0] << ": no areas: " << graph.reason << "\n";
    return 1;
  }
  return 0;
}

// ---------------------------------------------------------------------------------- parameters

const char* kParametersHelp =
    "Usage: areamatch parameters [--paper] [--json | --markdown] [--set NAME=VALUE ...]\n"
    "Every setting that --set takes (segmenter, matcher, clusterer, selection), with its value and what it does.\n"
    "Lengths in metres, areas in m^2, angles in radians; lists as 2,1.2,0.7.\n"
    "  --paper       the values of the paper's matcher (--paper of match and eval)\n"
    "  --set N=V     show the values after these settings (and check them)\n"
    "  --json        one JSON array: name, value, meaning, of (whose), shapes_map_data\n"
    "  --markdown    the table of docs/parameters.md\n"
    "A setting marked * shapes what a prepared map holds: maps prepared under another value are refused.\n";

int run_parameters(const std::vector<std::string>& tokens) {
  const Args args(tokens, {"paper", "json", "markdown", "help"}, {"set"});
  if (args.flag("help")) {
    std::cout << kParametersHelp;
    return 0;
  }
  args.expect_positional(0, "");
  if (args.flag("json") && args.flag("markdown")) throw UsageError("give --json or --markdown, not both");
  const auto settings = settings_from(args);
  auto rows_of = [&](auto matcher) {
    areamatch::set_parameters(matcher, settings);
    return std::pair(areamatch::parameter_rows(matcher), areamatch::parameters_markdown(matcher));
  };
  const auto [rows, markdown] = args.flag("paper") ? rows_of(areamatch::PaperMatcher{}) : rows_of(areamatch::Matcher<>{});
  if (args.flag("json")) {
    std::string out = "[";
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto& r = rows[i];
      out += std::string(i ? ",\n " : "") + "{\"name\": " + areamatch::detail::json_quote(r.name) + ", \"value\": " +
             areamatch::detail::json_quote(r.value) + ", \"meaning\": " + areamatch::detail::json_quote(r.meaning) + ", \"of\": \"" +
             r.of + "\", \"shapes_map_data\": " + (r.shapes_map_data ? "true" : "false") + "}";
    }
    std::cout << out << "]\n";
  } else if (args.flag("markdown")) {
    std::cout << markdown;
  } else {
    std::size_t width = 0;
    for (const auto& r : rows) width = std::max(width, std::min<std::size_t>(r.name.size() + r.value.size() + 5, 56));
    const bool paper = args.flag("paper");
    const std::map<std::string, std::string> heading = {
        {"segmenter", "segmenter (VoronoiSegmenter::Params):"},
        {"matcher", paper ? "matcher (MatcherParams::paper()):" : "matcher (MatcherParams):"},
        {"clusterer", paper ? "clusterer (AngularClusterer::Params):" : "clusterer (PoseClusterer::Params):"},
        {"selection", "selection (WholeMapSelection::Params):"}};
    std::string part;
    for (const auto& r : rows) {
      if (r.of != part) std::cout << heading.at(part = r.of) << "\n";
      std::string line = "  " + r.name + (r.shapes_map_data ? "*" : "") + " = " + r.value;
      std::cout << line << std::string(width > line.size() ? width - line.size() : 1, ' ') << r.meaning << "\n";
    }
  }
  return 0;
}

// --------------------------------------------------------------------------------------- match

// The options of matching one pair, shared by match and warp.
// The help texts below say "--threads N ... (default 2"; keep them with the constant.
static_assert(areamatch::default_program_threads == 2, "update the help texts' --threads default");

/// A help text with the decision options' defaults filled in from the library's own
/// (`MatcherParams{}`), so that the program cannot print another default than the one it uses:
/// {min_score}, {min_agreement}, {gate_max_lower_walls}, {gate_min_overlap_m2}, {gate_both_ways_min_occupied},
/// {gate_both_ways_min_margin}, {accept_p_correct}.
std::string with_decision_defaults(std::string text) {
  const areamatch::MatcherParams defaults;
  // Whole numbers as such (format_double's shortest form of 100 is 1e+02).
  auto plain = [](double v) { return v == std::floor(v) && std::abs(v) < 1e9 ? format_fixed(v, 0) : format_double(v); };
  const std::pair<std::string, std::string> values[] = {
      {"{min_score}", plain(defaults.decision.min_score)},
      {"{min_agreement}", plain(defaults.decision.min_agreement)},
      {"{gate_max_lower_walls}", plain(defaults.decision.gate_max_lower_walls)},
      {"{gate_min_overlap_m2}", plain(defaults.decision.gate_min_overlap_m2)},
      {"{gate_both_ways_min_occupied}", plain(defaults.decision.gate_both_ways_min_occupied)},
      {"{gate_both_ways_min_margin}", plain(defaults.decision.gate_both_ways_min_margin)},
      {"{accept_p_correct}", plain(defaults.decision.accept_p_correct)}};
  for (const auto& [key, value] : values) {
    for (std::size_t at = text.find(key); at != std::string::npos; at = text.find(key, at + value.size())) {
      text.replace(at, key.size(), value);
    }
  }
  return text;
}

const std::string kPairOptionsHelp = with_decision_defaults(
    "  --source-resolution R   metres per pixel of SOURCE (default: its YAML, else 0.05)\n"
    "  --dest-resolution R     metres per pixel of DEST (default: its YAML, else 0.05)\n"
    "  --door-width M          door width for both maps, metres (default 1.2, see segment --help)\n"
    "  --source-door-width M   door width of SOURCE only (with --dest-door-width; not with --door-width)\n"
    "  --dest-door-width M     door width of DEST only\n"
    "  --allow-reflection      also try the mirror image of SOURCE\n"
    "  --estimate-scale        SOURCE's resolution is unknown (0.5-2x the given one): estimate it; the\n"
    "                          result's scale is the estimate (about 10x slower)\n"
    "  --paper                 the paper's matching as written (k = 3, largest angular cluster)\n"
    "  --k N                   mutual nearest neighbours per area (default 10; paper 3)\n"
    "  --min-p-correct P       reject when the calibrated probability that the answer is right is below P\n"
    "                          (default 0: off; see docs/evaluation.md)\n"
    "  --min-score S           reject when the best whole-map score is below S (default {min_score})\n"
    "  --min-agreement A       reject when the maps agree less than A under the best transform and the\n"
    "                          model is not sure (default {min_agreement}; 0 with --gate-max-lower-walls 2 and --gate-min-overlap 0\n"
    "                          always answers;\n"
    "                          see docs/evaluation.md)\n"
    "  --gate-max-lower-walls W  at or above --min-agreement, accept on the agreement alone only where the\n"
    "                          lower of the two wall agreements is at most W (default {gate_max_lower_walls}; above 1: always)\n"
    "  --gate-min-overlap M2   ... and the maps share at least M2 square metres of free space (default {gate_min_overlap_m2};\n"
    "                          0: whatever the overlap)\n"
    "                          Above W the gate still opens where the walls of rooms seen but not entered agree\n"
    "                          (default {gate_both_ways_min_occupied}) and no rival comes within margin {gate_both_ways_min_margin}: --set\n"
    "                          decision.gate_both_ways_min_occupied=Q, decision.gate_both_ways_min_margin=M\n"
    "  --threads N             load and segment the two maps side by side on N threads (default 2; 0: one\n"
    "                          per core); the same result for any N\n" +
    std::string(kSetHelp));

const std::set<std::string> kPairFlags = {"allow-reflection", "paper", "estimate-scale", "help"};
const std::set<std::string> kPairOptions = {"source-resolution", "dest-resolution", "door-width", "source-door-width",
                                            "dest-door-width", "k", "min-score", "min-agreement", "gate-max-lower-walls", "gate-min-overlap",
                                            "min-p-correct", "threads", "set"};

/// What the pair options of `args` ask of loading, segmenting and matching.
areamatch::MapPairOptions map_pair_options(const Args& args) {
  const bool shared_door = args.text("door-width").has_value();
  if (shared_door && (args.text("source-door-width") || args.text("dest-door-width"))) {
    throw UsageError("give either --door-width or --source-door-width/--dest-door-width, not both");
  }
  areamatch::MapPairOptions options;
  options.source_load.resolution = args.number("source-resolution", /*positive=*/true);
  options.dest_load.resolution = args.number("dest-resolution", /*positive=*/true);
  const auto door = door_width(args, "door-width");
  options.source_door_width_m = door ? door : door_width(args, "source-door-width");
  options.dest_door_width_m = door ? door : door_width(args, "dest-door-width");
  options.paper = args.flag("paper");
  options.allow_reflection = args.flag("allow-reflection");
  options.estimate_scale = args.flag("estimate-scale");
  options.threads = static_cast<unsigned>(args.integer("threads", 0, 256).value_or(areamatch::default_program_threads));
  options.settings = settings_from(args);
  return options;
}

/// Why an answer was accepted, with the deciding number: the model, or the agreement gate (which
/// accepts what the model underrates).
std::string acceptance_line(const areamatch::MatchResult& result, const areamatch::MapPairOptions& options) {
  const areamatch::MatcherParams params = options.paper ? areamatch::detail::configured_matcher(areamatch::PaperMatcher{}, options).params
                                                        : areamatch::detail::configured_matcher(areamatch::Matcher<>{}, options).params;
  if (result.p_correct >= params.decision.accept_p_correct) {
    return "accepted: p_correct " + format_fixed(result.p_correct, 3) + " >= " + format_double(params.decision.accept_p_correct);
  }
  return "accepted by the agreement: agreement " + format_fixed(result.evidence.agreement, 3) + " >= --min-agreement " +
         format_double(params.decision.min_agreement) + " (p_correct " + format_fixed(result.p_correct, 3) + " is below " +
         format_double(params.decision.accept_p_correct) + ": the model alone would not have accepted it)";
}

/// What a user can try after a rejection, from what the refusal says and the options that were
/// not given.
std::vector<std::string> rejection_hints(const areamatch::MatchResult& result, const areamatch::MapPairOptions& options) {
  std::vector<std::string> hints;
  if (!options.allow_reflection.value_or(false)) {
    hints.push_back("mirrored answers were not tried: if one map may be mirrored (its y axis flipped), try --allow-reflection");
  }
  if (!options.source_door_width_m && !options.dest_door_width_m) {
    hints.push_back("both maps were segmented with the default door width: if their rooms split differently, try --door-width W "
                    "(the widest door, metres)");
  }
  // Last, after what may find a better answer: "not sure" is not "different".
  if (result.rejection == areamatch::Rejection::not_sure) {
    hints.push_back(std::string(hints.empty() ? "" : "if that does not help: ") +
                    "not sure is not 'different': if you know both maps show the same building, `areamatch assess SOURCE DEST "
                    "--same-building` measures SOURCE under this transform, and --min-agreement 0 --gate-max-lower-walls 2 "
                    "--gate-min-overlap 0 accepts it here, at your own risk");
  }
  return hints;
}

const std::string kMatchHelp =
    std::string("usage: areamatch match SOURCE DEST [options]\n"
                "Finds the transform that lays map SOURCE onto map DEST (both ROS YAML, PNG or PGM).\n"
                "Exit status: 0 matched, 1 no acceptable match (with the reason), 2 bad input or usage.\n"
                "Options:\n") +
    kPairOptionsHelp +
    "  --json                  print exactly one JSON object on stdout\n"
    "  --png OUT.png           picture: SOURCE with matched areas tinted | DEST with SOURCE's walls over it\n"
    "  --svg OUT.svg           DEST with matched areas tinted and SOURCE's walls as vectors\n"
    "  --labels OUT.png        16-bit PNG the size of SOURCE: each pixel of a SOURCE area holds the id + 1 of\n"
    "                          the DEST area it corresponds to (0: none), to carry room labels over;\n"
    "                          written only when matched. The JSON lists the pairs with their local transforms\n"
    "What the output's numbers mean:\n"
    "  agreement   how well the two maps agree under the answer, 0-1: the walls each way and the shared free space\n"
    "  p_correct   the calibrated probability that the answer is right (a model fitted on real and generated pairs)\n"
    "  margin      the score's margin over the best answer that differs (another turn or place); small: ambiguous\n"
    "An answer is accepted when p_correct >= " + format_double(areamatch::DecisionParams{}.accept_p_correct) +
    ", or when the agreement passes --min-agreement where the model\n"
    "underrates cluttered maps; the output says which. A rejection says 'different places' when the evidence is\n"
    "against (a whole-map score below --min-score, or p_correct below " +
    format_double(areamatch::DecisionParams{}.different_places_p) + ") and 'not sure' otherwise: the answer\n"
    "may be right, and the output says what to try.\n";

/// `match_map_files` (the paper's matcher with `options.paper`) with a progress line on a terminal.
areamatch::MapPairRun match_files_with_progress(const std::string& command, const std::string& source_path,
                                                const std::string& dest_path, const areamatch::MapPairOptions& options) {
  areamatch_cli::ProgressLine line("areamatch " + command);
  areamatch::MapPairRun result = areamatch::detail::with_default_matcher(options, [&](auto matcher) {
    matcher.progress = line.callback();
    return areamatch::match_map_files(matcher, source_path, dest_path, options);
  });
  line.finish();
  return result;
}

int run_match(const std::vector<std::string>& tokens) {
  const Args args(tokens, merged(kPairFlags, {"json"}), merged(kPairOptions, {"png", "svg", "labels"}));
  if (args.flag("help")) {
    std::cout << kMatchHelp;
    return 0;
  }
  make_output_folders(args, {"png", "svg", "labels"});
  args.expect_positional(2, "SOURCE DEST");
  const areamatch::MapPairOptions options = map_pair_options(args);

  note_assumed_defaults(args.positional()[0], options.source_load, "--source-resolution");
  note_assumed_defaults(args.positional()[1], options.dest_load, "--dest-resolution");
  const auto run = match_files_with_progress("match", args.positional()[0], args.positional()[1], options);
  const auto& [source, dest, source_graph, dest_graph, result] = run;

  if (const auto png = args.text("png")) {
    areamatch::write_png(*png, areamatch::render_match(source, source_graph, dest, dest_graph, result));
  }
  if (const auto svg = args.text("svg")) {
    areamatch::write_text_file(*svg, areamatch::overlay_svg(areamatch::render_match_overlay(source, dest, dest_graph, result),
                                                            dest, source, result.T_dest_source));
  }
  if (const auto labels = args.text("labels")) {
    if (result.ok) {
      areamatch::GreyImage image(source_graph.grid.width, source_graph.grid.height, 65535);
      const std::vector<int> ids = areamatch::correspondence_labels(source_graph, result.matched_areas);
      for (std::size_t i = 0; i < ids.size(); ++i) image.values[i] = static_cast<std::uint16_t>(std::min(ids[i], 65535));
      areamatch::write_png(*labels, image);
    } else {
      std::cerr << "areamatch match: " << *labels << " not written: no acceptable match\n";
    }
  }
  if (args.flag("json")) {
    std::cout << areamatch::match_result_json(result) << "\n";
  } else {
    const auto& T = result.T_dest_source;
    std::cout << (result.ok ? "matched" : "no match") << ": rotation " << format_fixed(T.rotation * 180.0 / areamatch::pi, 2)
              << " deg, translation (" << format_fixed(T.translation.x(), 3) << ", " << format_fixed(T.translation.y(), 3)
              << ") m" << (result.scale_estimated ? ", scale " + format_fixed(T.scale, 4) : std::string())
              << (T.reflected ? ", reflected" : "") << ", score " << format_fixed(result.score, 3)
              << ", p_correct " << format_fixed(result.p_correct, 3) << ", margin " << format_fixed(result.margin, 3)
              << (result.ambiguous ? " (ambiguous: another transform scores almost as well)" : "") << ", "
              << result.matched_areas.size()
              << " matched areas (" << result.statistics.source_areas << " / " << result.statistics.dest_areas
              << " areas), " << format_fixed(1000.0 * result.timings.total_s, 1) << " ms (match "
              << format_fixed(1000.0 * result.timings.match_s, 1) << " ms)\n";
  }
  if (!result.ok) {
    std::cerr << "areamatch match: no acceptable match: " << result.reason << "\n";
    for (const std::string& hint : rejection_hints(result, options)) std::cerr << "areamatch match: " << hint << "\n";
    return 1;
  }
  if (!args.flag("json")) std::cout << acceptance_line(result, options) << "\n";
  return 0;
}

// ---------------------------------------------------------------------------------------- warp

const std::string kWarpHelp =
    std::string("usage: areamatch warp SOURCE DEST [--points IN.csv] [options]\n"
                "Matches SOURCE onto DEST, then bends SOURCE onto DEST with a smooth warp (docs/warp.md) and\n"
                "carries points across: each line 'col,row' of IN.csv (SOURCE pixels; '#' comments and blank\n"
                "lines are copied) becomes the DEST pixel the warp takes it to.\n"
                "Exit status: 0 warped, 1 no acceptable match (with the reason), 2 bad input or usage.\n"
                "Options:\n"
                "  --points IN.csv          SOURCE pixel coordinates to carry over, one 'col,row' a line\n"
                "  --out OUT.csv            write the carried points there (default: standard output)\n"
                "  --grid OUT.yaml          SOURCE resampled into DEST's frame through the warp (PGM + YAML)\n"
                "  --json                   print exactly one JSON object: the match, the warp's figures and the\n"
                "                           points (unless --out)\n"
                "  --control-spacing M      control grid spacing of the warp, metres (default ") +
    format_double(areamatch::WarpParams{}.control_spacing_m) +
    ")\n"
    "  --bend-length M          shortest bend the warp follows, metres (default " +
    format_double(areamatch::WarpParams{}.bend_length_m) + ")\n" +
    kPairOptionsHelp;

/// One line of a points file: a pixel, or a line to copy (comment, blank).
struct PointLine {
  std::string text;
  std::optional<Eigen::Vector2d> pixel;
};

std::vector<PointLine> read_point_lines(const std::string& path, const areamatch::OccupancyGrid& source) {
  std::ifstream in(path);
  if (!in) throw areamatch::io_error("cannot read points file " + path);
  std::vector<PointLine> lines;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    PointLine out{line, std::nullopt};
    const auto first = line.find_first_not_of(" \t");
    if (first != std::string::npos && line[first] != '#') {
      std::string fields = line;
      std::replace(fields.begin(), fields.end(), ',', ' ');
      std::istringstream parse(fields);
      double col = 0.0, row = 0.0;
      std::string extra;
      if (!(parse >> col >> row) || (parse >> extra) || !std::isfinite(col) || !std::isfinite(row)) {
        throw areamatch::format_error(path + ":" + std::to_string(number) + ": expected 'col,row' (two numbers), got '" +
                                      line + "'");
      }
      if (col < -0.5 || row < -0.5 || col > source.width() - 0.5 || row > source.height() - 0.5) {
        throw areamatch::parameter_error(path + ":" + std::to_string(number) + ": pixel (" + format_double(col) + ", " +
                                         format_double(row) + ") is outside SOURCE (" + std::to_string(source.width()) +
                                         " x " + std::to_string(source.height()) + " pixels)");
      }
      out.pixel = Eigen::Vector2d(col, row);
    }
    lines.push_back(std::move(out));
  }
  return lines;
}

int run_warp(const std::vector<std::string>& tokens) {
  const Args args(tokens, merged(kPairFlags, {"json"}),
                  merged(kPairOptions, {"points", "out", "grid", "control-spacing", "bend-length"}));
  if (args.flag("help")) {
    std::cout << kWarpHelp;
    return 0;
  }
  make_output_folders(args, {"out", "grid"});
  args.expect_positional(2, "SOURCE DEST");
  const areamatch::MapPairOptions options = map_pair_options(args);
  areamatch::WarpParams warp_params;
  if (const auto v = args.number("control-spacing", true)) warp_params.control_spacing_m = *v;
  if (const auto v = args.number("bend-length", true)) warp_params.bend_length_m = *v;
  warp_params.validate();
  if (args.text("out") && !args.text("points")) throw UsageError("--out needs --points");

  note_assumed_defaults(args.positional()[0], options.source_load, "--source-resolution");
  note_assumed_defaults(args.positional()[1], options.dest_load, "--dest-resolution");
  const auto run = match_files_with_progress("warp", args.positional()[0], args.positional()[1], options);
  const auto& [source, dest, source_graph, dest_graph, result] = run;
  std::vector<PointLine> lines;
  if (const auto points = args.text("points")) lines = read_point_lines(*points, source);
  if (!result.ok) {
    if (args.flag("json")) std::cout << "{\"match\": " << areamatch::match_result_json(result) << "}\n";
    std::cerr << "areamatch warp: no acceptable match, nothing warped: " << result.reason << "\n";
    return 1;
  }
  const auto warp_start = std::chrono::steady_clock::now();
  const areamatch::WarpResult warp = areamatch::fit_warp(source, dest, result.T_dest_source, warp_params);
  const double warp_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - warp_start).count();

  const Eigen::Affine2d source_world = source.world_from_pixel(), dest_pixel = dest.pixel_from_world();
  std::ostringstream csv;
  std::string json_points;
  for (const PointLine& line : lines) {
    if (!line.pixel) {
      csv << line.text << "\n";
      continue;
    }
    const Eigen::Vector2d q = dest_pixel * warp.field.apply(source_world * *line.pixel);
    csv << format_fixed(q.x(), 3) << "," << format_fixed(q.y(), 3) << "\n";
    json_points += std::string(json_points.empty() ? "" : ", ") + "[" + format_fixed(q.x(), 3) + ", " + format_fixed(q.y(), 3) + "]";
  }
  if (const auto out = args.text("out")) areamatch::write_text_file(*out, csv.str());
  if (const auto grid = args.text("grid")) {
    areamatch::save_map(areamatch::resample_through(source, warp.field, areamatch::GridInfo::of(dest)),
                        std::filesystem::path(*grid).replace_extension(".pgm").string());
  }
  auto number = [](double v, int digits) { return std::isfinite(v) ? format_fixed(v, digits) : std::string("null"); };
  if (args.flag("json")) {
    std::cout << "{\"match\": " << areamatch::match_result_json(result)
              << ", \"warp\": " << areamatch::warp_result_json(warp, warp_params, warp_s)
              << (args.text("points") && !args.text("out") ? ", \"points\": [" + json_points + "]" : "") << "}\n";
  } else {
    if (args.text("points") && !args.text("out")) std::cout << csv.str();
    std::cerr << "areamatch warp: walls " << number(warp.rigid_median_m, 3) << " m off (median) under the rigid answer, "
              << number(warp.warped_median_m, 3) << " m under the warp (95th percentile " << number(warp.rigid_p95_m, 3)
              << " -> " << number(warp.warped_p95_m, 3) << " m); displacement median " << number(warp.median_displacement_m, 3)
              << " m, max " << number(warp.max_displacement_m, 3) << " m; " << format_fixed(1000.0 * warp_s, 1) << " ms\n";
  }
  return 0;
}

// -------------------------------------------------------------------------------------- assess

const std::string kAssessHelp =
    std::string("usage: areamatch assess MAP REFERENCE [--json] [--png OUT.png] [options]\n"
                "Evaluates MAP (e.g. a SLAM map) against REFERENCE (a floor plan, a laser-scanner map): MAP is\n"
                "matched onto REFERENCE and bent onto it by a smooth warp; the report says where MAP is wrong and\n"
                "by how much (wall error both ways under the rigid answer and under the warp, each area's\n"
                "displacement), how broken (rigid pieces), how complete (coverage) and how consistently\n"
                "connected (topology). docs/assessment.md defines every number.\n"
                "Exit status: 0 assessed, 1 MAP could not be placed on REFERENCE (with the reason), 2 bad input or usage.\n"
                "Options:\n"
                "  --json                   print exactly one JSON object with every number\n"
                "  --png OUT.png            picture: REFERENCE with MAP's walls coloured by local error, broken pieces\n"
                "                           outlined, a legend\n"
                "  --same-building          the maps show the same building (MAP against its own ground truth): assess\n"
                "                           under the best transform even when the match is rejected, and say so\n"
                "  --error-scale M          the local error the picture draws fully red, metres (default 0.5)\n"
                "  --control-spacing M      control grid spacing of the warp, metres (default ") +
    format_double(areamatch::WarpParams{}.control_spacing_m) +
    ")\n"
    "  --bend-length M          shortest bend the warp follows, metres (default " +
    format_double(areamatch::WarpParams{}.bend_length_m) + ")\n" + kPairOptionsHelp;

std::string assessment_text(const areamatch::MapAssessment& a) {
  auto m = [](double v) { return std::isfinite(v) ? format_fixed(v, 3) + " m" : std::string("n/a"); };
  auto pct = [](double v) { return std::isfinite(v) ? format_fixed(100.0 * v, 1) + " %" : std::string("n/a"); };
  auto walls = [&](const char* title, const areamatch::WallErrors& w) {
    const auto& f = w.map_to_reference;
    const auto& b = w.reference_to_map;
    return std::string(title) + "\n    map walls to reference walls:  mean " + m(f.mean_m) + ", median " + m(f.median_m) +
           ", 95th percentile " + m(f.p95_m) + "; " + pct(f.within_tolerance) + " within tolerance, " + pct(f.at_cap) +
           " with no wall near (" + std::to_string(f.points) + " points)\n    reference walls to map walls:  mean " +
           m(b.mean_m) + ", median " + m(b.median_m) + ", 95th percentile " + m(b.p95_m) + "; " + pct(b.within_tolerance) +
           " within tolerance, " + pct(b.at_cap) + " not drawn (" + std::to_string(b.points) + " points)\n";
  };
  const areamatch::Similarity2& T = a.match.T_dest_source;
  std::ostringstream out;
  out << "placed: rotation " << format_fixed(T.rotation * 180.0 / areamatch::pi, 2) << " deg, translation ("
      << format_fixed(T.translation.x(), 3) << ", " << format_fixed(T.translation.y(), 3) << ") m"
      << (T.reflected ? ", reflected" : "") << ", p_correct " << format_fixed(a.match.p_correct, 3)
      << (a.decision_overridden ? " (the match was rejected; assessed because of --same-building)" : "") << "\n";
  out << walls("wall error under the rigid answer:", a.rigid_walls);
  out << walls("wall error under the warp:", a.warped_walls);
  out << "local error (the warp's displacement at the map's walls): median " << m(a.warp.median_displacement_m) << ", max "
      << m(a.warp.max_displacement_m) << "\n";
  const auto& pieces = a.brokenness.pieces;
  out << "brokenness: " << a.brokenness.broken_pieces() << " broken piece" << (a.brokenness.broken_pieces() == 1 ? "" : "s")
      << " (" << pieces.size() << " rigid piece" << (pieces.size() == 1 ? "" : "s") << ")\n";
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    out << "    piece " << k + 1 << ": " << pieces[k].areas.size() << " areas, " << format_fixed(pieces[k].size_m2, 1) << " m2";
    if (k == 0) out << ", the main piece";
    else out << ", turned " << format_fixed(pieces[k].rotation_rad * 180.0 / areamatch::pi, 2) << " deg and shifted " << m(pieces[k].shift_m) << " against it";
    out << "\n";
  }
  const auto& c = a.coverage;
  out << "coverage: " << pct(c.explored_share) << " of the reference's rooms and corridors explored (" << format_fixed(c.explored_m2, 1)
      << " of " << format_fixed(c.reference_m2, 1) << " m2); reference areas found " << c.found << ", partly " << c.partly_found
      << ", missed " << c.missed << "; map areas the reference lacks " << c.extra_map_areas.size()
      << "; reference passages missing " << c.missing_passages.size() << "\n";
  const auto& t = a.topology;
  out << "topology: " << t.map_consistent << " of " << t.map_passages
      << " map passages join the same areas in the reference; " << t.reference_consistent << " of " << t.reference_passages
      << " reference passages are in the map\n";
  out << "time: match " << format_fixed(1000.0 * a.timings.match_s, 1) << " ms, warp " << format_fixed(1000.0 * a.timings.warp_s, 1)
      << " ms, assessment " << format_fixed(1000.0 * a.timings.assess_s, 1) << " ms\n";
  return out.str();
}

int run_assess(const std::vector<std::string>& tokens) {
  const Args args(tokens, merged(kPairFlags, {"json", "same-building"}),
                  merged(kPairOptions, {"png", "error-scale", "control-spacing", "bend-length"}));
  if (args.flag("help")) {
    std::cout << kAssessHelp;
    return 0;
  }
  make_output_folders(args, {"png"});
  args.expect_positional(2, "MAP REFERENCE");
  const areamatch::MapPairOptions options = map_pair_options(args);
  if (options.estimate_scale) {
    throw UsageError("assess measures MAP in its own metres: give its resolution (--source-resolution) instead of --estimate-scale");
  }
  areamatch::AssessParams params;
  params.assume_same_building = args.flag("same-building");
  if (const auto v = args.number("control-spacing", true)) params.warp.control_spacing_m = *v;
  if (const auto v = args.number("bend-length", true)) params.warp.bend_length_m = *v;
  const double error_scale = args.number("error-scale", true).value_or(0.5);
  params.validate();

  note_assumed_defaults(args.positional()[0], options.source_load, "--source-resolution");
  note_assumed_defaults(args.positional()[1], options.dest_load, "--dest-resolution");
  const auto run = match_files_with_progress("assess", args.positional()[0], args.positional()[1], options);
  areamatch::MapAssessment assessment =
      areamatch::assess_match(run.source, run.source_graph, run.dest, run.dest_graph, run.result, params);
  assessment.timings.match_s = run.result.timings.total_s;
  assessment.timings.total_s += run.result.timings.total_s;
  if (const auto png = args.text("png")) {
    areamatch::write_png(*png, areamatch::render_assessment(run.source, run.source_graph, run.dest, assessment, error_scale));
  }
  if (args.flag("json")) std::cout << areamatch::assessment_json(assessment) << "\n";
  if (!assessment.ok) {
    std::cerr << "areamatch assess: " << assessment.reason
              << (run.result.matched_areas.empty() ? "" : " (if MAP and REFERENCE are the same building, --same-building assesses it all the same)")
              << "\n";
    return 1;
  }
  if (!args.flag("json")) std::cout << assessment_text(assessment);
  return 0;
}

// --------------------------------------------------------------------------------------- merge

const std::string kMergeHelp = with_decision_defaults(
    "usage: areamatch merge MAP MAP... [options]\n"
    "Places several maps of one building (robot maps, scans, a floor plan) in one frame: every pair is\n"
    "matched, the accepted matches are fitted together (least squares, so loops of matches agree), a\n"
    "match the others contradict is dropped, and the maps are fused into one occupancy grid in the\n"
    "reference map's world frame. A map that cannot be placed is listed with the reason.\n"
    "Exit status: 0 every map placed, 1 some not placed (listed), 2 bad input or usage.\n"
    "Options:\n"
    "  --reference MAP      the map whose frame is the merged frame (default: the first)\n"
    "  --out MERGED.yaml    write the merged map as a ROS map_server YAML + PGM beside it\n"
    "  --png OUT.png        picture: the merged map with each map's walls in its own colour\n"
    "  --json               print exactly one JSON object on stdout\n"
    "  --allow-reflection   a map may be a mirror image of the others\n"
    "  --door-width M       door width for every map, metres (default 1.2, see segment --help)\n"
    "  --merged-resolution M  metres per cell of the merged map (default: the finest map's)\n"
    "  --wall-share S       a merged cell is occupied when at least this share of the maps that saw it\n"
    "                       saw a wall (default 0.5)\n"
    "  --max-residual M     drop a match whose areas land more than M metres apart under the fitted\n"
    "                       poses (default 1.0)\n"
    "  --until-connected    match a pair only while its maps are not yet joined (fewer matches, no loop\n"
    "                       checks; default: every pair)\n"
    "  --no-same-side       use the accepted matches' transforms as they are (default: each refined by\n"
    "                       ICP that pairs walls only with walls facing the same way)\n"
    "  --non-rigid          bend each map onto the reference's walls before fusing (as `areamatch warp`),\n"
    "                       so that maps that bend differently do not leave walls side by side; parts the\n"
    "                       reference did not see stay rigid: make the reference the fullest map or plan\n"
    "  --control-spacing M  with --non-rigid: the warps' control grid spacing, metres (default 1)\n"
    "  --bend-length M      with --non-rigid: the shortest bend a warp follows, metres (default 4)\n"
    "  --threads N          match N pairs at once (default 2; 0: one per core); same results for any N\n"
    "  --min-agreement A    accept a match when the maps agree at least A (default {min_agreement}) ...\n"
    "  --gate-max-lower-walls W  ... and the lower of the two wall agreements is at most W (default {gate_max_lower_walls};\n"
    "                       above 1: whatever the walls)\n"
    "  --gate-min-overlap M2  ... and the maps share at least M2 m² of free space (default {gate_min_overlap_m2}; 0: any)\n"
    "  --min-p-correct P    reject a match below this probability of being right (default 0: off)\n"
    "Every map is read as by `areamatch info` (a bare image at 0.05 m per pixel).\n");

/// "#rrggbb", as a picture's colour is named in text.
std::string hex_color(const areamatch::Rgb& c) {
  char text[8];
  std::snprintf(text, sizeof text, "#%02x%02x%02x", c[0], c[1], c[2]);
  return text;
}

/// `areamatch merge`'s MergeParams from its options.
template <class SameFile>
areamatch::MergeParams merge_params_from(const Args& args, const std::vector<std::string>& paths, const SameFile& same_file) {
  areamatch::MergeParams merge_params;
  merge_params.names = paths;
  if (const auto reference = args.text("reference")) {
    const auto it = std::find_if(paths.begin(), paths.end(), [&](const std::string& p) { return same_file(p, *reference); });
    if (it == paths.end()) throw UsageError("--reference '" + *reference + "' is not one of the maps given");
    merge_params.reference = static_cast<std::size_t>(it - paths.begin());
  }
  if (const auto r = args.number("merged-resolution", /*positive=*/true)) merge_params.fuse.resolution = *r;
  if (const auto share = args.number("wall-share", true)) {
    if (*share > 1.0) throw UsageError("--wall-share must be in (0, 1], got " + format_double(*share));
    merge_params.fuse.wall_share = *share;
  }
  if (const auto residual = args.number("max-residual", true)) merge_params.max_residual_m = *residual;
  if (args.flag("until-connected")) merge_params.strategy = areamatch::MergeStrategy::until_connected;
  merge_params.refine_same_side = !args.flag("no-same-side");
  merge_params.non_rigid = args.flag("non-rigid");
  if (!merge_params.non_rigid && (args.text("control-spacing") || args.text("bend-length"))) {
    throw UsageError("--control-spacing and --bend-length shape the warps of --non-rigid; give --non-rigid too");
  }
  if (const auto v = args.number("control-spacing", true)) merge_params.warp.control_spacing_m = *v;
  if (const auto v = args.number("bend-length", true)) merge_params.warp.bend_length_m = *v;
  merge_params.threads = static_cast<unsigned>(args.integer("threads", 0, 256).value_or(areamatch::default_program_threads));
  return merge_params;
}

/// `areamatch merge`'s summary without --json: what was placed where, the merged map, dropped matches.
void print_merge_summary(const areamatch::MergeResult& result, const std::vector<std::string>& paths,
                         const areamatch::MergeParams& merge_params, bool drawn, double total_s, double prepare_s) {
  std::size_t placed = 0, used = 0, accepted = 0;
  for (const auto& m : result.maps) placed += m.placed;
  for (const auto& e : result.edges) used += e.used, accepted += e.match.ok;
  std::cout << "placed " << placed << " of " << paths.size() << " maps in the frame of " << paths[result.reference] << " ("
            << result.edges.size() << " matches, " << accepted << " accepted, " << used << " used), "
            << format_fixed(1000.0 * total_s, 0) << " ms (prepare " << format_fixed(1000.0 * prepare_s, 0)
            << ", match " << format_fixed(1000.0 * result.timings.matching_s, 0)
            << (merge_params.non_rigid ? ", warp " + format_fixed(1000.0 * result.timings.warp_s, 0) : std::string()) << ", fuse "
            << format_fixed(1000.0 * result.timings.fuse_s, 0) << ")\n";
  if (!result.merged.empty()) {
    std::cout << "  merged map: " << result.merged.width() << " x " << result.merged.height() << " cells, "
              << result.double_walls.wall_cells << " wall cells, " << result.double_walls.doubled_cells << " doubled ("
              << format_fixed(100.0 * result.double_walls.share(), 1) << " %: a parallel wall "
              << format_fixed(merge_params.double_walls.min_gap_m, 2) << "-" << format_fixed(merge_params.double_walls.max_gap_m, 2)
              << " m away across free space)\n";
    constexpr double doubled_hint_share = 0.05;  // one wall in twenty doubled: plain to see, worth bending
    if (!merge_params.non_rigid && result.double_walls.share() >= doubled_hint_share) {
      std::cout << "  doubled walls: the maps bend against each other; --non-rigid bends each onto the reference\n";
    }
  }
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const auto& m = result.maps[i];
    if (!m.placed) continue;
    const auto& T = m.T_reference_map;
    std::cout << "  " << paths[i] << ": rotation " << format_fixed(T.rotation * 180.0 / areamatch::pi, 2) << " deg, translation ("
              << format_fixed(T.translation.x(), 3) << ", " << format_fixed(T.translation.y(), 3) << ") m"
              << (T.reflected ? ", reflected" : "") << ", residual " << format_fixed(m.residual_m, 3) << " m";
    if (drawn) std::cout << ", drawn in " << hex_color(areamatch::map_color(static_cast<int>(i)));
    if (m.warp) {
      std::cout << "; warp: walls " << format_fixed(m.warp->rigid_median_m, 3) << " -> " << format_fixed(m.warp->warped_median_m, 3)
                << " m median off the reference's, moved up to " << format_fixed(m.warp->max_displacement_m, 2) << " m";
    }
    std::cout << "\n";
  }
  for (const auto& e : result.edges) {
    if (e.match.ok && !e.used) std::cout << "  dropped " << paths[e.source] << " -> " << paths[e.dest] << ": " << e.note << "\n";
  }
}

int run_merge(const std::vector<std::string>& tokens) {
  const Args args(tokens, {"json", "allow-reflection", "until-connected", "no-same-side", "non-rigid", "help"},
                  {"reference", "out", "png", "door-width", "merged-resolution", "resolution", "wall-share", "max-residual", "min-agreement",
                   "gate-max-lower-walls", "gate-min-overlap", "min-p-correct", "threads", "control-spacing", "bend-length", "set"});
  if (args.flag("help")) {
    std::cout << kMergeHelp << kSetHelp;
    return 0;
  }
  // `--resolution` is an input map's cell size in info and segment; merge's output cell size
  // was once `--resolution` too, so the old spelling is refused rather than read either way.
  if (args.text("resolution")) {
    throw UsageError("--resolution is an input map's metres per cell (info, segment); the merged map's is "
                     "--merged-resolution");
  }
  make_output_folders(args, {"out", "png"});
  const std::vector<std::string>& paths = args.positional();
  if (paths.size() < 2) throw UsageError("expected at least two maps: MAP MAP...");
  namespace fs = std::filesystem;
  auto same_file = [](const std::string& a, const std::string& b) {
    std::error_code error;
    return fs::equivalent(a, b, error) || fs::weakly_canonical(a, error) == fs::weakly_canonical(b, error);
  };
  for (std::size_t i = 0; i < paths.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (same_file(paths[i], paths[j])) throw UsageError("map '" + paths[i] + "' is given twice (as '" + paths[j] + "')");
    }
  }
  const areamatch::MergeParams merge_params = merge_params_from(args, paths, same_file);
  // The matcher's options as `areamatch match` sets them (its threads stay 1: merging spreads pairs).
  areamatch::MapPairOptions match_options;
  match_options.allow_reflection = args.flag("allow-reflection");
  match_options.settings = settings_from(args);
  areamatch::Matcher<> matcher = areamatch::detail::configured_matcher(areamatch::Matcher<>{}, match_options);
  matcher.segmenter = areamatch::detail::segmenter_with_door(matcher.segmenter, door_width(args, "door-width"));

  for (const auto& path : paths) note_assumed_defaults(path, {}, "");
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  // Each map loaded and prepared on its own, `--threads` at a time (errors: the first map's).
  areamatch_cli::ProgressLine line("areamatch merge");
  line.set("loading the maps");
  std::vector<areamatch::OccupancyGrid> grids(paths.size());
  areamatch::detail::for_each_index(paths.size(), merge_params.threads, [&](std::size_t i) { grids[i] = areamatch::load_map(paths[i]); });
  const auto loaded = clock::now();
  line.set("segmenting");
  std::vector<areamatch::Matcher<>::PreparedMap> maps(paths.size());
  areamatch::detail::for_each_index(paths.size(), merge_params.threads, [&](std::size_t i) { maps[i] = matcher.prepare(grids[i]); });
  const auto prepared = clock::now();
  matcher.progress = line.callback();
  const areamatch::MergeResult result = areamatch::merge_maps(matcher, maps, merge_params);
  line.finish();
  const auto seconds = areamatch::detail::seconds_between;

  std::vector<const areamatch::OccupancyGrid*> grid_pointers;
  for (const auto& map : maps) grid_pointers.push_back(&map.grid());
  if (const auto out = args.text("out")) {
    if (result.merged.empty()) throw UsageError("--out: no merged map was built");
    const std::string ext = fs::path(*out).extension().string();
    if (ext != ".yaml" && ext != ".yml") throw UsageError("--out must name a .yaml file (the PGM is written beside it), got '" + *out + "'");
    areamatch::save_map(result.merged, fs::path(*out).replace_extension(".pgm").string());
  }
  // The picture's legend names maps by file name without its extension (the whole path where two share one).
  std::vector<std::string> stems, names;
  for (const auto& path : paths) stems.push_back(fs::path(path).stem().string());
  for (std::size_t i = 0; i < stems.size(); ++i)
    names.push_back(std::count(stems.begin(), stems.end(), stems[i]) > 1 ? paths[i] : stems[i]);
  if (const auto png = args.text("png")) areamatch::write_png(*png, areamatch::render_merge(result, grid_pointers, names));
  const double total_s = seconds(start, clock::now());

  if (args.flag("json")) {
    std::cout << areamatch::merge_result_json(result, paths, {{"load_s", seconds(start, loaded)}, {"prepare_s", seconds(loaded, prepared)},
                                                              {"total_s", total_s}})
              << "\n";
  } else {
    print_merge_summary(result, paths, merge_params, args.text("png").has_value(), total_s, seconds(loaded, prepared));
  }
  for (std::size_t i = 0; i < paths.size(); ++i) {
    if (!result.maps[i].placed) std::cerr << "areamatch merge: " << paths[i] << " not placed: " << result.maps[i].reason << "\n";
  }
  return result.ok ? 0 : 1;
}

// ---------------------------------------------------------------------------------------- eval

const std::string kEvalHelp = with_decision_defaults(
    "usage: areamatch eval MANIFEST [options]\n"
    "Matches every pair of a manifest (the format of shared/pairs.json; paths relative to it) and prints\n"
    "a table: areas, segmentation/matching/total times, the transform, and with ground truth the\n"
    "rotation error, the mean displacement of the source's free-space edge and whether it is correct\n"
    "by the manifest's correct_if (as shared/tools/score.py judges). Summary lines follow.\n"
    "Exit status: 0 when it ran (wrong matches are data, not failure), 2 on a bad manifest or a pair\n"
    "whose maps cannot be read (the other pairs still run).\n"
    "Options:\n"
    "  --out DIR          write DIR/results.json, DIR/results.csv, DIR/report.md and DIR/pairs/*.png\n"
    "  --repeat N         run each pair N times: median times, and a check that results agree bit for bit\n"
    "  --only A,B         only the pairs with these names\n"
    "  --no-reflection    do not try mirror images (a pair's \"allow_reflection\" overrides either way)\n"
    "  --paper            the paper's matching as written\n"
    "  --k N              mutual nearest neighbours per area (default 10; paper 3)\n"
    "  --min-p-correct P  reject when the calibrated probability of a right answer is below P (default 0: off)\n"
    "  --min-score S      reject when the best whole-map score is below S (default {min_score})\n"
    "  --min-agreement A  reject when the maps agree less than A under the best transform (default {min_agreement})\n"
    "  --gate-max-lower-walls W  at or above A, accept on the agreement alone only where the lower wall\n"
    "                     agreement is at most W (default {gate_max_lower_walls}; above 1: always)\n"
    "  --gate-min-overlap M2  ... and the maps share at least M2 m² of free space (default {gate_min_overlap_m2}; 0: any)\n"
    "  --estimate-scale   estimate each source's scale (its resolution may be off by 0.5-2x); the summary\n"
    "                     gives the scale errors against the ground truth\n"
    "  --source-resolution R  take every source map as R m/pixel (a pair's source_resolution still wins)\n"
    "  --cross-buildings  also run every two maps of different buildings (maps joined by a pair are one\n"
    "                     building): these must be rejected; the summary gives both acceptance rates\n"
    "  --picture-scale F  shrink pictures by this integer factor (default: to at most 2000 px wide)\n"
    "Per pair, the manifest may give door_width_m, source_resolution, destination_resolution,\n"
    "allow_reflection, ambiguous (reported, and counted apart in the summary) and different_buildings\n"
    "(true: the maps must not match; correct when rejected).\n");

std::vector<std::string> split_names(const std::string& list) {
  std::vector<std::string> names;
  std::string::size_type start = 0;
  while (start <= list.size()) {
    const auto comma = std::min(list.find(',', start), list.size());
    if (comma > start) names.push_back(list.substr(start, comma - start));
    start = comma + 1;
  }
  return names;
}

/// A file name for a pair's picture: its index (names may differ only in characters a file name
/// cannot hold) and its name with anything but letters, digits, '-', '_' and '.' replaced.
std::string picture_name(std::size_t index, const std::string& pair_name) {
  std::string safe;
  for (char c : pair_name) safe += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.') ? c : '_';
  char prefix[32];
  std::snprintf(prefix, sizeof prefix, "%03zu_", index + 1);
  return prefix + safe + ".png";
}

int run_eval(const std::vector<std::string>& tokens) {
  const Args args(tokens, {"no-reflection", "paper", "cross-buildings", "estimate-scale", "help"},
                  {"out", "repeat", "only", "k", "min-score", "min-agreement", "gate-max-lower-walls", "gate-min-overlap", "min-p-correct",
                   "picture-scale", "source-resolution", "set"});
  if (args.flag("help")) {
    std::cout << kEvalHelp << kSetHelp;
    return 0;
  }
  args.expect_positional(1, "MANIFEST");
  areamatch::EvalOptions options;
  options.repeat = static_cast<int>(args.integer("repeat", 1, 1000).value_or(1));
  options.matching.paper = args.flag("paper");
  options.matching.allow_reflection = !args.flag("no-reflection");
  options.matching.estimate_scale = args.flag("estimate-scale");
  options.matching.settings = settings_from(args);
  options.matching.source_load.resolution = args.number("source-resolution", /*positive=*/true);
  const auto picture_scale = args.integer("picture-scale", 1, 100);
  const auto out = args.text("out");

  areamatch::Manifest manifest = areamatch::load_manifest(args.positional()[0]);
  if (const auto only = args.text("only")) {
    const auto names = split_names(*only);
    for (const auto& name : names) {
      if (std::none_of(manifest.pairs.begin(), manifest.pairs.end(), [&](const auto& p) { return p.name == name; })) {
        throw UsageError("--only: no pair named '" + name + "' in " + manifest.path);
      }
    }
    manifest.pairs.erase(std::remove_if(manifest.pairs.begin(), manifest.pairs.end(),
                                        [&](const auto& p) { return std::find(names.begin(), names.end(), p.name) == names.end(); }),
                         manifest.pairs.end());
  }
  if (args.flag("cross-buildings")) {
    const auto cross = areamatch::cross_building_pairs(manifest);
    manifest.pairs.insert(manifest.pairs.end(), cross.begin(), cross.end());
  }
  areamatch::check_manifest_files(manifest);
  if (out) {
    std::error_code ec;
    std::filesystem::create_directories(*out + "/pairs", ec);
    if (ec) throw areamatch::io_error(*out + ": cannot create folder (" + ec.message() + ")");
  }

  std::vector<areamatch::PairEvaluation> rows;
  std::vector<std::string> pictures;
  for (std::size_t i = 0; i < manifest.pairs.size(); ++i) {
    const auto& pair = manifest.pairs[i];
    areamatch::MapPairRun run;
    rows.push_back(areamatch::evaluate_pair(pair, manifest.correct_if, options, out ? &run : nullptr));
    const auto& row = rows.back();
    std::cerr << "[" << i + 1 << "/" << manifest.pairs.size() << "] " << pair.name << ": "
              << (!row.failure.empty()               ? "error"
                  : row.pair.different_buildings ? (row.correct ? "rejected (different buildings)" : "ACCEPTED (different buildings)")
                  : row.error                    ? (row.correct ? "correct" : "WRONG")
                                                 : (row.result.ok ? "matched" : "no match"))
              << ", " << format_fixed(1000.0 * row.timings.total_s, 1) << " ms\n";
    pictures.emplace_back();
    if (out && row.failure.empty()) {
      const auto picture = areamatch::render_match(run.source, run.source_graph, run.dest, run.dest_graph, row.result);
      constexpr int max_picture_width = 2000;
      const int factor = picture_scale ? static_cast<int>(*picture_scale) : (picture.width + max_picture_width - 1) / max_picture_width;
      pictures.back() = "pairs/" + picture_name(i, pair.name);
      areamatch::write_png(*out + "/" + pictures.back(), areamatch::downscaled(picture, factor));
    }
  }
  const auto summary = areamatch::summarize(rows);
  std::cout << areamatch::eval_table(rows, summary);
  if (out) {
    areamatch::write_text_file(*out + "/results.json", areamatch::eval_json(manifest, rows, summary));
    areamatch::write_text_file(*out + "/results.csv", areamatch::eval_csv(rows));
    areamatch::write_text_file(*out + "/report.md", areamatch::eval_markdown(manifest, rows, summary, pictures));
    std::cout << "wrote " << *out << "/report.md, results.json, results.csv and " << summary.pairs - summary.failed
              << " pictures in " << *out << "/pairs\n";
  }
  if (summary.failed > 0) {
    std::cerr << "areamatch eval: " << summary.failed << " pair(s) could not run (see the errors above)\n";
    return 2;
  }
  return 0;
}

// ----------------------------------------------------------------------------------- calibrate

const std::string kCalibrateHelp = with_decision_defaults(
    "usage: areamatch calibrate RESULTS.csv [RESULTS.csv ...] [options]\n"
    "Fits the accept/reject decision (p_correct, include/areamatch/match/decision/decision.hpp) on the rows of\n"
    "'areamatch eval --out DIR' runs (DIR/results.csv; run them with --cross-buildings for pairs that\n"
    "must be rejected) and measures it by leave-one-building-out cross-validation: each building's\n"
    "pairs are judged by a model fitted without any pair that touches that building (maps joined by a\n"
    "pair of one building are one building). A row is right when its transform is within the\n"
    "manifest's correct_if; pairs of different buildings are wrong; ambiguous pairs are left out.\n"
    "The rule judged is the matcher's: accepted when p_correct >= P, or agreement >= A with the lower\n"
    "of the two wall agreements <= W. Prints per\n"
    "building and in total the false rejects (right answers refused) and false accepts (wrong answers\n"
    "accepted), the same in-sample, the totals of other rules, the coefficients fitted on all rows and\n"
    "a reliability table.\n"
    "Real buildings judge, generated ones only train: a building with a map of a generated pair\n"
    "(manifest kind 'synthetic') is generated; the rates are also given per real building and per\n"
    "modality (the kinds of the two maps, learnt from the manifests' kinds: SLAM map, layout,\n"
    "furnished layout, hand-held scan), and --choose-rule's choice is judged by nested\n"
    "leave-one-real-building-out (generated buildings always train).\n"
    "Options:\n"
    "  --l2 L             L2 penalty on the weights (default 1)\n"
    "  --accept-p P       accepted on the model alone at p_correct >= P (default {accept_p_correct})\n"
    "  --min-agreement A  accepted at agreement >= A (default {min_agreement}; above 1: the model alone)\n"
    "  --gate-max-lower-walls W  ... when the lower wall agreement is <= W (default {gate_max_lower_walls}; above 1: always)\n"
    "  --gate-min-overlap M2  ... and the shared free space is >= M2 m² (default {gate_min_overlap_m2}; 0: any; kept, not\n"
    "                     chosen, by --choose-rule)\n"
    "  --gate-both-ways-occupied Q  above W, the gate needs the occupied walls to agree >= Q (default\n"
    "                     {gate_both_ways_min_occupied}; above 1: off; kept, not chosen, by --choose-rule)\n"
    "  --gate-both-ways-margin M  ... and a margin >= M to the best rival (default {gate_both_ways_min_margin}; kept)\n"
    "  --simulated A.csv,B.csv  eval results of simulated SLAM maps (onto their plans and onto others): they\n"
    "                     do not train the model; Q and M are chosen on them and the generated rows (no\n"
    "                     wrong answer accepted, the fewest right ones refused), and they are judged\n"
    "                     building by building with Q and M chosen without that building\n"
    "  --svg OUT.svg      the reliability diagram of the real buildings' rows (cross-validated)\n"
    "  --predictions OUT.csv  every row with its buildings, label, agreement, the cross-validated and\n"
    "                     the in-sample p_correct and whether the rule accepts it (cross-validated):\n"
    "                     to see which pairs a building's false rejects and accepts are\n"
    "  --choose-rule      also choose A, P and W from data (the fewest false rejects with at most F of the\n"
    "                     wrong answers accepted, judged on leave-one-building-out predictions) and\n"
    "                     measure that choice by nested leave-one-building-out cross-validation: each\n"
    "                     building is judged by a model and thresholds chosen without it (slow: one\n"
    "                     inner cross-validation per building)\n"
    "  --max-false-accept F  the bound for --choose-rule (default 0.005)\n"
    "  --choose-on all|real  the rows --choose-rule chooses on: every row, generated ones too\n"
    "                     (default), or real buildings' alone; judged on real buildings either way\n");

/// `calibrate --choose-rule`: the rule chosen on the rows' cross-validated predictions, and that choice
/// judged by nested leave-one-building-out cross-validation.
void report_chosen_rule(const Args& args, const std::vector<CalibrationRow>& rows, const std::vector<std::string>& buildings,
                        const areamatch_cli::JudgingBuildings& judging, const areamatch_cli::MapRoles& roles,
                        const std::vector<double>& predicted, double l2, const areamatch::DecisionParams& base,
                        const Rule& given) {
  const auto line = areamatch_cli::counts_line;
  const double max_false_accept = args.number("max-false-accept", false, true).value_or(0.005);
  if (max_false_accept > 1.0) throw UsageError("--max-false-accept must be a share between 0 and 1");
  // Chosen on every row (or, --choose-on real, on real buildings' alone); judged on real ones.
  const std::string choose_on = args.text("choose-on").value_or("all");
  if (choose_on != "real" && choose_on != "all") throw UsageError("--choose-on must be real or all, got '" + choose_on + "'");
  const bool choose_on_all = choose_on == "all";
  std::vector<std::size_t> judged_rows;
  std::vector<double> judged_predicted;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!choose_on_all && !judging.judged(i)) continue;
    judged_rows.push_back(i);
    judged_predicted.push_back(predicted[i]);
  }
  const Rule shipped = choose_rule(rows, judged_rows, judged_predicted, max_false_accept, given);
  std::vector<Rule> chosen;
  std::vector<signed char> accepted;
  try {
    accepted = nested_rule_cv(rows, judging, l2, base, max_false_accept, choose_on_all, given, chosen);
  } catch (const areamatch::parameter_error& e) {
    throw UsageError(std::string("--choose-rule: without two of the buildings the rows left are not enough to fit on (") +
                     e.what() + "); nested cross-validation needs more buildings with right answers");
  }
  DecisionCounts nested_total;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (accepted[i] >= 0) nested_total.add(rows[i].sample.correct, rows[i].different_buildings, accepted[i] > 0);
  }
  std::map<std::array<double, 4>, int> folds;
  for (const Rule& fold_rule : chosen) {
    ++folds[{fold_rule.gate.min_agreement, fold_rule.gate.gate_max_lower_walls, fold_rule.gate.gate_min_overlap_m2, fold_rule.accept_p}];
  }
  std::cout << "\nrule chosen on all rows (at most " << format_double(max_false_accept)
            << " of the wrong answers accepted, leave-one-building-out predictions): agreement >= "
            << format_double(shipped.gate.min_agreement) << " with lower wall agreement <= "
            << format_double(shipped.gate.gate_max_lower_walls) << " on at least " << format_fixed(shipped.gate.gate_min_overlap_m2, 0)
            << " m2 shared (above it: occupied walls >= " << format_double(shipped.gate.gate_both_ways_min_occupied)
            << " and margin >= " << format_double(shipped.gate.gate_both_ways_min_margin) << ", given), or p_correct >= "
            << format_double(shipped.accept_p)
            << " (above 1: off)\nrules chosen in the " << chosen.size() << " folds:";
  for (const auto& [thresholds, n] : folds) {
    std::cout << " [agreement " << format_double(thresholds[0]) << ", lower walls " << format_double(thresholds[1])
              << ", overlap " << format_fixed(thresholds[2], 0) << ", p " << format_double(thresholds[3]) << "] x" << n;
  }
  std::cout << "\n\n"
            << areamatch_cli::judged_report(rows, accepted, buildings, judging, roles,
                                            "nested leave-one-building-out (model and thresholds chosen without the building)")
            << line("total (nested cross-validation)", nested_total);
}

/// `calibrate --simulated`: the gate's both-ways thresholds chosen on the generated rows (their
/// cross-validated p_correct) and the simulated ones (their own, from a model that never saw them),
/// and the simulated rows judged building by building, each by thresholds chosen without it.
void report_both_ways_choice(const std::vector<CalibrationRow>& rows, const std::vector<CalibrationRow>& simulated,
                             const std::vector<std::string>& buildings, const areamatch_cli::JudgingBuildings& judging,
                             const std::vector<double>& predicted, const Rule& rule) {
  auto choose_without = [&](int held) {
    std::vector<const CalibrationRow*> choosing;
    std::vector<double> p;
    auto touches = [&](const CalibrationRow& r) { return r.source_building == held || r.dest_building == held; };
    for (std::size_t i = 0; i < rows.size(); ++i) {
      if (judging.judged(i) || touches(rows[i])) continue;  // real rows judge, they do not choose
      choosing.push_back(&rows[i]);
      p.push_back(predicted[i]);
    }
    for (const CalibrationRow& r : simulated) {
      if (touches(r)) continue;
      choosing.push_back(&r);
      p.push_back(r.shipped_p);
    }
    return areamatch_cli::choose_both_ways(choosing, p, rule);
  };
  const Rule all = choose_without(-1);
  std::cout << "\nthe gate's both-ways part chosen on the generated and simulated rows (no wrong answer accepted, the "
               "fewest right ones refused): occupied walls >= "
            << format_double(all.gate.gate_both_ways_min_occupied) << ", margin >= " << format_double(all.gate.gate_both_ways_min_margin)
            << " (judged: occupied " << format_double(rule.gate.gate_both_ways_min_occupied) << ", margin "
            << format_double(rule.gate.gate_both_ways_min_margin) << ")\n"
            << "simulated maps by building, each judged by thresholds chosen without it:\n"
               "building | chosen occupied, margin | right answers | right and accepted | wrong transforms | accepted | "
               "onto other buildings | accepted\n";
  std::map<int, std::array<std::size_t, 6>> per_building;  // by the simulated map's building
  for (const CalibrationRow& r : simulated) per_building[r.source_building];
  std::array<std::size_t, 6> total{};
  for (auto& [b, c] : per_building) {
    const Rule held = choose_without(b);
    for (const CalibrationRow& r : simulated) {
      if (r.source_building != b) continue;
      const bool accepted = held.accepts(r, r.shipped_p);
      const std::size_t column = r.different_buildings ? 4 : r.sample.correct ? 0 : 2;
      ++c[column];
      c[column + 1] += accepted;
    }
    for (std::size_t k = 0; k < c.size(); ++k) total[k] += c[k];
    std::cout << buildings[static_cast<std::size_t>(b)] << " | " << format_double(held.gate.gate_both_ways_min_occupied) << ", "
              << format_double(held.gate.gate_both_ways_min_margin) << " | " << c[0] << " | " << c[1] << " | " << c[2] << " | " << c[3]
              << " | " << c[4] << " | " << c[5] << "\n";
  }
  std::cout << "total | | " << total[0] << " | " << total[1] << " | " << total[2] << " | " << total[3] << " | " << total[4]
            << " | " << total[5] << "\n";
}

/// `calibrate`'s reliability tables (cross-validated): all rows, then the real buildings' alone (what
/// --svg draws).
void report_reliability(const Args& args, const std::vector<CalibrationRow>& rows, const std::vector<double>& predicted,
                        const areamatch_cli::JudgingBuildings& judging) {
  std::cout << "\nreliability (cross-validated): bin | rows | mean predicted | observed right | observed right, "
               "classes weighted equally (the fit's prior)\n";
  constexpr int bins = 10;
  auto print_table = [&](const std::vector<ReliabilityBin>& table) {
    for (int b = 0; b < bins; ++b) {
      const ReliabilityBin& r = table[static_cast<std::size_t>(b)];
      std::cout << format_fixed(b / double(bins), 1) << "-" << format_fixed((b + 1) / double(bins), 1) << " | " << r.rows
                << " | " << (r.rows ? format_fixed(r.mean_predicted, 3) : "-") << " | "
                << (r.rows ? format_fixed(r.observed, 3) : "-") << " | "
                << (r.rows ? format_fixed(r.observed_balanced, 3) : "-") << "\n";
    }
  };
  const std::vector<ReliabilityBin> table = reliability(predicted, rows, bins);
  print_table(table);
  // The real buildings' rows alone: what a user's maps meet.
  std::vector<CalibrationRow> real_rows;
  std::vector<double> real_predicted;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!judging.judged(i)) continue;
    real_rows.push_back(rows[i]);
    real_predicted.push_back(predicted[i]);
  }
  const std::vector<ReliabilityBin> real_table = reliability(real_predicted, real_rows, bins);
  if (!judging.all_judge) {
    std::cout << "\nreliability of the real buildings' rows alone (cross-validated; --svg draws this one):\n";
    print_table(real_table);
  }
  if (const auto svg = args.text("svg")) areamatch::write_text_file(*svg, reliability_svg(real_table));
}

int run_calibrate(const std::vector<std::string>& tokens) {
  const Args args(tokens, {"help", "choose-rule"}, {"l2", "accept-p", "min-agreement", "gate-max-lower-walls", "gate-min-overlap", "gate-both-ways-occupied", "gate-both-ways-margin", "simulated", "svg", "predictions", "max-false-accept", "choose-on"});
  if (args.flag("help")) {
    std::cout << kCalibrateHelp;
    return 0;
  }
  make_output_folders(args, {"svg", "predictions"});
  if (args.positional().empty()) throw UsageError("expected at least one RESULTS.csv");
  const double l2 = args.number("l2", true).value_or(1.0);
  areamatch::DecisionParams base;
  base.accept_p_correct = args.fraction("accept-p").value_or(base.accept_p_correct);
  base.validate();
  const double gate = args.fraction("min-agreement").value_or(areamatch::DecisionParams{}.min_agreement);
  const double gate_walls =
      args.number("gate-max-lower-walls", false, true).value_or(areamatch::DecisionParams{}.gate_max_lower_walls);
  const double gate_overlap =
      args.number("gate-min-overlap", false, true).value_or(areamatch::DecisionParams{}.gate_min_overlap_m2);
  const double both_ways_occupied =
      args.number("gate-both-ways-occupied", false, true).value_or(areamatch::DecisionParams{}.gate_both_ways_min_occupied);
  const double both_ways_margin = args.number("gate-both-ways-margin").value_or(areamatch::DecisionParams{}.gate_both_ways_min_margin);
  std::vector<CalibrationRow> rows;
  areamatch_cli::MapRoles roles;
  for (const auto& path : args.positional()) {
    auto more = read_calibration_rows(path, &roles);
    rows.insert(rows.end(), std::make_move_iterator(more.begin()), std::make_move_iterator(more.end()));
  }
  // Simulated SLAM maps (--simulated): their buildings are assigned with the others' (a simulated
  // map joins its plan), but they never train the model; they choose the gate's both-ways part.
  std::vector<CalibrationRow> simulated;
  for (const auto& path : split_names(args.text("simulated").value_or(""))) {
    auto more = read_calibration_rows(path, &roles);
    simulated.insert(simulated.end(), std::make_move_iterator(more.begin()), std::make_move_iterator(more.end()));
  }
  const std::size_t calibration_rows = rows.size();
  rows.insert(rows.end(), std::make_move_iterator(simulated.begin()), std::make_move_iterator(simulated.end()));
  const std::vector<std::string> buildings = assign_buildings(rows);
  simulated.assign(std::make_move_iterator(rows.begin() + static_cast<std::ptrdiff_t>(calibration_rows)),
                   std::make_move_iterator(rows.end()));
  rows.resize(calibration_rows);
  if (rows.empty()) throw UsageError("no labelled rows in the RESULTS.csv files");
  const areamatch_cli::JudgingBuildings judging = areamatch_cli::judging_buildings(rows, buildings.size(), roles);
  const auto real_buildings = static_cast<std::size_t>(std::count(judging.judges.begin(), judging.judges.end(), 1));
  std::vector<areamatch::DecisionSample> all;
  for (const auto& r : rows) all.push_back(r.sample);
  const areamatch::DecisionParams fitted = areamatch::fit_decision(all, l2, base);
  const std::vector<double> predicted = leave_one_building_out(rows, l2, base);
  std::vector<double> in_sample;
  for (const auto& r : rows) in_sample.push_back(areamatch::p_correct(r.sample.features, fitted));

  // The rule judged: the model at accept_p, else the agreement gate with these thresholds; the
  // other rules beside it: the model alone at 0.5 (gate shut: no agreement reaches 2), the gate alone.
  areamatch::DecisionParams gate_thresholds;
  gate_thresholds.min_agreement = gate;
  gate_thresholds.gate_max_lower_walls = gate_walls;
  gate_thresholds.gate_min_overlap_m2 = gate_overlap;
  gate_thresholds.gate_both_ways_min_occupied = both_ways_occupied;
  gate_thresholds.gate_both_ways_min_margin = both_ways_margin;
  areamatch::DecisionParams shut = gate_thresholds;
  shut.min_agreement = 2.0;
  const Rule rule{base.accept_p_correct, gate_thresholds}, model_half{0.5, shut}, gate_alone{2.0, gate_thresholds};
  std::vector<DecisionCounts> per_building(buildings.size());
  DecisionCounts cv_total, in_sample_total, cv_model_half, gate_only;
  std::vector<signed char> cv_accepted(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CalibrationRow& r = rows[i];
    const bool accepted = rule.accepts(r, predicted[i]);
    cv_accepted[i] = accepted;
    cv_total.add(r.sample.correct, r.different_buildings, accepted);
    in_sample_total.add(r.sample.correct, r.different_buildings, rule.accepts(r, in_sample[i]));
    cv_model_half.add(r.sample.correct, r.different_buildings, model_half.accepts(r, predicted[i]));
    gate_only.add(r.sample.correct, r.different_buildings, gate_alone.accepts(r, 0.0));
    DecisionCounts::add_per_building(per_building, r, accepted);
  }
  const auto line = areamatch_cli::counts_line;
  std::cout << rows.size() << " rows, " << buildings.size() << " buildings (" << real_buildings
            << (judging.all_judge ? " judging: no real building, generated ones judge" : " real, which judge; the others generated, which only train")
            << "); rule: agreement >= " << format_double(gate)
            << " with lower wall agreement <= " << format_double(gate_walls) << " (above it: occupied walls >= "
            << format_double(both_ways_occupied) << " and margin >= " << format_double(both_ways_margin) << "), or p_correct >= "
            << format_double(base.accept_p_correct) << "\n\n"
            << "leave-one-building-out, every building (a pair of two buildings counts under both):\n"
            << "building | right answers | false rejects | wrong answers of one building | accepted | pairs of different buildings | accepted\n";
  for (std::size_t b = 0; b < buildings.size(); ++b) {
    std::cout << line(buildings[b] + (judging.judges[b] ? "" : " (generated)"), per_building[b]);
  }
  std::cout << line("total (cross-validated)", cv_total) << line("total (in-sample)", in_sample_total)
            << line("other rule: p_correct >= 0.5 alone (cross-validated)", cv_model_half)
            << line("other rule: agreement >= " + format_double(gate) + " (lower walls <= " + format_double(gate_walls) +
                        ", or occupied walls >= " + format_double(both_ways_occupied) + " with margin >= " +
                        format_double(both_ways_margin) + ") alone",
                    gate_only);
  std::cout << "\n" << areamatch_cli::judged_report(rows, cv_accepted, buildings, judging, roles, "leave-one-building-out");
  std::cout << "\nfitted on all rows: bias = " << format_fixed(fitted.bias, 3) << ", weights = {";
  for (std::size_t i = 0; i < fitted.weights.size(); ++i) {
    std::cout << (i ? ", " : "") << format_fixed(fitted.weights[i], 3);
  }
  std::cout << "}  (" ;
  for (std::size_t i = 0; i < areamatch::DecisionFeatures::size; ++i) {
    std::cout << (i ? ", " : "") << areamatch::DecisionFeatures::names[i];
  }
  std::cout << ")\n";
  report_reliability(args, rows, predicted, judging);
  if (const auto out = args.text("predictions")) {
    areamatch::write_text_file(*out, predictions_csv(rows, buildings, predicted, in_sample, rule));
  }
  if (!args.flag("choose-rule")) {
    for (const char* name : {"choose-on", "max-false-accept"}) {
      if (args.text(name)) throw UsageError(std::string("--") + name + " needs --choose-rule");
    }
  }
  if (args.flag("choose-rule")) report_chosen_rule(args, rows, buildings, judging, roles, predicted, l2, base, rule);
  if (!simulated.empty()) report_both_ways_choice(rows, simulated, buildings, judging, predicted, rule);
  return 0;
}

// ---------------------------------------------------------------------------------------- main

const char* kMainHelp =
    "usage: areamatch COMMAND [ARGS] (areamatch COMMAND --help for details)\n"
    "Aligns 2D occupancy-grid maps of one building through their Area Graphs.\n"
    "Commands:\n"
    "  info MAP          size, resolution, origin and free/occupied/unknown fractions of a map\n"
    "  segment MAP       split a map into areas and passages (its Area Graph), with pictures\n"
    "  match SOURCE DEST find the transform between two maps of one building\n"
    "  warp SOURCE DEST  bend one map onto another beyond the rigid transform, and carry points across\n"
    "  assess MAP REF    where MAP is wrong against REF (a plan, a ground truth), how broken, how complete\n"
    "  merge MAP MAP...  place several maps of one building in one frame and fuse them into one map\n"
    "  eval MANIFEST     match every pair of a manifest and score it against its ground truth\n"
    "  generate OUTDIR   write a synthetic layout + robot map pair with ground truth\n"
    "  simulate PLAN OUTDIR  simulated laser-SLAM maps of a floor plan, with ground truth\n"
    "  calibrate CSV...  fit the accept/reject decision on eval results, cross-validated by building\n"
    "  parameters        every setting --set takes, with its value and what it does\n"
    "  version           print the version\n"
    "Exit status: 0 success, 1 no acceptable result, 2 bad input or usage, 3 internal error (a bug:\n"
    "please report it with the command and the maps) or out of memory.\n"
    "A run of match, warp, assess or merge over a second shows its stage on stderr when stderr is a\n"
    "terminal (AREAMATCH_PROGRESS=always draws it anyway, =never never).\n";

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> all(argv + 1, argv + argc);
  if (all.empty() || all[0] == "--help" || all[0] == "-h" || all[0] == "help") {
    std::cout << kMainHelp;
    return all.empty() ? 2 : 0;
  }
  const std::map<std::string, std::function<int(const std::vector<std::string>&)>> commands = {
      {"info", run_info}, {"generate", run_generate}, {"simulate", run_simulate}, {"segment", run_segment}, {"match", run_match}, {"warp", run_warp}, {"assess", run_assess}, {"merge", run_merge}, {"eval", run_eval}, {"calibrate", run_calibrate}, {"parameters", run_parameters}};
  const std::string command = all[0];
  const std::vector<std::string> rest(all.begin() + 1, all.end());
  try {
    if (command == "version" || command == "--version") {
      std::cout << "areamatch " << areamatch::version_string << "\n";
      return 0;
    }
    const auto it = commands.find(command);
    if (it == commands.end()) throw UsageError("unknown command '" + command + "' (see areamatch --help)");
    return it->second(rest);
  } catch (const UsageError& e) {
    std::cerr << "areamatch " << command << ": " << e.what() << "\n";
    return 2;
  } catch (const areamatch::error& e) {
    std::cerr << "areamatch " << command << ": " << e.what() << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    std::cerr << "areamatch " << command << ": out of memory\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "areamatch " << command << ": internal error (please report it with the command and the maps): "
              << e.what() << "\n";
    return 3;
  }
}
