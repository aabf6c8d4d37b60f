#pragma once
/// \file warp/params.hpp
/// The settings of a non-rigid warp (warp/fit.hpp): how fine its control grid is, how stiff it
/// is, and how walls are paired. Lengths in metres.

#include "../error.hpp"
#include "../transform.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace areamatch {

struct WarpParams {
  /// Spacing of the control grid whose displacements are interpolated bilinearly between nodes.
  /// Finer than a room, so that each room's walls can move on their own.
  double control_spacing_m = 1.0;
  /// The warp's stiffness as a length: a bend whose wavelength is about this long costs as much
  /// as it gains where walls are as dense as in an office floor (0.5 m of wall per m²); shorter
  /// bends (a misdrawn wall, a wall hidden behind furniture) are not followed, longer ones (SLAM
  /// drift, a schematic plan's stretched wing) are.
  double bend_length_m = 4.0;
  /// The gates before the last are solved on a coarser control grid of this spacing (two levels:
  /// the coarse warp then starts the fine one on the last gate), so that the large early moves
  /// cost a quarter of the unknowns and the fine grid needs no factorization (a map broken into
  /// pieces, `WarpStart::pieces`: each piece's warp so); 0 (or not above `control_spacing_m`):
  /// every gate on the fine grid. Measured in docs/warp.md.
  double coarse_spacing_m = 2.0;
  /// Wall pairing gates, one stage each, shrinking as the warp settles.
  std::vector<double> gates_m{2.0, 1.2, 0.8, 0.5, 0.3};
  int iterations_per_gate = 3;
  /// Share of the gated pairs kept, the closest first (furniture and streaks are outliers).
  double keep_fraction = 0.8;
  /// Source wall points are taken about this far apart.
  double point_spacing_m = 0.1;
  /// Cell of the destination's nearest-wall lookup.
  double lookup_cell_m = 0.1;
  /// The destination's wall normals come from its wall points within this radius.
  double normal_radius_m = 0.2;
  /// A wall point's free side from the free cells within this radius: walls are paired only
  /// with walls facing the same way (never a wall's other face).
  double free_side_radius_m = 0.1;
  /// Weight of the distance along the destination's wall (point to point) against the distance
  /// across it (point to line): small, so that walls may slide along each other, but not zero,
  /// so that a corridor's length is held.
  double along_wall_weight = 0.1;
  /// Pull of each node's displacement towards where it started (none: the rigid transform, unless
  /// a `WarpStart` gives one), per m² of the grid: keeps nodes that no wall reaches where the
  /// start put them.
  double rest_weight = 1e-3;
  /// A map broken into pieces (`WarpStart::pieces`): where they meet, which piece's warp moves a
  /// point is decided again on cells of this side, by which piece's warp lays their walls best
  /// (the pieces' labels come from tiles' rigid fits, coarser than a cut).
  double piece_label_cell_m = 0.25;
  /// ... for the cells this close to another piece's cells (how far the given labels may be off).
  double piece_boundary_m = 1.5;
  /// The control grid reaches this far beyond the source's walls.
  double margin_m = 2.0;
  /// `WarpResult`'s wall figures count the source wall points whose destination wall lies within
  /// this distance under the rigid transform (farther ones are furniture, streaks or rooms the
  /// destination lacks, which no warp should lay on a wall).
  double report_within_m = 1.0;

  /// The stiffness of the bending energy (∫ |∂²d|² dA weighted against ∫ residual² ds along the
  /// walls), from `bend_length_m`: (λ / 2π)⁴ · 0.5 m⁻¹.
  double bending_weight() const {
    const double l = bend_length_m / (2.0 * pi);
    return 0.5 * l * l * l * l;
  }

  void validate() const {
    detail::require_positive(control_spacing_m, "WarpParams::control_spacing_m");
    detail::require_positive(bend_length_m, "WarpParams::bend_length_m");
    detail::require_non_negative(coarse_spacing_m, "WarpParams::coarse_spacing_m");
    if (gates_m.empty()) throw parameter_error("WarpParams::gates_m must not be empty");
    for (double g : gates_m) detail::require_positive(g, "WarpParams::gates_m");
    if (iterations_per_gate < 1) throw parameter_error("WarpParams::iterations_per_gate must be >= 1");
    if (!(keep_fraction > 0.0 && keep_fraction <= 1.0)) throw parameter_error("WarpParams::keep_fraction must be in (0, 1]");
    detail::require_positive(point_spacing_m, "WarpParams::point_spacing_m");
    detail::require_positive(lookup_cell_m, "WarpParams::lookup_cell_m");
    detail::require_positive(normal_radius_m, "WarpParams::normal_radius_m");
    detail::require_positive(free_side_radius_m, "WarpParams::free_side_radius_m");
    detail::require_non_negative(along_wall_weight, "WarpParams::along_wall_weight");
    detail::require_positive(rest_weight, "WarpParams::rest_weight");
    detail::require_positive(piece_label_cell_m, "WarpParams::piece_label_cell_m");
    detail::require_non_negative(piece_boundary_m, "WarpParams::piece_boundary_m");
    detail::require_non_negative(margin_m, "WarpParams::margin_m");
    detail::require_positive(report_within_m, "WarpParams::report_within_m");
  }
};

}  // namespace areamatch
