// Every pair of ../shared/pairs.json with the default matcher, its YAML resolutions, the pair's
// door width where given and reflection allowed: correct by the manifest's correct_if, judged
// as shared/tools/score.py judges. Ambiguous pairs are reported, not required. Skipped (exit 77)
// when ../shared is not present. The hand-held scans of ../shared/handheld (a second sensor) are
// judged too, with a leave-one-place-out check of the decision.
#include <areamatch/areamatch.hpp>
#include <areamatch/evaluation.hpp>
#include <areamatch/io.hpp>
#include <areamatch/io/evaluate.hpp>

#include <doctest/doctest.h>

#include "test_support.hpp"

#include <map>
#include <set>
#include <string>
#include <vector>

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

namespace {

/// Maps joined by a pair of one building form one building (as `cross_building_pairs` groups them).
struct Buildings {
  std::map<std::string, std::string> parent;
  std::string find(const std::string& m) {
    if (!parent.count(m)) parent[m] = m;
    std::string r = m;
    while (parent[r] != r) r = parent[r];
    return parent[m] = r;
  }
  void join(const std::string& a, const std::string& b) { parent[find(a)] = find(b); }
};

struct JudgedRow {
  ManifestPair pair;
  PairEvaluation row;
  bool right = false;  ///< the transform is within correct_if (pairs of different buildings: never)
};

/// The shared pairs of different buildings every CI run checks (every 3rd of the 596), judged
/// once per process: the rejection test and the decision's cross-validation both use them.
const std::vector<JudgedRow>& shared_cross_rows(const std::string& shared) {
  static const std::vector<JudgedRow> rows = [&] {
    const Manifest manifest = load_manifest(shared + "/pairs.json");
    const std::vector<ManifestPair> cross = cross_building_pairs(manifest);
    std::vector<JudgedRow> out;
    for (std::size_t i = 0; i < cross.size(); i += 3) {
      out.push_back({cross[i], evaluate_pair(cross[i], manifest.correct_if, EvalOptions{}), false});
    }
    return out;
  }();
  return rows;
}

}  // namespace

