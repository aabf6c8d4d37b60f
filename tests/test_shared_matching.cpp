// Every pair of ../shared/pairs.json with the default matcher, its YAML resolutions, the pair's
// door width where given and reflection allowed: correct by the manifest's correct_if, judged
// as shared/tools/score.py judges. Ambiguous pairs are reported, not required. Skipped (exit 77)
// when ../shared is not present.
#include <areamatch/areamatch.hpp>
#include <areamatch/evaluation.hpp>
#include <areamatch/io.hpp>
#include <areamatch/io/evaluate.hpp>

#include <doctest/doctest.h>

#include "test_support.hpp"

using namespace areamatch;

TEST_CASE("every non-ambiguous shared pair is matched correctly") {
  const std::string shared = areamatch_test::shared_dir();
  if (shared.empty()) return;
  const Manifest manifest = load_manifest(shared + "/pairs.json");
  REQUIRE(!manifest.pairs.empty());
  const EvalOptions options;  // reflection allowed, the pair's door width, its YAML resolutions
  for (const ManifestPair& pair : manifest.pairs) {
    REQUIRE(pair.ground_truth);
    const PairEvaluation row = evaluate_pair(pair, manifest.correct_if, options);
    REQUIRE_MESSAGE(row.failure.empty(), row.failure);
    const MatchResult& r = row.result;
    MESSAGE(pair.name << (pair.ambiguous ? " (ambiguous)" : "") << ": " << (row.correct ? "correct" : "WRONG")
                      << ", rotation error " << row.error->rotation_error_deg << " deg, displacement "
                      << row.error->mean_displacement_m << " m, confidence " << r.confidence << ", match "
                      << 1000.0 * r.timings.match_s << " ms");
    if (!pair.ambiguous) CHECK_MESSAGE(row.correct, pair.name);
  }
}

TEST_CASE("pairs of maps of different shared buildings are rejected (every 3rd of the 596)") {
  const std::string shared = areamatch_test::shared_dir();
  if (shared.empty()) return;
  const Manifest manifest = load_manifest(shared + "/pairs.json");
  const std::vector<ManifestPair> cross = cross_building_pairs(manifest);
  CHECK(cross.size() == 596);  // 36 maps of 14 buildings
  const EvalOptions options;
  std::size_t tried = 0, rejected = 0;
  for (std::size_t i = 0; i < cross.size(); i += 3) {
    const PairEvaluation row = evaluate_pair(cross[i], manifest.correct_if, options);
    REQUIRE_MESSAGE(row.failure.empty(), row.failure);
    ++tried;
    rejected += row.correct;
    if (!row.correct) MESSAGE("accepted " << cross[i].name << ": agreement " << row.result.evidence.agreement);
  }
  MESSAGE(rejected << " of " << tried << " pairs of different buildings rejected");
  CHECK(rejected >= tried * 95 / 100);
}

TEST_CASE("the manifest reader refuses bad manifests with the pair and field named") {
  const std::string dir = areamatch_test::temp_dir();
  auto write = [&](const std::string& name, const std::string& text) {
    const std::string path = dir + "/" + name;
    areamatch_test::write_bytes(path, text);
    return path;
  };
  CHECK_THROWS_AS(load_manifest(dir + "/missing.json"), io_error);
  CHECK_THROWS_WITH_AS(load_manifest(write("a.json", "{\"pairs\": 3}")), doctest::Contains("\"pairs\" must be an array"), format_error);
  CHECK_THROWS_WITH_AS(load_manifest(write("b.json", "{\"pairs\": [{\"name\": \"x\", \"source\": \"a.yaml\"}]}")),
                       doctest::Contains("pair 'x': destination"), format_error);
  CHECK_THROWS_WITH_AS(load_manifest(write("c.json", "{\"pairs\": [{\"name\": \"x\", \"source\": \"a\", \"destination\": \"b\"},"
                                                     "{\"name\": \"x\", \"source\": \"a\", \"destination\": \"b\"}]}")),
                       doctest::Contains("duplicate"), format_error);
  CHECK_THROWS_WITH_AS(load_manifest(write("d.json", "{\"pairs\": [{\"name\": \"x\", \"source\": \"a\", \"destination\": \"b\", "
                                                     "\"ground_truth\": {\"pixel_transform\": [[1, 0], [0, 1]]}}]}")),
                       doctest::Contains("pixel_transform"), format_error);
  const Manifest ok = load_manifest(write("e.json", "{\"pairs\": [{\"name\": \"x\", \"source\": \"a.yaml\", \"destination\": \"/abs/b.yaml\"}]}"));
  REQUIRE(ok.pairs.size() == 1);
  CHECK(ok.pairs[0].source == dir + "/a.yaml");
  CHECK(ok.pairs[0].destination == "/abs/b.yaml");
  CHECK_FALSE(ok.pairs[0].ground_truth);
}

TEST_CASE("manifest: different_buildings pairs, and the cross-building pairs of a manifest") {
  const std::string dir = areamatch_test::temp_dir();
  const std::string truth = R"("ground_truth": {"pixel_transform": [[1, 0, 0], [0, 1, 0]]})";
  areamatch_test::write_bytes(dir + "/m.json",
                              R"({"pairs": [{"name": "ab", "source": "a.yaml", "destination": "b.yaml", )" + truth + "},\n" +
                                  R"({"name": "bc", "source": "b.yaml", "destination": "c.png", "destination_resolution": 0.1, )" + truth + "},\n" +
                                  R"({"name": "de", "source": "d/x.yaml", "destination": "e/x.yaml", "door_width_m": 0.9, )" + truth + "},\n" +
                                  R"({"name": "neg", "source": "a.yaml", "destination": "d/x.yaml", "different_buildings": true}]})");
  const Manifest m = load_manifest(dir + "/m.json");  // a different_buildings pair needs no ground truth
  REQUIRE(m.pairs.size() == 4);
  CHECK(m.pairs[3].different_buildings);
  const auto cross = cross_building_pairs(m);
  // Buildings {a, b, c} and {d/x, e/x}: 3 × 2 pairs, named by path without extension.
  REQUIRE(cross.size() == 6);
  CHECK(cross[0].name == "a x d/x");
  CHECK(cross[0].different_buildings);
  CHECK(cross[0].allow_reflection == std::optional<bool>(true));
  bool c_has_its_resolution = false;
  for (const auto& p : cross) {
    if (p.source == dir + "/c.png") c_has_its_resolution = p.source_resolution == std::optional<double>(0.1);
  }
  CHECK(c_has_its_resolution);
  areamatch_test::write_bytes(dir + "/bad.json",
                              R"({"pairs": [{"name": "n", "source": "a", "destination": "b", "different_buildings": true, )" + truth + "}]}");
  CHECK_THROWS_WITH_AS(load_manifest(dir + "/bad.json"), doctest::Contains("different_buildings has no ground_truth"), format_error);
}
