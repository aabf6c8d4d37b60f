#pragma once
/// \file assess/tiles.hpp
/// The tile stages of `find_pieces` (assess/pieces.hpp): a map's walls dealt into square tiles,
/// each tile's own rigid fit (a breadth-first walk, each fit starting from a neighbour's), and
/// the tiles grouped where neighbouring fits agree.

#include "../area_graph.hpp"
#include "../detail/disjoint_sets.hpp"
#include "../detail/thinning.hpp"
#include "../grid.hpp"
#include "../match/verification/correspondence.hpp"
#include "../match/verification/refine.hpp"
#include "../transform.hpp"
#include "params.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <queue>
#include <vector>

namespace areamatch {
namespace detail {

/// Whether two fits agree at `at` (map world): turn and placed position.
inline bool fits_agree(const Similarity2& a, const Similarity2& b, const Eigen::Vector2d& at, const AssessParams& params) {
  return std::abs(wrap_angle(a.rotation - b.rotation)) <= params.piece_rotation_tolerance_rad &&
         (a * at - b * at).norm() <= params.piece_shift_tolerance_m;
}

/// A map's wall points (its areas' free-space edges) dealt into square tiles, row-major.
struct WallTiles {
  Eigen::Vector2d lo = Eigen::Vector2d::Zero();  ///< the tiles' corner, map world
  double side = 1.0;
  int columns = 0, rows = 0;
  std::vector<std::vector<Eigen::Vector2d>> walls;  ///< per tile: its wall points
  std::vector<std::vector<int>> wall_area;          ///< per tile point: its area
  std::vector<std::vector<Eigen::Vector2d>> sides;  ///< per tile point: its free side

