#pragma once
/// \file assess/pieces.hpp
/// Brokenness (Birk, "A quantitative assessment of structural errors in grid maps", Autonomous
/// Robots 2010): into how many rigid pieces a map falls, each with its transform onto the
/// reference relative to the main (largest) piece.
///
/// The map's walls (its areas' free-space edges) are dealt into square tiles
/// (`piece_tile_m`: smaller than a long corridor, which a bend leaves no longer rigid). Every
/// tile gets its own rigid fit — trimmed ICP of its walls onto the reference's, started from a
/// neighbouring tile already fitted (a breadth-first walk from the tile with the most walls), so
/// that the fits follow a map that turns step by step instead of jumping to the next room; a fit
/// counts only where it lays most of the tile's walls (`piece_min_wall_agreement`) and stays near
/// the whole map's transform. Neighbouring tiles are one piece when their fits agree: within
/// `piece_rotation_tolerance_rad`, and within `piece_shift_tolerance_m` at their common side. A
/// smooth bend (SLAM drift) turns little from one tile to the next and stays one piece however far
/// it bends in all; a failed loop closure turns everything beyond it at once. Pieces with fewer
/// than `piece_min_points` wall points and tiles too bare to fit join the neighbouring piece that
/// lays their walls best. Each piece is then fitted on all its walls, neighbouring pieces whose
/// own fits agree after all are joined, and each area goes to the piece holding most of its walls.

#include "../area_graph.hpp"
#include "../grid.hpp"
#include "../match/correspondence.hpp"
#include "../match/refine.hpp"
#include "../transform.hpp"
#include "params.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <queue>
#include <utility>
#include <vector>

namespace areamatch {

/// One rigid piece of a map.
struct RigidPiece {
  std::vector<int> areas;   ///< the map's area ids, ascending
  double size_m2 = 0.0;     ///< free space of those areas (the map's metres)
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();  ///< of that free space, map world
  /// The piece's own rigid fit (map world → reference world).
  Similarity2 T_reference_map;
  /// Relative to the main piece: its turn (radians) and how far it moves the piece's centroid
  /// beyond where the main piece's transform puts it (reference metres). Zero for the main piece.
  double rotation_rad = 0.0;
  double shift_m = 0.0;
  /// Share of the piece's wall points within `wall_tolerance_m` of a reference wall under its fit.
  double wall_agreement = 0.0;
};

/// The pieces, the main (largest) first, then by size.
struct Brokenness {
  std::vector<RigidPiece> pieces;
  std::vector<int> piece_of_area;  ///< per map area: its piece's index
  /// The tiles the walls were fitted in (map world): origin, side, columns, rows, and per tile
  /// (row-major) its piece's index.
  Eigen::Vector2d tile_origin = Eigen::Vector2d::Zero();
  double tile_m = 1.0;
  int tile_columns = 0, tile_rows = 0;
  std::vector<int> piece_of_tile;
  /// Per tile: its own rigid fit where it had one that counts, else its piece's.
  std::vector<Similarity2> tile_fit;
  /// The tile a map point falls in (the nearest tile beyond them), row-major.
  std::size_t tile_at(const Eigen::Vector2d& map_point) const {
    const Eigen::Vector2d u = (map_point - tile_origin) / tile_m;
    const int c = std::clamp(static_cast<int>(std::floor(u.x())), 0, tile_columns - 1);
    const int r = std::clamp(static_cast<int>(std::floor(u.y())), 0, tile_rows - 1);
    return static_cast<std::size_t>(r) * static_cast<std::size_t>(tile_columns) + static_cast<std::size_t>(c);
  }
  /// A finer labelling where pieces meet (a cut runs through tiles, not along their sides): per
  /// cell of `piece_cell_m` over the tiles, row-major, the piece whose transform lays the walls
  /// around it best. Empty for a map in one piece.
  std::vector<int> piece_cells;
  double piece_cell_m = 0.5;
  /// The piece a map point belongs to.
  int piece_at(const Eigen::Vector2d& map_point) const {
    if (piece_of_tile.empty()) return 0;
    if (piece_cells.empty()) return piece_of_tile[tile_at(map_point)];
    const int per_tile = static_cast<int>(std::lround(tile_m / piece_cell_m));
    const Eigen::Vector2d u = (map_point - tile_origin) / piece_cell_m;
    const int c = std::clamp(static_cast<int>(std::floor(u.x())), 0, tile_columns * per_tile - 1);
    const int r = std::clamp(static_cast<int>(std::floor(u.y())), 0, tile_rows * per_tile - 1);
    return piece_cells[static_cast<std::size_t>(r) * static_cast<std::size_t>(tile_columns * per_tile) + static_cast<std::size_t>(c)];
  }
  /// The rigid fit that starts a warp at a map point: its tile's own, or its piece's where the
  /// finer labelling gives the point to another piece than its tile's.
  const Similarity2& local_fit(const Eigen::Vector2d& map_point) const {
    const std::size_t t = tile_at(map_point);
    const int piece = piece_at(map_point);
    return piece == piece_of_tile[t] ? tile_fit[t] : pieces[static_cast<std::size_t>(piece)].T_reference_map;
  }
  /// Birk's brokenness: the pieces beyond the main one (0 for a map in one piece).
  std::size_t broken_pieces() const { return pieces.empty() ? 0 : pieces.size() - 1; }
};

namespace detail {

/// Union-find over areas (smaller root wins, so the result does not depend on the join order).
class AreaSets {
 public:
  explicit AreaSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  int find(int a) {
    while (parent_[static_cast<std::size_t>(a)] != a) {
      parent_[static_cast<std::size_t>(a)] = parent_[static_cast<std::size_t>(parent_[static_cast<std::size_t>(a)])];
      a = parent_[static_cast<std::size_t>(a)];
    }
    return a;
  }
  void join(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }

