#pragma once
/// \file assess/params.hpp
/// The settings of a map assessment (assess/report.hpp): how walls are compared, what counts as
/// a broken piece, when a room counts as found. Lengths in metres, angles in radians.

#include "../error.hpp"
#include "../match/verification/refine.hpp"
#include "../transform.hpp"
#include "../warp/params.hpp"

#include <cmath>
#include <vector>

namespace areamatch {

struct AssessParams {
  /// The warp that measures local error (warp/params.hpp).
  WarpParams warp;
  /// The caller knows the two maps show the same building (a map assessed against its own
  /// ground truth): a match the decision rejected is assessed all the same, under its best
  /// transform (`MapAssessment::decision_overridden` says so). Off: a rejected match is not
  /// assessed, since a map placed wrongly would be measured against the wrong walls.
  bool assume_same_building = false;

  // Wall error (both ways).
  /// Wall points are taken about this far apart.
  double wall_spacing_m = 0.1;
  /// Cell of the nearest-wall lookups (exact to a fraction of it).
  double wall_lookup_cell_m = 0.05;
  /// Wall distances are capped here: a wall farther from any wall of the other map is not a
  /// displaced wall but one the other map lacks (furniture, a streak, an unmapped room); the
  /// share at the cap is reported apart.
  double wall_distance_cap_m = 1.0;
  /// The share of wall points within this distance is reported (a wall "in place").
  double wall_tolerance_m = 0.2;
  /// A reference wall counts for the map's completeness only within this distance of the map's
  /// free space: walls of rooms the map never reached are a matter of coverage, not of error.
  double explored_reach_m = 0.5;

  // Brokenness (assess/pieces.hpp).
  /// Each area's own rigid fit: trimmed ICP of its walls onto the reference's with these gates,
  /// started from an already fitted neighbour's transform (so a fit follows a map that turns
  /// step by step and does not jump to the next room).
  RefineParams piece_icp = [] {
    RefineParams p;
    p.gates_m = {1.0, 0.6, 0.3};
    p.iterations_per_gate = 6;
    p.max_points = 800;
    p.same_side_only = true;  // a room's face of a wall, never the next room's
    return p;
  }();
  /// A piece is fitted by ICP from its first tile's fit and from the tiles' own fits that lay most
  /// of its walls as they are: this many starts in all (at least 1).
  std::size_t piece_fit_starts = 3;
  /// After the warp, each piece's transform is the rigid fit of its walls' warped places, and
  /// the walls are dealt again this many times to the piece whose fit lays them nearest
  /// (`fit_pieces_to_warp`): 0 keeps the labels the pieces were found with.
  int piece_refit_rounds = 2;
  /// The walls are fitted in square tiles of this side: a few rooms' worth, smaller than a long
  /// corridor (which a bent map's corridor no longer is rigidly).
  double piece_tile_m = 6.0;
  /// Tiles with fewer wall points than this are too bare to fit; they join a neighbour's piece.
  std::size_t piece_min_wall_points = 60;
  /// A tile's own fit counts only when at least this share of its wall points lies within
  /// `wall_tolerance_m` of a reference wall under it: a room full of furniture and laser streaks
  /// fits anything a little, and such a fit says nothing about a break.
  double piece_min_wall_agreement = 0.5;
  /// A tile's own fit counts only within this turn and shift (at its centre) of the fit it started
  /// from (its neighbour's; the whole map's for the first tile): more is ICP sliding to another
  /// room, not the map. Measured from the neighbour, not from the whole map, so that breaks that
  /// add up (three cuts of 8 degrees each) are followed piece by piece.
  double piece_max_rotation_rad = 20.0 * pi / 180.0;
  double piece_max_shift_m = 3.0;
  /// A tile whose fit from its neighbour's does not count is fitted again from that start turned
  /// by each of these about the tile's middle (on every fourth wall point; the best is then refined
  /// on all): beyond a failed loop closure the walls turn by several degrees at once, more than the
  /// first gate of `piece_icp` reaches from the neighbour's fit. The generator's breaks turn 2–10°;
  /// ICP mends a few degrees from the nearest start. Empty: no retries.
  std::vector<double> piece_retry_turns_rad = {-5.0 * pi / 180.0, 5.0 * pi / 180.0, -10.0 * pi / 180.0, 10.0 * pi / 180.0};
  /// ...and keeps the best retried fit only when it lays at least this share of the tile's walls:
  /// the best of several starts needs more than one fit does, since in a cluttered room one of
  /// them lays half the walls by chance (what that did to a real SLAM map: docs/assessment.md).
  double piece_retry_min_wall_agreement = 0.7;
  /// Neighbouring tiles are one rigid piece when their own fits differ by at most this turn...
  double piece_rotation_tolerance_rad = 1.0 * pi / 180.0;
  /// ...and place the middle of their common side at most this far apart. A smooth bend turns
  /// little from one tile to the next; a failed loop closure turns everything beyond it at once.
  /// Loose, because a tile across a corridor may slide along it.
  double piece_shift_tolerance_m = 0.5;
  /// A tile's own fit starts the warp (assess/report.hpp) only where it places the tile's middle
  /// within this of where its piece's fit does; farther, the tile slid a wall period along a row
  /// of like rooms (its walls lie on walls all the same), which its piece's fit, made on all the
  /// piece's walls, does not, and a warp started there stays there. Nearer, the difference is
  /// the bend across the piece, which the tile's fit takes out before the warp starts.
  double piece_start_max_offset_m = 1.0;
  /// A piece with fewer wall points than this is joined to its neighbour: a tile or two whose
  /// walls are mostly furniture are no evidence of a broken map.
  std::size_t piece_min_points = 600;

