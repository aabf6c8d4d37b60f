#pragma once
// `areamatch calibrate`: fits the accept/reject decision (areamatch/match/decision/decision.hpp) on the
// rows of `areamatch eval --out DIR` runs (DIR/results.csv) and measures it by leave-one-
// building-out cross-validation: each building's pairs are judged by a model fitted without any
// pair that touches that building. Program code, not library API.

#include <areamatch/error.hpp>
#include "eval_report.hpp"
#include "manifest.hpp"
#include <areamatch/detail/format.hpp>
#include <areamatch/match/decision/acceptance.hpp>
#include <areamatch/match/decision/decision.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numeric>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace areamatch_cli {

/// What kind of map a map is, learnt from the kinds of the pairs it is in (`MapRoles`): a robot's
/// SLAM map, a floor-plan layout, a layout with furniture drawn in, a hand-held scan, or a
/// generated map. Generated buildings may train the decision but do not judge it.
enum class MapRole { unknown, slam, layout, furnished, scan, generated };

inline const char* role_name(MapRole role) {
  switch (role) {
    case MapRole::slam: return "SLAM map";
    case MapRole::layout: return "layout";
    case MapRole::furnished: return "furnished layout";
    case MapRole::scan: return "hand-held scan";
    case MapRole::generated: return "generated map";
    default: return "map of unknown kind";
  }
}

/// The roles of a pair's two maps by its manifest kind ({unknown, unknown} for a kind not known).
inline std::array<MapRole, 2> roles_of_kind(const std::string& kind) {
  if (kind == "slam_to_layout") return {MapRole::slam, MapRole::layout};
  if (kind == "furnished_to_layout") return {MapRole::furnished, MapRole::layout};
  if (kind == "sensor_to_layout") return {MapRole::scan, MapRole::layout};
  if (kind == "sensor_to_sensor") return {MapRole::scan, MapRole::scan};
  if (kind.rfind("synthetic", 0) == 0) return {MapRole::generated, MapRole::generated};
  return {MapRole::unknown, MapRole::unknown};
}

/// Map path (canonical) -> role, from every pair of one building read, ambiguous ones included.
using MapRoles = std::map<std::string, MapRole>;

inline MapRole role_of(const MapRoles& roles, const std::string& map) {
  const auto it = roles.find(map);
  return it == roles.end() ? MapRole::unknown : it->second;
}

/// One labelled row of an eval CSV.
struct CalibrationRow {
  std::string name, kind, source, destination;
  bool different_buildings = false;
  /// What the agreement gate reads (`areamatch::detail::passes_agreement_gate`): the row's evidence
  /// (the shared free space 0 where not measured) and its margin.
  areamatch::MatchEvidence evidence;
  double margin = std::nan("");
  double shipped_p = std::nan("");  ///< the row's own p_correct (the model that ran it)
  areamatch::DecisionSample sample;
  int source_building = -1, dest_building = -1;  ///< filled by `assign_buildings`
  /// The two buildings, as `areamatch::leave_one_building_out` takes them.
  std::array<std::size_t, 2> buildings() const {
    return {static_cast<std::size_t>(source_building), static_cast<std::size_t>(dest_building)};
  }
};

/// The fields of one CSV line (RFC 4180 quoting, as `detail::csv_field` writes it).
inline std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        out.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        out.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.emplace_back();
    } else if (c != '\r') {
      out.back() += c;
    }
  }
  return out;
}

