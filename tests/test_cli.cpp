// The areamatch program: help, info, generate, segment, match, warp, assess, eval, and exit status 2 with a
// message for bad input.
#include <doctest/doctest.h>

#include <areamatch/detail/format.hpp>
#include <areamatch/io.hpp>
#include <areamatch/match/params.hpp>

#include "test_support.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <cstdio>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <utility>
#include <vector>

namespace {

struct Run {
  int status;
  std::string out;  // stdout and stderr together
};

/// Runs the program; `stderr_too` false keeps only stdout (stderr is dropped).
Run run(const std::string& arguments, bool stderr_too = true) {
  const std::string command = std::string(AREAMATCH_CLI) + " " + arguments + (stderr_too ? " 2>&1" : " 2>/dev/null");
  FILE* pipe = ::popen(command.c_str(), "r");
  REQUIRE(pipe != nullptr);
  std::string out;
  char buffer[4096];
  while (std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) out.append(buffer, n);
  const int raw = ::pclose(pipe);
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, out};
}

std::string read_text(const std::string& path) {
  const auto bytes = areamatch::detail::read_file_bytes(path);
  return std::string(bytes.begin(), bytes.end());
}

}  // namespace

TEST_CASE("help and version") {
  CHECK(run("--help").status == 0);
  CHECK(run("--help").out.find("info MAP") != std::string::npos);
  CHECK(run("info --help").status == 0);
  CHECK(run("generate --help").out.find("--seed") != std::string::npos);
  CHECK(run("version").out.find("areamatch 0.1") != std::string::npos);
  CHECK(run("").status == 2);
  const Run unknown = run("frobnicate");
  CHECK(unknown.status == 2);
  CHECK(unknown.out.find("unknown command 'frobnicate'") != std::string::npos);
}

TEST_CASE("help texts print the library's own defaults of the decision options") {
  const areamatch::MatcherParams defaults;
  using areamatch::detail::format_double;
  const std::string agreement = "(default " + format_double(defaults.decision.min_agreement);
  const std::string walls = "(default " + format_double(defaults.decision.gate_max_lower_walls) + ";";
  const std::string overlap = "(default " + areamatch::detail::format_fixed(defaults.decision.gate_min_overlap_m2, 0) + ";";
  for (const char* command : {"match", "warp", "assess", "merge", "eval", "calibrate"}) {
    const std::string help = run(std::string(command) + " --help").out;
    INFO(command);
    CHECK(help.find(agreement) != std::string::npos);
    CHECK(help.find(walls) != std::string::npos);
    CHECK(help.find(overlap) != std::string::npos);
    CHECK(help.find("{min_agreement}") == std::string::npos);
  }
  CHECK(run("calibrate --help").out.find("(default " + format_double(defaults.decision.accept_p_correct) + ")") !=
        std::string::npos);
}

TEST_CASE("generate writes a pair that info reads back") {
  const std::string dir = areamatch_test::temp_dir() + "/pair";
  const Run gen = run("generate " + dir + " --seed 3 --width 16 --height 12 --rotation 120 --mirror");
  INFO(gen.out);
  REQUIRE(gen.status == 0);
  for (const char* file : {"layout.pgm", "layout.yaml", "robot.png", "robot.yaml", "layout_labels.png", "pairs.json",
                           "overlay.png", "overlay.svg"}) {
    CHECK(areamatch_test::is_dir(dir));
    CHECK(areamatch::detail::read_file_bytes(dir + "/" + file).size() > 0);
  }
  const Run info = run("info " + dir + "/layout.yaml");
  CHECK(info.status == 0);
  CHECK(info.out.find("resolution: 0.05 m/cell") != std::string::npos);
  const Run json = run("info " + dir + "/robot.yaml --json");
  CHECK(json.status == 0);
  CHECK(json.out.rfind("{", 0) == 0);
  CHECK(json.out.find("\"free_cells\":") != std::string::npos);
  // Same seed, same files.
  const std::string again = areamatch_test::temp_dir() + "/pair_again";
  REQUIRE(run("generate " + again + " --seed 3 --width 16 --height 12 --rotation 120 --mirror").status == 0);
  CHECK(areamatch::detail::read_file_bytes(dir + "/robot.png") == areamatch::detail::read_file_bytes(again + "/robot.png"));
  CHECK(areamatch::detail::read_file_bytes(dir + "/pairs.json") == areamatch::detail::read_file_bytes(again + "/pairs.json"));
}

TEST_CASE("segment writes pictures, labels and JSON; an empty map exits 1") {
  const std::string dir = areamatch_test::temp_dir() + "/segment";
  REQUIRE(run("generate " + dir + " --seed 5 --width 20 --height 14").status == 0);
  const Run seg = run("segment " + dir + "/layout.yaml --png " + dir + "/seg.png --svg " + dir + "/seg.svg --labels " +
                      dir + "/labels.png --graph " + dir + "/graph.json --show-skeleton");
  INFO(seg.out);
  CHECK(seg.status == 0);
  CHECK(seg.out.rfind("areas ", 0) == 0);
  const auto labels = areamatch::read_image(dir + "/labels.png");
  const auto layout = areamatch::load_map(dir + "/layout.yaml");
  CHECK(labels.width == layout.width());
  CHECK(labels.height == layout.height());
  CHECK(labels.max_value == 65535);
  const auto json = areamatch::detail::read_file_bytes(dir + "/graph.json");
  const std::string text(json.begin(), json.end());
  CHECK(text.find("\"areas\": [") != std::string::npos);
  CHECK(text.find("\"passages\": [") != std::string::npos);
  // Same input, same JSON.
  REQUIRE(run("segment " + dir + "/layout.yaml --graph " + dir + "/graph2.json").status == 0);
  CHECK(areamatch::detail::read_file_bytes(dir + "/graph2.json") == json);
  // --json is a flag, as in every other command: the same graph on stdout, and nothing else.
  const Run printed = run("segment " + dir + "/layout.yaml --json", false);
  CHECK(printed.status == 0);
  CHECK(printed.out == text + "\n");
  // The old spelling `--json FILE` is refused with what to write instead, not read as a second map.
  const Run old_spelling = run("segment " + dir + "/layout.yaml --json " + dir + "/graph3.json");
  CHECK(old_spelling.status == 2);
  CHECK(old_spelling.out.find("write it to a file with --graph " + dir + "/graph3.json") != std::string::npos);
  const Run old_order = run("segment --json " + dir + "/graph3.json " + dir + "/layout.yaml");
  CHECK(old_order.status == 2);
  CHECK(old_order.out.find("write it to a file with --graph " + dir + "/graph3.json") != std::string::npos);

  areamatch_test::write_bytes(dir + "/walls.pgm", std::string("P5 3 3 255\n") + std::string(9, '\0'));
  const Run empty = run("segment " + dir + "/walls.pgm");
  CHECK(empty.status == 1);
  CHECK(empty.out.find("no areas: the map has no free cells") != std::string::npos);
  const Run door = run("segment " + dir + "/layout.yaml --door-width -1");
  CHECK(door.status == 2);
  CHECK(door.out.find("--door-width must be positive") != std::string::npos);
  REQUIRE(run("segment " + dir + "/layout.yaml --speckle-size 0.5").status == 0);
  const Run speckle = run("segment " + dir + "/layout.yaml --speckle-size -1");
  CHECK(speckle.status == 2);
  CHECK(speckle.out.find("--speckle-size must not be negative") != std::string::npos);
  REQUIRE(run("segment " + dir + "/layout.yaml --min-traced-width 0.1").status == 0);
  const Run traced = run("segment " + dir + "/layout.yaml --min-traced-width -1");
  CHECK(traced.status == 2);
  CHECK(traced.out.find("--min-traced-width must not be negative") != std::string::npos);
}

