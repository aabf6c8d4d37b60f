#pragma once
/// \file match/decision/decision.hpp
/// Whether a match is right: a calibrated probability from several signals of the result, and
/// the rule that turns it into `MatchResult::ok`.
///
/// No single measure separates right from wrong answers across buildings and sensors (the wall
/// agreement of true pairs of unseen buildings overlaps that of pairs of different buildings),
/// so the decision is a logistic model over signals that fail in different ways:
///
///   walls_best, walls_worst  the better and the worse of the two overlap-restricted wall
///                            agreements (`MatchEvidence::forward/reverse_wall_agreement`)
///   rooms                    `MatchEvidence::room_agreement`: the common part cut into the same rooms
///   margin, log_margin       `MatchResult::margin` and log10(margin + 0.01): how far the
///                            answer stands out from the pair's own alternatives (other clusters'
///                            refined answers, the mirror); the log spreads the small margins
///                            where right and wrong answers part (0.003 against 0.1)
///   log_overlap              log10 of the common free space in m² (a small overlap proves little)
///   turn_margin              `MatchEvidence::turn_margin`: how far the answer's walls stand out from
///                            those of its own quarter turns and mirror images, each refined (in a
///                            building of repeated rooms the wrong answer is often the right one turned)
///   free_iou                 `MatchEvidence::free_iou`: how much of the two maps' free space is shared
///   occupied_walls           `MatchEvidence::occupied_wall_agreement` (0 when not measured): whether
///                            the walls away from the shared free space — of rooms seen but not
///                            entered — fall on each other too (two alike buildings agree in
///                            their shared part, not there)
///
/// Two weights are fitted negative: walls_worst and log_overlap. They are conditional effects
/// beside the signals they move with (walls_worst with walls_best, log_overlap with the margins
/// and free_iou), not a claim that agreeing walls or more shared space count against an answer:
/// both wall agreements rising together still raise p_correct (tests/test_decision.cpp pins the
/// signs, so a refit that flips one is looked at).
///
/// The coefficients are fitted by `fit_decision` (L2-regularised logistic regression, both classes
/// weighted equally) and chosen by leave-one-building-out cross-validation over every real
/// building we have plus synthetic ones (`areamatch calibrate`, docs/evaluation.md). Fitting your
/// own on your buildings and sensors works the same way.

#include "../../error.hpp"
#include "../result.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace areamatch {

/// The signals of one result that the decision reads (see the file comment).
struct DecisionFeatures {
  static constexpr std::size_t size = 9;
  std::array<double, size> values{};  ///< in the order of `names`
  static constexpr std::array<const char*, size> names = {"walls_best",  "walls_worst", "rooms",
                                                          "margin",      "log_margin",  "log_overlap",
                                                          "turn_margin", "free_iou",    "occupied_walls"};
  /// The position of signal `name` in `values`; throws `parameter_error` for a name not in `names`.
  static std::size_t index(std::string_view name) {
    for (std::size_t i = 0; i < size; ++i) {
      if (name == names[i]) return i;
    }
    throw parameter_error("DecisionFeatures: no signal named '" + std::string(name) + "'");
  }
  /// Signal `name`'s value, by name (positions shift when a signal is added; names do not).
  double& operator[](std::string_view name) { return values[index(name)]; }
  double operator[](std::string_view name) const { return values[index(name)]; }
};