  // Coverage and topology (assess/coverage.hpp).
  /// Coverage and each area's displacement are sampled on cells of this side.
  double sample_cell_m = 0.1;
  /// A reference area is found when at least this share of its free space is explored, partly
  /// found from `partly_found_share`, missed below.
  double found_share = 0.5;
  double partly_found_share = 0.1;
  /// A map area the reference lacks: less than this share of it lands on the reference's free space.
  double extra_area_share = 0.3;
  /// A reference passage between two found areas is missing from the map when no map passage
  /// lies within this distance of it (under the warp).
  double passage_distance_m = 1.0;

  void validate() const {
    warp.validate();
    detail::require_positive(wall_spacing_m, "AssessParams::wall_spacing_m");
    detail::require_positive(wall_lookup_cell_m, "AssessParams::wall_lookup_cell_m");
    detail::require_positive(wall_distance_cap_m, "AssessParams::wall_distance_cap_m");
    detail::require_positive(wall_tolerance_m, "AssessParams::wall_tolerance_m");
    detail::require_non_negative(explored_reach_m, "AssessParams::explored_reach_m");
    piece_icp.validate();
    detail::require_positive(piece_tile_m, "AssessParams::piece_tile_m");
    detail::require_non_negative(piece_refit_rounds, "AssessParams::piece_refit_rounds");
    if (piece_fit_starts < 1) throw parameter_error("AssessParams::piece_fit_starts must be at least 1");
    if (piece_min_wall_points < 3) throw parameter_error("AssessParams::piece_min_wall_points must be >= 3");
    detail::require_positive(piece_max_rotation_rad, "AssessParams::piece_max_rotation_rad");
    detail::require_positive(piece_max_shift_m, "AssessParams::piece_max_shift_m");
    detail::require_non_negative(piece_start_max_offset_m, "AssessParams::piece_start_max_offset_m");
    for (const double turn : piece_retry_turns_rad) {
      if (!std::isfinite(turn)) throw parameter_error("AssessParams::piece_retry_turns_rad must be finite");
    }
    detail::require_positive(piece_rotation_tolerance_rad, "AssessParams::piece_rotation_tolerance_rad");
    detail::require_positive(piece_shift_tolerance_m, "AssessParams::piece_shift_tolerance_m");
    detail::require_positive(sample_cell_m, "AssessParams::sample_cell_m");
    auto share = [](double v, const char* name) {
      if (!(v >= 0.0 && v <= 1.0)) throw parameter_error(std::string("AssessParams::") + name + " must be in [0, 1]");
    };
    share(found_share, "found_share");
    share(partly_found_share, "partly_found_share");
    share(extra_area_share, "extra_area_share");
    share(piece_min_wall_agreement, "piece_min_wall_agreement");
    share(piece_retry_min_wall_agreement, "piece_retry_min_wall_agreement");
    if (partly_found_share > found_share) throw parameter_error("AssessParams::partly_found_share must not exceed found_share");
    detail::require_positive(passage_distance_m, "AssessParams::passage_distance_m");
  }
};

}  // namespace areamatch