 private:
  std::vector<int> parent_;
};

/// Whether two fits agree at `at` (map world): turn and placed position.
inline bool fits_agree(const Similarity2& a, const Similarity2& b, const Eigen::Vector2d& at, const AssessParams& params) {
  return std::abs(wrap_angle(a.rotation - b.rotation)) <= params.piece_rotation_tolerance_rad &&
         (a * at - b * at).norm() <= params.piece_shift_tolerance_m;
}

/// The finer labelling of `Brokenness::piece_cells`: each cell whose tile or a neighbouring tile
/// lies in another piece goes to the piece (of those) under whose transform most of the wall points
/// within a tile's half side lie on a reference wall; the others keep their tile's piece.
inline std::vector<int> piece_cells(const Brokenness& b, const std::vector<std::vector<Eigen::Vector2d>>& tile_walls,
                                    const BoundaryLookup& reference, const AssessParams& params) {
  const int per_tile = std::max(1, static_cast<int>(std::lround(b.tile_m / b.piece_cell_m)));
  const int columns = b.tile_columns * per_tile, rows = b.tile_rows * per_tile;
  const double radius = 0.5 * b.tile_m;
  std::vector<int> out(static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows));
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < columns; ++c) {
      const int tc = c / per_tile, tr = r / per_tile;
      const int own = b.piece_of_tile[static_cast<std::size_t>(tr) * static_cast<std::size_t>(b.tile_columns) + static_cast<std::size_t>(tc)];
      int& label = out[static_cast<std::size_t>(r) * static_cast<std::size_t>(columns) + static_cast<std::size_t>(c)];
      label = own;
      std::vector<int> candidates{own};
      std::vector<const std::vector<Eigen::Vector2d>*> near;
      for (int dr = -1; dr <= 1; ++dr) {
        for (int dc = -1; dc <= 1; ++dc) {
          if (tc + dc < 0 || tr + dr < 0 || tc + dc >= b.tile_columns || tr + dr >= b.tile_rows) continue;
          const std::size_t t = static_cast<std::size_t>(tr + dr) * static_cast<std::size_t>(b.tile_columns) + static_cast<std::size_t>(tc + dc);
          near.push_back(&tile_walls[t]);
          if (std::find(candidates.begin(), candidates.end(), b.piece_of_tile[t]) == candidates.end()) candidates.push_back(b.piece_of_tile[t]);
        }
      }
      if (candidates.size() == 1) continue;
      const Eigen::Vector2d centre = b.tile_origin + b.piece_cell_m * Eigen::Vector2d(c + 0.5, r + 0.5);
      std::vector<Eigen::Vector2d> points;
      for (const auto* walls : near) {
        for (const auto& p : *walls) {
          if ((p - centre).squaredNorm() <= radius * radius) points.push_back(p);
        }
      }
      std::size_t best = 0;
      for (const int piece : candidates) {
        const std::size_t on = reference.count_within(points, b.pieces[static_cast<std::size_t>(piece)].T_reference_map, params.wall_tolerance_m);
        if (on > best) best = on, label = piece;
      }
    }
  }
  return out;
}

}  // namespace detail

