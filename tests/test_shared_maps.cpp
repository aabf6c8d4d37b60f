// Every map of ../shared/maps loads with the right size, resolution and free cells. The expected
// free counts come from OpenCV with the reference scorers' rule (grey >= 240 is free), so this
// also checks that our PNG/PGM decoding and colour averaging agree with them.
// Skipped (exit 77, reported by ctest) when ../shared is not present.
#include <areamatch/io.hpp>

#include <doctest/doctest.h>

#include "test_support.hpp"

using namespace areamatch;

namespace {
struct Expected {
  const char* yaml;
  int width;
  int height;
  double resolution;
  std::size_t free_cells;
};
const Expected kMaps[] = {
    {"Freiburg52_scan.yaml", 643, 354, 0.050000, 142930},
    {"Freiburg52_scan_furnitures_rot58.yaml", 641, 733, 0.050000, 136845},
    {"Freiburg79_scan.yaml", 800, 544, 0.050000, 128193},
    {"Freiburg79_scan_furnitures_rot164_s80.yaml", 736, 595, 0.062500, 78034},
    {"NLB.yaml", 999, 850, 0.050000, 499355},
    {"NLB_furnitures_rot247.yaml", 1173, 1252, 0.050000, 489963},
    {"freiburg_building52.yaml", 543, 292, 0.058334, 92301},
    {"freiburg_building52_rot37.yaml", 609, 560, 0.058334, 92314},
    {"freiburg_building79.yaml", 700, 289, 0.045520, 128963},
    {"freiburg_building79_rot301.yaml", 608, 749, 0.045520, 128934},
    {"lab_b.yaml", 1237, 672, 0.043900, 183725},
    {"lab_b_rot123.yaml", 1237, 1404, 0.043900, 183750},
    {"lab_b_scan.yaml", 974, 365, 0.050000, 172461},
    {"lab_b_scan_furnitures_rot329_s80.yaml", 819, 652, 0.062500, 105380},
    {"lab_ipa.yaml", 864, 768, 0.050000, 121861},
    {"lab_ipa_furnitures_rot17.yaml", 1051, 987, 0.050000, 112729},
    {"map.yaml", 544, 768, 0.050029, 123767},
    {"map_rot211.yaml", 862, 939, 0.050029, 123753},
    {"office_a.yaml", 1194, 685, 0.050000, 611807},
    {"office_a_furnitures_rot98_s80.yaml", 676, 1023, 0.062500, 378080},
    {"office_b.yaml", 1194, 685, 0.050000, 454187},
    {"office_b_furnitures_rot37.yaml", 1366, 1266, 0.050000, 432131},
    {"office_c.yaml", 1683, 965, 0.050000, 510628},
    {"office_c_furnitures_rot123_s80.yaml", 1381, 1550, 0.062500, 295949},
    {"office_d.yaml", 1122, 661, 0.050000, 353199},
    {"office_d_furnitures_rot211.yaml", 1302, 1145, 0.050000, 333710},
    {"office_e.yaml", 1234, 727, 0.050000, 322503},
    {"office_e_furnitures_rot301_s80.yaml", 1007, 1146, 0.062500, 197682},
    {"office_f.yaml", 1234, 689, 0.050000, 371357},
    {"office_f_furnitures_rot58.yaml", 1238, 1412, 0.050000, 345818},
    {"office_g.yaml", 2050, 2314, 0.050000, 1150429},
    {"office_g_furnitures_rot164_s80.yaml", 2087, 2232, 0.062500, 675324},
    {"office_h.yaml", 1030, 1028, 0.050000, 630164},
    {"office_h_furnitures_rot247.yaml", 1349, 1350, 0.050000, 571471},
    {"office_i.yaml", 1650, 2057, 0.050000, 1133112},
    {"office_i_furnitures_rot329_s80.yaml", 1979, 2091, 0.062500, 683250},
};
}  // namespace

TEST_CASE("every shared map loads with the right size, resolution and free cells") {
  const std::string shared = areamatch_test::shared_dir();
  if (shared.empty()) {
    MESSAGE("skipped: no shared maps folder");
    return;
  }
  for (const Expected& e : kMaps) {
    INFO(e.yaml);
    const LoadedMap loaded = load_map_with_image(shared + "/maps/" + e.yaml);
    CHECK(loaded.grid.width() == e.width);
    CHECK(loaded.grid.height() == e.height);
    CHECK(loaded.grid.resolution() == doctest::Approx(e.resolution).epsilon(1e-12));
    const CellCounts counts = loaded.grid.count();
    CHECK(counts.free == e.free_cells);
    CHECK(counts.total() == static_cast<std::size_t>(e.width) * e.height);
  }
}

TEST_CASE("shared maps survive a save/load round trip") {
  const std::string shared = areamatch_test::shared_dir();
  if (shared.empty()) return;
  const std::string dir = areamatch_test::temp_dir();
  for (const char* name : {"map.yaml", "lab_b.yaml", "NLB.yaml"}) {
    const OccupancyGrid grid = load_map(shared + "/maps/" + name);
    const std::string yaml = save_map(grid, dir + "/copy_" + std::string(name) + ".png");
    CHECK(load_map(yaml) == grid);
  }
}
