#pragma once
/// \file match/decision/acceptance.hpp
/// Applies the rule that sets `MatchResult::ok`, whose thresholds and model are `DecisionParams`
/// (match/decision/decision.hpp; docs/matching.md, "the decision"): an answer is refused when its whole-map
/// score is below `min_score`, when the maps agree too little and the calibrated model is not sure
/// (`min_agreement`, `accept_p_correct`; the agreement alone does not do on little shared free space,
/// `gate_min_overlap_m2`, or where the walls agree both ways, `gate_max_lower_walls`, unless the
/// walls of rooms seen but not entered agree too and no rival comes close, `gate_both_ways_*`), when the
/// model finds it too likely wrong (`min_p_correct`), or when a rival is too close
/// (`min_margin`); and words each refusal.

#include "../../detail/format.hpp"
#include "../result.hpp"
#include "decision.hpp"

#include <string>

namespace areamatch::detail {

/// Whether the walls agree both ways well enough for the gate to open there: the walls of rooms
/// seen but not entered agree too (`gate_both_ways_min_occupied`) and no rival comes within
/// `margin` (`gate_both_ways_min_margin`).
inline bool both_ways_agreement_holds(const MatchEvidence& evidence, double margin, const DecisionParams& rule) {
  return evidence.occupied_wall_agreement >= rule.gate_both_ways_min_occupied && margin >= rule.gate_both_ways_min_margin;
}

/// Whether the agreement gate lets an answer through whatever the model says: the maps agree
/// (`min_agreement`) and share enough free space for that to mean something
/// (`gate_min_overlap_m2`), and either one map's walls are largely unexplained by the other's
/// (`gate_max_lower_walls`) or, where they agree both ways, `both_ways_agreement_holds`. From the
/// signals alone (`evidence`, the answer's `margin`), so that `areamatch calibrate` judges its
/// rows by the same rule.
inline bool passes_agreement_gate(const MatchEvidence& evidence, double margin, const DecisionParams& rule) {
  return evidence.agreement >= rule.min_agreement && evidence.overlap_m2 >= rule.gate_min_overlap_m2 &&
         (lower_wall_agreement(evidence) <= rule.gate_max_lower_walls || both_ways_agreement_holds(evidence, margin, rule));
}

/// `passes_agreement_gate` of a result.
inline bool passes_agreement_gate(const MatchResult& result, const DecisionParams& rule) {
  return passes_agreement_gate(result.evidence, result.margin, rule);
}

/// A refusal: its reason (empty when accepted) and what it says of the maps.
struct Refusal {
  std::string reason;
  Rejection kind = Rejection::none;
};

/// Why the answer in `result` (margins, evidence and p_correct measured) is refused, and whether
/// that says "different places" or "not sure"; an empty reason when it is accepted.
/// `score_gate`: its score is on the whole-map scale that `min_score` applies to.
inline Refusal refusal(const MatchResult& result, const DecisionParams& rule, bool score_gate) {
  const MatchEvidence& evidence = result.evidence;
  const std::string p_text = "p_correct " + format_fixed(result.p_correct, 3);
  // Said of a refusal whose model all but rules the answer out, and of one it does not.
  const bool model_against = result.p_correct < rule.different_places_p;
  const Rejection weak = model_against ? Rejection::different_places : Rejection::not_sure;
  const std::string weak_words = model_against ? "different places: " : "not sure: ";
  const std::string unsure_tail =
      model_against ? "" : "; it may be another building, or this one mapped too differently (clutter, bends, a partial map)";
  if (score_gate && result.score < rule.min_score) {
    return {"different places: best whole-map score " + format_fixed(result.score, 3) + " is below min_score " +
                format_double(rule.min_score) + ": the maps do not match",
            Rejection::different_places};
  }
  const bool model_sure = result.p_correct >= rule.accept_p_correct;
  if (evidence.agreement < rule.min_agreement && !model_sure) {
    return {weak_words + "the maps agree too little under the best transform to accept it: agreement " +
                format_fixed(evidence.agreement, 3) + " < min_agreement " + format_double(rule.min_agreement) +
                " (the destination's walls near the source's free space explained: " +
                format_fixed(evidence.reverse_wall_agreement, 3) + ", the source's near the destination's: " +
                format_fixed(evidence.forward_wall_agreement, 3) + ", free-space IoU " + format_fixed(evidence.free_iou, 3) +
                "; " + p_text + " < accept_p_correct " + format_double(rule.accept_p_correct) +
                (model_against ? " and < different_places_p " + format_double(rule.different_places_p) : "") + ")" +
                unsure_tail,
            weak};
  }
  // Agreement enough, but on too little shared free space: the gate is closed, the model decides.
  if (evidence.agreement >= rule.min_agreement && evidence.overlap_m2 < rule.gate_min_overlap_m2 && !model_sure) {
    return {"not sure: the maps agree (agreement " + format_fixed(evidence.agreement, 3) + " >= min_agreement " +
                format_double(rule.min_agreement) + ") on too little shared free space to go on that alone (" +
                format_fixed(evidence.overlap_m2, 1) + " m² < gate_min_overlap_m2 " + format_fixed(rule.gate_min_overlap_m2, 0) +
                "), where the calibrated model judges alone, and it is not sure enough: " + p_text + " < accept_p_correct " +
                format_double(rule.accept_p_correct),
            Rejection::not_sure};
  }
  // Agreement enough, but the walls agree both ways too, where alike buildings and a symmetric
  // building's turned copies agree as well: the gate asks for more, else the model decides.
  if (evidence.agreement >= rule.min_agreement && !passes_agreement_gate(result, rule) && !model_sure) {
    const bool occupied_short = !(evidence.occupied_wall_agreement >= rule.gate_both_ways_min_occupied);
    const std::string shortfall =
        occupied_short ? "the walls of rooms seen but not entered agree " + format_fixed(evidence.occupied_wall_agreement, 3) +
                             " < gate_both_ways_min_occupied " + format_double(rule.gate_both_ways_min_occupied) +
                             ": alike buildings agree like this too"
                       : "a rival comes within margin " + format_fixed(result.margin, 3) + " < gate_both_ways_min_margin " +
                             format_double(rule.gate_both_ways_min_margin) + ": a symmetric building's turned copy agrees as well";
    return {"not sure: the maps agree (agreement " + format_fixed(evidence.agreement, 3) + " >= min_agreement " +
                format_double(rule.min_agreement) + ") and their walls agree both ways (the lower " +
                format_fixed(lower_wall_agreement(evidence), 3) + " > gate_max_lower_walls " +
                format_double(rule.gate_max_lower_walls) + "), but " + shortfall +
                "; the calibrated model, judging alone, is not sure enough: " + p_text + " < accept_p_correct " +
                format_double(rule.accept_p_correct),
            Rejection::not_sure};
  }
  if (result.p_correct < rule.min_p_correct) {
    return {weak_words + "the answer is too likely wrong: " + p_text + " < min_p_correct " +
                format_double(rule.min_p_correct) + " (wall agreement " +
                format_fixed(evidence.forward_wall_agreement, 3) + " / " + format_fixed(evidence.reverse_wall_agreement, 3) +
                ", rooms " + format_fixed(evidence.room_agreement, 3) + ", margin " + format_fixed(result.margin, 3) +
                ", overlap " + format_fixed(evidence.overlap_m2, 1) + " m²)",
            weak};
  }
  if (result.margin < rule.min_margin) {
    return {"not sure: ambiguous: a different transform scores within " + format_fixed(result.margin, 3) +
                " of the best (min_margin " + format_double(rule.min_margin) + ")",
            Rejection::not_sure};
  }
  return {};
}

}  // namespace areamatch::detail
