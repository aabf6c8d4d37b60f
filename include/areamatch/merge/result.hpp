#pragma once
/// \file merge/result.hpp
/// What `merge_maps` (merge.hpp) gives: each pairwise match, where each map ended up, the fused map.

#include "../grid.hpp"
#include "../match/result.hpp"
#include "../transform.hpp"
#include "../warp/fit.hpp"
#include "double_walls.hpp"

#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace areamatch {

/// One pairwise match of the merge.
struct MergeEdge {
  std::size_t source = 0;   ///< index of the map matched onto `dest`
  std::size_t dest = 0;
  MatchResult match;
  /// The transform the pose fit uses: `match.T_dest_source`, refined when accepted
  /// (`MergeParams::refine_same_side`).
  Similarity2 T_dest_source;
  /// Whether the edge took part in the final pose fit (accepted and not contradicted).
  bool used = false;
  /// Why not used: the match's rejection reason, or the contradiction; empty when used.
  std::string note;
  /// RMS distance (m) between its anchors laid both ways round under the final poses; NaN when
  /// the edge is not used.
  double residual_m = std::numeric_limits<double>::quiet_NaN();
};

/// Where one map ended up.
struct MergedMap {
  bool placed = false;
  std::string reason;              ///< why not placed (empty when placed)
  Similarity2 T_reference_map;     ///< this map's world → the reference map's world
  PixelTransform pixel_transform = PixelTransform::Zero();  ///< this map's pixel → the reference's pixel
  /// RMS of the residuals of the used edges that touch it (0 when only tree edges place it, NaN
  /// when not placed).
  double residual_m = std::numeric_limits<double>::quiet_NaN();
  /// With `MergeParams::non_rigid`: the warp that lays this map on the reference (its rigid part
  /// is `T_reference_map`) and how well it lays the walls; none for the reference, a map not
  /// placed, or a rigid merge.
  std::optional<WarpResult> warp;
};

/// Wall-clock seconds per step.
struct MergeTimings {
  double matching_s = 0.0;
  double refine_s = 0.0;  ///< `MergeParams::refine_same_side`
  double fit_s = 0.0;
  double warp_s = 0.0;  ///< `MergeParams::non_rigid`
  double fuse_s = 0.0;
  double total_s = 0.0;
};

struct MergeResult {
  bool ok = false;                  ///< every map placed
  std::size_t reference = 0;
  std::vector<MergedMap> maps;      ///< in the order given
  std::vector<MergeEdge> edges;     ///< every match run, in the order run
  /// The fused map in the reference's world frame (empty when not built or nothing placed but the
  /// reference; see merge/fuse.hpp).
  OccupancyGrid merged;
  /// The merged map's walls and how many of them are doubled (merge/double_walls.hpp): what a
  /// non-rigid merge should leave fewer of.
  DoubleWalls double_walls;
  MergeTimings timings;
};

}  // namespace areamatch