TEST_CASE("bad input: exit status 2 and a message naming the problem") {
  const std::string dir = areamatch_test::temp_dir();
  auto expect = [](const std::string& arguments, const std::string& message) {
    const Run r = run(arguments);
    INFO(arguments << " -> " << r.out);
    CHECK(r.status == 2);
    CHECK(r.out.find(message) != std::string::npos);
  };
  expect("info /no/such/map.yaml", "cannot open");
  expect("info " + dir, "is a directory");
  expect("info", "expected 1 argument");
  expect("info a.png b.png", "expected 1 argument");
  areamatch_test::write_bytes(dir + "/cli_empty.png", "");
  expect("info " + dir + "/cli_empty.png", "file is empty");
  areamatch_test::write_bytes(dir + "/cli_bad.pgm", "P5 10 10 255\nxx");
  expect("info " + dir + "/cli_bad.pgm", "truncated PGM");
  areamatch_test::write_bytes(dir + "/cli_ok.pgm", std::string("P5 2 2 255\n\xfe\xfe\x00\x00", 15));
  expect("info " + dir + "/cli_ok.pgm --resolution 0", "--resolution must be positive");
  expect("info " + dir + "/cli_ok.pgm --resolution -0.05", "--resolution must be positive");
  expect("info " + dir + "/cli_ok.pgm --resolution nan", "--resolution must be a number");
  expect("info " + dir + "/cli_ok.pgm --resolution abc", "--resolution must be a number");
  expect("info " + dir + "/cli_ok.pgm --free-thresh 1.5", "--free-thresh must be in [0, 1]");
  expect("info " + dir + "/cli_ok.pgm --resolution", "--resolution needs a value");
  expect("info " + dir + "/cli_ok.pgm --bogus", "unknown option --bogus");
  expect("generate " + dir + "/g --layout spiral", "--layout must be");
  expect("generate " + dir + "/g --explored 2", "explored_fraction");
  expect("generate " + dir + "/g --seed -4", "--seed must be a whole number");
  // A resolution typo that would make the map wider than any building (1e300 for 0.05).
  areamatch_test::write_bytes(dir + "/cli_huge.yaml", "image: cli_ok.pgm\nresolution: 1e300\norigin: [0, 0, 0]\n");
  expect("info " + dir + "/cli_huge.yaml", "cli_huge.yaml: 2 cells of 1e+300 m make it");
  expect("info " + dir + "/cli_ok.pgm --resolution 5000", "max_map_extent_m");
  // A text file as a map: the loader's error alone, no note on what would have been assumed.
  areamatch_test::write_bytes(dir + "/cli_text.png", "just some text\n");
  const Run text = run("info " + dir + "/cli_text.png");
  CHECK(text.status == 2);
  CHECK(text.out.find("has no YAML") == std::string::npos);
  // A valid bare image with a resolution override works.
  CHECK(run("info " + dir + "/cli_ok.pgm --resolution 0.1").status == 0);
}

TEST_CASE("match: a generated pair, JSON on stdout, pictures, exit codes") {
  const std::string dir = areamatch_test::temp_dir() + "/match_pair";
  REQUIRE(run("generate " + dir + " --seed 5 --width 20 --height 14 --rotation 75 --mirror").status == 0);
  const std::string pair = dir + "/robot.yaml " + dir + "/layout.yaml";
  // stdout alone must be exactly one JSON object.
  const Run json = run("match " + pair + " --allow-reflection --json", /*stderr_too=*/false);
  const std::string& out = json.out;
  CHECK(json.status == 0);
  CHECK(out.rfind("{\"ok\": true", 0) == 0);
  CHECK(out.find('\n') == out.size() - 1);
  for (const char* key : {"\"rotation_deg\"", "\"translation_m\"", "\"scale\"", "\"reflected\": true", "\"pixel_transform\"",
                          "\"score\"", "\"margin\"", "\"matched_areas\"", "\"segment_source_s\"", "\"segment_dest_s\"",
                          "\"match_s\"", "\"total_s\""}) {
    CHECK_MESSAGE(out.find(key) != std::string::npos, key);
  }
  const Run pictures = run("match " + pair + " --allow-reflection --png " + dir + "/m.png --svg " + dir + "/m.svg");
  CHECK(pictures.status == 0);
  CHECK(pictures.out.find("matched: rotation") != std::string::npos);
  CHECK(pictures.out.find("accepted: p_correct") != std::string::npos);  // why, with the deciding number
  // The mirrored pair without --allow-reflection: rejected, and the rejection names the flag.
  const Run unmirrored = run("match " + pair + " --door-width 1.2");
  INFO(unmirrored.out);
  CHECK(unmirrored.status == 1);
  CHECK(unmirrored.out.find("try --allow-reflection") != std::string::npos);
  CHECK(unmirrored.out.find("try --door-width") == std::string::npos);  // given
  CHECK(areamatch::detail::read_file_bytes(dir + "/m.png").size() > 0);
  CHECK(areamatch::detail::read_file_bytes(dir + "/m.svg").size() > 0);
  // The paper's matching as written (it loses real pairs, docs/evaluation.md) finds this clean one.
  const Run paper = run("match " + pair + " --paper --allow-reflection --door-width 1.1 --json", false);
  CHECK(paper.status == 0);
  CHECK(paper.out.find("\"reflected\": true") != std::string::npos);
  const std::size_t rotation_at = paper.out.find("\"rotation_deg\": ");
  REQUIRE(rotation_at != std::string::npos);
  CHECK(std::abs(std::stod(paper.out.substr(rotation_at + 16)) - 75.0) < 3.0);

  // Room labels carried over: the source's size, destination ids + 1 (0 = no counterpart).
  const Run labels = run("match " + pair + " --allow-reflection --json --labels " + dir + "/carried.png", false);
  REQUIRE(labels.status == 0);
  CHECK(labels.out.find("\"local_rotation_deg\"") != std::string::npos);
  CHECK(labels.out.find("\"iou\"") != std::string::npos);
  const areamatch::GreyImage robot = areamatch::read_image(dir + "/robot.png");
  const areamatch::GreyImage carried = areamatch::read_png(dir + "/carried.png");
  CHECK(carried.width == robot.width);
  CHECK(carried.height == robot.height);
  CHECK(carried.max_value == 65535);
  std::size_t labelled = 0;
  for (std::uint16_t v : carried.values) labelled += v > 0;
  CHECK(labelled > carried.values.size() / 10);
  // No acceptable match: no label file, exit 1.
  const Run refused = run("match " + pair + " --min-agreement 1 --labels " + dir + "/refused.png");
  CHECK(refused.status == 1);
  CHECK(refused.out.find("not written") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir + "/refused.png"));
}