/// The labelled rows of an eval CSV: pairs of different buildings (wrong by definition) and pairs
/// with ground truth (right when the transform is within the manifest's correct_if). Pairs that
/// could not run, have no ground truth, or are marked ambiguous are left out.
/// `roles` (when given) learns the roles of the maps of every pair of one building, ambiguous
/// ones included.
inline std::vector<CalibrationRow> read_calibration_rows(const std::string& path, MapRoles* roles = nullptr) {
  std::ifstream in(path);
  if (!in) throw areamatch::io_error("cannot read " + path);
  std::string line;
  if (!std::getline(in, line)) throw areamatch::format_error(path + ": empty");
  const std::vector<std::string> header = csv_fields(line);
  auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) throw areamatch::format_error(path + ": no column '" + name + "' (not an areamatch eval results.csv of this version)");
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t c_name = column("name"), c_kind = column("kind"), c_source = column("source"), c_dest = column("destination"),
                    c_ambiguous = column("ambiguous"), c_different = column("different_buildings"),
                    c_failure = column("failure"), c_truth = column("transform_correct"),
                    c_forward = column("forward_wall_agreement"), c_reverse = column("reverse_wall_agreement"),
                    c_rooms = column("room_agreement"), c_margin = column("margin"), c_overlap = column("overlap_m2"),
                    c_turn = column("turn_margin"), c_iou = column("free_iou"),
                    c_occupied = column("occupied_wall_agreement"),
                    c_p = column("p_correct"), c_agreement = column("agreement");
  std::vector<CalibrationRow> rows;
  std::size_t line_number = 1;
  auto value = [&](const std::vector<std::string>& f, std::size_t c) {
    if (f[c].empty()) return std::nan("");
    char* end = nullptr;
    const double v = std::strtod(f[c].c_str(), &end);
    if (end != f[c].c_str() + f[c].size()) {
      throw areamatch::format_error(path + ":" + std::to_string(line_number) + ": column '" + header[c] + "' holds '" + f[c] +
                                    "', not a number");
    }
    return v;
  };
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty()) continue;
    const std::vector<std::string> f = csv_fields(line);
    if (f.size() != header.size()) {
      throw areamatch::format_error(path + ":" + std::to_string(line_number) + ": " + std::to_string(f.size()) +
                                    " fields, the header has " + std::to_string(header.size()));
    }
    std::error_code ec;
    const std::string source = std::filesystem::weakly_canonical(f[c_source], ec).string();
    const std::string destination = std::filesystem::weakly_canonical(f[c_dest], ec).string();
    if (roles && f[c_different] != "true") {
      const auto pair_roles = roles_of_kind(f[c_kind]);
      for (auto [map, role] : {std::pair{&source, pair_roles[0]}, std::pair{&destination, pair_roles[1]}}) {
        MapRole& known = (*roles)[*map];
        if (known == MapRole::unknown) known = role;
      }
    }
    if (!f[c_failure].empty() || f[c_ambiguous] == "true" || f[c_p].empty()) continue;
    CalibrationRow row;
    row.name = f[c_name];
    row.kind = f[c_kind];
    row.different_buildings = f[c_different] == "true";
    if (!row.different_buildings && f[c_truth].empty()) continue;
    row.source = source;
    row.destination = destination;
    areamatch::MatchResult r;  // just the fields decision_features reads
    r.evidence.forward_wall_agreement = value(f, c_forward);
    r.evidence.reverse_wall_agreement = value(f, c_reverse);
    r.evidence.room_agreement = value(f, c_rooms);
    r.evidence.overlap_m2 = value(f, c_overlap);
    r.evidence.turn_margin = value(f, c_turn);
    r.evidence.free_iou = value(f, c_iou);
    r.evidence.occupied_wall_agreement = value(f, c_occupied);
    r.margin = value(f, c_margin);
    row.sample.features = areamatch::decision_features(r);
    row.evidence = r.evidence;
    row.evidence.agreement = value(f, c_agreement);
    if (!std::isfinite(row.evidence.overlap_m2)) row.evidence.overlap_m2 = 0.0;
    row.margin = r.margin;
    row.shipped_p = value(f, c_p);
    row.sample.correct = !row.different_buildings && f[c_truth] == "true";
    rows.push_back(std::move(row));
  }
  return rows;
}

/// Buildings: maps joined by a pair of one building are one building. Returns their names (the
/// first map's folder and file stem of each).
inline std::vector<std::string> assign_buildings(std::vector<CalibrationRow>& rows) {
  areamatch::BuildingGroups groups;
  for (const auto& r : rows) {
    groups.add(r.source);
    groups.add(r.destination);
    if (!r.different_buildings) groups.join(r.source, r.destination);
  }
  std::map<std::size_t, int> building_of_root;
  std::vector<std::string> names;
  for (auto& r : rows) {
    for (auto [path, out] : {std::pair{&r.source, &r.source_building}, std::pair{&r.destination, &r.dest_building}}) {
      const std::size_t root = groups.building(*path);
      const auto [it, added] = building_of_root.emplace(root, static_cast<int>(names.size()));
      if (added) {
        const std::filesystem::path p(groups.map(root));
        names.push_back(p.parent_path().filename().string() + "/" + p.stem().string());
      }
      *out = it->second;
    }
  }
  return names;
}

