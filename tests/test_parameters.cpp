// The settings table (parameters.hpp, parameter_table.hpp): every name reaches its own field and
// no other, values read back exactly, bad names and values are refused with a message that names
// them, and a setting the table does not mark as shaping a prepared map indeed leaves the map's
// data unchanged (else a prepared map would be silently reused under settings it was not built for).
#include "synthetic_cases.hpp"
#include "test_support.hpp"

#include <areamatch/matcher.hpp>
#include <areamatch/parameters.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

using namespace areamatch;

namespace {

/// A segmenter of the user's own: it has no settings of the table.
struct OwnSegmenter {
  AreaGraph segment(const OccupancyGrid& grid) const { return VoronoiSegmenter{}.segment(grid); }
};

std::vector<std::string> values_of(const std::vector<ParameterRow>& rows) {
  std::vector<std::string> out;
  for (const auto& r : rows) out.push_back(r.value);
  return out;
}

/// A different value of the same type (not necessarily a valid one).
template <class T>
void perturb(T& v) {
  if constexpr (std::is_same_v<T, bool>) {
    v = !v;
  } else if constexpr (std::is_integral_v<T>) {
    v = v + 1;
  } else if constexpr (std::is_floating_point_v<T>) {
    v = v * 1.5 + 0.1;
  } else {
    for (double& x : v) x = x * 1.5 + 0.1;
  }
}

/// Perturbs the `index`-th row of the matcher's table in place.
template <class M>
void perturb_row(M& matcher, std::size_t index) {
  std::size_t i = 0;
  for_each_parameter(matcher, [&](const ParameterInfo&, auto& field) {
    if (i++ == index) perturb(field);
  });
}

/// Every row of `matcher`'s table reads back exactly and reaches its own field alone.
template <class M>
void check_table(const M& start) {
  const std::vector<ParameterRow> rows = parameter_rows(start);
  std::set<std::string> names;
  std::vector<ParameterSetting> all;
  for (const auto& r : rows) {
    CHECK_MESSAGE(names.insert(r.name).second, "the name " << r.name << " twice");
    CHECK_FALSE(r.meaning.empty());
    all.push_back({r.name, r.value});
  }
  // Setting every row to its own text changes nothing.
  M m = start;
  set_parameters(m, all);
  CHECK(values_of(parameter_rows(m)) == values_of(rows));

  for (std::size_t i = 0; i < rows.size(); ++i) {
    M changed_matcher = start;
    perturb_row(changed_matcher, i);
    const std::vector<std::string> changed = values_of(parameter_rows(changed_matcher));
    for (std::size_t j = 0; j < rows.size(); ++j) {
      CHECK_MESSAGE((changed[j] != rows[j].value) == (i == j), "perturbing " << rows[i].name << " changed " << rows[j].name);
    }
    // Its text is read as that value.
    M read_back = start;
    for_each_parameter(read_back, [&](const ParameterInfo& info, auto& field) {
      if (info.name == rows[i].name) detail::parse_parameter(info.name, changed[i], field);
    });
    CHECK(values_of(parameter_rows(read_back)) == changed);
  }
}

/// What a prepared map's data holds, as text, and what its lookup answers across the map.
template <class Data>
std::string fingerprint(const Data& d) {
  std::ostringstream out;
  out.precision(17);
  auto points = [&](const std::vector<Eigen::Vector2d>& v) {
    for (const auto& p : v) out << p.x() << ' ' << p.y() << ';';
    out << '\n';
  };
  out << d.coarse.width << ' ' << d.coarse.height << ' ' << d.coarse.cell_m << '\n';
  for (int l : d.coarse.labels) out << l << ',';
  for (int l : d.fine().labels) out << l << ',';
  out << '\n' << d.wall_direction << '\n';
  points(d.edge_points);
  points(d.edge_sides);
  points(d.walls);
  for (auto c : d.free_edge) out << c << ',';
  points(d.lookup.points());
  out << d.lookup.has_normals() << d.lookup.has_sides() << '\n';
  points(d.occupied.points);
  out << d.occupied.cell_m << ' ' << d.occupied.origin.transpose() << '\n';
  for (auto w : d.occupied.near.words) out << w << ',';
  for (auto w : d.occupied.context.words) out << w << ',';
  // The lookup's answers from among its points to 3 m beyond them (it reaches 2 m).
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = -lo;
  for (const auto& p : d.lookup.points()) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  for (double y = lo.y() - 3.0; y < hi.y() + 3.0; y += 0.37) {
    for (double x = lo.x() - 3.0; x < hi.x() + 3.0; x += 0.37) {
      const Eigen::Vector2d* q = d.lookup.nearest({x, y});
      out << (q ? static_cast<long>(q - d.lookup.points().data()) : -1L) << ',';
    }
  }
  return out.str();
}

}  // namespace