/// The accept/reject rule in one place: its thresholds and the logistic model
/// p = 1 / (1 + exp(−(bias + Σ weights_i · x_i))) it reads. An answer is accepted (`MatchResult::ok`)
/// when its whole-map score is at least `min_score`, p ≥ `accept_p_correct` or the agreement gate
/// lets it through (agreement ≥ `min_agreement`, at least `gate_min_overlap_m2` of shared free
/// space, and either the lower wall agreement ≤ `gate_max_lower_walls` or, where the walls agree
/// both ways, the walls of rooms seen but not entered agreeing ≥ `gate_both_ways_min_occupied` with
/// a margin to the best rival ≥ `gate_both_ways_min_margin`), p ≥ `min_p_correct`, and no rival is
/// within `min_margin`. match/decision/acceptance.hpp applies it and words each refusal.
struct DecisionParams {
  /// Below this whole-map score (see `MatchResult::score`) the best transform is rejected, and the
  /// refusal says "different places". 0.1, below every right answer of the calibration rows (real:
  /// 0.357 and more) and of the simulated SLAM maps (0.181 and more: much furniture and many
  /// people); it decides no measured outcome (on those rows no answer below 0.25 would have been
  /// accepted otherwise) but words the refusal of maps whose edges barely meet. 0.25 until
  /// 2026-12-07, which called three right answers of simulated maps "different places", one of
  /// them at p_correct 0.98 (docs/evaluation.md, "Simulated laser-SLAM maps").
  double min_score = 0.1;
  /// Below this `MatchEvidence::agreement` the answer is rejected unless the model is sure
  /// (`accept_p_correct`); at or above it the agreement gate may accept it alone (below). 0.835:
  /// every true pair of the first calibration scored 0.840 or more (docs/evaluation.md). Above 1
  /// the gate never accepts and the model alone decides.
  double min_agreement = 0.835;
  /// The agreement gate accepts an answer the model is not sure of only where the lower of the two
  /// wall agreements (the decision's `walls_worst`) is at most this: a map whose walls the other
  /// cannot explain — a SLAM map's furniture and laser streaks against a plan — where the model
  /// underrates right answers; where the walls agree both ways the model judges alone (alike
  /// buildings agree like that too). Chosen by `areamatch calibrate --choose-rule` in its nested
  /// cross-validation (docs/evaluation.md). Above 1: the gate whatever the walls.
  double gate_max_lower_walls = 0.7;
  /// The agreement gate also needs at least this much shared free space (`MatchEvidence::
  /// overlap_m2`, destination m²): agreeing walls prove little on one room. 100 m² (a few rooms),
  /// chosen as `gate_max_lower_walls` was (docs/evaluation.md). 0: the gate whatever the overlap.
  double gate_min_overlap_m2 = 100.0;
  /// Where the walls agree both ways (the lower wall agreement above `gate_max_lower_walls`) the
  /// gate still opens when the walls away from the shared free space agree too
  /// (`MatchEvidence::occupied_wall_agreement` at least this) and the answer stands out from its
  /// rivals (`gate_both_ways_min_margin`). Two alike buildings agree in their shared corridors,
  /// not in the rooms seen but not entered; a simulated or clean SLAM map of the plan's building
  /// agrees in both (docs/evaluation.md, "Where the walls agree both ways"). 0.85: on the rows of
  /// `scripts/calibration_data.sh` and its simulated SLAM sets, the wrong answers in this region
  /// reach 0.771 and every value from 0.78 to 0.85 accepts and refuses the same rows; the choice
  /// (`areamatch calibrate --simulated`), left out plan by plan, keeps the strictest. Above 1: this
  /// part of the gate is off.
  double gate_both_ways_min_occupied = 0.85;
  /// ... and needs `MatchResult::margin` at least this: a symmetric building's turned copy agrees
  /// both ways as well as the right answer (a pentagonal floor, 72° apart), and only its margin,
  /// 0.000–0.006 (the right answers': mostly above 0.01; the few below 0.007, the pentagon's among
  /// them, are refused here unless the model is sure),
  /// says that the evidence cannot tell them apart. 0.007, chosen with
  /// `gate_both_ways_min_occupied` (docs/evaluation.md).
  double gate_both_ways_min_margin = 0.007;
  /// Below this margin to a different or mirrored rival the answer is rejected.
  double min_margin = 0.0;
  /// Fitted by `areamatch calibrate` (l2 = 1) on the 7392 rows of `scripts/calibration_data.sh`
  /// (141 buildings: shared/pairs.json and its pairs of different buildings both ways,
  /// shared/handheld/pairs.json with and without reflection and its pairs of different places,
  /// shared maps against hand-held ones both ways, three generated sets of 20 buildings with their
  /// cross pairs both ways, 50 generated hand-held pairs and 12 more buildings with their cross
  /// pairs; 2026-12-03, with occupied_walls the higher of its two directions). The
  /// leave-one-building-out rates are in docs/evaluation.md.
  double bias = -16.256;
  std::array<double, DecisionFeatures::size> weights = {12.079, -1.785, 1.611, 2.541, 2.024,
                                                        -0.793, 5.543,  2.833, 9.905};  ///< `names` order
  /// An answer is accepted on the model alone at or above this, even when the maps' agreement is
  /// below `min_agreement`: the rule is "p_correct ≥ accept_p_correct, or agreement
  /// ≥ min_agreement with the lower wall agreement ≤ gate_max_lower_walls". 0.85 is what
  /// `areamatch calibrate --choose-rule --max-false-accept 0.002` chooses from data (the fewest
  /// right answers rejected with at most 0.2 % of the wrong ones accepted, judged on
  /// leave-one-building-out predictions; 139 of the 141 folds of the nested cross-validation
  /// choose it too). Cross-validated by building the rule rejects 2 of 256 right answers and
  /// accepts 1 of 7134 wrong ones; the whole choice, cross-validated by building (nested), the
  /// same (docs/evaluation.md).
  double accept_p_correct = 0.85;
  /// Below this the answer is rejected whatever the agreement (0: off).
  double min_p_correct = 0.0;
  /// A refused answer is called "different places" (`Rejection::different_places`) only when
  /// p_correct is below this — the model puts 99 % on the answer being wrong — and "not sure"
  /// above it. It words the refusal and never changes `ok`. 0.01 by principle; on the rows of
  /// `scripts/calibration_data.sh` (2026-12-05), with p_correct cross-validated by building, no
  /// right answer of a real building is below it (the lowest: Intel's 0.038) and 84 % of their
  /// wrong ones are (docs/evaluation.md, "What a rejection says").
  double different_places_p = 0.01;