/// Which rows judge the decision: those of real maps only. A building judges when it has a real
/// map (a simulated SLAM map of a real plan joins the plan's building, so that it never trains
/// the model that judges that building, but its rows do not judge); generated buildings and rows
/// with a generated map only train. When no row is real, every row judges (`all_judge`).
struct JudgingBuildings {
  std::vector<char> judges;     ///< per building
  std::vector<char> row_judged; ///< per row
  bool all_judge = false;       ///< no real row: the generated ones judge
  bool judged(std::size_t row) const { return row_judged[row] != 0; }
};

inline JudgingBuildings judging_buildings(const std::vector<CalibrationRow>& rows, std::size_t buildings, const MapRoles& roles) {
  JudgingBuildings out;
  out.judges.assign(buildings, 0);
  auto generated = [&](const std::string& map) { return role_of(roles, map) == MapRole::generated; };
  for (const auto& r : rows) {
    if (!generated(r.source)) out.judges[static_cast<std::size_t>(r.source_building)] = 1;
    if (!generated(r.destination)) out.judges[static_cast<std::size_t>(r.dest_building)] = 1;
  }
  out.row_judged.resize(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CalibrationRow& r = rows[i];
    out.row_judged[i] = !generated(r.source) && !generated(r.destination);
  }
  if (std::find(out.row_judged.begin(), out.row_judged.end(), 1) == out.row_judged.end()) {
    out.judges.assign(buildings, 1);
    out.row_judged.assign(rows.size(), 1);
    out.all_judge = true;
  }
  return out;
}

/// The modality a row belongs to: its two maps' roles, source first ("SLAM map -> layout").
inline std::string modality(const CalibrationRow& r, const MapRoles& roles) {
  return std::string(role_name(role_of(roles, r.source))) + " -> " + role_name(role_of(roles, r.destination));
}

/// Outcome counts of a decision on some rows.
struct DecisionCounts {
  std::size_t right = 0, right_rejected = 0;  ///< right transforms, and those rejected (false rejects)
  std::size_t wrong_same = 0, wrong_same_accepted = 0;  ///< wrong transforms of one building, accepted
  std::size_t different = 0, different_accepted = 0;    ///< pairs of different buildings, accepted
  void add(bool right_answer, bool different_buildings, bool accepted) {
    if (right_answer) {
      ++right;
      right_rejected += !accepted;
    } else if (different_buildings) {
      ++different;
      different_accepted += accepted;
    } else {
      ++wrong_same;
      wrong_same_accepted += accepted;
    }
  }
  /// Counts a row under its buildings (under both for a pair of two).
  static void add_per_building(std::vector<DecisionCounts>& per_building, const CalibrationRow& r, bool accepted) {
    per_building[static_cast<std::size_t>(r.source_building)].add(r.sample.correct, r.different_buildings, accepted);
    if (r.dest_building != r.source_building) {
      per_building[static_cast<std::size_t>(r.dest_building)].add(r.sample.correct, r.different_buildings, accepted);
    }
  }
  void add(const DecisionCounts& o) {
    right += o.right, right_rejected += o.right_rejected, wrong_same += o.wrong_same;
    wrong_same_accepted += o.wrong_same_accepted, different += o.different, different_accepted += o.different_accepted;
  }
};

/// Leave-one-building-out predictions of the rows (`areamatch::leave_one_building_out`).
inline std::vector<double> leave_one_building_out(const std::vector<CalibrationRow>& rows, double l2,
                                                  const areamatch::DecisionParams& base) {
  std::vector<areamatch::DecisionSample> samples;
  std::vector<std::array<std::size_t, 2>> buildings;
  for (const auto& r : rows) {
    samples.push_back(r.sample);
    buildings.push_back(r.buildings());
  }
  return areamatch::leave_one_building_out(samples, buildings, l2, base);
}

