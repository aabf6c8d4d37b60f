#pragma once
/// \file assess/report.hpp
/// A map assessed against a reference (a floor plan, a laser-scanner map, a trusted map): where it
/// is wrong and by how much, how broken, how complete. One report (docs/assessment.md):
///   - global: the rigid answer and the wall error both ways under it (assess/wall_error.hpp);
///   - local: the warp that bends the map onto the reference (warp/fit.hpp) — its displacement,
///     per map area, is how far each part of the map is off once the whole is placed — and the
///     wall error under it;
///   - brokenness: the rigid pieces (assess/pieces.hpp);
///   - coverage and topology (assess/coverage.hpp).

#include "../area_graph.hpp"
#include "../detail/timing.hpp"
#include "../grid.hpp"
#include "../match/raster.hpp"
#include "../match/result.hpp"
#include "../warp/fit.hpp"
#include "coverage.hpp"
#include "params.hpp"
#include "pieces.hpp"
#include "wall_error.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace areamatch {

/// How far the warp moves one map area beyond the rigid answer (reference metres).
struct AreaDisplacement {
  int area = -1;
  double median_m = 0.0;
  double max_m = 0.0;
};

struct AssessTimings {
  double match_s = 0.0;   ///< segmenting and matching (0 when the match was given)
  double warp_s = 0.0;
  double assess_s = 0.0;  ///< everything after the warp
  double total_s = 0.0;
};

struct MapAssessment {
  /// Whether the map could be placed on the reference at all (the match was accepted); without
  /// it every figure below is empty and `reason` says why.
  bool ok = false;
  std::string reason;
  /// The match was rejected and assessed all the same (`AssessParams::assume_same_building`).
  bool decision_overridden = false;
  MatchResult match;
  WarpResult warp;
  WallErrors rigid_walls;   ///< under the match's rigid transform
  WallErrors warped_walls;  ///< under the warp
  std::vector<AreaDisplacement> area_displacement;  ///< per map area, in area order
  Brokenness brokenness;
  Coverage coverage;
  TopologyConsistency topology;
  AssessTimings timings;
  AssessParams params;  ///< the settings it was made with
};

namespace detail {

inline std::vector<AreaDisplacement> area_displacements(const AreaRaster& raster, const WarpField& warp) {
  std::vector<AreaDisplacement> out;
  std::vector<double> moved;
  for (std::size_t a = 0; a < raster.area_cells.size(); ++a) {
    moved.clear();
    for (const int k : raster.area_cells[a]) moved.push_back(warp.displacement(raster.centre(static_cast<std::size_t>(k))).norm());
    AreaDisplacement d;
    d.area = static_cast<int>(a);
    if (!moved.empty()) {
      d.max_m = *std::max_element(moved.begin(), moved.end());
      d.median_m = median_and_p95(moved)[0];
    }
    out.push_back(d);
  }
  return out;
}

}  // namespace detail

/// Assesses `map` against `reference` from a match already made (`result`, map = source,
/// reference = destination; the graphs those the match used). A match that was not accepted
/// gives `ok == false` with its reason — an unplaced map is not assessed against a guess — unless
/// `params.assume_same_building` and the match has a best transform.
inline MapAssessment assess_match(const OccupancyGrid& map, const AreaGraph& map_graph, const OccupancyGrid& reference,
                                  const AreaGraph& reference_graph, const MatchResult& result, const AssessParams& params = {}) {
  params.validate();
  const auto start = detail::Clock::now();
  MapAssessment out;
  out.params = params;
  out.match = result;
  const bool has_transform = result.ok || !result.matched_areas.empty();
  if (!result.ok && !(params.assume_same_building && has_transform)) {
    out.reason = "the map could not be placed on the reference: " + result.reason;
    return out;
  }
  out.decision_overridden = !result.ok;
  if (!(map_graph.grid == GridInfo::of(map)) || !(reference_graph.grid == GridInfo::of(reference))) {
    throw parameter_error("assess_match: each graph must be the segmentation of its map");
  }
  out.ok = true;
  const Similarity2& T = result.T_dest_source;
  // The pieces first: the warp starts from the tiles' own rigid fits (a bent map's rooms each
  // nearly in place, a broken map's pieces each moved by its own fit), so that its first pairs
  // are the right walls even where the rigid answer leaves a wall nearer another one.
  const BoundaryLookup reference_lookup = detail::wall_lookup(reference, params.warp);
  out.brokenness = find_pieces(map, map_graph, reference_lookup, T, params);
  const auto pieces_found = detail::Clock::now();
  const Brokenness& pieces = out.brokenness;
  WarpStart start_from_tiles;
  if (!pieces.tile_fit.empty()) {
    // Each piece's warp starts from its tiles' fits, and beyond its own cells (its grid reaches
    // across a cut) from the piece's fit, not the neighbour's.
    start_from_tiles.displacement = [&](const Eigen::Vector2d& p, int piece) {
      const bool own = pieces.pieces.size() <= 1 || pieces.piece_at(p) == piece;
      const Similarity2& fit = own ? pieces.local_fit(p) : pieces.pieces[static_cast<std::size_t>(piece)].T_reference_map;
      return Eigen::Vector2d(fit * p - T * p);
    };
  }
  start_from_tiles.pieces = pieces.labels();
  out.warp = fit_warp(map, reference_lookup, T, params.warp, start_from_tiles);
  const auto warped = detail::Clock::now();
  out.timings.warp_s = detail::seconds_between(pieces_found, warped);

  const WallSets walls(map, reference, params);
  fit_pieces_to_warp(out.brokenness, walls.map_points, out.warp.field, reference_lookup, params);
  const Similarity2 back = T.inverse();
  const WarpField& field = out.warp.field;
  out.rigid_walls = wall_errors(
      map, walls, [&](const Eigen::Vector2d& p) { return T * p; }, [&](const Eigen::Vector2d& q) { return back * q; },
      T.scale, params);
  out.warped_walls = wall_errors(
      map, walls, [&](const Eigen::Vector2d& p) { return field.apply(p); },
      [&](const Eigen::Vector2d& q) { return field.inverse(q, 1e-4); }, T.scale, params);

  const AreaRaster map_raster = make_area_raster(map_graph, params.sample_cell_m);
  const AreaRaster reference_raster = make_area_raster(reference_graph, params.sample_cell_m);
  out.area_displacement = detail::area_displacements(map_raster, field);
  out.coverage = map_coverage(map, map_graph, map_raster, reference, reference_graph, reference_raster, result.matched_areas,
                              field, params);
  out.topology = topology_consistency(map_graph, reference_graph, result.matched_areas);
  out.timings.assess_s = detail::seconds_between(start, pieces_found) + detail::seconds_since(warped);
  out.timings.total_s = detail::seconds_since(start);
  return out;
}

/// Segments both maps with `matcher`'s segmenter, matches `map` onto `reference` with it, and
/// assesses the map (`assess_match`). Any `Matcher<...>`.
template <class M>
MapAssessment assess_map(const M& matcher, const OccupancyGrid& map, const OccupancyGrid& reference,
                         const AssessParams& params = {}) {
  params.validate();
  const auto start = detail::Clock::now();
  const AreaGraph map_graph = matcher.segmenter.segment(map);
  const AreaGraph reference_graph = matcher.segmenter.segment(reference);
  const MatchResult result = matcher.match(map, map_graph, reference, reference_graph);
  const double match_s = detail::seconds_since(start);
  MapAssessment out = assess_match(map, map_graph, reference, reference_graph, result, params);
  out.timings.match_s = match_s;
  out.timings.total_s += match_s;
  return out;
}

}  // namespace areamatch