  std::size_t size() const { return walls.size(); }
  std::vector<std::size_t> neighbours(std::size_t t) const {
    std::vector<std::size_t> out;
    const int c = static_cast<int>(t % static_cast<std::size_t>(columns)), r = static_cast<int>(t / static_cast<std::size_t>(columns));
    if (c > 0) out.push_back(t - 1);
    if (c + 1 < columns) out.push_back(t + 1);
    if (r > 0) out.push_back(t - static_cast<std::size_t>(columns));
    if (r + 1 < rows) out.push_back(t + static_cast<std::size_t>(columns));
    return out;
  }
  Eigen::Vector2d centre(std::size_t t) const {
    return Eigen::Vector2d(lo.x() + side * (static_cast<double>(t % static_cast<std::size_t>(columns)) + 0.5),
                           lo.y() + side * (static_cast<double>(t / static_cast<std::size_t>(columns)) + 0.5));
  }
  /// The middle of two neighbouring tiles' common side (a tile's centre for a == b).
  Eigen::Vector2d shared_edge(std::size_t a, std::size_t b) const { return Eigen::Vector2d(0.5 * (centre(a) + centre(b))); }
  /// Share of tile t's walls that `fit` lays on a reference wall.
  double agreement(std::size_t t, const Similarity2& fit, const BoundaryLookup& reference, const AssessParams& params) const {
    return walls[t].empty() ? 0.0 : boundary_inlier_fraction(walls[t], reference, fit, params.wall_tolerance_m);
  }
};

inline WallTiles wall_tiles(const OccupancyGrid& map, const AreaGraph& graph, const AssessParams& params) {
  WallTiles tiles;
  const auto area_walls = area_wall_points(graph, free_edge_cells(map, graph), params.piece_icp.point_spacing_m);
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::max()), hi = -lo;
  for (const auto& walls : area_walls) {
    for (const auto& p : walls) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  if (!(lo.x() <= hi.x())) lo = hi = Eigen::Vector2d::Zero();
  tiles.lo = lo;
  tiles.side = params.piece_tile_m;
  tiles.columns = static_cast<int>((hi.x() - lo.x()) / tiles.side) + 1;
  tiles.rows = static_cast<int>((hi.y() - lo.y()) / tiles.side) + 1;
  const std::size_t n = static_cast<std::size_t>(tiles.columns) * static_cast<std::size_t>(tiles.rows);
  tiles.walls.resize(n);
  tiles.wall_area.resize(n);
  for (std::size_t a = 0; a < area_walls.size(); ++a) {
    for (const auto& p : area_walls[a]) {
      const int c = std::min(tiles.columns - 1, static_cast<int>((p.x() - lo.x()) / tiles.side));
      const int r = std::min(tiles.rows - 1, static_cast<int>((p.y() - lo.y()) / tiles.side));
      const std::size_t t = static_cast<std::size_t>(r) * static_cast<std::size_t>(tiles.columns) + static_cast<std::size_t>(c);
      tiles.walls[t].push_back(p);
      tiles.wall_area[t].push_back(static_cast<int>(a));
    }
  }
  tiles.sides.resize(n);
  for (std::size_t t = 0; t < n; ++t) tiles.sides[t] = free_sides(map, tiles.walls[t], params.piece_icp.free_side_radius_m);
  return tiles;
}

/// Each tile's own fit, walked breadth-first from the tile with the most walls, each starting
/// from the neighbour it was reached from (and, where that fails, from it turned by
/// `piece_retry_turns_rad`, a retry kept from `piece_retry_min_wall_agreement`). `fitted[t]`: the
/// fit counts (enough walls, near its start, laying most of them); the others keep their start.
inline void fit_each_tile(const WallTiles& tiles, const BoundaryLookup& reference, const Similarity2& T,
                          const AssessParams& params, std::vector<Similarity2>& fit, std::vector<char>& fitted) {
  const std::size_t n = tiles.size();
  fit.assign(n, T);
  fitted.assign(n, 0);
  std::vector<char> visited(n, 0);
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return tiles.walls[a].size() > tiles.walls[b].size(); });
  for (const std::size_t start : order) {
    if (visited[start] || tiles.walls[start].empty()) continue;
    std::queue<std::size_t> queue;
    queue.push(start);
    visited[start] = 1;
    while (!queue.empty()) {
      const std::size_t i = queue.front();
      queue.pop();
      if (tiles.walls[i].size() >= params.piece_min_wall_points) {
        const Eigen::Vector2d c = tiles.shared_edge(i, i);
        const Similarity2 start = fit[i];
        auto counts = [&](const Similarity2& own) {
          return std::abs(wrap_angle(own.rotation - start.rotation)) <= params.piece_max_rotation_rad &&
                 (own * c - start * c).norm() <= params.piece_max_shift_m;
        };
        Similarity2 best = refine_icp(tiles.walls[i], reference, fit[i], params.piece_icp, &tiles.sides[i]);
        double best_agreement = counts(best) ? tiles.agreement(i, best, reference, params) : -1.0;
        if (best_agreement < params.piece_min_wall_agreement && !params.piece_retry_turns_rad.empty()) {
          // The turned starts are compared on every fourth wall point (a fourth of the cost: most
          // tiles that get here are cluttered ones, where no start fits); the best is then refined
          // on all of them.
          const bool sided = tiles.sides[i].size() == tiles.walls[i].size();
          const std::vector<Eigen::Vector2d> few = detail::every_kth(tiles.walls[i], 4);
          const std::vector<Eigen::Vector2d> few_sides = sided ? detail::every_kth(tiles.sides[i], 4) : std::vector<Eigen::Vector2d>{};
          Similarity2 best_start = start;
          double best_start_agreement = -1.0;
          for (const double turn : params.piece_retry_turns_rad) {
            Similarity2 about_centre;  // the start turned about the tile's middle
            about_centre.rotation = turn;
            about_centre.translation = c - Eigen::Rotation2Dd(turn) * c;
            const Similarity2 own = refine_icp(few, reference, start * about_centre, params.piece_icp, sided ? &few_sides : nullptr);
            const double agreement =
                counts(own) ? boundary_inlier_fraction(few, reference, own, params.wall_tolerance_m) : -1.0;
            if (agreement > best_start_agreement) {
              best_start = own;
              best_start_agreement = agreement;
            }
          }
          if (best_start_agreement >= params.piece_retry_min_wall_agreement) {
            const Similarity2 own = refine_icp(tiles.walls[i], reference, best_start, params.piece_icp, &tiles.sides[i]);
            const double agreement = counts(own) ? tiles.agreement(i, own, reference, params) : -1.0;
            if (agreement >= params.piece_retry_min_wall_agreement && agreement > best_agreement) {
              best = own;
              best_agreement = agreement;
            }
          }
        }
        if (best_agreement >= params.piece_min_wall_agreement) {
          fit[i] = best;
          fitted[i] = 1;
        }
      }
      for (const std::size_t j : tiles.neighbours(i)) {
        if (visited[j] || tiles.walls[j].empty()) continue;
        visited[j] = 1;
        fit[j] = fit[i];  // start from this neighbour's fit (or what it started from)
        queue.push(j);
      }
    }
  }
}