/// The matcher's rule: accepted at p_correct ≥ accept_p, or where the agreement gate of `gate`
/// lets the answer through (the library's `detail::passes_agreement_gate`: agreement, shared free
/// space, lower wall agreement, or where the walls agree both ways the occupied walls and margin).
struct Rule {
  double accept_p = 0.9;
  areamatch::DecisionParams gate;  ///< its agreement gate's thresholds (the rest is not read)
  bool accepts(const CalibrationRow& r, double p) const {
    return p >= accept_p || areamatch::detail::passes_agreement_gate(r.evidence, r.margin, gate);
  }
};

/// One line per row: its buildings, label, agreement, cross-validated and in-sample p_correct, and
/// whether `rule` accepts it on the cross-validated p (`areamatch calibrate --predictions`).
inline std::string predictions_csv(const std::vector<CalibrationRow>& rows, const std::vector<std::string>& buildings,
                                   const std::vector<double>& cross_validated, const std::vector<double>& in_sample,
                                   const Rule& rule) {
  std::ostringstream out;
  out << "name,source,destination,source_building,dest_building,different_buildings,right,agreement,"
         "p_correct_cv,p_correct_in_sample,accepted_cv\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CalibrationRow& r = rows[i];
    out << areamatch::detail::csv_field(r.name) << ',' << areamatch::detail::csv_field(r.source) << ','
        << areamatch::detail::csv_field(r.destination) << ','
        << areamatch::detail::csv_field(buildings[static_cast<std::size_t>(r.source_building)]) << ','
        << areamatch::detail::csv_field(buildings[static_cast<std::size_t>(r.dest_building)]) << ','
        << (r.different_buildings ? "true" : "false") << ',' << (r.sample.correct ? "true" : "false") << ','
        << areamatch::detail::format_double(r.evidence.agreement) << ',' << areamatch::detail::format_double(cross_validated[i]) << ','
        << areamatch::detail::format_double(in_sample[i])
        << ',' << (rule.accepts(r, cross_validated[i]) ? "true" : "false") << '\n';
  }
  return out.str();
}

/// The thresholds `choose_rule` tries (above 1: that part off).
inline const std::vector<double>& accept_p_grid() {
  static const std::vector<double> grid = {0.5, 0.6, 0.7, 0.8, 0.85, 0.9, 0.95, 0.98, 0.99, 1.01};
  return grid;
}
inline const std::vector<double>& min_agreement_grid() {
  static const std::vector<double> grid = {0.8, 0.81, 0.82, 0.83, 0.835, 0.84, 0.85, 0.86, 0.87, 0.88, 0.9, 1.01};
  return grid;
}
/// From lenient to strict, as the others (above 1: the gate whatever the walls).
inline const std::vector<double>& max_lower_walls_grid() {
  static const std::vector<double> grid = {1.01, 0.9, 0.8, 0.75, 0.7, 0.65, 0.6, 0.55, 0.5};
  return grid;
}

/// The rule with the fewest false rejects on rows `subset` (judged by `predicted`, one per row of
/// `subset`) whose share of wrong answers accepted stays at or below `max_false_accept`; ties go
/// to fewer false accepts, then to the stricter thresholds. When no rule keeps the bound, the one
/// with the fewest false accepts. The gate's least overlap and its both-ways part are given (`given`),
/// not chosen: chosen too, the
/// overlap freed the false-accept budget for looser thresholds elsewhere, and the nested
/// cross-validation accepted 6 of 2390 real wrong answers instead of 0 (docs/evaluation.md).
inline Rule choose_rule(const std::vector<CalibrationRow>& rows, const std::vector<std::size_t>& subset,
                        const std::vector<double>& predicted, double max_false_accept, const Rule& given) {
  std::size_t wrong = 0;
  for (std::size_t i : subset) wrong += !rows[i].sample.correct;
  const double allowed = max_false_accept * static_cast<double>(wrong);
  Rule best;
  bool best_keeps = false;
  std::size_t best_rejects = 0, best_accepts = 0;
  bool first = true;
  for (double accept_p : accept_p_grid()) {
    for (double min_agreement : min_agreement_grid()) {
      for (double max_lower_walls : max_lower_walls_grid()) {
        Rule rule = given;
        rule.accept_p = accept_p;
        rule.gate.min_agreement = min_agreement;
        rule.gate.gate_max_lower_walls = max_lower_walls;
        std::size_t rejects = 0, accepts = 0;
        for (std::size_t k = 0; k < subset.size(); ++k) {
          const CalibrationRow& r = rows[subset[k]];
          const bool accepted = rule.accepts(r, predicted[k]);
          rejects += r.sample.correct && !accepted;
          accepts += !r.sample.correct && accepted;
        }
        const bool keeps = static_cast<double>(accepts) <= allowed;
        // The grids run from lenient to strict: on a tie the later (stricter) rule wins.
        const bool better = first || (keeps && !best_keeps) ||
                            (keeps == best_keeps && (keeps ? std::pair(rejects, accepts) <= std::pair(best_rejects, best_accepts)
                                                           : std::pair(accepts, rejects) <= std::pair(best_accepts, best_rejects)));
        if (better) {
          best = rule;
          best_keeps = keeps;
          best_rejects = rejects;
          best_accepts = accepts;
          first = false;
        }
      }
    }
  }
  return best;
}

