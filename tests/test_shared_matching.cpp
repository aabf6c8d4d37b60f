// Every pair of ../shared/pairs.json with the default matcher, its YAML resolutions, the pair's
// door width where given and reflection allowed: correct by the manifest's correct_if, judged
// as shared/tools/score.py judges. Ambiguous pairs are reported, not required. Skipped (exit 77)
// when ../shared is not present. The hand-held scans of ../shared/handheld (a second sensor) are
// judged too, with a leave-one-place-out check of the decision.
#include <areamatch/areamatch.hpp>
#include <areamatch/evaluation.hpp>
#include <areamatch/io.hpp>
#include <eval/evaluate.hpp>

#include <doctest/doctest.h>

#include "test_support.hpp"

#include <array>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

using namespace areamatch;

namespace {

struct JudgedRow {
  ManifestPair pair;
  PairEvaluation row;
  bool right = false;  ///< the transform is within correct_if (pairs of different buildings: never)
  std::shared_ptr<const MapPairRun> run;  ///< the maps, graphs and result (shared pairs only)
};

/// Every pair of shared/pairs.json, judged once per process (reflection allowed, the pair's door
/// width, its YAML resolutions): the matching test and the decision's cross-validation use them.
const std::vector<JudgedRow>& shared_pair_rows(const std::string& shared) {
  static const std::vector<JudgedRow> rows = [&] {
    const Manifest manifest = load_manifest(shared + "/pairs.json");
    std::vector<JudgedRow> out;
    for (const ManifestPair& pair : manifest.pairs) {
      auto run = std::make_shared<MapPairRun>();
      const PairEvaluation row = evaluate_pair(pair, manifest.correct_if, EvalOptions{}, run.get());
      out.push_back({pair, row, row.transform_correct, std::move(run)});
    }
    return out;
  }();
  return rows;
}

/// The shared pairs of different buildings every CI run checks (every 3rd of the 740), judged
/// once per process: the rejection test and the decision's cross-validation both use them.
const std::vector<JudgedRow>& shared_cross_rows(const std::string& shared) {
  static const std::vector<JudgedRow> rows = [&] {
    const Manifest manifest = load_manifest(shared + "/pairs.json");
    const std::vector<ManifestPair> cross = cross_building_pairs(manifest);
    std::vector<JudgedRow> out;
    for (std::size_t i = 0; i < cross.size(); i += 3) {
      out.push_back({cross[i], evaluate_pair(cross[i], manifest.correct_if, EvalOptions{}), false, nullptr});
    }
    return out;
  }();
  return rows;
}

/// The buildings of `rows`' maps: maps joined by a pair of one building are one building.
BuildingGroups building_groups(const std::vector<const JudgedRow*>& rows) {
  BuildingGroups buildings;
  for (const JudgedRow* r : rows) {
    buildings.add(r->pair.source);
    buildings.add(r->pair.destination);
    if (!r->pair.different_buildings) buildings.join(r->pair.source, r->pair.destination);
  }
  return buildings;
}

}  // namespace

/// Known failures (issue 42): the Intel Research Lab's cluttered, bent SLAM map onto its schematic
/// layout. The transform is right (rotation error under 1 degree, displacement under 0.3 m) but
/// the decision rejects it. The test checks that both still hold, so that a change that makes
/// the matcher accept them is noticed here (then take them off this list); a wrong transform
/// fails as any other pair does.
const std::set<std::string>& known_rejected_right_answers() {
  static const std::set<std::string> names = {"intel", "intel_rot123"};
  return names;
}

TEST_CASE("every non-ambiguous shared pair is matched correctly (known rejections checked, not skipped)") {
  const std::string shared = areamatch_test::shared_dir();
  if (shared.empty()) return;
  const std::vector<JudgedRow>& rows = shared_pair_rows(shared);
  REQUIRE(!rows.empty());
  std::size_t known_seen = 0;
  for (const JudgedRow& judged : rows) {
    const ManifestPair& pair = judged.pair;
    const PairEvaluation& row = judged.row;
    REQUIRE(pair.ground_truth);
    REQUIRE_MESSAGE(row.failure.empty(), row.failure);
    const MatchResult& r = row.result;
    const std::string verdict = row.correct ? "correct" : row.transform_correct ? "REJECTED (right transform)" : "WRONG";
    MESSAGE(pair.name << std::string(pair.ambiguous ? " (ambiguous)" : "") << ": " << verdict << ", rotation error "
                      << row.error->rotation_error_deg << " deg, displacement " << row.error->mean_displacement_m
                      << " m, p_correct " << r.p_correct << ", agreement " << r.evidence.agreement << ", match "
                      << 1000.0 * r.timings.match_s << " ms");
    if (known_rejected_right_answers().count(pair.name)) {
      ++known_seen;
      CHECK_MESSAGE(row.transform_correct, pair.name << ": a known rejection whose transform is now wrong");
      CHECK_MESSAGE(!r.ok, pair.name << ": a known rejection is now accepted: take it off known_rejected_right_answers");
      continue;
    }
    if (!pair.ambiguous) CHECK_MESSAGE(row.correct, pair.name);
  }
  CHECK(known_seen == known_rejected_right_answers().size());  // the list follows the manifest
}