  void validate() const {
    detail::require_non_negative(min_score, "DecisionParams::min_score");
    detail::require_non_negative(min_agreement, "DecisionParams::min_agreement");
    detail::require_non_negative(gate_max_lower_walls, "DecisionParams::gate_max_lower_walls");
    detail::require_non_negative(gate_min_overlap_m2, "DecisionParams::gate_min_overlap_m2");
    detail::require_non_negative(gate_both_ways_min_occupied, "DecisionParams::gate_both_ways_min_occupied");
    if (!std::isfinite(gate_both_ways_min_margin)) {
      throw parameter_error("DecisionParams::gate_both_ways_min_margin must be finite");
    }
    if (!std::isfinite(min_margin)) throw parameter_error("DecisionParams::min_margin must be finite");
    if (!std::isfinite(bias)) throw parameter_error("DecisionParams::bias must be finite");
    for (double w : weights) {
      if (!std::isfinite(w)) throw parameter_error("DecisionParams::weights must be finite");
    }
    if (!(min_p_correct >= 0.0 && min_p_correct <= 1.0)) {
      throw parameter_error("DecisionParams::min_p_correct must be in [0, 1]");
    }
    if (!(accept_p_correct >= 0.0 && accept_p_correct <= 1.0)) {
      throw parameter_error("DecisionParams::accept_p_correct must be in [0, 1]");
    }
    if (!(different_places_p >= 0.0 && different_places_p <= 1.0)) {
      throw parameter_error("DecisionParams::different_places_p must be in [0, 1]");
    }
  }
};

/// The lower of the two wall agreements in [0, 1] (0 when not measured): the decision's
/// `walls_worst`, and what limits the agreement gate (`DecisionParams::gate_max_lower_walls`).
inline double lower_wall_agreement(const MatchEvidence& e) {
  const double lower = std::min(e.forward_wall_agreement, e.reverse_wall_agreement);
  return std::isfinite(lower) ? std::clamp(lower, 0.0, 1.0) : 0.0;
}

/// The decision's signals of a result (NaN-free: missing margins count as none).
inline DecisionFeatures decision_features(const MatchResult& r) {
  const MatchEvidence& e = r.evidence;
  auto unit = [](double v) { return std::isfinite(v) ? std::clamp(v, 0.0, 1.0) : 0.0; };
  DecisionFeatures f;
  const double margin = unit(r.margin);
  // Not measured (the turn check needs the refinement): no sign that the answer stands out.
  const double turn_margin = std::isfinite(e.turn_margin) ? std::clamp(e.turn_margin, -1.0, 1.0) : 0.0;
  f["walls_best"] = unit(std::max(e.forward_wall_agreement, e.reverse_wall_agreement));
  f["walls_worst"] = lower_wall_agreement(e);
  f["rooms"] = unit(e.room_agreement);
  f["margin"] = margin;
  f["log_margin"] = std::log10(margin + 0.01);
  f["log_overlap"] = std::log10(std::max(1.0, std::isfinite(e.overlap_m2) ? e.overlap_m2 : 1.0));
  f["turn_margin"] = turn_margin;
  f["free_iou"] = unit(e.free_iou);
  f["occupied_walls"] = unit(e.occupied_wall_agreement);
  return f;
}

/// The model's probability that the answer with these signals is right.
inline double p_correct(const DecisionFeatures& f, const DecisionParams& p) {
  double z = p.bias;
  for (std::size_t i = 0; i < DecisionFeatures::size; ++i) z += p.weights[i] * f.values[i];
  return 1.0 / (1.0 + std::exp(-z));
}

