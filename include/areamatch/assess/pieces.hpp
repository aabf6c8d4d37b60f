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
/// the fit it started from; a tile across a cut, whose walls turned at once, is fitted again from
/// that start turned a few ways (`piece_retry_turns_rad`). Neighbouring tiles are one piece when
/// their fits agree: within `piece_rotation_tolerance_rad`, and within `piece_shift_tolerance_m`
/// at their common side. A smooth bend (SLAM drift) turns little from one tile to the next and
/// stays one piece however far it bends in all; a failed loop closure turns everything beyond it
/// at once. The fitted tiles of a group with fewer than `piece_min_points` wall points first join
/// the fitted neighbour whose fit lays their walls best (tile fits scatter, and a piece's tiles
/// gather that way); groups still that small and tiles too bare to fit join the neighbouring piece
/// that lays their walls best. Each piece is then fitted on all its walls,
/// neighbouring pieces whose own fits agree after all are joined, and each area goes to the piece
/// holding most of its walls. Once the map is warped (assess/report.hpp), `fit_pieces_to_warp`
/// makes each piece's fit the rigid fit of its warped walls and joins the pieces that then agree.

#include "../area_graph.hpp"
#include "../grid.hpp"
#include "../match/verification/correspondence.hpp"
#include "../match/verification/refine.hpp"
#include "../transform.hpp"
#include "../warp/field.hpp"
#include "params.hpp"
#include "tiles.hpp"

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
  /// The piece's own rigid fit (map world → reference world): the ICP fit of its walls from
  /// `find_pieces`, made the least-squares fit of where the warp takes them by `fit_pieces_to_warp`.
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
  /// Per tile: its own rigid fit where it had one that counts and it lies within
  /// `AssessParams::piece_start_max_offset_m` of its piece's fit at the tile's middle, else its piece's.
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
  /// `piece_cells` along a tile's side.
  int cells_per_tile() const { return static_cast<int>(std::lround(tile_m / piece_cell_m)); }
  /// The piece a map point belongs to.
  int piece_at(const Eigen::Vector2d& map_point) const {
    if (piece_of_tile.empty()) return 0;
    if (piece_cells.empty()) return piece_of_tile[tile_at(map_point)];
    const int per_tile = cells_per_tile();
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
  /// The labelling of `piece_at` as a raster (the finer cells where there are, else the tiles),
  /// for a warp that moves each piece with its own field (`WarpStart::pieces`); empty for a map
  /// in one piece.
  PieceLabels labels() const {
    PieceLabels out;
    if (pieces.size() <= 1 || piece_of_tile.empty()) return out;
    out.origin = tile_origin;
    if (piece_cells.empty()) {
      out.cell_m = tile_m;
      out.columns = tile_columns;
      out.rows = tile_rows;
      out.labels = piece_of_tile;
    } else {
      const int per_tile = cells_per_tile();
      out.cell_m = piece_cell_m;
      out.columns = tile_columns * per_tile;
      out.rows = tile_rows * per_tile;
      out.labels = piece_cells;
    }
    return out;
  }
  /// Birk's brokenness: the pieces beyond the main one (0 for a map in one piece).
  std::size_t broken_pieces() const { return pieces.empty() ? 0 : pieces.size() - 1; }
};