/// The both-ways thresholds `choose_both_ways` tries, strict to lenient (occupied above 1: off).
inline const std::vector<double>& both_ways_occupied_grid() {
  static const std::vector<double> grid = {2.0, 0.95, 0.9, 0.85, 0.8, 0.75, 0.7};
  return grid;
}
inline const std::vector<double>& both_ways_margin_grid() {
  static const std::vector<double> grid = {0.05, 0.02, 0.01, 0.007, 0.005, 0.002, 0.0};
  return grid;
}

/// `base` with the gate's both-ways thresholds (`gate_both_ways_min_occupied`, `gate_both_ways_min_margin`)
/// chosen on `rows` (each judged on `predicted`, one per row): the fewest right answers refused with
/// no wrong answer accepted — a symmetric building's turned copy is as wrong as another building —
/// ties to the stricter; when no choice accepts none, the fewest accepted.
inline Rule choose_both_ways(const std::vector<const CalibrationRow*>& rows, const std::vector<double>& predicted,
                             const Rule& base) {
  Rule best = base;
  std::pair<std::size_t, std::size_t> best_key{std::numeric_limits<std::size_t>::max(), 0};
  for (double occupied : both_ways_occupied_grid()) {
    for (double margin : both_ways_margin_grid()) {
      Rule rule = base;
      rule.gate.gate_both_ways_min_occupied = occupied;
      rule.gate.gate_both_ways_min_margin = margin;
      std::size_t refused = 0, accepted_wrong = 0;
      for (std::size_t k = 0; k < rows.size(); ++k) {
        const bool accepted = rule.accepts(*rows[k], predicted[k]);
        refused += rows[k]->sample.correct && !accepted;
        accepted_wrong += !rows[k]->sample.correct && accepted;
      }
      const std::pair<std::size_t, std::size_t> key{accepted_wrong, refused};
      if (key < best_key) {  // strict to lenient: a tie keeps the stricter
        best = rule;
        best_key = key;
      }
    }
  }
  return best;
}