TEST_CASE("pairs of maps of different shared buildings are rejected (every 3rd of the 596)") {
  const std::string shared = areamatch_test::shared_dir();
  if (shared.empty()) return;
  const Manifest manifest = load_manifest(shared + "/pairs.json");
  CHECK(cross_building_pairs(manifest).size() == 596);  // 36 maps of 14 buildings
  std::size_t tried = 0, rejected = 0;
  for (const JudgedRow& r : shared_cross_rows(shared)) {
    REQUIRE_MESSAGE(r.row.failure.empty(), r.row.failure);
    ++tried;
    rejected += r.row.correct;
    if (!r.row.correct) MESSAGE("accepted " << r.pair.name << ": agreement " << r.row.result.evidence.agreement);
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


TEST_CASE("hand-held scans: right answers accepted, mirrors and other places refused; the rule fitted without a place judges it") {
  const std::string shared = areamatch_test::shared_dir();
  if (shared.empty()) return;
  if (!areamatch_test::is_dir(shared + "/handheld/maps")) {
    MESSAGE("skipped: no shared/handheld");
    return;
  }
  const Manifest manifest = load_manifest(shared + "/handheld/pairs.json");
  EvalOptions plain;  // the pair's door width, no reflection: nothing in this data is mirrored
  plain.matching.allow_reflection = false;
  const EvalOptions mirrors;  // reflection allowed
  std::vector<JudgedRow> rows;
  std::size_t layout_pairs = 0, layout_ok = 0, scan_pairs = 0, scan_ok = 0, mirrored_accepted = 0;
  for (const ManifestPair& pair : manifest.pairs) {
    const PairEvaluation row = evaluate_pair(pair, manifest.correct_if, plain);
    REQUIRE_MESSAGE(row.failure.empty(), row.failure);
    MESSAGE(pair.name << ": " << (row.correct ? "correct" : row.transform_correct ? "REJECTED" : "WRONG") << ", p_correct "
                      << row.result.p_correct << ", agreement " << row.result.evidence.agreement);
    if (!pair.ambiguous) {
      const bool to_layout = pair.kind == "sensor_to_layout";
      (to_layout ? layout_pairs : scan_pairs) += 1;
      (to_layout ? layout_ok : scan_ok) += row.correct;
      rows.push_back({pair, row, row.transform_correct});
    }
    const PairEvaluation mirrored = evaluate_pair(pair, manifest.correct_if, mirrors);
    if (mirrored.result.ok && mirrored.result.T_dest_source.reflected) {
      ++mirrored_accepted;
      MESSAGE(pair.name << ": a MIRRORED answer accepted with --allow-reflection");
    }
  }
  MESSAGE("scan -> layout " << layout_ok << " / " << layout_pairs << ", scan <-> scan " << scan_ok << " / " << scan_pairs);
  CHECK(layout_pairs == 22);
  CHECK(layout_ok >= 20);
  CHECK(scan_pairs == 36);
  CHECK(scan_ok >= 33);
  CHECK(mirrored_accepted == 0);

  const std::vector<ManifestPair> cross = cross_building_pairs(manifest);
  CHECK(cross.size() == 175);  // F5 (15 maps), HIH (5), KPT4A (5)
  std::size_t cross_accepted = 0;
  for (const ManifestPair& pair : cross) {
    const PairEvaluation row = evaluate_pair(pair, manifest.correct_if, mirrors);
    REQUIRE_MESSAGE(row.failure.empty(), row.failure);
    cross_accepted += row.result.ok;
    if (row.result.ok) MESSAGE("accepted " << pair.name << ": p_correct " << row.result.p_correct);
    rows.push_back({pair, row, false});
  }
  MESSAGE(cross_accepted << " of " << cross.size() << " pairs of different places accepted");
  CHECK(cross_accepted * 100 <= cross.size());  // >= 99 % rejected

  // Leave one place out: the rule's model fitted without any pair that touches a place (on the
  // other two places, the shared pairs and every 3rd shared pair of different buildings) must
  // still judge that place: a rule that only works where it was fitted fails here.
  const std::size_t handheld_rows = rows.size();
  const Manifest shared_manifest = load_manifest(shared + "/pairs.json");
  for (const ManifestPair& pair : shared_manifest.pairs) {
    if (pair.ambiguous) continue;
    const PairEvaluation row = evaluate_pair(pair, shared_manifest.correct_if, EvalOptions{});
    rows.push_back({pair, row, row.transform_correct});
  }
  for (const JudgedRow& r : shared_cross_rows(shared)) rows.push_back(r);
  Buildings buildings;
  for (const JudgedRow& r : rows) {
    buildings.find(r.pair.source);
    buildings.find(r.pair.destination);
    if (!r.pair.different_buildings) buildings.join(r.pair.source, r.pair.destination);
  }
  std::set<std::string> places;
  for (std::size_t i = 0; i < handheld_rows; ++i) places.insert(buildings.find(rows[i].pair.source));
  REQUIRE(places.size() == 3);
  const MatcherParams defaults;
  std::size_t right = 0, false_rejects = 0, wrong = 0, false_accepts = 0;
  for (const std::string& held : places) {
    std::vector<DecisionSample> train;
    for (const JudgedRow& r : rows) {
      if (buildings.find(r.pair.source) != held && buildings.find(r.pair.destination) != held) {
        train.push_back({decision_features(r.row.result), r.right});
      }
    }
    const DecisionParams model = fit_decision(train);
    for (std::size_t i = 0; i < handheld_rows; ++i) {
      const JudgedRow& r = rows[i];
      if (buildings.find(r.pair.source) != held) continue;  // each row once, under its source's place
      const bool accepted = r.row.result.evidence.agreement >= defaults.min_agreement ||
                            p_correct(decision_features(r.row.result), model) >= defaults.decision.accept_p_correct;
      if (r.right) {
        ++right;
        false_rejects += !accepted;
      } else {
        ++wrong;
        false_accepts += accepted;
      }
    }
  }
  MESSAGE("leave one place out: " << false_rejects << " of " << right << " right answers rejected, " << false_accepts << " of "
                                  << wrong << " wrong ones accepted");
  CHECK(false_rejects * 100 <= right * 5);
  CHECK(false_accepts * 100 <= wrong * 2);
}
