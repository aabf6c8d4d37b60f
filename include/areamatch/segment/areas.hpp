#pragma once
/// \file segment/areas.hpp
/// Stage 5–6 of segmentation: skeleton regions and passages → area polygons (the Area Graph).
///
/// Free space is labelled by growing every region from its skeleton samples, 4-connected, with
/// each passage's line (wall to wall) as a barrier, so every free cell ends up in exactly one
/// area. Growth first covers the free space *opened* by a disc of `min_clearance_m` (what the
/// skeleton can reach); from there it may go `fringe_m` further into thinner space (corners,
/// cracks). Laser streaks through windows and doors — free space too thin to pass that leads
/// away from the building — stay outside every area; `AreaGraph::covered_fraction` says how much.
/// Areas smaller than `min_area_m2` merge into the neighbour they share the longest border with.
/// Polygons come from Boost.Polygon's rectilinear set operations on the labelled cells, so they
/// follow the cell boundaries exactly and are valid.

#include "../area_graph.hpp"
#include "../detail/distance_transform.hpp"
#include "../error.hpp"
#include "../geometry.hpp"
#include "../grid.hpp"
#include "binarize.hpp"
#include "rooms.hpp"

#include <boost/polygon/polygon.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

namespace areamatch {

/// Parameters of `build_areas`. Lengths in metres, areas in m².
struct AreaParams {
  /// Areas smaller than this merge into a neighbour (or are dropped when they have none).
  double min_area_m2 = 1.0;
  /// How far labelling continues beyond the space the skeleton reaches.
  double fringe_m = 0.5;
  /// Must equal the skeleton's `min_clearance_m`: the radius of the opening.
  double min_clearance_m = 0.25;
  /// An area whose hull diameter exceeds this many times its widest free disc's diameter is a
  /// corridor.
  double corridor_elongation = 3.5;

  void validate() const {
    for (double v : {min_area_m2, fringe_m, min_clearance_m, corridor_elongation}) {
      if (!(std::isfinite(v) && v >= 0.0)) throw parameter_error("AreaParams: values must be >= 0 and finite");
    }
  }
};

namespace detail {

/// Marks the cells a straight line crosses, with no diagonal gaps (so a 4-connected flood
/// cannot slip through).
template <class Mark>
void supercover_line(const Eigen::Vector2d& a, const Eigen::Vector2d& b, Mark&& mark) {
  const double length = (b - a).norm();
  const int steps = std::max(1, static_cast<int>(std::ceil(length * 4.0)));
  int pc = static_cast<int>(std::floor(a.x())), pr = static_cast<int>(std::floor(a.y()));
  mark(pc, pr);
  for (int i = 1; i <= steps; ++i) {
    const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(i) / steps);
    const int c = static_cast<int>(std::floor(p.x())), r = static_cast<int>(std::floor(p.y()));
    if (c != pc && r != pr) mark(c, pr);  // close the diagonal step
    if (c != pc || r != pr) mark(c, r);
    pc = c;
    pr = r;
  }
}

inline Eigen::Vector2d lattice_to_world(const OccupancyGrid& grid, const Eigen::Vector2d& p) {
  return grid.pixel_to_world(p - Eigen::Vector2d(0.5, 0.5));
}

}  // namespace detail