TEST_CASE("parameters: every value reads back exactly, and each name reaches its own field alone") {
  check_table(Matcher<>{});
  check_table(PaperMatcher{});
  const std::vector<ParameterRow> rows = parameter_rows(Matcher<>{});
  std::set<std::string> owners;
  for (const auto& r : rows) owners.insert(r.of);
  CHECK(owners == std::set<std::string>{"segmenter", "matcher", "clusterer", "selection"});
  // A matcher of other policies lists what it has: the paper's clusterer, no selection settings.
  const auto paper = parameter_rows(PaperMatcher{});
  CHECK(std::any_of(paper.begin(), paper.end(), [](const auto& r) { return r.name == "clusterer.threshold_rad"; }));
  CHECK(std::none_of(paper.begin(), paper.end(), [](const auto& r) { return r.of == "selection"; }));
}

TEST_CASE("parameters: names, values and validation refused with messages that name them") {
  Matcher<> m;
  auto refused = [&](const std::string& name, const std::string& value) {
    Matcher<> m2 = m;
    std::string message;
    try {
      set_parameters(m2, {{name, value}});
    } catch (const parameter_error& e) {
      message = e.what();
    }
    return message;
  };
  CHECK(refused("decision.min_agrement", "0.9").find("no parameter named 'decision.min_agrement' (did you mean decision.min_agreement?)") !=
        std::string::npos);
  CHECK(refused("nothing_like_it", "1").find("no parameter named 'nothing_like_it';") != std::string::npos);
  CHECK(refused("k", "ten").find("parameter k must be a number, got 'ten'") != std::string::npos);
  CHECK(refused("k", "2.5").find("parameter k must be a whole number >= 0") != std::string::npos);
  CHECK(refused("k", "-1").find("parameter k must be a whole number >= 0") != std::string::npos);
  CHECK(refused("refine", "yes").find("parameter refine must be true or false, got 'yes'") != std::string::npos);
  CHECK(refused("decision.weights", "1,2").find("parameter decision.weights takes 9 numbers, got 2") != std::string::npos);
  CHECK(refused("refinement.gates_m", "2,,1").find("must be a number, got ''") != std::string::npos);
  CHECK(refused("coarse_cell_m", "0").find("coarse_cell_m") != std::string::npos);  // validate()
  CHECK(refused("rooms.door_width_m", "-1").find("door width must be a positive number") != std::string::npos);
  CHECK(refused("k", "0").find("k must be >= 1") != std::string::npos);
  CHECK(refused("selection.wall_score_weight", "2").find("wall_score_weight must be in [0, 1]") != std::string::npos);
  CHECK(refused("selection.verify_candidates", "0").find("verify_candidates") != std::string::npos);
  // Settings the matcher's policies do not have.
  PaperMatcher paper;
  CHECK_THROWS_WITH_AS(set_parameters(paper, {{"selection.verify_candidates", "5"}}), doctest::Contains("no parameter named"),
                       parameter_error);
  Matcher<OwnSegmenter> own;
  CHECK_THROWS_WITH_AS(set_parameters(own, {{"rooms.door_width_m", "1.5"}}), doctest::Contains("only VoronoiSegmenter has it"),
                       parameter_error);
  // Not in the table: what the segmenter derives itself, and how many threads.
  CHECK_FALSE(refused("skeleton.keep_clearance_m", "1").empty());
  CHECK_FALSE(refused("threads", "4").empty());

  set_parameters(m, {{"rooms.door_width_m", "1.5"}, {"refinement.gates_m", "2,1,0.5"}, {"allow_reflection", "true"},
                     {"decision.min_agreement", "0.9"}, {"k", "7"}, {"decision.min_agreement", "0.8"},
                     {"selection.verify_candidates", "64"}, {"clusterer.translation_m", "0.5"}});
  CHECK(m.segmenter.params.rooms.door_width_m == 1.5);
  CHECK(m.params.refinement.gates_m == std::vector<double>{2.0, 1.0, 0.5});
  CHECK(m.params.allow_reflection);
  CHECK(m.params.k == 7);
  CHECK(m.params.decision.min_agreement == 0.8);  // in order: the last wins
  CHECK(m.selection.params.verify_candidates == 64);
  CHECK(m.clusterer.params.translation_m == 0.5);
  CHECK(parameter_is_segmenters("rooms.door_width_m"));
  CHECK_FALSE(parameter_is_segmenters("k"));
}