/// One labelled example for `fit_decision`.
struct DecisionSample {
  DecisionFeatures features;
  bool correct = false;
};

/// L2-regularised logistic regression (Newton's method), the right and the wrong examples
/// weighted equally in total, so that the fit does not lean on how many pairs of different
/// buildings were run. `l2` penalises the weights (not the bias). Keeps `min_p_correct` of `base`.
/// Throws `parameter_error` without examples of both kinds.
inline DecisionParams fit_decision(const std::vector<DecisionSample>& samples, double l2 = 1.0,
                                   const DecisionParams& base = {}) {
  constexpr int d = static_cast<int>(DecisionFeatures::size) + 1;
  std::size_t positives = 0;
  for (const auto& s : samples) positives += s.correct;
  const std::size_t negatives = samples.size() - positives;
  if (positives == 0 || negatives == 0) {
    throw parameter_error("fit_decision needs right and wrong examples (got " + std::to_string(positives) + " and " +
                          std::to_string(negatives) + ")");
  }
  if (!(l2 > 0.0) || !std::isfinite(l2)) throw parameter_error("fit_decision: l2 must be positive");
  const double n = static_cast<double>(samples.size());
  const double w_pos = 0.5 * n / static_cast<double>(positives), w_neg = 0.5 * n / static_cast<double>(negatives);
  Eigen::Matrix<double, d, 1> beta = Eigen::Matrix<double, d, 1>::Zero();
  for (int iteration = 0; iteration < 100; ++iteration) {
    Eigen::Matrix<double, d, 1> gradient = Eigen::Matrix<double, d, 1>::Zero();
    Eigen::Matrix<double, d, d> hessian = Eigen::Matrix<double, d, d>::Zero();
    for (const auto& s : samples) {
      Eigen::Matrix<double, d, 1> x;
      x(0) = 1.0;
      for (int i = 1; i < d; ++i) x(i) = s.features.values[static_cast<std::size_t>(i - 1)];
      const double p = 1.0 / (1.0 + std::exp(-beta.dot(x)));
      const double w = s.correct ? w_pos : w_neg;
      gradient += w * (p - (s.correct ? 1.0 : 0.0)) * x;
      hessian += w * std::max(p * (1.0 - p), 1e-12) * x * x.transpose();
    }
    for (int i = 1; i < d; ++i) {
      gradient(i) += l2 * beta(i);
      hessian(i, i) += l2;
    }
    hessian(0, 0) += 1e-9;
    const Eigen::Matrix<double, d, 1> step = hessian.ldlt().solve(gradient);
    beta -= step;
    if (step.cwiseAbs().maxCoeff() < 1e-10) break;
  }
  DecisionParams out = base;
  out.bias = beta(0);
  for (int i = 1; i < d; ++i) out.weights[static_cast<std::size_t>(i - 1)] = beta(i);
  return out;
}

/// Leave-one-building-out predictions: `predicted[i]` is example i's probability from the model
/// fitted on the examples that touch none of its buildings (`buildings[i]`: the buildings of its
/// two maps, numbered from 0; the same number twice for a pair of one building). An example of
/// two buildings is predicted once per building and keeps the less favourable probability (the
/// lower for a right answer, the higher for a wrong one). Throws `parameter_error` when the
/// sizes differ or a fold's training examples are all of one kind.
inline std::vector<double> leave_one_building_out(const std::vector<DecisionSample>& samples,
                                                  const std::vector<std::array<std::size_t, 2>>& buildings,
                                                  double l2 = 1.0, const DecisionParams& base = {}) {
  if (samples.size() != buildings.size()) {
    throw parameter_error("leave_one_building_out: one pair of buildings per example");
  }
  std::size_t count = 0;
  for (const auto& b : buildings) count = std::max({count, b[0] + 1, b[1] + 1});
  std::vector<double> predicted(samples.size(), -1.0);
  for (std::size_t held = 0; held < count; ++held) {
    std::vector<DecisionSample> train;
    std::vector<std::size_t> test;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      if (buildings[i][0] == held || buildings[i][1] == held) test.push_back(i);
      else train.push_back(samples[i]);
    }
    if (test.empty()) continue;
    const DecisionParams model = fit_decision(train, l2, base);
    for (std::size_t i : test) {
      const double p = p_correct(samples[i].features, model);
      double& out = predicted[i];
      out = out < 0.0 ? p : samples[i].correct ? std::min(out, p) : std::max(out, p);
    }
  }
  return predicted;
}

}  // namespace areamatch