/// Nested leave-one-building-out cross-validation of the whole procedure: for each judging (real)
/// building, the model is fitted and the rule's thresholds chosen (`choose_rule` on the other
/// buildings' rows, all or real ones alone, and their own leave-one-building-out predictions) without any pair
/// that touches it, and then its pairs are judged; generated buildings only ever train. A pair of
/// two buildings is judged under both and counts as accepted only when both accept a right
/// answer, or either accepts a wrong one. Returns per row 1 (accepted), 0 (rejected) or −1 (not
/// judged: a generated building's); `chosen` gets each fold's rule.
inline std::vector<signed char> nested_rule_cv(const std::vector<CalibrationRow>& rows, const JudgingBuildings& judging, double l2,
                                               const areamatch::DecisionParams& base, double max_false_accept, bool choose_on_all,
                                               const Rule& given, std::vector<Rule>& chosen) {
  std::vector<int> verdict(rows.size(), -1);
  for (std::size_t held = 0; held < judging.judges.size(); ++held) {
    if (!judging.judges[held]) continue;  // generated buildings train, they do not judge
    std::vector<std::size_t> train, test;
    std::vector<areamatch::DecisionSample> samples;
    std::vector<std::array<std::size_t, 2>> groups;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto& r = rows[i];
      const std::array<std::size_t, 2> b = r.buildings();
      if (b[0] == held || b[1] == held) {
        test.push_back(i);
      } else {
        train.push_back(i);
        samples.push_back(r.sample);
        groups.push_back(b);
      }
    }
    if (test.empty()) continue;
    // The thresholds are chosen on all rows of the other buildings (or their judging rows alone),
    // each predicted by a model fitted without its buildings (the inner leave-one-building-out).
    // Choosing on real rows alone is unstable with few real buildings: without F5 the fold chose
    // a gate that accepted 3 % of F5's pairs of different places (docs/evaluation.md).
    const std::vector<double> train_predicted = areamatch::leave_one_building_out(samples, groups, l2, base);
    std::vector<std::size_t> inner;
    std::vector<double> inner_predicted;
    for (std::size_t k = 0; k < train.size(); ++k) {
      if (!choose_on_all && !judging.judged(train[k])) continue;
      inner.push_back(train[k]);
      inner_predicted.push_back(train_predicted[k]);
    }
    const Rule rule = choose_rule(rows, inner, inner_predicted, max_false_accept, given);
    chosen.push_back(rule);
    const areamatch::DecisionParams model = areamatch::fit_decision(samples, l2, base);
    for (std::size_t i : test) {
      const bool accepted = rule.accepts(rows[i], areamatch::p_correct(rows[i].sample.features, model));
      int& v = verdict[i];
      v = v < 0 ? accepted : rows[i].sample.correct ? (v && accepted) : (v || accepted);
    }
  }
  return std::vector<signed char>(verdict.begin(), verdict.end());
}

inline std::string percent(std::size_t part, std::size_t whole) {
  if (whole == 0) return "-";
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(1);
  s << 100.0 * static_cast<double>(part) / static_cast<double>(whole) << " %";
  return s.str();
}

/// One table line of counts: name | right | false rejects (%) | wrong of one building | accepted |
/// different buildings | accepted (%).
inline std::string counts_line(const std::string& name, const DecisionCounts& c) {
  return name + " | " + std::to_string(c.right) + " | " + std::to_string(c.right_rejected) + " (" +
         percent(c.right_rejected, c.right) + ") | " + std::to_string(c.wrong_same) + " | " +
         std::to_string(c.wrong_same_accepted) + " | " + std::to_string(c.different) + " | " +
         std::to_string(c.different_accepted) + " (" + percent(c.different_accepted, c.different) + ")\n";
}

/// The judging buildings' view of `accepted` (one per row; rows not judged are skipped): per
/// judging building, per modality (`modality`), their total, and the total of the other buildings'
/// rows (those that only train), each line titled with `what`.
inline std::string judged_report(const std::vector<CalibrationRow>& rows, const std::vector<signed char>& accepted,
                                 const std::vector<std::string>& buildings, const JudgingBuildings& judging,
                                 const MapRoles& roles, const std::string& what) {
  std::vector<DecisionCounts> per_building(buildings.size());
  std::map<std::string, DecisionCounts> per_modality;
  DecisionCounts judged_total, training_total;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CalibrationRow& r = rows[i];
    if (accepted[i] < 0) continue;
    const bool a = accepted[i] > 0;
    if (!judging.judged(i)) {
      training_total.add(r.sample.correct, r.different_buildings, a);
      continue;
    }
    judged_total.add(r.sample.correct, r.different_buildings, a);
    per_modality[modality(r, roles)].add(r.sample.correct, r.different_buildings, a);
    DecisionCounts::add_per_building(per_building, r, a);
  }
  const std::string kind = judging.all_judge ? "buildings (no real building in the rows: generated ones judge)" : "real buildings";
  std::string out = what + ", " + kind + ":\nbuilding | right answers | false rejects | wrong answers of one building | "
                    "accepted | pairs of different buildings | accepted\n";
  for (std::size_t b = 0; b < buildings.size(); ++b) {
    if (judging.judges[b]) out += counts_line(buildings[b], per_building[b]);
  }
  out += "modality (source -> destination) | right answers | false rejects | wrong answers of one building | accepted | "
         "pairs of different buildings | accepted\n";
  for (const auto& [name, counts] : per_modality) out += counts_line(name, counts);
  out += counts_line(judging.all_judge ? "total, all buildings" : "total, real buildings", judged_total);
  if (!judging.all_judge && training_total.right + training_total.wrong_same + training_total.different > 0) {
    out += counts_line("total, generated buildings (they train, they do not judge)", training_total);
  }
  return out;
}


