#pragma once
/// \file merge/params.hpp
/// Parameters of `merge_maps` (merge.hpp).

#include "../error.hpp"
#include "../warp/params.hpp"
#include "double_walls.hpp"
#include "fuse.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace areamatch {

/// How a merge names map i in its messages, JSON and picture legend: `names[i]` when given, else "map i".
inline std::string merge_map_name(const std::vector<std::string>& names, std::size_t i) {
  return i < names.size() ? names[i] : "map " + std::to_string(i);
}

/// Which pairs of maps are matched.
enum class MergeStrategy {
  all_pairs,        ///< every pair: loops of matches check each other (the default)
  until_connected   ///< a pair only while its two maps are not yet joined by accepted matches:
                    ///< fewer matches (N − 1 at best), no loop checks
};

/// Parameters of `merge_maps`.
struct MergeParams {
  /// The map whose world frame is the merged frame (index into the maps).
  std::size_t reference = 0;
  MergeStrategy strategy = MergeStrategy::all_pairs;
  /// An accepted match whose anchors land further apart than this (RMS, metres) under the fitted
  /// poses is contradicted by the others and dropped. 1 m: above what right matches leave on
  /// bending hand-held scans (0.1–0.5 m, their ground truth itself is good to ~0.3 m) and below
  /// the smallest wrong answer that matters, a slide by one room (≥ 2.5 m).
  double max_residual_m = 1.0;
  /// A map joined to the others by one accepted match only, and that accepted by the calibrated
  /// model alone (not through the agreement gate: `DecisionParams::min_agreement`,
  /// `gate_max_lower_walls`), must reach this p_correct:
  /// nothing else corroborates it, and a merge tries every pair, so one false accept would place
  /// a map of another building. 0.9: the model-alone threshold of the decision until 2026-12-01
  /// (its cross-validated false accepts 5 of 3567). In the F5 merge every scan has at least five
  /// accepted matches; an apartment scan added to it had one, at 0.814 (docs/merging.md).
  double lone_match_min_p_correct = 0.9;
  /// How the merged grid is made (its resolution: the finest map's by default).
  FuseParams fuse;
  /// Threads matching pairs at once (`all_pairs` only; 0: one per hardware thread). The results
  /// are the same, bit for bit, for any count: each pair's match lands in its own place.
  unsigned threads = 1;
  /// Refine each accepted match before the pose fit (when the matcher refines at all) by ICP from
  /// its transform with the matcher's last (smallest) gate, pairing each wall point with the
  /// nearest wall facing the same way (`RefineParams::same_side_only`). The matcher's ICP pairs nearest points, and where one
  /// partial map entered a room the other did not, that room's side of a wall is pulled onto the
  /// other side: N = 2 generated merges placed maps up to 0.13 m off (0.013 m with this).
  bool refine_same_side = true;
  /// Bend each placed map onto the reference's walls before fusing (step 4 of the file comment);
  /// false: each map is laid by its rigid pose alone.
  bool non_rigid = false;
  /// The warps' settings (`non_rigid`).
  WarpParams warp;
  /// How the merged map's doubled walls are counted (`MergeResult::double_walls`).
  DoubleWallParams double_walls;
  /// Build the merged grid (false: poses only).
  bool build_merged_map = true;
  /// The maps' names in messages (e.g. their paths); "map i" when empty.
  std::vector<std::string> names;

  void validate(std::size_t map_count) const {
    if (map_count < 2) throw parameter_error("merging needs at least two maps, got " + std::to_string(map_count));
    if (reference >= map_count) {
      throw parameter_error("MergeParams::reference is " + std::to_string(reference) + " but there are only " +
                            std::to_string(map_count) + " maps");
    }
    detail::require_positive(max_residual_m, "MergeParams::max_residual_m");
    if (!(lone_match_min_p_correct >= 0.0 && lone_match_min_p_correct <= 1.0)) {
      throw parameter_error("MergeParams::lone_match_min_p_correct must be in [0, 1]");
    }
    if (!names.empty() && names.size() != map_count) throw parameter_error("MergeParams::names: one name per map, or none");
    fuse.validate();
    if (non_rigid) warp.validate();
    double_walls.validate();
  }
  std::string name(std::size_t i) const { return merge_map_name(names, i); }
};

}  // namespace areamatch