TEST_CASE("match --estimate-scale: a source whose resolution is wrong") {
  const std::string dir = areamatch_test::temp_dir() + "/scale_pair";
  // Small: the command runs the pipeline ~20 times, and the sanitizer build runs this too.
  REQUIRE(run("generate " + dir + " --seed 9 --width 15 --height 11 --rotation 40").status == 0);
  const std::string pair = dir + "/robot.yaml " + dir + "/layout.yaml";
  // The robot map is 0.05 m per pixel; told 0.08, the true scale is 0.625.
  const Run r = run("match " + pair + " --source-resolution 0.08 --door-width 0.9 --estimate-scale --json", false);
  INFO(r.out);
  REQUIRE(r.status == 0);
  CHECK(r.out.find("\"scale_estimated\": true") != std::string::npos);
  const auto at = r.out.find("\"scale\": ");
  REQUIRE(at != std::string::npos);
  const double scale = std::stod(r.out.substr(at + 9));
  CHECK(scale == doctest::Approx(0.625).epsilon(0.02));
  const Run paper = run("match " + pair + " --estimate-scale --paper");
  CHECK(paper.status == 2);
  CHECK(paper.out.find("estimate_scale needs refine") != std::string::npos);
}

TEST_CASE("the progress line: on a terminal or when asked, on stderr only, cleared at the end") {
  const std::string dir = areamatch_test::temp_dir() + "/progress_pair";
  REQUIRE(run("generate " + dir + " --seed 9 --width 15 --height 11 --rotation 40").status == 0);
  const std::string match = " " + std::string(AREAMATCH_CLI) + " match " + dir + "/robot.yaml " + dir +
                            "/layout.yaml --source-resolution 0.08 --door-width 0.9 --estimate-scale --json";
  // A run's stderr, read through a pipe; its stdout goes to a file, read back into `out`.
  const std::string out_file = dir + "/stdout.json";
  auto run_streams = [&](const std::string& command, std::string& out) {
    FILE* pipe = ::popen((command + " 2>&1 >" + out_file).c_str(), "r");
    REQUIRE(pipe != nullptr);
    std::string err;
    char buffer[4096];
    while (std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) err.append(buffer, n);
    CHECK(::pclose(pipe) == 0);
    out = read_text(out_file);
    return err;
  };
  const std::string clear = "\r\033[K";
  // Asked for (AREAMATCH_PROGRESS=always draws from the start): the stages on stderr, the line
  // cleared before the program ends, the JSON on stdout untouched.
  std::string out;
  const std::string err = run_streams("AREAMATCH_PROGRESS=always" + match, out);
  INFO(err);
  CHECK(err.find(clear + "areamatch match: trying scales") != std::string::npos);
  CHECK(err.size() >= clear.size());
  CHECK(err.compare(err.size() - clear.size(), clear.size(), clear) == 0);
  CHECK(out.find('\r') == std::string::npos);
  CHECK(out.find("\"scale_estimated\": true") != std::string::npos);
  // Piped (as here) or told never: no line.
  CHECK(run_streams(match, out).find('\r') == std::string::npos);
  CHECK(run_streams("AREAMATCH_PROGRESS=never" + match, out).find('\r') == std::string::npos);
}

TEST_CASE("parameters and --set: one table of settings; a setting reaches the match; bad ones exit 2") {
  const Run table = run("parameters", false);
  REQUIRE(table.status == 0);
  CHECK(table.out.find("segmenter (VoronoiSegmenter::Params):\n  binarize.unknown_is_free = false") == 0);
  CHECK(table.out.find("  decision.min_agreement = " + areamatch::detail::format_double(areamatch::MatcherParams{}.decision.min_agreement)) !=
        std::string::npos);
  CHECK(table.out.find("  coarse_cell_m* = 0.25") != std::string::npos);  // shapes a prepared map
  CHECK(run("parameters --paper", false).out.find("  k = 3 ") != std::string::npos);
  CHECK(run("parameters --set k=7 --set refinement.gates_m=2,1", false).out.find("  refinement.gates_m* = 2,1 ") != std::string::npos);
  const Run json = run("parameters --json", false);
  CHECK(json.status == 0);
  CHECK(json.out.find("{\"name\": \"k\", \"value\": \"10\", \"meaning\": ") != std::string::npos);
  CHECK(run("parameters --markdown", false).out.find("| `k` | 10 | ") != std::string::npos);

  const std::string dir = areamatch_test::temp_dir() + "/set_option";
  REQUIRE(run("generate " + dir + " --seed 6 --width 16 --height 12").status == 0);
  const std::string pair = dir + "/robot.yaml " + dir + "/layout.yaml";
  const Run plain = run("match " + pair + " --json --threads 1", false);
  const Run same = run("match " + pair + " --json --threads 1 --set k=10 --set allow_reflection=false", false);
  const Run named = run("match " + pair + " --json --threads 1 --k 4 --min-agreement 0.5", false);
  const Run set = run("match " + pair + " --json --threads 1 --set k=4 --set decision.min_agreement=0.5", false);
  auto without_times = [](std::string text) {
    std::string out;
    std::istringstream lines(text);
    for (std::string item; std::getline(lines, item, ',');) {
      if (item.find("_s\"") == std::string::npos) out += item + ",";
    }
    return out;
  };
  CHECK(without_times(plain.out) == without_times(same.out));
  CHECK(without_times(named.out) == without_times(set.out));  // --k and --set k are one setting
  const Run door = run("segment " + dir + "/layout.yaml --set rooms.door_width_m=0.6", false);
  const Run door_named = run("segment " + dir + "/layout.yaml --door-width 0.6", false);
  CHECK(door.status == 0);
  CHECK(door.out.substr(0, door.out.find("covered")) == door_named.out.substr(0, door_named.out.find("covered")));

  // (no structured binding: clang will not capture one in CHECK_MESSAGE)
  for (const auto& bad : {std::pair<std::string, std::string>{"--set k", "--set takes NAME=VALUE, got 'k'"},
                          {"--set decision.min_agrement=0.9", "did you mean decision.min_agreement?"},
                          {"--set k=ten", "parameter k must be a number, got 'ten'"},
                          {"--set coarse_cell_m=0", "coarse_cell_m"}}) {
    const Run r = run("match " + pair + " " + bad.first);
    CHECK_MESSAGE(r.status == 2, bad.first);
    CHECK_MESSAGE(r.out.find(bad.second) != std::string::npos, r.out);
  }
  const Run segment_matching = run("segment " + dir + "/layout.yaml --set k=3");
  CHECK(segment_matching.status == 2);
  CHECK(segment_matching.out.find("a matching setting") != std::string::npos);
  CHECK(run("parameters --json --markdown").status == 2);
}

