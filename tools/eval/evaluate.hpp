#pragma once
/// \file eval/evaluate.hpp
/// Evaluating the matcher on the pairs of a manifest (`eval/manifest.hpp`): per pair, the areas,
/// the times of each step (median over repeats), the transform and — with ground truth — its
/// error judged exactly as `shared/tools/score.py` judges it. Reports: `eval/eval_report.hpp`.
///
/// \code
/// const areamatch::Manifest manifest = areamatch::load_manifest("pairs.json");
/// areamatch::EvalOptions options;  // reflection allowed unless a pair says otherwise
/// std::vector<areamatch::PairEvaluation> rows;
/// for (const auto& pair : manifest.pairs) rows.push_back(areamatch::evaluate_pair(pair, manifest.correct_if, options));
/// const areamatch::EvalSummary summary = areamatch::summarize(rows);
/// \endcode

#include "manifest.hpp"

#include <areamatch/evaluation.hpp>
#include <areamatch/io/match_files.hpp>

#include <algorithm>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

namespace areamatch {

struct EvalOptions {
  /// Matching options for every pair; a pair's `door_width_m`, `*_resolution` and
  /// `allow_reflection` override them. Reflection is allowed by default because real pairs of
  /// a SLAM map and a layout are often mirror images (shared/pairs.json has several).
  MapPairOptions matching = [] {
    MapPairOptions o;
    o.allow_reflection = true;
    return o;
  }();
  int repeat = 1;  ///< runs per pair; times are the median, results must agree bit for bit
};

/// One row of an evaluation.
struct PairEvaluation {
  ManifestPair pair;
  std::string failure;             ///< non-empty when the pair could not run (bad map file, ...)
  MatchResult result;              ///< of the last run (all runs agree when `repeatable`)
  std::size_t source_areas = 0;
  std::size_t dest_areas = 0;
  MatchTimings timings;            ///< each field the median over the repeats
  std::optional<MatchError> error; ///< with ground truth only
  /// ok and within the manifest's `correct_if`; for a pair of different buildings: rejected
  bool correct = false;
  /// The transform is within `correct_if`, whether or not the matcher accepted it (with ground
  /// truth only): what a decision rule is calibrated against.
  bool transform_correct = false;
  bool repeatable = true;          ///< every repeat gave a bit-identical transform and score
  int runs = 0;
};

/// Counts and time statistics over the rows (failed rows excluded from times).
struct EvalSummary {
  std::size_t pairs = 0;
  std::size_t failed = 0;
  std::size_t matched = 0;         ///< result.ok
  std::size_t with_truth = 0;
  std::size_t correct = 0;
  std::size_t non_ambiguous = 0;   ///< with ground truth and not marked ambiguous
  std::size_t correct_non_ambiguous = 0;
  std::size_t not_repeatable = 0;
  std::size_t same_building = 0;        ///< pairs not marked different_buildings (that ran)
  std::size_t same_accepted = 0;        ///< ... and ok
  std::size_t different_buildings = 0;  ///< pairs that must not match (that ran)
  std::size_t different_rejected = 0;   ///< ... and not ok
  double median_total_s = 0.0, mean_total_s = 0.0;
  double median_match_s = 0.0, mean_match_s = 0.0;
  double median_segment_s = 0.0;   ///< per map
  double median_rotation_error_deg = 0.0, median_displacement_m = 0.0;  ///< over rows with truth
  std::size_t scale_estimated = 0;  ///< rows whose result estimated the source's scale
  double median_scale_error = 0.0, max_scale_error = 0.0;  ///< over those rows with truth
};

namespace detail {

inline double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

inline double mean_of(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x;
  return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}

/// Same transform and score, bit for bit.
inline bool same_answer(const MatchResult& a, const MatchResult& b) {
  return a.ok == b.ok && std::memcmp(a.pixel_transform.data(), b.pixel_transform.data(), sizeof(double) * 6) == 0 &&
         std::memcmp(&a.score, &b.score, sizeof(double)) == 0;
}

inline MatchTimings median_timings(const std::vector<MatchTimings>& runs) {
  auto median_field = [&](double MatchTimings::*field) {
    std::vector<double> v;
    for (const auto& t : runs) v.push_back(t.*field);
    return median_of(std::move(v));
  };
  MatchTimings m;
  for (double MatchTimings::*field : {&MatchTimings::segment_source_s, &MatchTimings::segment_dest_s,
                                      &MatchTimings::prepare_s, &MatchTimings::features_s,
                                      &MatchTimings::hypotheses_s, &MatchTimings::clustering_s, &MatchTimings::selection_s,
                                      &MatchTimings::match_s, &MatchTimings::total_s}) {
    m.*field = median_field(field);
  }
  return m;
}

}  // namespace detail

/// The options one pair runs with: `options.matching` with the pair's own settings over it.
inline MapPairOptions pair_options(const ManifestPair& pair, const EvalOptions& options) {
  MapPairOptions o = options.matching;
  if (pair.door_width_m) o.source_door_width_m = o.dest_door_width_m = pair.door_width_m;
  if (pair.source_resolution) o.source_load.resolution = pair.source_resolution;
  if (pair.destination_resolution) o.dest_load.resolution = pair.destination_resolution;
  if (pair.allow_reflection) o.allow_reflection = *pair.allow_reflection;
  return o;
}

/// Runs one pair `options.repeat` times and judges it. A map that cannot be loaded or segmented
/// gives a row with `failure` set, not an exception, so that one bad pair does not hide the
/// others. `last_run`, when given, receives the maps, graphs and result of the last run (for
/// pictures).
inline PairEvaluation evaluate_pair(const ManifestPair& pair, const CorrectnessThresholds& correct_if,
                                    const EvalOptions& options, MapPairRun* last_run = nullptr) {
  if (options.repeat < 1) throw parameter_error("EvalOptions::repeat must be at least 1");
  PairEvaluation row;
  row.pair = pair;
  const MapPairOptions matching = pair_options(pair, options);
  std::vector<MatchTimings> timings;
  std::optional<MapPairRun> run;
  for (int i = 0; i < options.repeat; ++i) {
    try {
      run = match_map_files(pair.source, pair.destination, matching);
    } catch (const std::exception& e) {
      row.failure = e.what();
      return row;
    }
    if (i > 0 && !detail::same_answer(run->result, row.result)) row.repeatable = false;
    row.result = run->result;
    timings.push_back(run->result.timings);
    ++row.runs;
  }
  row.timings = detail::median_timings(timings);
  row.source_areas = run->source_graph.areas.size();
  row.dest_areas = run->dest_graph.areas.size();
  if (pair.different_buildings) row.correct = !row.result.ok;
  if (pair.ground_truth) {
    row.error = match_error(row.result.pixel_transform, *pair.ground_truth, free_edge_pixels(run->source),
                            run->dest.resolution());
    row.transform_correct = row.error->correct(correct_if);
    row.correct = row.result.ok && row.transform_correct;
  }
  if (last_run) *last_run = std::move(*run);
  return row;
}

inline EvalSummary summarize(const std::vector<PairEvaluation>& rows) {
  EvalSummary s;
  std::vector<double> total, match, segment, rotation, displacement, scale_errors;
  for (const auto& r : rows) {
    ++s.pairs;
    if (!r.failure.empty()) {
      ++s.failed;
      continue;
    }
    s.matched += r.result.ok;
    s.not_repeatable += !r.repeatable;
    total.push_back(r.timings.total_s);
    match.push_back(r.timings.match_s);
    segment.push_back(r.timings.segment_source_s);
    segment.push_back(r.timings.segment_dest_s);
    if (r.pair.different_buildings) {
      ++s.different_buildings;
      s.different_rejected += !r.result.ok;
    } else {
      ++s.same_building;
      s.same_accepted += r.result.ok;
    }
    s.scale_estimated += r.result.scale_estimated;
    if (!r.error) continue;
    if (r.result.scale_estimated) scale_errors.push_back(r.error->scale_error);
    ++s.with_truth;
    s.correct += r.correct;
    if (!r.pair.ambiguous) {
      ++s.non_ambiguous;
      s.correct_non_ambiguous += r.correct;
    }
    rotation.push_back(r.error->rotation_error_deg);
    displacement.push_back(r.error->mean_displacement_m);
  }
  s.median_total_s = detail::median_of(total);
  s.mean_total_s = detail::mean_of(total);
  s.median_match_s = detail::median_of(match);
  s.mean_match_s = detail::mean_of(match);
  s.median_segment_s = detail::median_of(segment);
  s.median_rotation_error_deg = detail::median_of(rotation);
  s.median_displacement_m = detail::median_of(displacement);
  s.median_scale_error = detail::median_of(scale_errors);
  for (double e : scale_errors) s.max_scale_error = std::max(s.max_scale_error, e);
  return s;
}

}  // namespace areamatch
