#pragma once
/// \file match/scale/scale.hpp
/// Matching when the source map's resolution is not known (a scanned floor plan, a map whose
/// YAML is wrong): `MatcherParams::estimate_scale`.
///
/// Segmentation depends on the scale — a door is a passage because it is narrower than the door
/// width in metres — so the scale cannot be read off one segmentation of a wrongly scaled map.
/// The matcher therefore segments and matches the source at candidate scales spread evenly (in
/// log scale) over [min_scale, max_scale], each ending in an ICP that refines the scale too;
/// the candidates whose results the maps agree with most (`MatchEvidence::agreement`) are
/// finalists: each one's scale is swept, the whole pipeline runs once more at the swept scale,
/// and the re-run the maps agree with most wins. With 8 candidates per doubling (the default)
/// the nearest one is within 4.4 % of the truth, well inside what the ICP pulls in.
///
/// Scale s means: the source's true resolution is s × its given resolution. The result's
/// `T_dest_source` maps the source's world frame *as given* to the destination's, so its
/// `scale` is the estimate.

#include "../../error.hpp"
#include "../../grid.hpp"
#include "../../transform.hpp"
#include "../result.hpp"

#include <cmath>
#include <vector>

namespace areamatch {

struct ScaleParams {
  double min_scale = 0.5;          ///< the source's resolution may be wrong by this factor ...
  double max_scale = 2.0;          ///< ... up to this one
  int candidates_per_doubling = 8; ///< candidate scales per factor 2 (8: 4.4 % from the truth at worst)
  /// After the best candidate, scales within ± this share of it are tried in `sweep_step`
  /// steps (each with a rigid ICP, judged by `MatchEvidence::agreement`): the ICP alone pulls
  /// the scale in poorly, since walls slide along themselves.
  double sweep_range = 0.06;
  double sweep_step = 0.005;
  /// The sweep's rigid ICP starts near the answer: only the refinement's last, tight gates.
  std::vector<double> sweep_gates_m{0.7, 0.4};
  /// The best this many candidates are each swept and re-run, and the re-run the maps agree
  /// with most wins: one candidate's agreement can flatter a wrong scale that its re-run does
  /// not confirm (docs/evaluation.md, scale estimation). Each finalist costs one more sweep and
  /// one more match.
  std::size_t finalists = 2;

  void validate() const {
    detail::require_positive(min_scale, "ScaleParams::min_scale");
    if (!(std::isfinite(max_scale) && max_scale >= min_scale)) {
      throw parameter_error("ScaleParams::max_scale must be finite and at least min_scale");
    }
    if (max_scale / min_scale > 1024.0) throw parameter_error("ScaleParams: max_scale / min_scale must be at most 1024");
    if (candidates_per_doubling < 1 || candidates_per_doubling > 64) {
      throw parameter_error("ScaleParams::candidates_per_doubling must be in [1, 64]");
    }
    if (!(sweep_range >= 0.0 && sweep_range < 0.5)) throw parameter_error("ScaleParams::sweep_range must be in [0, 0.5)");
    if (!(sweep_step > 0.0 && sweep_step <= 0.5)) throw parameter_error("ScaleParams::sweep_step must be in (0, 0.5]");
    if (sweep_range / sweep_step > 1000.0) throw parameter_error("ScaleParams: at most 1000 sweep steps each way");
    if (sweep_gates_m.empty()) throw parameter_error("ScaleParams::sweep_gates_m must not be empty");
    for (double g : sweep_gates_m) detail::require_positive(g, "ScaleParams::sweep_gates_m");
    if (finalists < 1 || finalists > 16) throw parameter_error("ScaleParams::finalists must be in [1, 16]");
  }
};

/// The candidate scales, ascending: min_scale · 2^(k / candidates_per_doubling) up to max_scale,
/// with max_scale itself when the steps do not land on it.
inline std::vector<double> scale_candidates(const ScaleParams& p) {
  p.validate();
  std::vector<double> out;
  const double span = std::log2(p.max_scale / p.min_scale) * p.candidates_per_doubling;
  const int steps = static_cast<int>(std::floor(span + 1e-9));
  for (int k = 0; k <= steps; ++k) out.push_back(p.min_scale * std::exp2(static_cast<double>(k) / p.candidates_per_doubling));
  if (span - steps > 1e-9) out.push_back(p.max_scale);
  return out;
}

/// `T` with its scale multiplied by `factor` about the source point `centre` (which stays put).
inline Similarity2 scaled_about(const Similarity2& T, double factor, const Eigen::Vector2d& centre) {
  Similarity2 out = T;
  out.scale = T.scale * factor;
  out.translation = T * centre - out.linear() * centre;
  return out;
}

/// The grid with its resolution and origin multiplied by `scale`: its world frame is the given
/// one scaled by `scale` about the world origin.
inline OccupancyGrid rescaled_grid(const OccupancyGrid& grid, double scale) {
  OccupancyGrid out = grid;
  out.set_resolution(grid.resolution() * scale);
  Pose2 origin = grid.origin();
  origin.x *= scale;
  origin.y *= scale;
  out.set_origin(origin);
  return out;
}

/// A transform from the scaled source frame (`rescaled_grid(…, scale)`) expressed from the given
/// source frame: the same map of points, with `scale` folded in.
inline Similarity2 from_scaled_source(const Similarity2& T_dest_scaled, double scale) {
  Similarity2 T = T_dest_scaled;
  T.scale *= scale;
  return T;
}

}  // namespace areamatch
