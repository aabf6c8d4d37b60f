#pragma once
/// \file eval/eval_report.hpp
/// An evaluation (`eval/evaluate.hpp`) as a text table for the terminal, JSON, CSV and a Markdown
/// report with one picture per pair. Times in milliseconds in the table, CSV and Markdown,
/// seconds in JSON (like `match_result_json`).

#include "evaluate.hpp"

#include <areamatch/detail/format.hpp>
#include <areamatch/io/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace areamatch {

namespace detail {

inline std::string milliseconds(double seconds) { return format_fixed(1000.0 * seconds, 1); }

/// The columns shared by the table, the CSV and the Markdown report.
inline const std::vector<std::string>& eval_columns() {
  static const std::vector<std::string> columns = {
      "pair",     "areas src/dst", "seg src ms", "seg dst ms", "match ms", "total ms",
      "matched",  "score",         "rot deg",    "rot err deg", "disp m",  "correct"};
  return columns;
}

inline std::vector<std::string> eval_cells(const PairEvaluation& r) {
  const std::string name = r.pair.name + (r.pair.ambiguous ? " (ambiguous)" : "") +
                           (r.pair.different_buildings ? " (different)" : "");
  if (!r.failure.empty()) return {name, "-", "-", "-", "-", "-", "error", "-", "-", "-", "-", "-"};
  const MatchTimings& t = r.timings;
  const Similarity2& T = r.result.T_dest_source;
  return {name,
          std::to_string(r.source_areas) + "/" + std::to_string(r.dest_areas),
          milliseconds(t.segment_source_s),
          milliseconds(t.segment_dest_s),
          milliseconds(t.match_s),
          milliseconds(t.total_s),
          r.result.ok ? "yes" : "no",
          format_fixed(r.result.score, 3),
          format_fixed(T.rotation * 180.0 / pi, 2) + (T.reflected ? " mirrored" : ""),
          r.error ? format_fixed(r.error->rotation_error_deg, 2) : "-",
          r.error ? format_fixed(r.error->mean_displacement_m, 3) : "-",
          r.error || r.pair.different_buildings ? (r.correct ? "yes" : "NO") : "-"};
}

inline std::vector<std::string> eval_summary_lines(const EvalSummary& s) {
  std::vector<std::string> lines;
  if (s.with_truth > 0) {
    lines.push_back("correct: " + std::to_string(s.correct) + " / " + std::to_string(s.with_truth) + " (" +
                    std::to_string(s.correct_non_ambiguous) + " / " + std::to_string(s.non_ambiguous) +
                    " not marked ambiguous); median rotation error " + format_fixed(s.median_rotation_error_deg, 2) +
                    " deg, median displacement " + format_fixed(s.median_displacement_m, 3) + " m");
  } else {
    lines.push_back("no ground truth: transforms, scores and times only");
  }
  lines.push_back("matched (ok): " + std::to_string(s.matched) + " / " + std::to_string(s.pairs - s.failed) +
                  (s.failed ? "; " + std::to_string(s.failed) + " pair(s) could not run" : ""));
  if (s.different_buildings > 0) {
    auto percent = [](std::size_t a, std::size_t b) { return b ? " (" + format_fixed(100.0 * a / b, 1) + " %)" : ""; };
    lines.push_back("pairs of one building accepted: " + std::to_string(s.same_accepted) + " / " +
                    std::to_string(s.same_building) + percent(s.same_accepted, s.same_building) +
                    "; pairs of different buildings rejected: " + std::to_string(s.different_rejected) + " / " +
                    std::to_string(s.different_buildings) + percent(s.different_rejected, s.different_buildings));
  }
  lines.push_back("time per pair: median " + milliseconds(s.median_total_s) + " ms, mean " + milliseconds(s.mean_total_s) +
                  " ms; matching median " + milliseconds(s.median_match_s) + " ms, mean " + milliseconds(s.mean_match_s) +
                  " ms; segmentation median " + milliseconds(s.median_segment_s) + " ms per map");
  if (s.scale_estimated > 0 && s.with_truth > 0) {
    lines.push_back("scale estimated for " + std::to_string(s.scale_estimated) + " pair(s): median scale error " +
                    format_fixed(100.0 * s.median_scale_error, 2) + " %, largest " +
                    format_fixed(100.0 * s.max_scale_error, 2) + " %");
  }
  if (s.not_repeatable) lines.push_back("NOT REPEATABLE: " + std::to_string(s.not_repeatable) + " pair(s) changed between runs");
  return lines;
}

inline std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

inline std::string markdown_cell(const std::string& s) {
  std::string out;
  for (char c : s) out += c == '|' ? std::string("\\|") : c == '\n' ? std::string(" ") : std::string(1, c);
  return out;
}

}  // namespace detail

