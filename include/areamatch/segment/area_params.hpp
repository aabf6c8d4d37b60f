#pragma once
/// \file segment/area_params.hpp
/// Parameters of `build_areas` (segment/areas.hpp).

#include "../error.hpp"

namespace areamatch {

/// Parameters of `build_areas`. Lengths in metres, areas in m².
struct AreaParams {
  /// Areas smaller than this merge into a neighbour (or are dropped when they have none).
  double min_area_m2 = 1.0;
  /// How far labelling continues beyond the space the skeleton reaches.
  double fringe_m = 0.5;
  /// The skeleton's `min_clearance_m` (`VoronoiSegmenter` sets it from `SkeletonParams::min_clearance_m`
  /// and refuses another value here; `build_areas` called directly reads it): labelling first grows
  /// over free cells at least this far from every wall, where the skeleton lives.
  double min_clearance_m = 0.25;
  /// An area whose hull diameter exceeds this many times its widest free disc's diameter is a
  /// corridor.
  double corridor_elongation = 3.5;

  void validate() const {
    detail::require_non_negative(min_area_m2, "AreaParams::min_area_m2");
    detail::require_non_negative(fringe_m, "AreaParams::fringe_m");
    detail::require_non_negative(min_clearance_m, "AreaParams::min_clearance_m");
    detail::require_non_negative(corridor_elongation, "AreaParams::corridor_elongation");
  }
};

}  // namespace areamatch