/// Per tile, the root tile of its group: fitted neighbours whose fits agree at their common side
/// are one group; the fitted tiles of a group with too few wall points join the fitted neighbour
/// whose fit lays their walls best; groups with enough wall points then keep their tiles, the rest
/// join the neighbouring group laying their walls best (tiles no group reaches: the first).
inline std::vector<int> group_tiles(const WallTiles& tiles, const BoundaryLookup& reference, const AssessParams& params,
                                    const std::vector<Similarity2>& fit, const std::vector<char>& fitted) {
  const std::size_t n = tiles.size();
  DisjointSets sets(n);
  for (std::size_t t = 0; t < n; ++t) {
    for (const std::size_t u : tiles.neighbours(t)) {
      if (u > t && fitted[t] && fitted[u] && fits_agree(fit[t], fit[u], tiles.shared_edge(t, u), params)) {
        sets.join(t, u);
      }
    }
  }
  std::vector<std::size_t> set_points(n, 0);  // per group root
  for (std::size_t t = 0; t < n; ++t) {
    if (fitted[t]) set_points[sets.find(t)] += tiles.walls[t].size();
  }
  // Fitted tiles of a small group join the fitted neighbour (of another group) whose fit lays
  // their walls best, whether its group is small or large: tile fits scatter by a degree or so (a
  // cluttered or bent map's), so the tiles of a piece beyond a break can fall into groups of one or
  // two tiles each; laid best by each other's fits they gather into their piece, where joining the
  // large group next door one by one would hide the break.
  for (bool joined = true; joined;) {
    joined = false;
    for (std::size_t t = 0; t < n; ++t) {
      if (!fitted[t] || set_points[sets.find(t)] >= params.piece_min_points) continue;
      std::size_t best = t;
      double best_agreement = -1.0;
      for (const std::size_t u : tiles.neighbours(t)) {
        if (!fitted[u] || sets.find(u) == sets.find(t)) continue;
        const double a = tiles.agreement(t, fit[u], reference, params);
        if (a > best_agreement) best = u, best_agreement = a;
      }
      if (best != t) {
        const std::size_t a = sets.find(t), b = sets.find(best);
        sets.join(a, b);
        set_points[sets.find(a)] = set_points[a] + set_points[b];
        joined = true;
      }
    }
  }
  std::vector<int> root(n, -1);
  for (std::size_t t = 0; t < n; ++t) {
    const int r = static_cast<int>(sets.find(t));
    if (fitted[t] && set_points[static_cast<std::size_t>(r)] >= params.piece_min_points) root[t] = r;
  }
  if (std::all_of(root.begin(), root.end(), [](int r) { return r < 0; })) {
    root.assign(n, 0);  // nothing big enough to call a piece: one piece, the whole map
  }
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t t = 0; t < n; ++t) {
      if (root[t] >= 0) continue;
      int best = -1;
      double best_agreement = -1.0;
      for (const std::size_t u : tiles.neighbours(t)) {
        const int r = root[u];
        if (r < 0) continue;
        const double a = tiles.agreement(t, fit[static_cast<std::size_t>(r)], reference, params);
        if (a > best_agreement) best = r, best_agreement = a;
      }
      if (best >= 0) root[t] = best, changed = true;
    }
  }
  for (auto& r : root) r = std::max(r, 0);
  return root;
}