/// A fixed-width table, one line per pair, then the summary lines; failed pairs list their error.
inline std::string eval_table(const std::vector<PairEvaluation>& rows, const EvalSummary& summary) {
  const auto& columns = detail::eval_columns();
  std::vector<std::vector<std::string>> cells;
  for (const auto& r : rows) cells.push_back(detail::eval_cells(r));
  std::vector<std::size_t> width(columns.size());
  for (std::size_t c = 0; c < columns.size(); ++c) {
    width[c] = columns[c].size();
    for (const auto& line : cells) width[c] = std::max(width[c], line[c].size());
  }
  auto line_of = [&](const std::vector<std::string>& line) {
    std::string out;
    for (std::size_t c = 0; c < line.size(); ++c) {
      const std::string pad(width[c] - line[c].size(), ' ');
      out += c == 0 ? line[c] + pad : "  " + pad + line[c];  // names left, numbers right
    }
    return out + "\n";
  };
  std::string out = line_of(columns);
  for (const auto& line : cells) out += line_of(line);
  for (const auto& r : rows) {
    if (!r.failure.empty()) out += "error in " + r.pair.name + ": " + r.failure + "\n";
    else if (!r.result.ok) out += "no match for " + r.pair.name + ": " + r.result.reason + "\n";
  }
  for (const auto& l : detail::eval_summary_lines(summary)) out += l + "\n";
  return out;
}