namespace detail {

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


/// Per piece (indexed by its root tile), the areas whose wall points lie mostly in its tiles.
inline std::vector<std::vector<int>> areas_by_piece(const WallTiles& tiles, const std::vector<int>& piece_of_tile, std::size_t n_areas) {
  const std::size_t n = tiles.size();
  std::vector<std::vector<std::size_t>> votes(n_areas);
  for (std::size_t t = 0; t < n; ++t) {
    for (const int a : tiles.wall_area[t]) {
      auto& v = votes[static_cast<std::size_t>(a)];
      if (v.empty()) v.assign(n, 0);
      ++v[static_cast<std::size_t>(piece_of_tile[t])];
    }
  }
  std::vector<std::vector<int>> grouped(n);
  for (std::size_t a = 0; a < n_areas; ++a) {
    if (votes[a].empty()) continue;
    const auto piece = static_cast<std::size_t>(std::max_element(votes[a].begin(), votes[a].end()) - votes[a].begin());
    grouped[piece].push_back(static_cast<int>(a));
  }
  return grouped;
}

/// The pieces (sorted, the main one first) into `out`: each one's turn and shift relative to the
/// main piece, and each area's piece index.
inline void number_pieces(std::vector<std::pair<RigidPiece, std::size_t>>& found, Brokenness& out) {
  const Similarity2 main = found.front().first.T_reference_map;
  for (std::size_t k = 0; k < found.size(); ++k) {
    RigidPiece& piece = found[k].first;
    piece.rotation_rad = k == 0 ? 0.0 : wrap_angle(piece.T_reference_map.rotation - main.rotation);
    piece.shift_m = k == 0 ? 0.0 : (piece.T_reference_map * piece.centroid - main * piece.centroid).norm();
    for (const int a : piece.areas) out.piece_of_area[static_cast<std::size_t>(a)] = static_cast<int>(k);
    out.pieces.push_back(std::move(piece));  // found[k].second stays for the caller
  }
}

/// Neighbouring pieces whose fits agree at the middle of their common border (`fits_agree`) joined
/// into one, the pieces renumbered (the largest first) and every index into them with them. `from`
/// and `to` are per piece its wall points and their warped places; a joined piece is fitted on
/// theirs together, and they are regrouped to the new numbers.
inline void join_agreeing_pieces(Brokenness& b, std::vector<std::vector<Eigen::Vector2d>>& from,
                                 std::vector<std::vector<Eigen::Vector2d>>& to, const AssessParams& params) {
  const std::size_t n = b.pieces.size();
  const PieceLabels labels = b.labels();
  if (labels.empty()) return;
  // Per pair of pieces that touch: the sum and count of the middles of the cell sides between them.
  std::vector<Eigen::Vector2d> border_sum(n * n, Eigen::Vector2d::Zero());
  std::vector<std::size_t> border_count(n * n, 0);
  const auto columns = static_cast<std::size_t>(labels.columns);
  for (int r = 0; r < labels.rows; ++r) {
    for (int c = 0; c < labels.columns; ++c) {
      const int here = labels.labels[static_cast<std::size_t>(r) * columns + static_cast<std::size_t>(c)];
      const Eigen::Vector2d centre = labels.origin + labels.cell_m * Eigen::Vector2d(c + 0.5, r + 0.5);
      for (const auto& [dc, dr] : {std::pair<int, int>{1, 0}, std::pair<int, int>{0, 1}}) {
        if (c + dc >= labels.columns || r + dr >= labels.rows) continue;
        const int there = labels.labels[static_cast<std::size_t>(r + dr) * columns + static_cast<std::size_t>(c + dc)];
        if (there == here) continue;
        const std::size_t lo = static_cast<std::size_t>(std::min(here, there)), hi = static_cast<std::size_t>(std::max(here, there));
        border_sum[lo * n + hi] += centre + 0.5 * labels.cell_m * Eigen::Vector2d(dc, dr);
        ++border_count[lo * n + hi];
      }
    }
  }
  DisjointSets sets(n);
  bool joined = false;
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t c = a + 1; c < n; ++c) {
      const std::size_t count = border_count[a * n + c];
      if (count == 0) continue;
      const Eigen::Vector2d middle = border_sum[a * n + c] / static_cast<double>(count);
      if (fits_agree(b.pieces[a].T_reference_map, b.pieces[c].T_reference_map, middle, params)) joined |= sets.join(a, c);
    }
  }
  if (!joined) return;
  // The joined pieces, in the order of their first member (a set's root is its smallest member,
  // so it comes first); then the largest first.
  std::vector<std::size_t> group_of(n), firsts;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t root = sets.find(k);
    if (root == k) firsts.push_back(k);
    group_of[k] = root == k ? firsts.size() - 1 : group_of[root];
  }
  std::vector<RigidPiece> grouped(firsts.size());
  std::vector<std::vector<Eigen::Vector2d>> group_from(firsts.size()), group_to(firsts.size());
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t g = group_of[k];
    const RigidPiece& piece = b.pieces[k];
    RigidPiece& into = grouped[g];
    into.areas.insert(into.areas.end(), piece.areas.begin(), piece.areas.end());
    into.centroid += piece.size_m2 * piece.centroid;
    into.size_m2 += piece.size_m2;
    group_from[g].insert(group_from[g].end(), from[k].begin(), from[k].end());
    group_to[g].insert(group_to[g].end(), to[k].begin(), to[k].end());
  }
  for (std::size_t g = 0; g < firsts.size(); ++g) {
    RigidPiece& piece = grouped[g];
    std::sort(piece.areas.begin(), piece.areas.end());
    if (piece.size_m2 > 0.0) piece.centroid /= piece.size_m2;
    piece.T_reference_map = b.pieces[firsts[g]].T_reference_map;
    if (group_from[g].size() >= 3) piece.T_reference_map = least_squares_rigid(group_from[g], group_to[g], piece.T_reference_map);
  }
  std::vector<std::size_t> order(firsts.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return grouped[x].size_m2 > grouped[y].size_m2; });
  std::vector<int> number_of_group(firsts.size());
  for (std::size_t i = 0; i < order.size(); ++i) number_of_group[order[i]] = static_cast<int>(i);
  b.pieces.clear();
  from.clear();
  to.clear();
  for (const std::size_t g : order) {
    b.pieces.push_back(std::move(grouped[g]));
    from.push_back(std::move(group_from[g]));
    to.push_back(std::move(group_to[g]));
  }
  auto renumber = [&](int& piece) { piece = number_of_group[group_of[static_cast<std::size_t>(piece)]]; };
  for (int& piece : b.piece_of_area) renumber(piece);
  for (int& piece : b.piece_of_tile) renumber(piece);
  for (int& piece : b.piece_cells) renumber(piece);
  if (b.pieces.size() <= 1) b.piece_cells.clear();
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

  const detail::WallTiles tiles = detail::wall_tiles(map, graph, params);
  const std::size_t n = tiles.size();
  std::vector<Similarity2> fit;
  std::vector<char> fitted;
  detail::fit_each_tile(tiles, reference, T, params, fit, fitted);
  const std::vector<int> root = detail::group_tiles(tiles, reference, params, fit, fitted);

  // Pieces: fit each on all its walls, then join neighbours whose fits agree after all.
  std::vector<std::vector<std::size_t>> members(n);
  for (std::size_t t = 0; t < n; ++t) members[static_cast<std::size_t>(root[t])].push_back(t);
  std::vector<Similarity2> piece_fit(n, T);
  for (std::size_t r = 0; r < n; ++r) {
    if (!members[r].empty()) piece_fit[r] = detail::fit_tile_group(tiles, members[r], fit[r], fit, fitted, reference, T, params);
  }
  detail::DisjointSets pieces(n);
  for (std::size_t t = 0; t < n; ++t) {
    for (const std::size_t u : tiles.neighbours(t)) {
      const int a = root[t], b = root[u];
      if (u > t && a != b &&
          detail::fits_agree(piece_fit[static_cast<std::size_t>(a)], piece_fit[static_cast<std::size_t>(b)], tiles.shared_edge(t, u), params)) {
        pieces.join(static_cast<std::size_t>(a), static_cast<std::size_t>(b));
      }
    }
  }
  std::vector<int> piece_of_tile(n);
  for (std::size_t t = 0; t < n; ++t) piece_of_tile[t] = static_cast<int>(pieces.find(static_cast<std::size_t>(root[t])));
  std::vector<std::vector<std::size_t>> tiles_of(n);
  for (std::size_t t = 0; t < n; ++t) tiles_of[static_cast<std::size_t>(piece_of_tile[t])].push_back(t);

  // Each area goes to the piece holding most of its wall points (the largest piece without any).
  const std::vector<std::vector<int>> grouped = detail::areas_by_piece(tiles, piece_of_tile, n_areas);
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
    piece.T_reference_map = members[r].size() == tiles_of[r].size()
                                ? piece_fit[r]
                                : detail::fit_tile_group(tiles, tiles_of[r], piece_fit[r], fit, fitted, reference, T, params);
    std::size_t on = 0, all = 0;
    for (const std::size_t t : tiles_of[r]) {
      on += reference.count_within(tiles.walls[t], piece.T_reference_map, params.wall_tolerance_m);
      all += tiles.walls[t].size();
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
  detail::number_pieces(found, out);

  std::vector<int> index_of_root(n, 0);  // tiles of a piece no area went to: the main piece's
  for (std::size_t k = 0; k < found.size(); ++k) index_of_root[found[k].second] = static_cast<int>(k);
  out.tile_origin = tiles.lo;
  out.tile_m = tiles.side;
  out.tile_columns = tiles.columns;
  out.tile_rows = tiles.rows;
  out.piece_of_tile.resize(n);
  out.tile_fit.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    out.piece_of_tile[t] = index_of_root[static_cast<std::size_t>(piece_of_tile[t])];
    const Similarity2& piece_fit_here = out.pieces[static_cast<std::size_t>(out.piece_of_tile[t])].T_reference_map;
    const Eigen::Vector2d middle = tiles.centre(t);
    const bool near_piece = (fit[t] * middle - piece_fit_here * middle).norm() <= params.piece_start_max_offset_m;
    out.tile_fit[t] = fitted[t] && near_piece ? fit[t] : piece_fit_here;
  }
  if (out.pieces.size() > 1) out.piece_cells = detail::piece_cells(out, tiles.walls, reference, params);
  return out;
}