TEST_CASE("match: bad input and usage exit 2 with a message, no acceptable match exits 1") {
  const std::string dir = areamatch_test::temp_dir() + "/match_bad";
  REQUIRE(run("generate " + dir + " --seed 6 --width 16 --height 12").status == 0);
  const std::string pair = dir + "/robot.yaml " + dir + "/layout.yaml";
  for (const std::string& bad : {std::string("--source-resolution 0"), std::string("--dest-resolution -1"),
                                 std::string("--source-resolution nan"), std::string("--dest-resolution abc"),
                                 std::string("--door-width 1 --source-door-width 1"), std::string("--k 0"),
                                 std::string("--gate-max-lower-walls -1")}) {
    const Run r = run("match " + pair + " " + bad);
    CHECK_MESSAGE(r.status == 2, bad);
    CHECK_MESSAGE(!r.out.empty(), bad);
  }
  CHECK(run("match " + dir + "/robot.yaml").status == 2);
  CHECK(run("match " + dir + "/missing.yaml " + dir + "/layout.yaml").status == 2);
  // A map without free cells (all wall, all unknown, one pixel) is bad input: exit 2 naming the file.
  areamatch::write_image(dir + "/walls.png", areamatch::GreyImage(40, 40, 255, 0));
  areamatch::write_image(dir + "/unknown.png", areamatch::GreyImage(40, 40, 255, 205));
  areamatch::write_image(dir + "/pixel.png", areamatch::GreyImage(1, 1, 255, 0));
  for (const std::string name : {"walls.png", "unknown.png"}) {
    const Run none = run("match " + dir + "/" + name + " " + dir + "/layout.yaml --json");
    INFO(none.out);
    CHECK(none.status == 2);
    CHECK(none.out.find(name + ": the map has no free cells") != std::string::npos);
  }
  const Run pixel = run("match " + dir + "/layout.yaml " + dir + "/pixel.png");
  INFO(pixel.out);
  CHECK(pixel.status == 2);
  CHECK(pixel.out.find("pixel.png") != std::string::npos);
  // Free space too narrow for any area is still a map: no areas, exit 1, JSON on stdout.
  areamatch::GreyImage slit(40, 40, 255, 0);
  for (int x = 5; x < 35; ++x) slit.values[20 * 40 + x] = 254;  // one cell wide
  areamatch::write_image(dir + "/slit.png", slit);
  const Run none = run("match " + dir + "/slit.png " + dir + "/layout.yaml --json");
  CHECK(none.status == 1);
  CHECK(none.out.find("\"ok\": false") != std::string::npos);
  CHECK(none.out.find("no areas") != std::string::npos);
  // Numbers out of their range, and a typo, name the option.
  // (A plain pair, not a structured binding: clang refuses to capture bindings in INFO's lambda.)
  for (const auto& bad_and_message : std::vector<std::pair<std::string, std::string>>{
           {"--door-width 1e308", "--door-width must be at most 20 m"},
           {"--source-resolution 1e-9", "robot.yaml: resolution 1e-09 m per cell is finer than areamatch::min_resolution_m"},
           {"--min-agreement 5", "--min-agreement must be in [0, 1]"},
           {"--min-p-correct -0.1", "--min-p-correct must be in [0, 1]"},
           {"--min-score 1.5", "--min-score must be in [0, 1]"},
           {"--alow-reflection", "unknown option --alow-reflection (did you mean --allow-reflection?)"}}) {
    const std::string& bad = bad_and_message.first;
    const std::string& message = bad_and_message.second;
    const Run r = run("match " + pair + " " + bad);
    INFO(bad << " -> " << r.out);
    CHECK(r.status == 2);
    CHECK(r.out.find(message) != std::string::npos);
  }
  CHECK(run("match " + pair + " --zzzz").out.find("did you mean") == std::string::npos);
  // Another building's layout, which the model doubts: at --min-agreement 0 the agreement accepts
  // it alone only where the lower wall agreement is at most --gate-max-lower-walls (0: nowhere; above
  // 1: always).
  const std::string other = areamatch_test::temp_dir() + "/match_bad_other";
  REQUIRE(run("generate " + other + " --seed 1234 --width 24 --height 26").status == 0);
  const std::string cross = dir + "/robot.yaml " + other + "/layout.yaml --min-agreement 0";
  const Run gated = run("match " + cross + " --gate-max-lower-walls 0");
  CHECK(gated.status == 1);
  CHECK(gated.out.find("gate_max_lower_walls") != std::string::npos);
  // The maps agree but the gate stays closed: "not sure", never "not the same building", and what
  // to try when the user knows better.
  CHECK(gated.out.find("no acceptable match: not sure: the maps agree") != std::string::npos);
  CHECK(gated.out.find("not the same building") == std::string::npos);
  CHECK(gated.out.find("--same-building") != std::string::npos);
  CHECK(run("match " + cross + " --gate-max-lower-walls 0 --json").out.find("\"rejection\": \"not sure\"") != std::string::npos);
  const Run by_agreement = run("match " + cross + " --gate-max-lower-walls 2");
  CHECK(by_agreement.status == 0);
  CHECK(by_agreement.out.find("accepted by the agreement: agreement ") != std::string::npos);
  CHECK(by_agreement.out.find("the model alone would not have accepted it") != std::string::npos);
}

TEST_CASE("warp: points carried across line for line, a resampled map, JSON; bad input exits 2, no match exits 1") {
  const std::string dir = areamatch_test::temp_dir() + "/warp_pair";
  REQUIRE(run("generate " + dir + " --seed 7 --width 18 --height 13 --rotation 30").status == 0);
  const std::string pair = dir + "/robot.yaml " + dir + "/layout.yaml";
  const std::string points = dir + "/points.csv";
  areamatch::detail::write_file_text(points, "# col,row\n10,12\n\n 40.5 , 33\n");
  const Run carried = run("warp " + pair + " --points " + points + " --out " + dir + "/out.csv --grid " + dir + "/onto.yaml");
  INFO(carried.out);
  REQUIRE(carried.status == 0);
  CHECK(carried.out.find("under the warp") != std::string::npos);
  std::istringstream lines(read_text(dir + "/out.csv"));
  std::vector<std::string> out;
  for (std::string line; std::getline(lines, line);) out.push_back(line);
  REQUIRE(out.size() == 4);  // one line per input line
  CHECK(out[0] == "# col,row");
  CHECK(out[2].empty());
  CHECK(std::count(out[1].begin(), out[1].end(), ',') == 1);
  CHECK(std::count(out[3].begin(), out[3].end(), ',') == 1);
  const Run info = run("info " + dir + "/onto.yaml --json");
  CHECK(info.status == 0);
  const Run layout_info = run("info " + dir + "/layout.yaml --json");
  auto field = [](const std::string& json, const std::string& key) {
    const auto at = json.find("\"" + key + "\": ");
    return at == std::string::npos ? std::string() : json.substr(at, json.find_first_of(",}", at) - at);
  };
  CHECK(field(info.out, "width") == field(layout_info.out, "width"));
  CHECK(field(info.out, "height") == field(layout_info.out, "height"));
  // JSON: the match, the warp's figures and the points, exactly one object.
  const Run json = run("warp " + pair + " --points " + points + " --json", false);
  REQUIRE(json.status == 0);
  CHECK(json.out.rfind("{\"match\": {\"ok\": true", 0) == 0);
  CHECK(json.out.find('\n') == json.out.size() - 1);
  for (const char* key : {"\"warp\"", "\"rigid_median_m\"", "\"warped_median_m\"", "\"max_displacement_m\"", "\"points\": [["}) {
    CHECK_MESSAGE(json.out.find(key) != std::string::npos, key);
  }
  // Bad input: exit 2, the problem named.
  areamatch::detail::write_file_text(dir + "/bad.csv", "10,12\n10;twelve\n");
  const Run malformed = run("warp " + pair + " --points " + dir + "/bad.csv");
  CHECK(malformed.status == 2);
  CHECK(malformed.out.find("bad.csv:2") != std::string::npos);
  areamatch::detail::write_file_text(dir + "/outside.csv", "100000,5\n");
  const Run outside = run("warp " + pair + " --points " + dir + "/outside.csv");
  CHECK(outside.status == 2);
  CHECK(outside.out.find("outside SOURCE") != std::string::npos);
  const Run missing = run("warp " + pair + " --points " + dir + "/missing.csv");
  CHECK(missing.status == 2);
  CHECK(missing.out.find("missing.csv") != std::string::npos);
  CHECK(run("warp " + pair + " --out " + dir + "/x.csv").status == 2);  // --out without --points
  CHECK(run("warp " + pair + " --bend-length 0").status == 2);
  CHECK(run("warp " + pair + " --control-spacing -1").status == 2);
  // A pair that does not match (another building's layout): exit 1, nothing warped (never a
  // silent identity warp).
  const std::string other = areamatch_test::temp_dir() + "/warp_other";
  REQUIRE(run("generate " + other + " --seed 1234 --width 24 --height 26").status == 0);
  const Run refused = run("warp " + dir + "/robot.yaml " + other + "/layout.yaml --points " + points + " --out " + dir +
                          "/refused.csv");
  CHECK(refused.status == 1);
  CHECK(refused.out.find("nothing warped") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir + "/refused.csv"));
}