/// Builds the Area Graph from detected rooms (see the file comment). `grid` gives the frame and
/// the free-cell count for `covered_fraction`.
inline AreaGraph build_areas(const OccupancyGrid& grid, const FreeSpace& space, const RoomDetection& rooms,
                             const AreaParams& params = {}) {
  params.validate();
  const int W = space.width, H = space.height;
  const std::size_t N = static_cast<std::size_t>(W) * H;
  const double res = grid.resolution();
  AreaGraph graph;
  graph.grid = {grid.width(), grid.height(), res, grid.origin()};
  graph.labels.assign(N, -1);

  // The opening of free space by a disc of min_clearance: what the skeleton can reach.
  const double radius = params.min_clearance_m / res;
  const auto wall_d2 = detail::squared_distance_transform(W, H, [&](int c, int r) { return !space.is_free(c, r); });
  std::vector<std::uint8_t> core(N, 0);
  for (std::size_t i = 0; i < N; ++i) core[i] = space.free[i] && std::sqrt(wall_d2[i]) - 0.5 >= radius;
  const auto core_d2 = detail::squared_distance_transform(W, H, [&](int c, int r) { return core[static_cast<std::size_t>(r) * W + c] != 0; });
  std::vector<std::uint8_t> opened(N, 0);
  for (std::size_t i = 0; i < N; ++i) opened[i] = space.free[i] && std::sqrt(core_d2[i]) <= radius + 0.5;

  // Passage lines are barriers.
  std::vector<std::uint8_t> barrier(N, 0);
  const SampleGraph& g = rooms.graph;
  for (const auto& p : rooms.passages) {
    const SkeletonSample& s = g.samples[p.sample];
    const Eigen::Vector2d direction = (s.foot_b - s.foot_a).normalized();
    detail::supercover_line(s.foot_a - direction, s.foot_b + direction, [&](int c, int r) {
      if (space.is_free(c, r)) barrier[static_cast<std::size_t>(r) * W + c] = 1;
    });
  }

  // Grow regions from their skeleton samples: first over the opened space, then into the fringe.
  std::vector<int>& label = graph.labels;
  std::vector<std::size_t> queue;
  for (std::size_t s = 0; s < g.samples.size(); ++s) {
    const int region = rooms.region_of_sample[s];
    if (region < 0) continue;
    const int c = static_cast<int>(std::floor(g.samples[s].position.x()));
    const int r = static_cast<int>(std::floor(g.samples[s].position.y()));
    if (!space.is_free(c, r)) continue;
    const std::size_t i = static_cast<std::size_t>(r) * W + c;
    if (barrier[i] || label[i] >= 0) continue;
    label[i] = region;
    queue.push_back(i);
  }
  auto grow = [&](std::vector<std::size_t>& frontier, bool into_fringe) {
    std::vector<std::size_t> next;
    for (std::size_t head = 0; head < frontier.size(); ++head) {
      const std::size_t i = frontier[head];
      const int c = static_cast<int>(i % W), r = static_cast<int>(i / W);
      const int dc[4] = {1, -1, 0, 0}, dr[4] = {0, 0, 1, -1};
      for (int k = 0; k < 4; ++k) {
        const int nc = c + dc[k], nr = r + dr[k];
        if (nc < 0 || nr < 0 || nc >= W || nr >= H) continue;
        const std::size_t j = static_cast<std::size_t>(nr) * W + nc;
        if (label[j] >= 0 || barrier[j] || !space.free[j]) continue;
        if (!into_fringe && !opened[j]) continue;
        label[j] = label[i];
        (into_fringe ? next : frontier).push_back(j);
      }
    }
    frontier.swap(next);
  };
  grow(queue, false);
  queue.clear();
  for (std::size_t i = 0; i < N; ++i)
    if (label[i] >= 0) queue.push_back(i);
  const int fringe_steps = static_cast<int>(std::ceil(params.fringe_m / res));
  for (int step = 0; step < fringe_steps && !queue.empty(); ++step) grow(queue, true);
  // Barrier cells join the area most of their neighbours belong to.
  auto majority_of_neighbours = [&](std::size_t i) {
    const int c = static_cast<int>(i % W), r = static_cast<int>(i / W);
    std::map<int, int> votes;
    const int dc[4] = {1, -1, 0, 0}, dr[4] = {0, 0, 1, -1};
    for (int k = 0; k < 4; ++k) {
      const int nc = c + dc[k], nr = r + dr[k];
      if (nc < 0 || nr < 0 || nc >= W || nr >= H) continue;
      const int l = label[static_cast<std::size_t>(nr) * W + nc];
      if (l >= 0) ++votes[l];
    }
    int best = -1, best_votes = 0;
    for (const auto& [l, v] : votes)
      if (v > best_votes) best = l, best_votes = v;
    return best;
  };
  std::vector<std::pair<std::size_t, int>> barrier_labels;
  for (std::size_t i = 0; i < N; ++i)
    if (barrier[i] && label[i] < 0) barrier_labels.push_back({i, majority_of_neighbours(i)});
  for (const auto& [i, l] : barrier_labels) label[i] = l;

  // Every 4-connected piece of a label is its own region; pieces of one skeleton region beyond
  // its largest and everything small then merge into neighbours.
  std::vector<int> piece(N, -1);
  std::vector<std::size_t> piece_size;
  std::vector<int> piece_region;
  {
    std::vector<std::size_t> stack;
    for (std::size_t start = 0; start < N; ++start) {
      if (label[start] < 0 || piece[start] >= 0) continue;
      const int id = static_cast<int>(piece_size.size());
      std::size_t size = 0;
      piece[start] = id;
      stack.assign(1, start);
      while (!stack.empty()) {
        const std::size_t i = stack.back();
        stack.pop_back();
        ++size;
        const int c = static_cast<int>(i % W), r = static_cast<int>(i / W);
        const int dc[4] = {1, -1, 0, 0}, dr[4] = {0, 0, 1, -1};
        for (int k = 0; k < 4; ++k) {
          const int nc = c + dc[k], nr = r + dr[k];
          if (nc < 0 || nr < 0 || nc >= W || nr >= H) continue;
          const std::size_t j = static_cast<std::size_t>(nr) * W + nc;
          if (piece[j] < 0 && label[j] == label[start]) {
            piece[j] = id;
            stack.push_back(j);
          }
        }
      }
      piece_size.push_back(size);
      piece_region.push_back(label[start]);
    }
  }
  const std::size_t piece_count = piece_size.size();
  // Merging: repeatedly, the smallest piece below min_area joins the neighbour it shares most
  // border with. Union-find over pieces; borders counted once.
  std::map<std::pair<int, int>, std::size_t> border;
  for (int r = 0; r < H; ++r)
    for (int c = 0; c < W; ++c) {
      const int p = piece[static_cast<std::size_t>(r) * W + c];
      if (p < 0) continue;
      if (c + 1 < W) {
        const int q = piece[static_cast<std::size_t>(r) * W + c + 1];
        if (q >= 0 && q != p) ++border[{std::min(p, q), std::max(p, q)}];
      }
      if (r + 1 < H) {
        const int q = piece[static_cast<std::size_t>(r + 1) * W + c];
        if (q >= 0 && q != p) ++border[{std::min(p, q), std::max(p, q)}];
      }
    }
  std::vector<int> parent(piece_count);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int p) {
    while (parent[p] != p) p = parent[p] = parent[parent[p]];
    return p;
  };
  std::vector<std::size_t> size(piece_size);
  const auto min_cells = static_cast<std::size_t>(std::ceil(params.min_area_m2 / (res * res)));
  std::vector<bool> dropped(piece_count, false);
  while (true) {
    int smallest = -1;
    for (std::size_t p = 0; p < piece_count; ++p) {
      if (find(static_cast<int>(p)) != static_cast<int>(p) || dropped[p] || size[p] >= min_cells) continue;
      if (smallest < 0 || size[p] < size[smallest]) smallest = static_cast<int>(p);
    }
    if (smallest < 0) break;
    std::map<int, std::size_t> shared;
    for (const auto& [pair, count] : border) {
      const int a = find(pair.first), b = find(pair.second);
      if (a == b) continue;
      if (a == smallest) shared[b] += count;
      else if (b == smallest) shared[a] += count;
    }
    int target = -1;
    std::size_t most = 0;
    for (const auto& [q, count] : shared)
      if (count > most && !dropped[q]) target = q, most = count;
    if (target < 0) {
      dropped[smallest] = true;
      continue;
    }
    parent[smallest] = target;
    size[target] += size[smallest];
  }

  // Final ids: surviving roots in order of their first cell (raster order).
  std::vector<int> area_of_root(piece_count, -1);
  std::vector<int> root_of_area;
  for (std::size_t i = 0; i < N; ++i) {
    if (piece[i] < 0) continue;
    const int root = find(piece[i]);
    if (dropped[root]) {
      label[i] = -1;
      continue;
    }
    if (area_of_root[root] < 0) {
      area_of_root[root] = static_cast<int>(root_of_area.size());
      root_of_area.push_back(root);
    }
    label[i] = area_of_root[root];
  }
  const int area_count = static_cast<int>(root_of_area.size());

  // Which skeleton region became which area: the area holding most of the region's cells.
  std::vector<std::map<int, std::size_t>> region_votes(rooms.region_count());
  for (std::size_t i = 0; i < N; ++i)
    if (piece[i] >= 0 && label[i] >= 0) ++region_votes[piece_region[piece[i]]][label[i]];
  std::vector<int> area_of_region(rooms.region_count(), -1);
  for (int r = 0; r < rooms.region_count(); ++r) {
    std::size_t most = 0;
    for (const auto& [a, v] : region_votes[r])
      if (v > most) area_of_region[r] = a, most = v;
  }

  // Areas: polygons from the labelled cells, and their measures.
  graph.areas.resize(area_count);
  {
    std::vector<std::vector<boost::polygon::rectangle_data<int>>> runs(area_count);
    for (int r = 0; r < H; ++r) {
      int c = 0;
      while (c < W) {
        const int l = label[static_cast<std::size_t>(r) * W + c];
        int end = c + 1;
        while (end < W && label[static_cast<std::size_t>(r) * W + end] == l) ++end;
        if (l >= 0) runs[l].emplace_back(c, r, end, r + 1);
        c = end;
      }
    }
    for (int a = 0; a < area_count; ++a) {
      Area& area = graph.areas[a];
      area.id = a;
      area.size_m2 = 0.0;
      boost::polygon::polygon_90_set_data<int> cells;
      for (const auto& run : runs[a]) {
        cells.insert(run);
        area.size_m2 += (boost::polygon::xh(run) - boost::polygon::xl(run)) * res * res;
      }
      std::vector<boost::polygon::polygon_90_with_holes_data<int>> polygons;
      cells.get(polygons);
      auto to_ring = [&](auto begin, auto end) {
        bg::model::ring<Point2> ring;
        for (auto it = begin; it != end; ++it) {
          const Eigen::Vector2d w = detail::lattice_to_world(grid, Eigen::Vector2d((*it).x(), (*it).y()));
          ring.push_back({w.x(), w.y()});
        }
        if (!ring.empty()) ring.push_back(ring.front());
        return ring;
      };
      double best = -1.0;
      for (const auto& p : polygons) {
        Polygon2 polygon;
        polygon.outer() = to_ring(p.begin(), p.end());
        for (auto h = p.begin_holes(); h != p.end_holes(); ++h) polygon.inners().push_back(to_ring(h->begin(), h->end()));
        bg::correct(polygon);
        const double size = bg::area(polygon);
        if (size > best) best = size, area.polygon = std::move(polygon);
      }
      bg::convex_hull(area.polygon, area.convex_hull);
      Point2 centroid(0.0, 0.0);
      bg::centroid(area.polygon, centroid);
      area.centroid = to_vector(centroid);
    }
  }
  for (std::size_t s = 0; s < g.samples.size(); ++s) {
    const int region = rooms.region_of_sample[s];
    if (region < 0 || area_of_region[region] < 0) continue;
    Area& area = graph.areas[area_of_region[region]];
    area.max_clearance_m = std::max(area.max_clearance_m, g.samples[s].clearance * res);
  }
  for (Area& area : graph.areas) {
    double diameter = 0.0;
    const auto& hull = area.convex_hull.outer();
    for (std::size_t i = 0; i < hull.size(); ++i)
      for (std::size_t j = i + 1; j < hull.size(); ++j) diameter = std::max(diameter, bg::distance(hull[i], hull[j]));
    const double width = 2.0 * std::max(area.max_clearance_m, res);
    area.kind = diameter > params.corridor_elongation * width ? AreaKind::corridor : AreaKind::room;
  }

  // Passages between the areas their regions became.
  std::vector<std::pair<std::pair<int, int>, const DetectedPassage*>> kept;
  for (const auto& p : rooms.passages) {
    const int a = area_of_region[p.region_a], b = area_of_region[p.region_b];
    if (a < 0 || b < 0 || a == b) continue;
    kept.push_back({{std::min(a, b), std::max(a, b)}, &p});
  }
  for (const auto& [areas, detected] : kept) {
    const SkeletonSample& s = g.samples[detected->sample];
    Passage passage;
    passage.id = static_cast<int>(graph.passages.size());
    passage.kind = PassageKind::door;
    passage.area_a = areas.first;
    passage.area_b = areas.second;
    passage.position = detail::lattice_to_world(grid, s.position);
    const Eigen::Vector2d fa = detail::lattice_to_world(grid, s.foot_a), fb = detail::lattice_to_world(grid, s.foot_b);
    passage.width_m = (fb - fa).norm();
    passage.line = Segment2(to_point(fa), to_point(fb));
    graph.areas[areas.first].passages.push_back(passage.id);
    graph.areas[areas.second].passages.push_back(passage.id);
    graph.passages.push_back(passage);
  }

  std::size_t labelled = 0;
  for (std::size_t i = 0; i < N; ++i) labelled += label[i] >= 0 && grid.cells()[i] == CellState::free;
  const std::size_t free_cells = grid.count().free;
  graph.covered_fraction = free_cells ? static_cast<double>(labelled) / free_cells : 0.0;
  return graph;
}

}  // namespace areamatch