TEST_CASE("prepared maps give the same results as their grids on every shared pair") {
  const std::string shared = areamatch_test::shared_dir();
  if (shared.empty()) return;
  for (const JudgedRow& judged : shared_pair_rows(shared)) {
    REQUIRE(judged.run);
    const MapPairRun& run = *judged.run;
    const Matcher<> matcher = detail::configured_matcher(Matcher<>{}, pair_options(judged.pair, EvalOptions{}));
    const MatchResult prepared =
        matcher.match(matcher.prepare(run.source, run.source_graph), matcher.prepare(run.dest, run.dest_graph));
    const std::string a = match_result_json(prepared), b = match_result_json(run.result);
    CHECK_MESSAGE(a.substr(0, a.find("\"timings\"")) == b.substr(0, b.find("\"timings\"")), judged.pair.name);
  }
}

TEST_CASE("pairs of maps of different shared buildings are rejected (every 3rd of the 740)") {
  const std::string shared = areamatch_test::shared_dir();
  if (shared.empty()) return;
  const Manifest manifest = load_manifest(shared + "/pairs.json");
  CHECK(cross_building_pairs(manifest).size() == 740);  // 40 maps of 15 buildings (the Intel lab's four since 2026-12-04)
  std::size_t tried = 0, rejected = 0;
  for (const JudgedRow& r : shared_cross_rows(shared)) {
    REQUIRE_MESSAGE(r.row.failure.empty(), r.row.failure);
    ++tried;
    rejected += r.row.correct;
    if (!r.row.correct) MESSAGE("accepted " << r.pair.name << ": agreement " << r.row.result.evidence.agreement);
  }
  MESSAGE(rejected << " of " << tried << " pairs of different buildings rejected");
  CHECK(rejected * 1000 >= tried * 995);  // >= 99.5 % (issue 42)
}