/// A group of tiles' rigid fit: trimmed ICP of all their walls from `start` and from the members'
/// own fits that lay most of them unrefined (`tile_fit` where `fitted`; fits within
/// `piece_rotation_tolerance_rad` / 10 and `piece_shift_tolerance_m` / 10 of another count once;
/// `piece_fit_starts` starts in all), the one laying most walls
/// within tolerance; the whole map's `T` where that lays more (on a cluttered map a fit can slide
/// or turn away to a worse place: Intel's one piece turned 11° to lay a fifth of its walls, where
/// the whole map's transform lays a quarter). One start can be a tile whose fit slid a wall period
/// along a row of like rooms, or turned a degree or two off in a cluttered room: the group's walls
/// then converge next to it, not to where the piece lies.
inline Similarity2 fit_tile_group(const WallTiles& tiles, const std::vector<std::size_t>& members, const Similarity2& start,
                                  const std::vector<Similarity2>& tile_fit, const std::vector<char>& fitted,
                                  const BoundaryLookup& reference, const Similarity2& T, const AssessParams& params) {
  std::vector<Eigen::Vector2d> points, piece_sides;
  Eigen::Vector2d middle = Eigen::Vector2d::Zero();
  for (const std::size_t t : members) {
    points.insert(points.end(), tiles.walls[t].begin(), tiles.walls[t].end());
    piece_sides.insert(piece_sides.end(), tiles.sides[t].begin(), tiles.sides[t].end());
    middle += tiles.centre(t);
  }
  if (!members.empty()) middle /= static_cast<double>(members.size());
  // The distinct starts, each scored unrefined on every fourth wall point; ICP from the first
  // start and from the best-scoring others, `piece_fit_starts` in all (one per tile would cost a
  // refit per tile: a large floor in one piece has hundreds).
  std::vector<Similarity2> starts{start};
  auto was_tried = [&](const Similarity2& s) {
    return std::any_of(starts.begin(), starts.end(), [&](const Similarity2& u) {
      return std::abs(wrap_angle(s.rotation - u.rotation)) <= 0.1 * params.piece_rotation_tolerance_rad &&
             (s * middle - u * middle).norm() <= 0.1 * params.piece_shift_tolerance_m;
    });
  };
  for (const std::size_t t : members) {
    if (fitted[t] && !was_tried(tile_fit[t])) starts.push_back(tile_fit[t]);
  }
  if (starts.size() > params.piece_fit_starts) {
    const std::vector<Eigen::Vector2d> few = detail::every_kth(points, 4);
    std::vector<std::size_t> score(starts.size());
    for (std::size_t k = 1; k < starts.size(); ++k) score[k] = reference.count_within(few, starts[k], params.wall_tolerance_m);
    std::vector<std::size_t> order(starts.size() - 1);
    std::iota(order.begin(), order.end(), std::size_t{1});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return score[a] > score[b]; });
    std::vector<Similarity2> kept{start};
    for (std::size_t i = 0; i + 1 < params.piece_fit_starts; ++i) kept.push_back(starts[order[i]]);
    starts = std::move(kept);
  }
  Similarity2 best = T;
  std::size_t best_on = reference.count_within(points, T, params.wall_tolerance_m);
  for (std::size_t k = 0; k < starts.size(); ++k) {
    const Similarity2 own = refine_icp(points, reference, starts[k], params.piece_icp, &piece_sides);
    const std::size_t on = reference.count_within(points, own, params.wall_tolerance_m);
    if (on > best_on || (k == 0 && on == best_on)) best = own, best_on = on;
  }
  return best;
}

}  // namespace detail
}  // namespace areamatch
