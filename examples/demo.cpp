// The README demo: a synthetic building, a degraded and turned "robot map" of it, both saved as
// ROS maps and read back, their Area Graphs, the match of the pair and its error against the
// generator's exact ground truth, and pictures.
//
//   demo [OUTDIR]      (default: areamatch-demo)
#include <areamatch/areamatch.hpp>
#include <areamatch/synthetic.hpp>
#include <areamatch/evaluation.hpp>
#include <areamatch/io.hpp>

#include <cstdio>
#include <filesystem>
#include <iostream>

int main(int argc, char** argv) {
  const std::string out = argc > 1 ? argv[1] : "areamatch-demo";
  try {
    std::filesystem::create_directories(out);

    areamatch::BuildingParams building_params;  // 30 m × 20 m, rooms along corridors
    const auto building = areamatch::generate_building(building_params, 2024);

    areamatch::RobotMapParams robot_params;
    robot_params.rotation_rad = 37.0 * areamatch::pi / 180.0;
    robot_params.resolution = 0.04;
    robot_params.wall_noise_m = 0.03;
    robot_params.max_clutter_per_room = 3;
    robot_params.speckle_per_m2 = 0.02;
    const auto robot = areamatch::make_robot_map(building, robot_params, 2024);

    const std::string layout_yaml = areamatch::save_map(building.layout, out + "/layout.pgm");
    const std::string robot_yaml = areamatch::save_map(robot.grid, out + "/robot.png");
    const bool round_trip = areamatch::load_map(layout_yaml) == building.layout &&
                            areamatch::load_map(robot_yaml) == robot.grid;

    areamatch::write_png(out + "/pair.png", areamatch::side_by_side(areamatch::render_grid(robot.grid),
                                                                    areamatch::render_grid(building.layout)));
    areamatch::write_png(out + "/overlay.png", areamatch::render_overlay(building.layout, robot.grid, robot.T_dest_source));
    areamatch::write_text_file(out + "/overlay.svg",
                               areamatch::overlay_svg(building.layout, robot.grid, robot.T_dest_source));

    // Area Graphs of both maps: rooms in colours, doors as lines with a dot sized by their width.
    const areamatch::VoronoiSegmenter segmenter;
    const auto layout_graph = segmenter.segment(building.layout);
    const auto robot_graph = segmenter.segment(robot.grid);
    areamatch::write_png(out + "/segmentation.png",
                         areamatch::side_by_side(areamatch::render_area_graph(robot.grid, robot_graph),
                                                 areamatch::render_area_graph(building.layout, layout_graph)));

    // Match the robot map onto the layout (mirror images allowed) and judge it by the ground truth.
    areamatch::Matcher<> matcher;
    matcher.params.allow_reflection = true;
    const auto result = matcher.match(robot.grid, robot_graph, building.layout, layout_graph);
    const auto error = areamatch::match_error(result.pixel_transform, robot.pixel_transform,
                                              areamatch::free_edge_pixels(robot.grid), building.layout.resolution());
    areamatch::write_png(out + "/match.png",
                         areamatch::side_by_side(areamatch::render_match_source(robot.grid, robot_graph, result),
                                                 areamatch::render_match_overlay(robot.grid, building.layout, layout_graph, result)));
    const bool correct = result.ok && error.correct({3.0, 0.5});

    const auto& T = robot.T_dest_source;
    std::printf("building: %zu areas, %zu doors, layout %dx%d cells at %.2f m\n", building.areas.size(),
                building.doors.size(), building.layout.width(), building.layout.height(), building.layout.resolution());
    std::printf("robot map: %dx%d cells at %.2f m, turned %.1f deg\n", robot.grid.width(), robot.grid.height(),
                robot.grid.resolution(), robot_params.rotation_rad * 180.0 / areamatch::pi);
    std::printf("ground truth robot -> layout: rotation %.2f deg, translation (%.3f, %.3f) m%s\n",
                T.rotation * 180.0 / areamatch::pi, T.translation.x(), T.translation.y(), T.reflected ? ", mirrored" : "");
    std::printf("area graphs: robot map %zu areas / %zu passages, layout %zu areas / %zu passages\n",
                robot_graph.areas.size(), robot_graph.passages.size(), layout_graph.areas.size(),
                layout_graph.passages.size());
    std::printf("save/load round trip: %s\n", round_trip ? "identical" : "DIFFERENT");
    std::printf("match: %s, rotation %.2f deg, translation (%.3f, %.3f) m%s, score %.3f, margin %.3f, %zu matched areas, "
                "%.1f ms\n", result.ok ? "ok" : result.reason.c_str(), result.T_dest_source.rotation * 180.0 / areamatch::pi,
                result.T_dest_source.translation.x(), result.T_dest_source.translation.y(),
                result.T_dest_source.reflected ? ", mirrored" : "", result.score, result.margin,
                result.matched_areas.size(), 1000.0 * result.timings.match_s);
    std::printf("error against the ground truth: rotation %.3f deg, mean wall displacement %.3f m -> %s\n",
                error.rotation_error_deg, error.mean_displacement_m, correct ? "CORRECT" : "WRONG");
    std::printf("pictures in %s/: pair.png (the two maps), segmentation.png (their areas and doors),\n"
                "  overlay.png and overlay.svg (robot walls in red on the layout, by the ground truth),\n"
                "  match.png (matched areas in the same colours; robot walls in red on the layout, by the match)\n",
                out.c_str());
    return round_trip && correct ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "demo: " << e.what() << "\n";
    return 2;
  }
}