/// The rigid pieces of `map` (segmented into `graph`) against the reference walls `reference`
/// (`detail::wall_lookup`: normals and free sides), starting from the whole map's transform `T`.
inline Brokenness find_pieces(const OccupancyGrid& map, const AreaGraph& graph, const BoundaryLookup& reference,
                              const Similarity2& T, const AssessParams& params) {
  Brokenness out;
  const std::size_t n_areas = graph.areas.size();
  out.piece_of_area.assign(n_areas, 0);
  if (n_areas == 0) return out;

  // The areas' wall points, dealt into square tiles.
  const auto area_walls = detail::area_wall_points(graph, detail::free_edge_cells(map, graph), params.piece_icp.point_spacing_m);
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::max()), hi = -lo;
  for (const auto& walls : area_walls) {
    for (const auto& p : walls) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  if (!(lo.x() <= hi.x())) lo = hi = Eigen::Vector2d::Zero();
  const double side = params.piece_tile_m;
  const int columns = static_cast<int>((hi.x() - lo.x()) / side) + 1, rows = static_cast<int>((hi.y() - lo.y()) / side) + 1;
  const std::size_t n = static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows);
  std::vector<std::vector<Eigen::Vector2d>> walls(n);
  std::vector<std::vector<int>> wall_area(n);  // per tile point: its area
  for (std::size_t a = 0; a < n_areas; ++a) {
    for (const auto& p : area_walls[a]) {
      const int c = std::min(columns - 1, static_cast<int>((p.x() - lo.x()) / side));
      const int r = std::min(rows - 1, static_cast<int>((p.y() - lo.y()) / side));
      const std::size_t t = static_cast<std::size_t>(r) * static_cast<std::size_t>(columns) + static_cast<std::size_t>(c);
      walls[t].push_back(p);
      wall_area[t].push_back(static_cast<int>(a));
    }
  }
  std::vector<std::vector<Eigen::Vector2d>> sides(n);
  for (std::size_t t = 0; t < n; ++t) sides[t] = detail::free_sides(map, walls[t], params.piece_icp.free_side_radius_m);
  auto neighbours = [&](std::size_t t) {
    std::vector<std::size_t> out_n;
    const int c = static_cast<int>(t % static_cast<std::size_t>(columns)), r = static_cast<int>(t / static_cast<std::size_t>(columns));
    if (c > 0) out_n.push_back(t - 1);
    if (c + 1 < columns) out_n.push_back(t + 1);
    if (r > 0) out_n.push_back(t - static_cast<std::size_t>(columns));
    if (r + 1 < rows) out_n.push_back(t + static_cast<std::size_t>(columns));
    return out_n;
  };
  auto shared_edge = [&](std::size_t a, std::size_t b) {  // the middle of two neighbouring tiles' common side
    auto centre = [&](std::size_t t) {
      return Eigen::Vector2d(lo.x() + side * (static_cast<double>(t % static_cast<std::size_t>(columns)) + 0.5),
                             lo.y() + side * (static_cast<double>(t / static_cast<std::size_t>(columns)) + 0.5));
    };
    return Eigen::Vector2d(0.5 * (centre(a) + centre(b)));
  };
  auto agreement = [&](std::size_t t, const Similarity2& fit) {
    return walls[t].empty() ? 0.0 : boundary_inlier_fraction(walls[t], reference, fit, params.wall_tolerance_m);
  };

  // Each tile's own fit, walked breadth-first from the tile with the most walls.
  std::vector<Similarity2> fit(n, T);
  std::vector<char> fitted(n, 0), visited(n, 0);
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return walls[a].size() > walls[b].size(); });
  for (const std::size_t start : order) {
    if (visited[start] || walls[start].empty()) continue;
    std::queue<std::size_t> queue;
    queue.push(start);
    visited[start] = 1;
    while (!queue.empty()) {
      const std::size_t i = queue.front();
      queue.pop();
      if (walls[i].size() >= params.piece_min_wall_points) {
        const Similarity2 own = refine_icp(walls[i], reference, fit[i], params.piece_icp, &sides[i]);
        const Eigen::Vector2d c = shared_edge(i, i);
        if (std::abs(wrap_angle(own.rotation - T.rotation)) <= params.piece_max_rotation_rad &&
            (own * c - T * c).norm() <= params.piece_max_shift_m && agreement(i, own) >= params.piece_min_wall_agreement) {
          fit[i] = own;
          fitted[i] = 1;
        }
      }
      for (const std::size_t j : neighbours(i)) {
        if (visited[j] || walls[j].empty()) continue;
        visited[j] = 1;
        fit[j] = fit[i];  // start from this neighbour's fit (or what it started from)
        queue.push(j);
      }
    }
  }

  // Fitted neighbours whose fits agree at their common side are one piece.
  detail::AreaSets sets(n);
  for (std::size_t t = 0; t < n; ++t) {
    for (const std::size_t u : neighbours(t)) {
      if (u > t && fitted[t] && fitted[u] && detail::fits_agree(fit[t], fit[u], shared_edge(t, u), params)) {
        sets.join(static_cast<int>(t), static_cast<int>(u));
      }
    }
  }
  std::vector<std::size_t> set_points(n, 0);
  for (std::size_t t = 0; t < n; ++t) {
    if (fitted[t]) set_points[static_cast<std::size_t>(sets.find(static_cast<int>(t)))] += walls[t].size();
  }
  // Tiles in a piece big enough keep it; the rest join the neighbouring piece laying their walls best.
  std::vector<int> root(n, -1);
  for (std::size_t t = 0; t < n; ++t) {
    const int r = sets.find(static_cast<int>(t));
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
      for (const std::size_t u : neighbours(t)) {
        const int r = root[u];
        if (r < 0) continue;
        const double a = agreement(t, fit[static_cast<std::size_t>(r)]);
        if (a > best_agreement) best = r, best_agreement = a;
      }
      if (best >= 0) root[t] = best, changed = true;
    }
  }
  for (auto& r : root) r = std::max(r, 0);  // tiles no piece reaches (no walls between): the first

  // Pieces: fit each on all its walls, then join neighbours whose fits agree after all.
  auto fit_tiles = [&](const std::vector<std::size_t>& tiles, const Similarity2& start) {
    std::vector<Eigen::Vector2d> points, piece_sides;
    for (const std::size_t t : tiles) {
      points.insert(points.end(), walls[t].begin(), walls[t].end());
      piece_sides.insert(piece_sides.end(), sides[t].begin(), sides[t].end());
    }
    const Similarity2 own = refine_icp(points, reference, start, params.piece_icp, &piece_sides);
    // On a cluttered map a piece's fit can slide (a corridor's length) or turn away from the whole
    // map's transform to a worse place (Intel: 11°, a fifth of its walls on the reference's
    // where the whole map's transform lays a quarter): the whole map's then.
    const double own_agreement = boundary_inlier_fraction(points, reference, own, params.wall_tolerance_m);
    return own_agreement < boundary_inlier_fraction(points, reference, T, params.wall_tolerance_m) ? T : own;
  };
  std::vector<std::vector<std::size_t>> members(n);
  for (std::size_t t = 0; t < n; ++t) members[static_cast<std::size_t>(root[t])].push_back(t);
  std::vector<Similarity2> piece_fit(n, T);
  for (std::size_t r = 0; r < n; ++r) {
    if (!members[r].empty()) piece_fit[r] = fit_tiles(members[r], fit[r]);
  }
  detail::AreaSets pieces(n);
  for (std::size_t t = 0; t < n; ++t) {
    for (const std::size_t u : neighbours(t)) {
      const int a = root[t], b = root[u];
      if (u > t && a != b &&
          detail::fits_agree(piece_fit[static_cast<std::size_t>(a)], piece_fit[static_cast<std::size_t>(b)], shared_edge(t, u), params)) {
        pieces.join(a, b);
      }
    }
  }

  // Each area goes to the piece holding most of its wall points (the largest piece without any).
  std::vector<int> piece_of_tile(n);
  for (std::size_t t = 0; t < n; ++t) piece_of_tile[t] = pieces.find(root[t]);
  std::vector<std::vector<std::size_t>> votes(n_areas);
  for (std::size_t t = 0; t < n; ++t) {
    for (const int a : wall_area[t]) {
      auto& v = votes[static_cast<std::size_t>(a)];
      if (v.empty()) v.assign(n, 0);
      ++v[static_cast<std::size_t>(piece_of_tile[t])];
    }
  }
  std::vector<std::vector<int>> grouped(n);
  std::vector<std::vector<std::size_t>> tiles_of(n);
  for (std::size_t t = 0; t < n; ++t) tiles_of[static_cast<std::size_t>(piece_of_tile[t])].push_back(t);
  std::vector<int> area_piece(n_areas, -1);
  for (std::size_t a = 0; a < n_areas; ++a) {
    if (votes[a].empty()) continue;
    area_piece[a] = static_cast<int>(std::max_element(votes[a].begin(), votes[a].end()) - votes[a].begin());
  }
  for (std::size_t a = 0; a < n_areas; ++a) {
    if (area_piece[a] >= 0) grouped[static_cast<std::size_t>(area_piece[a])].push_back(static_cast<int>(a));
  }
  std::vector<std::pair<RigidPiece, std::size_t>> found;  // each piece with its root tile
  for (std::size_t r = 0; r < n; ++r) {
    if (grouped[r].empty()) continue;
    RigidPiece piece;
    piece.areas = grouped[r];
    for (const int a : piece.areas) {
      const Area& area = graph.areas[static_cast<std::size_t>(a)];
      piece.size_m2 += area.size_m2;
      piece.centroid += area.size_m2 * area.centroid;
    }
    if (piece.size_m2 > 0.0) piece.centroid /= piece.size_m2;
    piece.T_reference_map = members[r].size() == tiles_of[r].size() ? piece_fit[r] : fit_tiles(tiles_of[r], piece_fit[r]);
    std::size_t on = 0, all = 0;
    for (const std::size_t t : tiles_of[r]) {
      on += reference.count_within(walls[t], piece.T_reference_map, params.wall_tolerance_m);
      all += walls[t].size();
    }
    piece.wall_agreement = all > 0 ? static_cast<double>(on) / static_cast<double>(all) : 0.0;
    found.push_back({std::move(piece), r});
  }
  if (found.empty()) {  // no area has walls: one piece under the whole map's transform
    RigidPiece piece;
    for (std::size_t a = 0; a < n_areas; ++a) piece.areas.push_back(static_cast<int>(a)), piece.size_m2 += graph.areas[a].size_m2;
    piece.T_reference_map = T;
    found.push_back({std::move(piece), 0});
  }
  std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first.size_m2 > b.first.size_m2; });
  const Similarity2 main = found.front().first.T_reference_map;
  std::vector<int> index_of_root(n, 0);  // tiles of a piece no area went to: the main piece's
  for (std::size_t k = 0; k < found.size(); ++k) {
    RigidPiece& piece = found[k].first;
    piece.rotation_rad = k == 0 ? 0.0 : wrap_angle(piece.T_reference_map.rotation - main.rotation);
    piece.shift_m = k == 0 ? 0.0 : (piece.T_reference_map * piece.centroid - main * piece.centroid).norm();
    for (const int a : piece.areas) out.piece_of_area[static_cast<std::size_t>(a)] = static_cast<int>(k);
    index_of_root[found[k].second] = static_cast<int>(k);
    out.pieces.push_back(std::move(piece));
  }
  out.tile_origin = lo;
  out.tile_m = side;
  out.tile_columns = columns;
  out.tile_rows = rows;
  out.piece_of_tile.resize(n);
  out.tile_fit.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    out.piece_of_tile[t] = index_of_root[static_cast<std::size_t>(piece_of_tile[t])];
    out.tile_fit[t] = fitted[t] ? fit[t] : out.pieces[static_cast<std::size_t>(out.piece_of_tile[t])].T_reference_map;
  }
  if (out.pieces.size() > 1) out.piece_cells = detail::piece_cells(out, walls, reference, params);
  return out;
}

}  // namespace areamatch