TEST_CASE("parameters: a setting not marked as shaping a prepared map leaves its data as it was") {
  const auto c = areamatch_test::synthetic_case(3);
  const OccupancyGrid& grid = c.robot.grid;
  const Matcher<> matcher;
  const AreaGraph graph = matcher.segmenter.segment(grid);
  REQUIRE(!graph.areas.empty());
  const std::string base = fingerprint(detail::build_map_data(grid, graph, matcher.features, matcher.params, true));

  const std::vector<ParameterRow> rows = parameter_rows(matcher);
  std::size_t unmarked = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].of == "segmenter") continue;  // the segmentation is the prepared map's own
    Matcher<> changed = matcher;
    perturb_row(changed, i);
    const MatcherParams& m = changed.params;
    const std::string differing = map_data_setting_differing(matcher.params, m);
    CHECK(differing == (rows[i].shapes_map_data ? rows[i].name : std::string()));
    if (rows[i].shapes_map_data) continue;
    ++unmarked;
    CHECK_MESSAGE(fingerprint(detail::build_map_data(grid, graph, matcher.features, m, true)) == base,
                  rows[i].name << " changes a prepared map's data but is not marked shapes_map_data");
  }
  CHECK(unmarked > 40);

  // The selection asks the lookups within their reach, or says why it cannot.
  Matcher<> far = matcher;
  far.selection.params.candidate_wall_distance_m = 2.5;  // the lookups reach 2 m (refinement.gates_m)
  CHECK_THROWS_WITH_AS(far.match(grid, grid), doctest::Contains("reaches beyond the edge lookups (2 m"), parameter_error);
}

TEST_CASE("parameters: docs/parameters.md lists exactly the table") {
  std::ifstream in(AREAMATCH_SOURCE_DIR "/docs/parameters.md");
  REQUIRE(in);
  std::stringstream text;
  text << in.rdbuf();
  const std::string doc = text.str();
  const std::string begin = "<!-- parameter-table-begin -->\n", end = "<!-- parameter-table-end -->";
  const auto from = doc.find(begin), to = doc.find(end);
  REQUIRE(from != std::string::npos);
  REQUIRE(to != std::string::npos);
  const std::string expected = parameters_markdown(Matcher<>{});
  CHECK_MESSAGE(doc.substr(from + begin.size(), to - from - begin.size()) == expected,
                "docs/parameters.md's table is stale: regenerate it with `areamatch parameters --markdown`");
}