/// Each piece's transform made the least-squares rigid fit of where `warp` takes its wall points
/// (`map_walls`, map world): the rigid motion that best describes the piece as warped. The tiles'
/// ICP fits that found the pieces weigh the walls they agree with best, so a bent piece's fit
/// leans to its best-fitting part and its turn is off by up to a degree or two; the warp has every
/// wall in place, bend and all. Which piece a wall point is fitted with starts from
/// `Brokenness::piece_at` and then goes to the piece whose fit lays it nearest its warped place,
/// `piece_refit_rounds` times: next to a cut the warp of one piece bends to follow the walls of its
/// neighbour that its labels gave it, and those walls would turn its rigid fit (a few per cent of
/// a piece's walls turn it by a degree). Turns, shifts and wall agreements (against `reference`)
/// follow the new fits. A piece with fewer than three points keeps its fit.
inline void fit_pieces_to_warp(Brokenness& b, const std::vector<Eigen::Vector2d>& map_walls, const WarpField& warp,
                               const BoundaryLookup& reference, const AssessParams& params) {
  if (b.pieces.empty()) return;
  const std::size_t n = map_walls.size(), n_pieces = b.pieces.size();
  std::vector<Eigen::Vector2d> warped(n);
  std::vector<std::size_t> label(n);
  for (std::size_t i = 0; i < n; ++i) {
    warped[i] = warp.apply(map_walls[i]);
    label[i] = static_cast<std::size_t>(b.piece_at(map_walls[i]));
  }
  std::vector<std::vector<Eigen::Vector2d>> from(n_pieces), to(n_pieces);
  for (int round = 0; round <= params.piece_refit_rounds; ++round) {
    for (std::size_t k = 0; k < n_pieces; ++k) from[k].clear(), to[k].clear();
    for (std::size_t i = 0; i < n; ++i) from[label[i]].push_back(map_walls[i]), to[label[i]].push_back(warped[i]);
    for (std::size_t k = 0; k < n_pieces; ++k) {
      Similarity2& T = b.pieces[k].T_reference_map;
      if (from[k].size() >= 3) T = detail::least_squares_rigid(from[k], to[k], T);
    }
    if (round == params.piece_refit_rounds || n_pieces == 1) break;
    bool dealt_again = false;  // none moved: the fits are those of these labels already
    for (std::size_t i = 0; i < n; ++i) {
      double nearest = (b.pieces[label[i]].T_reference_map * map_walls[i] - warped[i]).squaredNorm();
      for (std::size_t k = 0; k < n_pieces; ++k) {
        const double d = (b.pieces[k].T_reference_map * map_walls[i] - warped[i]).squaredNorm();
        if (d < nearest) nearest = d, label[i] = k, dealt_again = true;
      }
    }
    if (!dealt_again) break;
  }
  if (n_pieces > 1) detail::join_agreeing_pieces(b, from, to, params);
  const Similarity2 main = b.pieces.front().T_reference_map;
  for (std::size_t k = 0; k < b.pieces.size(); ++k) {
    RigidPiece& piece = b.pieces[k];
    if (!from[k].empty()) {
      piece.wall_agreement = static_cast<double>(reference.count_within(from[k], piece.T_reference_map, params.wall_tolerance_m)) /
                             static_cast<double>(from[k].size());
    }
    piece.rotation_rad = k == 0 ? 0.0 : wrap_angle(piece.T_reference_map.rotation - main.rotation);
    piece.shift_m = k == 0 ? 0.0 : (piece.T_reference_map * piece.centroid - main * piece.centroid).norm();
  }
}

}  // namespace areamatch