/// One CSV line per pair with the full numbers (times in ms); empty cells where not applicable.
inline std::string eval_csv(const std::vector<PairEvaluation>& rows) {
  using detail::csv_field;
  using detail::format_double;
  std::string out =
      "name,kind,source,destination,ambiguous,different_buildings,source_areas,dest_areas,segment_source_ms,segment_dest_ms,match_ms,total_ms,ok,reason,"
      "rotation_deg,translation_x_m,translation_y_m,scale,scale_estimated,reflected,score,margin,p_correct,agreement,wall_agreement,reverse_wall_agreement,forward_wall_agreement,free_iou,source_on_dest,dest_on_source,passage_agreement,room_agreement,overlap_m2,turn_margin,occupied_wall_agreement,rotation_error_deg,displacement_m,scale_error,correct,transform_correct,"
      "repeatable,runs,failure\n";
  for (const auto& r : rows) {
    const bool ran = r.failure.empty();
    const MatchTimings& t = r.timings;
    const Similarity2& T = r.result.T_dest_source;
    auto number = [&](double v) { return ran ? format_double(v) : std::string(); };
    out += csv_field(r.pair.name) + "," + csv_field(r.pair.kind) + "," + csv_field(r.pair.source) + "," +
           csv_field(r.pair.destination) + "," + (r.pair.ambiguous ? "true" : "false") + "," +
           (r.pair.different_buildings ? "true" : "false") + ",";
    out += ran ? std::to_string(r.source_areas) + "," + std::to_string(r.dest_areas) + "," : std::string(",,");
    out += number(1000.0 * t.segment_source_s) + "," + number(1000.0 * t.segment_dest_s) + "," +
           number(1000.0 * t.match_s) + "," + number(1000.0 * t.total_s) + ",";
    out += (ran ? std::string(r.result.ok ? "true" : "false") : std::string()) + "," + csv_field(r.result.reason) + ",";
    out += number(T.rotation * 180.0 / pi) + "," + number(T.translation.x()) + "," + number(T.translation.y()) + "," +
           number(T.scale) + "," + (ran ? std::string(r.result.scale_estimated ? "true" : "false") : std::string()) + "," +
           (ran ? std::string(T.reflected ? "true" : "false") : std::string()) + ",";
    out += number(r.result.score) + "," + number(r.result.margin) + "," + number(r.result.p_correct) + ",";
    const MatchEvidence& e = r.result.evidence;
    for (double v : {e.agreement, e.wall_agreement, e.reverse_wall_agreement, e.forward_wall_agreement, e.free_iou, e.source_on_dest,
                     e.dest_on_source, e.passage_agreement, e.room_agreement, e.overlap_m2, e.turn_margin,
                     e.occupied_wall_agreement}) {
      out += (std::isfinite(v) ? number(v) : std::string()) + ",";
    }
    out += r.error ? format_double(r.error->rotation_error_deg) + "," + format_double(r.error->mean_displacement_m) + "," +
                         format_double(r.error->scale_error) + "," + (r.correct ? "true" : "false") + "," +
                         (r.transform_correct ? "true" : "false") + ","
                   : std::string(",,,") + (r.pair.different_buildings && ran ? (r.correct ? "true" : "false") : "") + ",,";
    out += std::string(r.repeatable ? "true" : "false") + "," + std::to_string(r.runs) + "," + csv_field(r.failure) + "\n";
  }
  return out;
}

/// The manifest, the summary and per pair its row, its match result (as `match_result_json`)
/// and, with ground truth, its error.
inline std::string eval_json(const Manifest& manifest, const std::vector<PairEvaluation>& rows, const EvalSummary& s) {
  using detail::json_number;
  using detail::json_quote;
  std::string out = "{\"manifest\": " + json_quote(manifest.path) + ", \"correct_if\": {\"max_rotation_error_deg\": " +
                    json_number(manifest.correct_if.max_rotation_error_deg) + ", \"max_mean_displacement_m\": " +
                    json_number(manifest.correct_if.max_mean_displacement_m) + "},\n \"summary\": {";
  out += "\"pairs\": " + std::to_string(s.pairs) + ", \"failed\": " + std::to_string(s.failed) +
         ", \"matched\": " + std::to_string(s.matched) + ", \"with_ground_truth\": " + std::to_string(s.with_truth) +
         ", \"correct\": " + std::to_string(s.correct) + ", \"non_ambiguous\": " + std::to_string(s.non_ambiguous) +
         ", \"correct_non_ambiguous\": " + std::to_string(s.correct_non_ambiguous) +
         ", \"not_repeatable\": " + std::to_string(s.not_repeatable) +
         ", \"same_building\": " + std::to_string(s.same_building) +
         ", \"same_accepted\": " + std::to_string(s.same_accepted) +
         ", \"different_buildings\": " + std::to_string(s.different_buildings) +
         ", \"different_rejected\": " + std::to_string(s.different_rejected) +
         ", \"median_total_s\": " + json_number(s.median_total_s) + ", \"mean_total_s\": " + json_number(s.mean_total_s) +
         ", \"median_match_s\": " + json_number(s.median_match_s) + ", \"mean_match_s\": " + json_number(s.mean_match_s) +
         ", \"median_segment_s\": " + json_number(s.median_segment_s) +
         ", \"median_rotation_error_deg\": " + json_number(s.median_rotation_error_deg) +
         ", \"median_displacement_m\": " + json_number(s.median_displacement_m) +
         ", \"scale_estimated\": " + std::to_string(s.scale_estimated) +
         ", \"median_scale_error\": " + json_number(s.median_scale_error) +
         ", \"max_scale_error\": " + json_number(s.max_scale_error) + "},\n \"pairs\": [";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    out += std::string(i ? ",\n  " : "\n  ") + "{\"name\": " + json_quote(r.pair.name) + ", \"kind\": " +
           json_quote(r.pair.kind) + ", \"ambiguous\": " + (r.pair.ambiguous ? "true" : "false") +
           ", \"different_buildings\": " + (r.pair.different_buildings ? "true" : "false") +
           ", \"source\": " + json_quote(r.pair.source) + ", \"destination\": " + json_quote(r.pair.destination);
    if (!r.failure.empty()) {
      out += ", \"failure\": " + json_quote(r.failure) + "}";
      continue;
    }
    out += ", \"source_areas\": " + std::to_string(r.source_areas) + ", \"dest_areas\": " + std::to_string(r.dest_areas) +
           ", \"runs\": " + std::to_string(r.runs) + ", \"repeatable\": " + (r.repeatable ? "true" : "false");
    if (r.pair.different_buildings) out += std::string(", \"correct\": ") + (r.correct ? "true" : "false");
    if (r.error) {
      out += ", \"rotation_error_deg\": " + json_number(r.error->rotation_error_deg) +
             ", \"displacement_m\": " + json_number(r.error->mean_displacement_m) +
             ", \"scale_error\": " + json_number(r.error->scale_error) +
             ", \"correct\": " + (r.correct ? "true" : "false");
    }
    MatchResult shown = r.result;
    shown.timings = r.timings;  // the medians
    out += ", \"result\": " + match_result_json(shown) + "}";
  }
  return out + "\n ]}\n";
}