TEST_CASE("assess: a report, a picture, JSON; a map that cannot be placed exits 1 unless --same-building; bad input exits 2") {
  const std::string dir = areamatch_test::temp_dir() + "/assess_pair";
  REQUIRE(run("generate " + dir + " --seed 9 --width 20 --height 14 --rotation 50 --explored 0.7").status == 0);
  const std::string pair = dir + "/robot.yaml " + dir + "/layout.yaml";
  const Run report = run("assess " + pair + " --png " + dir + "/assess.png", false);
  INFO(report.out);
  REQUIRE(report.status == 0);
  for (const char* part : {"wall error under the rigid answer", "wall error under the warp", "brokenness: 0 broken pieces",
                           "coverage:", "topology:"}) {
    CHECK_MESSAGE(report.out.find(part) != std::string::npos, part);
  }
  CHECK(std::filesystem::file_size(dir + "/assess.png") > 0);
  const Run json = run("assess " + pair + " --json", false);
  REQUIRE(json.status == 0);
  CHECK(json.out.rfind("{\"ok\": true", 0) == 0);
  CHECK(json.out.find('\n') == json.out.size() - 1);
  for (const char* key : {"\"rigid_walls\"", "\"brokenness\"", "\"coverage\"", "\"topology\"", "\"area_displacement\""}) {
    CHECK_MESSAGE(json.out.find(key) != std::string::npos, key);
  }
  // Another building: not placed, exit 1 with the reason and the way out; --same-building assesses it anyway.
  const std::string other = areamatch_test::temp_dir() + "/assess_other";
  REQUIRE(run("generate " + other + " --seed 1234 --width 24 --height 26").status == 0);
  const std::string cross = dir + "/robot.yaml " + other + "/layout.yaml";
  const Run refused = run("assess " + cross);
  CHECK(refused.status == 1);
  CHECK(refused.out.find("could not be placed") != std::string::npos);
  const Run forced = run("assess " + cross + " --same-building");
  CHECK(forced.status == 0);
  CHECK(forced.out.find("assessed because of --same-building") != std::string::npos);
  // Bad input: exit 2, the problem named.
  const Run missing = run("assess " + dir + "/missing.yaml " + dir + "/layout.yaml");
  CHECK(missing.status == 2);
  CHECK(missing.out.find("missing.yaml") != std::string::npos);
  CHECK(run("assess " + pair + " --error-scale 0").status == 2);
  CHECK(run("assess " + pair + " --bend-length -2").status == 2);
  CHECK(run("assess " + pair + " --estimate-scale").status == 2);
  CHECK(run("assess " + dir + "/robot.yaml").status == 2);
}

TEST_CASE("eval: a generated manifest, its report files, repeat, no ground truth") {
  const std::string dir = areamatch_test::temp_dir() + "/eval_pair";
  REQUIRE(run("generate " + dir + " --seed 5 --width 18 --height 12 --rotation 75").status == 0);
  const std::string out = areamatch_test::temp_dir() + "/eval_out";
  const Run eval = run("eval " + dir + "/pairs.json --out " + out + " --repeat 2", /*stderr_too=*/false);
  INFO(eval.out);
  REQUIRE(eval.status == 0);
  CHECK(eval.out.find("synthetic_5") != std::string::npos);
  CHECK(eval.out.find("correct: 1 / 1") != std::string::npos);
  CHECK(eval.out.find("NOT REPEATABLE") == std::string::npos);
  for (const char* file : {"report.md", "results.json", "results.csv", "pairs/001_synthetic_5.png"}) {
    CHECK_MESSAGE(areamatch::detail::read_file_bytes(out + "/" + file).size() > 0, file);
  }
  const std::string report = read_text(out + "/report.md");
  CHECK(report.find("![synthetic_5](pairs/001_synthetic_5.png)") != std::string::npos);
  const std::string csv = read_text(out + "/results.csv");
  CHECK(csv.find("\nsynthetic_5,synthetic,") != std::string::npos);
  CHECK(csv.find(",p_correct,") != std::string::npos);
  CHECK(csv.find(",transform_correct,") != std::string::npos);
  CHECK(read_text(out + "/results.json").find("\"correct_non_ambiguous\": 1") != std::string::npos);

  // The same pair without ground truth: transforms and times only.
  std::string manifest = read_text(dir + "/pairs.json");
  const auto truth = manifest.find(",\n   \"ground_truth\"");
  REQUIRE(truth != std::string::npos);
  manifest = manifest.substr(0, truth) + "\n  }\n ]\n}\n";
  areamatch_test::write_bytes(dir + "/no_truth.json", manifest);
  const Run plain = run("eval " + dir + "/no_truth.json", false);
  INFO(plain.out);
  CHECK(plain.status == 0);
  CHECK(plain.out.find("no ground truth") != std::string::npos);
}

TEST_CASE("eval --cross-buildings: the maps of different generated buildings are rejected") {
  const std::string dir = areamatch_test::temp_dir() + "/eval_cross";
  REQUIRE(run("generate " + dir + " --count 2 --seed 40 --width 15 --height 11").status == 0);
  const std::string out = areamatch_test::temp_dir() + "/eval_cross_out";
  const Run eval = run("eval " + dir + "/pairs.json --cross-buildings --out " + out, false);
  INFO(eval.out);
  REQUIRE(eval.status == 0);
  // 2 buildings of 2 maps each: 2 true pairs and 4 pairs of different buildings.
  CHECK(eval.out.find("pairs of one building accepted: 2 / 2") != std::string::npos);
  CHECK(eval.out.find("pairs of different buildings rejected: 4 / 4") != std::string::npos);
  CHECK(eval.out.find("pair_40/robot x pair_41/layout (different)") != std::string::npos);
  const std::string csv = read_text(out + "/results.csv");
  CHECK(csv.find(",different_buildings,") != std::string::npos);
  CHECK(csv.find(",agreement,") != std::string::npos);
  CHECK(read_text(out + "/results.json").find("\"different_rejected\": 4") != std::string::npos);
}