/// One bin of a reliability table: its rows, their mean prediction, the share of right answers
/// among them, and that share with both classes weighted equally in total (the prior the model is
/// fitted under, `fit_decision`).
struct ReliabilityBin {
  std::size_t rows = 0;
  double mean_predicted = 0.0, observed = 0.0, observed_balanced = 0.0;
};

inline std::vector<ReliabilityBin> reliability(const std::vector<double>& predicted, const std::vector<CalibrationRow>& rows,
                                               int bins) {
  std::size_t positives = 0;
  for (const auto& r : rows) positives += r.sample.correct;
  const double n = static_cast<double>(rows.size());
  const double w_right = positives ? 0.5 * n / static_cast<double>(positives) : 0.0;
  const double w_wrong = positives < rows.size() ? 0.5 * n / static_cast<double>(rows.size() - positives) : 0.0;
  std::vector<ReliabilityBin> out(static_cast<std::size_t>(bins));
  std::vector<double> right(out.size(), 0.0), wrong(out.size(), 0.0);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto b = static_cast<std::size_t>(std::clamp(static_cast<int>(predicted[i] * bins), 0, bins - 1));
    ++out[b].rows;
    out[b].mean_predicted += predicted[i];
    (rows[i].sample.correct ? right[b] : wrong[b]) += 1.0;
  }
  for (std::size_t b = 0; b < out.size(); ++b) {
    if (out[b].rows == 0) continue;
    out[b].mean_predicted /= static_cast<double>(out[b].rows);
    out[b].observed = right[b] / static_cast<double>(out[b].rows);
    out[b].observed_balanced = w_right * right[b] / (w_right * right[b] + w_wrong * wrong[b]);
  }
  return out;
}

/// A reliability diagram as SVG: per bin of predicted probability, the share of right answers
/// with both classes weighted equally (dots, sized by the bin's rows) against the diagonal.
inline std::string reliability_svg(const std::vector<ReliabilityBin>& table) {
  const double size = 400.0, margin = 50.0;
  auto x = [&](double v) { return margin + v * size; };
  auto y = [&](double v) { return margin + (1.0 - v) * size; };
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(1);
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << size + 2 * margin << "\" height=\"" << size + 2 * margin
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<rect x=\"" << margin << "\" y=\"" << margin << "\" width=\"" << size << "\" height=\"" << size
    << "\" fill=\"none\" stroke=\"black\"/>\n<line x1=\"" << x(0) << "\" y1=\"" << y(0) << "\" x2=\"" << x(1) << "\" y2=\""
    << y(1) << "\" stroke=\"grey\" stroke-dasharray=\"4 4\"/>\n";
  for (int t = 0; t <= 10; t += 2) {
    const double v = t / 10.0;
    s << "<text x=\"" << x(v) << "\" y=\"" << y(0) + 16 << "\" text-anchor=\"middle\">" << v << "</text>\n<text x=\""
      << x(0) - 6 << "\" y=\"" << y(v) + 4 << "\" text-anchor=\"end\">" << v << "</text>\n";
  }
  s << "<text x=\"" << x(0.5) << "\" y=\"" << y(0) + 34 << "\" text-anchor=\"middle\">predicted p_correct "
    << "(leave-one-building-out)</text>\n<text transform=\"translate(14 " << y(0.5) << ") rotate(-90)\" "
    << "text-anchor=\"middle\">observed share of right answers (classes weighted equally)</text>\n";
  for (const ReliabilityBin& b : table) {
    if (b.rows == 0) continue;
    s << "<circle cx=\"" << x(b.mean_predicted) << "\" cy=\"" << y(b.observed_balanced) << "\" r=\""
      << 3.0 + 4.0 * std::log10(static_cast<double>(b.rows)) << "\" fill=\"steelblue\" fill-opacity=\"0.7\"/>\n<text x=\""
      << x(b.mean_predicted) + 8 << "\" y=\"" << y(b.observed_balanced) - 8 << "\">" << b.rows << "</text>\n";
  }
  s << "</svg>\n";
  return s.str();
}

}  // namespace areamatch_cli