/// A Markdown report: the summary, the table, and per pair its picture (`pictures[i]`, a path
/// relative to the report; empty for none) with the result's reason when not ok.
inline std::string eval_markdown(const Manifest& manifest, const std::vector<PairEvaluation>& rows,
                                 const EvalSummary& summary, const std::vector<std::string>& pictures) {
  using detail::format_fixed;
  using detail::markdown_cell;
  std::string out = "# areamatch evaluation of `" + manifest.path + "`\n\n";
  for (const auto& l : detail::eval_summary_lines(summary)) out += "- " + l + "\n";
  out += "\nCorrect when the rotation error is at most " + format_fixed(manifest.correct_if.max_rotation_error_deg, 2) +
         " deg and the mean displacement of the source's free-space edge at most " +
         format_fixed(manifest.correct_if.max_mean_displacement_m, 2) + " m (the manifest's `correct_if`).\n\n|";
  const auto& columns = detail::eval_columns();
  for (const auto& c : columns) out += " " + c + " |";
  out += "\n|";
  for (std::size_t c = 0; c < columns.size(); ++c) out += c == 0 ? "---|" : "---:|";
  out += "\n";
  for (const auto& r : rows) {
    out += "|";
    for (const auto& cell : detail::eval_cells(r)) out += " " + markdown_cell(cell) + " |";
    out += "\n";
  }
  out += "\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    out += "## " + markdown_cell(r.pair.name) + "\n\n`" + r.pair.source + "` onto `" + r.pair.destination + "`\n\n";
    if (!r.failure.empty()) {
      out += "Could not run: " + markdown_cell(r.failure) + "\n\n";
      continue;
    }
    if (!r.result.ok) out += "No match: " + markdown_cell(r.result.reason) + "\n\n";
    if (i < pictures.size() && !pictures[i].empty()) {
      out += "![" + markdown_cell(r.pair.name) + "](" + pictures[i] +
             ")\n\nLeft: source with matched areas tinted. Right: destination with the source's walls (red) laid over "
             "it by the result.\n\n";
    }
  }
  return out;
}

}  // namespace areamatch