TEST_CASE("calibrate: fits the decision on eval results, cross-validated by building; bad input exits 2") {
  const std::string dir = areamatch_test::temp_dir() + "/calibrate";
  REQUIRE(run("generate " + dir + " --count 4 --seed 70 --width 15 --height 11").status == 0);
  const std::string out = areamatch_test::temp_dir() + "/calibrate_out";
  REQUIRE(run("eval " + dir + "/pairs.json --cross-buildings --out " + out, false).status == 0);
  const Run fit = run("calibrate " + out + "/results.csv --svg " + out + "/reliability.svg --predictions " + out +
                          "/predictions.csv",
                      false);
  INFO(fit.out);
  CHECK(fit.status == 0);
  CHECK(fit.out.find("4 buildings") != std::string::npos);
  CHECK(fit.out.find("total (cross-validated)") != std::string::npos);
  CHECK(fit.out.find("fitted on all rows: bias = ") != std::string::npos);
  // A header and one line per row: 4 pairs of one building, 24 of two.
  const std::string predictions = read_text(out + "/predictions.csv");
  CHECK(predictions.rfind("name,source,destination,source_building,dest_building,different_buildings,right,", 0) == 0);
  CHECK(std::count(predictions.begin(), predictions.end(), '\n') == 29);
  // The thresholds chosen from data, the choice itself cross-validated (nested).
  const Run chosen = run("calibrate " + out + "/results.csv --choose-rule --max-false-accept 0.01", false);
  INFO(chosen.out);
  CHECK(chosen.status == 0);
  CHECK(chosen.out.find("rule chosen on all rows") != std::string::npos);
  CHECK(chosen.out.find("rules chosen in the 4 folds") != std::string::npos);
  CHECK(chosen.out.find("total (nested cross-validation) | ") != std::string::npos);
  CHECK(chosen.out.find(", lower walls ") != std::string::npos);
  const Run always = run("calibrate " + out + "/results.csv --gate-max-lower-walls 2", false);
  CHECK(always.status == 0);
  CHECK(always.out.find("with lower wall agreement <= 2 (above it: occupied walls >= 0.85 and margin >= 0.007), or "
                        "p_correct >= 0.85") != std::string::npos);
  const Run off = run("calibrate " + out + "/results.csv --gate-both-ways-occupied 2 --gate-both-ways-margin 0.01", false);
  CHECK(off.status == 0);
  CHECK(off.out.find("(above it: occupied walls >= 2 and margin >= 0.01)") != std::string::npos);
  // Simulated maps' rows choose the gate's both-ways part and are judged building by building
  // (here the same generated rows stand in for them).
  const Run both_ways = run("calibrate " + out + "/results.csv --simulated " + out + "/results.csv", false);
  INFO(both_ways.out);
  CHECK(both_ways.status == 0);
  CHECK(both_ways.out.find("the gate's both-ways part chosen on the generated and simulated rows") != std::string::npos);
  CHECK(both_ways.out.find("\ntotal | | 3 | ") != std::string::npos);  // its 3 right answers
  CHECK(run("calibrate " + out + "/results.csv --simulated " + out + "/missing.csv").status == 2);
  CHECK(run("calibrate " + out + "/results.csv --choose-rule --max-false-accept 2").status == 2);
  CHECK(run("calibrate " + out + "/results.csv --choose-on real").out.find("--choose-on needs --choose-rule") != std::string::npos);
  CHECK(run("calibrate " + out + "/results.csv --choose-rule --choose-on some").status == 2);
  CHECK(read_text(out + "/reliability.svg").find("<svg") != std::string::npos);
  CHECK(run("calibrate " + out + "/missing.csv").status == 2);
  CHECK(run("calibrate").status == 2);
  areamatch_test::write_bytes(out + "/bad.csv", "name,kind\na,b\n");
  const Run bad = run("calibrate " + out + "/bad.csv");
  CHECK(bad.status == 2);
  CHECK(bad.out.find("no column") != std::string::npos);
  // A number column holding text: bad input (exit 2, naming the line and column), not an internal error (3).
  {
    const std::string results = read_text(out + "/results.csv");
    const std::string header = results.substr(0, results.find('\n'));
    std::string row, separator;
    std::stringstream names(header);
    for (std::string name; std::getline(names, name, ',');) {
      const std::string field = name == "name" ? "a" : name == "different_buildings" ? "true" : name == "free_iou" ? "lots"
                              : name == "failure" || name == "transform_correct" || name == "reason" ? "" : "0";
      row += separator + field;
      separator = ",";
    }
    areamatch_test::write_bytes(out + "/text.csv", header + "\n" + row + "\n");
    const Run text = run("calibrate " + out + "/text.csv");
    CHECK(text.status == 2);
    CHECK_MESSAGE(text.out.find("text.csv:2: column 'free_iou' holds 'lots', not a number") != std::string::npos, text.out);
  }
  // Only pairs of one building: nothing to tell right from wrong by.
  REQUIRE(run("eval " + dir + "/pairs.json --out " + out + "/same", false).status == 0);
  const Run one_sided = run("calibrate " + out + "/same/results.csv");
  CHECK(one_sided.status == 2);
  CHECK(one_sided.out.find("right and wrong examples") != std::string::npos);
}

TEST_CASE("calibrate: real buildings judge, generated ones only train; rates per real building and per modality") {
  // Four generated buildings; the manifest calls two of them real SLAM-to-layout pairs (the kind
  // is what tells calibrate a real building from a generated one).
  const std::string dir = areamatch_test::temp_dir() + "/calibrate_real";
  REQUIRE(run("generate " + dir + " --count 4 --seed 90 --width 15 --height 11").status == 0);
  std::string manifest = read_text(dir + "/pairs.json");
  for (int k = 0; k < 2; ++k) {
    const auto at = manifest.find("\"kind\": \"synthetic\"");
    REQUIRE(at != std::string::npos);
    manifest.replace(at, std::string("\"kind\": \"synthetic\"").size(), "\"kind\": \"slam_to_layout\"");
  }
  areamatch_test::write_bytes(dir + "/pairs.json", manifest);
  const std::string out = areamatch_test::temp_dir() + "/calibrate_real_out";
  REQUIRE(run("eval " + dir + "/pairs.json --cross-buildings --out " + out, false).status == 0);
  const Run fit = run("calibrate " + out + "/results.csv", false);
  INFO(fit.out);
  REQUIRE(fit.status == 0);
  CHECK(fit.out.find("4 buildings (2 real, which judge; the others generated, which only train)") != std::string::npos);
  CHECK(fit.out.find("leave-one-building-out, real buildings:") != std::string::npos);
  CHECK(fit.out.find(" (generated) | ") != std::string::npos);
  // Each side's own pairs (right or wrong answers of one building: 2 each) and its pairs of
  // different buildings (the 4 maps of the two real buildings, each combination once: 4).
  auto counts = [&](const std::string& title) {
    const auto at = fit.out.find("\n" + title + " | ");
    REQUIRE_MESSAGE(at != std::string::npos, title);
    // The fields after the title: right | false rejects (%) | wrong | accepted | different | accepted (%).
    const std::string rest = fit.out.substr(at + title.size() + 4, fit.out.find('\n', at + 1) - at - title.size() - 4);
    std::vector<std::size_t> fields;
    std::istringstream cells(rest);
    for (std::string cell; std::getline(cells, cell, '|');) fields.push_back(std::stoul(cell));
    REQUIRE(fields.size() == 6);
    return std::array<std::size_t, 2>{fields[0] + fields[2], fields[4]};
  };
  CHECK(counts("total, real buildings") == std::array<std::size_t, 2>{2, 4});
  CHECK(counts("total, generated buildings (they train, they do not judge)") == std::array<std::size_t, 2>{2, 20});
  CHECK(counts("SLAM map -> layout")[0] == 2);
  const Run chosen = run("calibrate " + out + "/results.csv --choose-rule --max-false-accept 0.01", false);
  INFO(chosen.out);
  REQUIRE(chosen.status == 0);
  CHECK(chosen.out.find("rules chosen in the 2 folds") != std::string::npos);  // one per real building
  CHECK(chosen.out.find("nested leave-one-building-out (model and thresholds chosen without the building), real buildings:") !=
        std::string::npos);
}