TEST_CASE("the decision fitted without any real SLAM building judges the SLAM maps: right answers accepted, wrong ones not") {
  // The SLAM -> layout pairs are the few real buildings of the paper's setting; a rule that only
  // works because they were in its fit fails here. Fitted on the shared rows that touch no
  // building with a SLAM map (the furnished layouts and their pairs of different buildings),
  // judged with the shipped rule on every row that touches one.
  const std::string shared = areamatch_test::shared_dir();
  if (shared.empty()) return;
  std::vector<const JudgedRow*> rows;
  for (const JudgedRow& r : shared_pair_rows(shared)) {
    if (!r.pair.ambiguous) rows.push_back(&r);
  }
  for (const JudgedRow& r : shared_cross_rows(shared)) rows.push_back(&r);
  BuildingGroups buildings = building_groups(rows);
  std::set<std::size_t> slam_buildings;
  for (const JudgedRow& r : shared_pair_rows(shared)) {  // ambiguous ones too: freiburg79's SLAM maps
    if (r.pair.kind == "slam_to_layout") slam_buildings.insert(buildings.building(r.pair.source));
  }
  REQUIRE(slam_buildings.size() >= 4);  // freiburg52, lab_b, the ipa map, intel (and freiburg79's)
  auto touches_slam = [&](const JudgedRow& r) {
    return slam_buildings.count(buildings.building(r.pair.source)) || slam_buildings.count(buildings.building(r.pair.destination));
  };
  std::vector<DecisionSample> train;
  for (const JudgedRow* r : rows) {
    if (!touches_slam(*r)) train.push_back({decision_features(r->row.result), r->right});
  }
  const MatcherParams defaults;
  const DecisionParams model = fit_decision(train, 1.0, defaults.decision);
  std::size_t right = 0, right_accepted = 0, wrong = 0, wrong_accepted = 0;
  for (const JudgedRow* r : rows) {
    if (!touches_slam(*r)) continue;
    const MatchResult& m = r->row.result;
    const bool accepted = detail::passes_agreement_gate(m, defaults.decision) ||
                          p_correct(decision_features(m), model) >= defaults.decision.accept_p_correct;
    if (r->right) {
      ++right;
      right_accepted += accepted;
      const bool known = known_rejected_right_answers().count(r->pair.name) > 0;
      MESSAGE(r->pair.name << ": " << std::string(accepted ? "accepted" : "REJECTED") << std::string(known ? " (known rejection)" : ""));
      if (known) {
        CHECK_MESSAGE(!accepted, r->pair.name << ": a known rejection is accepted by the rule fitted without SLAM buildings");
      } else {
        CHECK_MESSAGE(accepted, r->pair.name);
      }
    } else {
      ++wrong;
      wrong_accepted += accepted;
      if (accepted) MESSAGE("accepted " << r->pair.name);
    }
  }
  MESSAGE(right_accepted << " of " << right << " right answers of SLAM buildings accepted, " << wrong_accepted << " of " << wrong
                         << " wrong ones (fitted on " << train.size() << " rows without a SLAM building)");
  CHECK(right >= 8);
  CHECK(wrong_accepted * 1000 <= wrong * 5);
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

TEST_CASE("BuildingGroups: maps joined by pairs of one building, transitively, numbered as first named") {
  BuildingGroups groups;
  CHECK(groups.add("a") == 0);
  CHECK(groups.add("b") == 1);
  groups.join("c", "b");  // c is new: number 2
  groups.join("d", "e");
  CHECK(groups.size() == 5);
  CHECK(groups.building("c") == 1);
  CHECK(groups.building("b") == 1);
  CHECK(groups.building("a") == 0);
  CHECK(groups.building("e") == 3);
  groups.join("e", "a");  // joins {d, e} with {a}: named by a, the first
  CHECK(groups.building("d") == 0);
  CHECK(groups.map(groups.building("d")) == "a");
  CHECK(groups.building("c") != groups.building("d"));
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
    MESSAGE(pair.name << ": " << std::string(row.correct ? "correct" : row.transform_correct ? "REJECTED" : "WRONG") << ", p_correct "
                      << row.result.p_correct << ", agreement " << row.result.evidence.agreement);
    if (!pair.ambiguous) {
      const bool to_layout = pair.kind == "sensor_to_layout";
      (to_layout ? layout_pairs : scan_pairs) += 1;
      (to_layout ? layout_ok : scan_ok) += row.correct;
      rows.push_back({pair, row, row.transform_correct, nullptr});
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
    rows.push_back({pair, row, false, nullptr});
  }
  MESSAGE(cross_accepted << " of " << cross.size() << " pairs of different places accepted");
  CHECK(cross_accepted * 100 <= cross.size());  // >= 99 % rejected

  // Leave one place out: the rule's model fitted without any pair that touches a place (on the
  // other two places, the shared pairs and every 3rd shared pair of different buildings) must
  // still judge that place: a rule that only works where it was fitted fails here.
  const std::size_t handheld_rows = rows.size();
  for (const JudgedRow& r : shared_pair_rows(shared)) {
    if (!r.pair.ambiguous) rows.push_back(r);
  }
  for (const JudgedRow& r : shared_cross_rows(shared)) rows.push_back(r);
  std::vector<const JudgedRow*> row_pointers;
  for (const JudgedRow& r : rows) row_pointers.push_back(&r);
  BuildingGroups buildings = building_groups(row_pointers);
  std::vector<DecisionSample> samples;
  std::vector<std::array<std::size_t, 2>> building_of;
  for (const JudgedRow& r : rows) {
    samples.push_back({decision_features(r.row.result), r.right});
    building_of.push_back({buildings.building(r.pair.source), buildings.building(r.pair.destination)});
  }
  std::set<std::size_t> places;
  for (std::size_t i = 0; i < handheld_rows; ++i) places.insert(building_of[i][0]);
  REQUIRE(places.size() == 3);
  const std::vector<double> predicted = leave_one_building_out(samples, building_of);
  const MatcherParams defaults;
  std::size_t right = 0, false_rejects = 0, wrong = 0, false_accepts = 0;
  for (std::size_t i = 0; i < handheld_rows; ++i) {
    const JudgedRow& r = rows[i];
    const bool accepted = detail::passes_agreement_gate(r.row.result, defaults.decision) ||
                          predicted[i] >= defaults.decision.accept_p_correct;
    if (r.right) {
      ++right;
      false_rejects += !accepted;
    } else {
      ++wrong;
      false_accepts += accepted;
    }
  }
  MESSAGE("leave one place out: " << false_rejects << " of " << right << " right answers rejected, " << false_accepts << " of "
                                  << wrong << " wrong ones accepted");
  CHECK(false_rejects * 100 <= right * 5);
  CHECK(false_accepts * 100 <= wrong * 2);
}

TEST_CASE("merging the F5 floor with a scan of each apartment: the floor placed, the apartments not") {
  // A merge tries every pair, so one falsely accepted match would place a map of another place:
  // KPT4A_02 has exactly one accepted match here (onto F5_07, accepted by the model alone at
  // p_correct 0.89), which MergeParams::lone_match_min_p_correct keeps out (docs/merging.md).
  const std::string shared = areamatch_test::shared_dir();
  if (shared.empty()) return;
  const std::string dir = shared + "/handheld/maps/";
  if (!areamatch_test::is_dir(dir)) {
    MESSAGE("skipped: no shared/handheld");
    return;
  }
  std::vector<std::string> names = {"F5_layout"};
  for (int i = 1; i <= 14; ++i) names.push_back(std::string(i < 10 ? "F5_0" : "F5_") + std::to_string(i));
  names.push_back("HIH_01");
  names.push_back("KPT4A_02");
  Matcher<> matcher;
  matcher.segmenter.params.with_door_width(0.9);
  std::vector<Matcher<>::PreparedMap> maps;
  for (const auto& name : names) maps.push_back(matcher.prepare(load_map(dir + name + ".yaml")));
  const MergeResult merged = merge_maps(matcher, maps);
  for (std::size_t i = 0; i < names.size(); ++i) {
    INFO(names[i] << ": " << merged.maps[i].reason);
    CHECK(merged.maps[i].placed == (i < 15));
  }
}
