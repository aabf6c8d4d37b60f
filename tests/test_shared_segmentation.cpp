// Segmentation of the real maps in ../shared/maps: every map segments, and on the layouts with a
// hand-made ground truth the mean room recall and precision reach 0.95 with the default door
// width. Skipped (exit 77) when ../shared is not present.
#include <areamatch/areamatch.hpp>
#include <areamatch/io.hpp>
#include <areamatch/segmentation_score.hpp>

#include <doctest/doctest.h>

#include "test_support.hpp"

#include <dirent.h>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

using namespace areamatch;

namespace {
std::vector<std::string> files_ending_with(const std::string& folder, const std::string& suffix) {
  std::vector<std::string> names;
  if (DIR* dir = ::opendir(folder.c_str())) {
    while (const dirent* entry = ::readdir(dir)) {
      const std::string name = entry->d_name;
      if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
        names.push_back(name);
    }
    ::closedir(dir);
  }
  std::sort(names.begin(), names.end());
  return names;
}
}  // namespace

TEST_CASE("every shared map segments into valid areas") {
  const std::string shared = areamatch_test::shared_dir();
  if (shared.empty()) return;
  const VoronoiSegmenter segmenter;
  for (const auto& name : files_ending_with(shared + "/maps", ".yaml")) {
    INFO(name);
    const AreaGraph graph = segmenter.segment(load_map(shared + "/maps/" + name));
    CHECK(graph.areas.size() >= 3);
    CHECK(graph.covered_fraction > 0.8);
    for (const auto& area : graph.areas) {
      std::string reason;
      CHECK_MESSAGE(bg::is_valid(area.polygon, reason), reason);
    }
  }
}

TEST_CASE("cross-modal consistency over the pairs of pairs.json") {
  // consistency.py's measure. The targets: furnished→layout ≥ 0.90 (asserted) and
  // SLAM→layout ≥ 0.70 (not met yet: printed, see docs/segmentation.md).
  const std::string shared = areamatch_test::shared_dir();
  if (shared.empty()) return;
  const YAML::Node manifest = YAML::LoadFile(shared + "/pairs.json");  // JSON is YAML
  const VoronoiSegmenter default_segmenter;
  std::map<std::string, std::vector<double>> by_kind;
  for (const auto& pair : manifest["pairs"]) {
    VoronoiSegmenter segmenter = default_segmenter;
    if (pair["door_width_m"]) segmenter.params.with_door_width(pair["door_width_m"].as<double>());
    const OccupancyGrid source = load_map(shared + "/" + pair["source"].as<std::string>());
    const OccupancyGrid dest = load_map(shared + "/" + pair["destination"].as<std::string>());
    PixelTransform transform;
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 3; ++j) transform(i, j) = pair["ground_truth"]["pixel_transform"][i][j].as<double>();
    const double share = segmentation_consistency(segmenter.segment(source).labels, source.width(), source.height(),
                                                  segmenter.segment(dest).labels, dest.width(), dest.height(), transform);
    MESSAGE(pair["name"].as<std::string>() << " (" << pair["kind"].as<std::string>() << "): " << share);
    by_kind[pair["kind"].as<std::string>()].push_back(share);
  }
  for (const auto& [kind, values] : by_kind) {
    double mean = 0.0;
    for (double v : values) mean += v / values.size();
    MESSAGE(kind << ": mean consistency " << mean << " over " << values.size() << " pairs");
    if (kind == "furnished_to_layout") CHECK(mean >= 0.90);
  }
}

TEST_CASE("room recall and precision on the layouts with ground truth") {
  const std::string shared = areamatch_test::shared_dir();
  if (shared.empty()) return;
  const VoronoiSegmenter segmenter;
  double recall = 0.0, precision = 0.0;
  int maps = 0;
  for (const auto& gt_name : files_ending_with(shared + "/maps", "_gt_segmentation.png")) {
    const std::string map = gt_name.substr(0, gt_name.size() - std::string("_gt_segmentation.png").size());
    const AreaGraph graph = segmenter.segment(load_map(shared + "/maps/" + map + ".yaml"));
    const auto rooms = rooms_from_image(read_image(shared + "/maps/" + gt_name));
    const SegmentationScore score = score_segmentation(graph.labels, rooms);
    MESSAGE(map << ": recall " << score.recall << ", precision " << score.precision << " (" << score.rooms
                << " rooms, " << score.areas << " areas)");
    recall += score.recall;
    precision += score.precision;
    ++maps;
  }
  REQUIRE(maps > 0);
  MESSAGE("mean over " << maps << " layouts: recall " << recall / maps << ", precision " << precision / maps);
  CHECK(recall / maps >= 0.95);
  CHECK(precision / maps >= 0.95);
}