TEST_CASE("generate --style handheld: a partial scan onto a line-drawn layout, matched") {
  const std::string dir = areamatch_test::temp_dir() + "/handheld";
  REQUIRE(run("generate " + dir + " --style handheld --seed 3 --width 20 --height 14").status == 0);
  CHECK(read_text(dir + "/pairs.json").find("\"door_width_m\": 1,") != std::string::npos);
  CHECK(read_text(dir + "/robot.yaml").find("resolution: 0.02") != std::string::npos);
  const Run eval = run("eval " + dir + "/pairs.json --no-reflection", false);
  INFO(eval.out);
  CHECK(eval.out.find("correct: 1 / 1") != std::string::npos);
  CHECK(run("generate " + dir + " --style sonar").status == 2);  // lidar is a style since 2026-12-04
}

TEST_CASE("eval: bad manifests exit 2 naming the pair and field") {
  const std::string dir = areamatch_test::temp_dir() + "/eval_bad";
  REQUIRE(run("generate " + dir + " --seed 2 --width 12 --height 10").status == 0);
  auto eval_of = [&](const std::string& name, const std::string& text) {
    areamatch_test::write_bytes(dir + "/" + name, text);
    return run("eval " + dir + "/" + name);
  };
  const std::string ok_pair = R"({"name": "a", "source": "robot.yaml", "destination": "layout.yaml"})";
  const std::string truth = R"("ground_truth": {"pixel_transform": [[1, 0, 0], [0, 1, 0]]})";
  const struct {
    const char* file;
    std::string text;
    const char* message;
  } cases[] = {
      {"missing_file.json", R"({"pairs": [{"name": "a", "source": "nope.yaml", "destination": "layout.yaml"}]})",
       "pair 'a': source"},
      {"number_type.json", R"({"pairs": [{"name": "a", "source": "robot.yaml", "destination": "layout.yaml", "door_width_m": "wide"}]})",
       "pair 'a': door_width_m must be a number"},
      {"bool_type.json", R"({"pairs": [{"name": "a", "source": "robot.yaml", "destination": "layout.yaml", "ambiguous": 3}]})",
       "pair 'a': ambiguous must be true or false"},
      {"name_type.json", R"({"pairs": [{"name": ["a"], "source": "robot.yaml", "destination": "layout.yaml"}]})",
       "pair 0: name must be a string"},
      {"missing_truth.json", R"({"pairs": [{"name": "a", "source": "robot.yaml", "destination": "layout.yaml", )" + truth +
                                 "}, " + R"({"name": "b", "source": "robot.yaml", "destination": "layout.yaml"}]})",
       "pair 'b': ground_truth missing"},
      {"duplicate.json", "{\"pairs\": [" + ok_pair + ", " + ok_pair + "]}", "pair 'a': duplicate pair name"},
      {"not_json.json", "{\"pairs\": [", "not valid JSON"},
      {"empty.json", "{\"pairs\": []}", "\"pairs\" is empty"},
      {"bad_resolution.json", R"({"pairs": [{"name": "a", "source": "robot.yaml", "destination": "layout.yaml", "source_resolution": -1}]})",
       "pair 'a': source_resolution must be positive"},
      {"different_type.json", R"({"pairs": [{"name": "a", "source": "robot.yaml", "destination": "layout.yaml", "different_buildings": 3}]})",
       "pair 'a': different_buildings must be true or false"},
  };
  for (const auto& c : cases) {
    const Run r = eval_of(c.file, c.text);
    INFO(c.file << ": " << r.out);
    CHECK(r.status == 2);
    CHECK(r.out.find(c.message) != std::string::npos);
  }
  const Run missing = run("eval " + dir + "/no_such_manifest.json");
  CHECK(missing.status == 2);
  CHECK(missing.out.find("cannot read manifest") != std::string::npos);
  const Run unknown_pair = run("eval " + dir + "/pairs.json --only nobody");
  CHECK(unknown_pair.status == 2);
  CHECK(unknown_pair.out.find("no pair named 'nobody'") != std::string::npos);

  // A corrupt map: the pair is reported as an error, the exit status is 2.
  areamatch_test::write_bytes(dir + "/corrupt.png", "not an image");
  const Run corrupt = eval_of("corrupt.json", R"({"pairs": [{"name": "a", "source": "corrupt.png", "destination": "layout.yaml"}]})");
  CHECK(corrupt.status == 2);
  CHECK(corrupt.out.find("error in a:") != std::string::npos);
}

TEST_CASE("the same pair matched by 20 processes gives bit-identical JSON (timings aside)") {
  const std::string dir = areamatch_test::temp_dir() + "/determinism";
  REQUIRE(run("generate " + dir + " --seed 9 --width 20 --height 14 --rotation 200 --mirror").status == 0);
  auto without_timings = [](std::string json) {
    const auto at = json.find(", \"timings\": {");
    return at == std::string::npos ? json : json.substr(0, at);
  };
  const std::string command = "match " + dir + "/robot.yaml " + dir + "/layout.yaml --allow-reflection --json";
  const Run first = run(command, false);
  REQUIRE(first.status == 0);
  const std::string expected = without_timings(first.out);
  CHECK(expected.find("\"pixel_transform\"") != std::string::npos);
  for (int i = 1, n = areamatch_test::quick_tests() ? 3 : 20; i < n; ++i) CHECK(without_timings(run(command, false).out) == expected);
  // The two maps loaded, segmented and prepared side by side or one after the other: the same.
  for (const char* threads : {" --threads 1", " --threads 2", " --threads 0"}) {
    CHECK(without_timings(run(command + threads, false).out) == expected);
  }
}

TEST_CASE("merge: maps of one building placed and fused, JSON, a merged map that info reads back; bad input") {
  const std::string dir = areamatch_test::temp_dir() + "/merge";
  REQUIRE(run("generate " + dir + "/a --seed 7 --width 18 --height 13 --rotation 60").status == 0);
  REQUIRE(run("generate " + dir + "/b --seed 8 --width 18 --height 13").status == 0);
  const std::string maps = dir + "/a/layout.yaml " + dir + "/a/robot.yaml";
  // --out into folders that do not exist yet: made before the work.
  const Run json = run("merge " + maps + " --json --out " + dir + "/new/folder/merged.yaml --png " + dir + "/merged.png", false);
  INFO(json.out);
  CHECK(json.status == 0);
  CHECK(json.out.rfind("{\"ok\": true, \"reference\": \"" + dir + "/a/layout.yaml\"", 0) == 0);
  CHECK(json.out.find('\n') == json.out.size() - 1);
  for (const char* key : {"\"placed\": true", "\"pixel_transform\"", "\"rotation_deg\"", "\"translation_m\"", "\"scale\"",
                          "\"reflected\"", "\"residual_m\"", "\"edges\"", "\"from\"", "\"to\"", "\"p_correct\"", "\"used\": true",
                          "\"timings\"", "\"prepare_s\"", "\"refine_s\"", "\"merge_s\""}) {
    CHECK_MESSAGE(json.out.find(key) != std::string::npos, key);
  }
  const areamatch::OccupancyGrid merged = areamatch::load_map(dir + "/new/folder/merged.yaml");
  CHECK(json.out.find("\"merged\": {\"width\": " + std::to_string(merged.width()) + ", \"height\": " +
                      std::to_string(merged.height())) != std::string::npos);
  const Run info = run("info " + dir + "/new/folder/merged.yaml");
  CHECK(info.status == 0);
  CHECK(info.out.find(std::to_string(merged.width()) + " x " + std::to_string(merged.height())) != std::string::npos);
  CHECK(areamatch::detail::read_file_bytes(dir + "/merged.png").size() > 0);
  // Saved and loaded again: the same grid (what map_server would load).
  areamatch::save_map(merged, dir + "/again.pgm");
  CHECK(areamatch::load_map(dir + "/again.yaml") == merged);

  const Run one_thread = run("merge " + maps + " --json --threads 1", false);
  CHECK(one_thread.out.substr(0, one_thread.out.find("\"timings\"")) == json.out.substr(0, json.out.find("\"timings\"")));
  const Run as_matched = run("merge " + maps + " --json --no-same-side", false);
  CHECK(as_matched.status == 0);
  CHECK(as_matched.out.find("\"refine_s\": 0,") != std::string::npos);
  const Run text = run("merge " + maps + " --reference " + dir + "/a/robot.yaml");
  CHECK(text.status == 0);
  CHECK(text.out.find("placed 2 of 2 maps in the frame of " + dir + "/a/robot.yaml") != std::string::npos);
  CHECK(text.out.find(" doubled (") != std::string::npos);
  CHECK(text.out.find("drawn in #") == std::string::npos);  // colours are named only for a picture
  const Run drawn = run("merge " + maps + " --png " + dir + "/drawn.png");
  CHECK(drawn.out.find("layout.yaml: rotation 0.00 deg") != std::string::npos);
  CHECK(drawn.out.find(", drawn in #e61717\n") != std::string::npos);  // map 0's colour (map_color), named for the legend
  CHECK(drawn.out.find(", drawn in #" + std::string("0f9937") + "\n") != std::string::npos);
  CHECK(json.out.find("\"doubled_wall_cells\"") != std::string::npos);
  // --non-rigid: the robot map bent onto the layout, its warp's figures in the JSON.
  const Run bent = run("merge " + maps + " --json --non-rigid --bend-length 5 --png " + dir + "/bent.png", false);
  CHECK(bent.status == 0);
  for (const char* key : {"\"warp\": {", "\"warped_median_m\"", "\"warp_s\""}) CHECK_MESSAGE(bent.out.find(key) != std::string::npos, key);
  const Run bent_text = run("merge " + maps + " --non-rigid");
  CHECK(bent_text.out.find("; warp: walls ") != std::string::npos);

  // Maps of different buildings only: listed as not placed, exit 1.
  const Run strangers = run("merge " + dir + "/a/layout.yaml " + dir + "/b/robot.yaml");
  CHECK(strangers.status == 1);
  CHECK(strangers.out.find(dir + "/b/robot.yaml not placed: no accepted match") != std::string::npos);
  // An all-unknown map: not placed, with the reason.
  areamatch::save_map(areamatch::OccupancyGrid(120, 90, 0.05), dir + "/unknown.pgm");
  const Run unknown = run("merge " + maps + " " + dir + "/unknown.yaml");
  CHECK(unknown.status == 1);
  CHECK(unknown.out.find("unknown.yaml not placed") != std::string::npos);
  CHECK(unknown.out.find("no areas") != std::string::npos);

  for (const auto& bad_input : std::vector<std::pair<std::string, std::string>>{
           {dir + "/a/layout.yaml", "at least two maps"},
           {maps + " " + dir + "/a/../a/robot.yaml", "is given twice"},
           {maps + " --reference " + dir + "/b/robot.yaml", "not one of the maps"},
           {maps + " --wall-share 2", "--wall-share must be in (0, 1]"},
           {maps + " --gate-max-lower-walls -1", "--gate-max-lower-walls must not be negative"},
           {maps + " --out " + dir + "/merged.pgm", "must name a .yaml file"},
           {maps + " --bend-length 3", "give --non-rigid too"},
           {maps + " --non-rigid --control-spacing 0", "--control-spacing"},
           // One meaning per flag name: --resolution is an input's cell size elsewhere.
           {maps + " --resolution 0.1", "the merged map's is --merged-resolution"},
           {maps + " --merged-resolution 0", "--merged-resolution must be positive"},
           {maps + " " + dir + "/missing.yaml", "missing.yaml"}}) {
    const std::string& arguments = bad_input.first;  // not a structured binding: the checks' lambdas capture it
    const std::string& message = bad_input.second;
    const Run bad = run("merge " + arguments);
    CHECK_MESSAGE(bad.status == 2, arguments);
    CHECK_MESSAGE(bad.out.find(message) != std::string::npos, bad.out);
  }
}

TEST_CASE("simulate and generate --style lidar: simulated SLAM maps with ground truth that eval scores; bad input exits 2") {
  const std::string dir = areamatch_test::temp_dir() + "/simulate";
  REQUIRE(run("generate " + dir + "/plan --seed 920 --width 18 --height 12").status == 0);
  const Run simulated = run("simulate " + dir + "/plan/layout.yaml " + dir + "/sim --count 2 --seed 3 --beams 271 --door-width 0.9");
  INFO(simulated.out);
  REQUIRE(simulated.status == 0);
  CHECK(simulated.out.find("wrote " + dir + "/sim/slam_4.png") != std::string::npos);
  const std::string manifest = read_text(dir + "/sim/pairs.json");
  CHECK(manifest.find("\"kind\": \"synthetic_lidar\"") != std::string::npos);
  CHECK(manifest.find("\"door_width_m\": 0.9") != std::string::npos);
  const Run eval = run("eval " + dir + "/sim/pairs.json", false);
  INFO(eval.out);
  CHECK(eval.status == 0);
  CHECK(eval.out.find("correct: ") != std::string::npos);
  // The same seed, the same map.
  REQUIRE(run("simulate " + dir + "/plan/layout.yaml " + dir + "/again --seed 3 --beams 271 --rotation 24.5").status == 0);
  REQUIRE(run("simulate " + dir + "/plan/layout.yaml " + dir + "/again2 --seed 3 --beams 271 --rotation 24.5").status == 0);
  CHECK(read_text(dir + "/again/slam_3.png") == read_text(dir + "/again2/slam_3.png"));
  const Run lidar = run("generate " + dir + "/lidar --seed 921 --width 18 --height 12 --style lidar --beams 271 --mirror");
  INFO(lidar.out);
  REQUIRE(lidar.status == 0);
  CHECK(read_text(dir + "/lidar/pairs.json").find("\"reflected\": true") != std::string::npos);
  // Bad input: each exits 2 with the option or the reason named.
  const Run fov = run("simulate " + dir + "/plan/layout.yaml " + dir + "/bad --fov 400");
  CHECK(fov.status == 2);
  CHECK(fov.out.find("--fov") != std::string::npos);
  const Run bend = run("simulate " + dir + "/plan/layout.yaml " + dir + "/bad --bend -1");
  CHECK(bend.status == 2);
  CHECK(bend.out.find("--bend") != std::string::npos);
  const Run missing = run("simulate " + dir + "/nothing.yaml " + dir + "/bad");
  CHECK(missing.status == 2);
  CHECK(missing.out.find("nothing.yaml") != std::string::npos);
  areamatch::save_map(areamatch::OccupancyGrid(30, 20, 0.05, {}, areamatch::CellState::occupied), dir + "/walls.pgm");
  const Run walls = run("simulate " + dir + "/walls.yaml " + dir + "/bad");
  CHECK(walls.status == 2);
  CHECK(walls.out.find("no free space wide enough") != std::string::npos);
  const Run not_lidar = run("generate " + dir + "/bad --beams 100");
  CHECK(not_lidar.status == 2);
  CHECK(not_lidar.out.find("--style lidar") != std::string::npos);
  CHECK(run("simulate " + dir + "/plan/layout.yaml").status == 2);
}
