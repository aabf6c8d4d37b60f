// slam_statistics MANIFEST [KIND]: what a SLAM map looks like, per source map of a manifest's pairs
// (those of KIND when given), against its destination (a floor plan) through the ground truth.
// Used to calibrate `areamatch simulate` against real SLAM maps (docs/synthetic.md). One line
// per pair, tab-separated:
//   edge_m_per_m2    free-space edge length per m² of free space (raggedness)
//   wall_cells       occupied cells per occupied cell next to free space (wall thickness in cells;
//                    meaningless for maps whose outside is occupied, as the dataset's are)
//   thin_free        share of free cells with fewer than half of their 5 × 5 neighbours free
//                    (streaks, sparse beams)
//   unknown_in_box   share of unknown cells in the free space's bounding box
//   off_plan         share of the occupied cells next to free space (the surfaces the laser saw)
//                    farther than 0.15 m from the plan's non-free cells (furniture, people, ray
//                    artefacts: what a plan does not have)
//   plan_on_map      share of the plan's walls (non-free cells next to free) near the map's free
//                    space that lie within 0.15 m of the map's occupied cells
#include <areamatch/io/map_files.hpp>
#include <eval/manifest.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

namespace {

using areamatch::CellState;
using areamatch::OccupancyGrid;

/// Per cell, whether a cell of `grid` that `take(state)` accepts lies within `radius` cells
/// (a square: rows, then columns).
template <class Take>
std::vector<char> near_cells(const OccupancyGrid& grid, int radius, Take take) {
  const int w = grid.width(), h = grid.height();
  std::vector<char> rows(static_cast<std::size_t>(w) * h, 0), out(rows.size(), 0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      bool any = false;
      for (int dx = -radius; dx <= radius && !any; ++dx) any = grid.contains(x + dx, y) && take(grid.at(x + dx, y));
      rows[grid.index(x, y)] = any;
    }
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      bool any = false;
      for (int dy = -radius; dy <= radius && !any; ++dy) any = grid.contains(x, y + dy) && rows[grid.index(x, y + dy)];
      out[grid.index(x, y)] = any;
    }
  }
  return out;
}

std::vector<char> near_state(const OccupancyGrid& grid, CellState state, int radius) {
  return near_cells(grid, radius, [state](CellState s) { return s == state; });
}

bool next_to(const OccupancyGrid& g, int x, int y, CellState state) {
  for (auto [dx, dy] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
    if (g.contains(x + dx, y + dy) && g.at(x + dx, y + dy) == state) return true;
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc < 2 || argc > 3) {
    std::cerr << "usage: slam_statistics MANIFEST [KIND]\n";
    return 2;
  }
  const areamatch::Manifest manifest = areamatch::load_manifest(argv[1]);
  std::cout << "pair\tedge_m_per_m2\twall_cells\tthin_free\tunknown_in_box\toff_plan\tplan_on_map\n";
  for (const auto& pair : manifest.pairs) {
    if (argc == 3 && pair.kind != argv[2]) continue;
    if (!pair.ground_truth || pair.different_buildings) continue;
    areamatch::LoadOptions source_options, dest_options;
    source_options.resolution = pair.source_resolution;
    dest_options.resolution = pair.destination_resolution;
    const OccupancyGrid map = areamatch::load_map(pair.source, source_options);
    const OccupancyGrid plan = areamatch::load_map(pair.destination, dest_options);
    const double res = map.resolution();
    std::size_t free = 0, edge = 0, occupied = 0, wall_face = 0, thin = 0, unknown_box = 0, box = 0;
    int x0 = map.width(), y0 = map.height(), x1 = -1, y1 = -1;
    for (int y = 0; y < map.height(); ++y) {
      for (int x = 0; x < map.width(); ++x) {
        const CellState s = map.at(x, y);
        if (s == CellState::free) {
          ++free;
          x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
          bool boundary = false;
          for (auto [dx, dy] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
            boundary = boundary || !map.contains(x + dx, y + dy) || map.at(x + dx, y + dy) != CellState::free;
          }
          edge += boundary;
          int around = 0;
          for (int dy = -2; dy <= 2; ++dy) {
            for (int dx = -2; dx <= 2; ++dx) around += map.contains(x + dx, y + dy) && map.at(x + dx, y + dy) == CellState::free;
          }
          thin += around < 13;
        } else if (s == CellState::occupied) {
          ++occupied;
          wall_face += next_to(map, x, y, CellState::free);
        }
      }
    }
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        ++box;
        unknown_box += map.at(x, y) == CellState::unknown;
      }
    }
    // Against the plan, through the ground truth (pixel → pixel).
    const areamatch::PixelTransform& T = *pair.ground_truth;
    const int reach = std::max(1, static_cast<int>(std::lround(0.15 / plan.resolution())));
    const std::vector<char> plan_solid_near = near_cells(plan, reach, [](CellState s) { return s != CellState::free; });
    std::size_t off = 0, mapped = 0;
    for (int y = 0; y < map.height(); ++y) {
      for (int x = 0; x < map.width(); ++x) {
        if (map.at(x, y) != CellState::occupied || !next_to(map, x, y, CellState::free)) continue;
        const Eigen::Vector2d q = T * Eigen::Vector3d(x, y, 1.0);
        const int px = static_cast<int>(std::lround(q.x())), py = static_cast<int>(std::lround(q.y()));
        ++mapped;
        off += !(plan.contains(px, py) && plan_solid_near[plan.index(px, py)]);
      }
    }
    // The plan's walls near the map's free space, on the map's occupied cells.
    const std::vector<char> map_occupied_near = near_state(map, CellState::occupied, std::max(1, static_cast<int>(std::lround(0.15 / res))));
    const std::vector<char> map_free_near = near_state(map, CellState::free, std::max(1, static_cast<int>(std::lround(0.5 / res))));
    const Eigen::Matrix<double, 2, 3> to_map = [&] {
      Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
      m.topRows<2>() = T;
      return Eigen::Matrix<double, 2, 3>(m.inverse().topRows<2>());
    }();
    std::size_t plan_walls = 0, plan_walls_on = 0;
    for (int y = 0; y < plan.height(); ++y) {
      for (int x = 0; x < plan.width(); ++x) {
        if (plan.at(x, y) == CellState::free || !next_to(plan, x, y, CellState::free)) continue;
        const Eigen::Vector2d q = to_map * Eigen::Vector3d(x, y, 1.0);
        const int mx = static_cast<int>(std::lround(q.x())), my = static_cast<int>(std::lround(q.y()));
        if (!map.contains(mx, my) || !map_free_near[map.index(mx, my)]) continue;
        ++plan_walls;
        plan_walls_on += map_occupied_near[map.index(mx, my)];
      }
    }
    const double free_m2 = static_cast<double>(free) * res * res;
    auto share = [](std::size_t a, std::size_t b) { return b ? static_cast<double>(a) / static_cast<double>(b) : 0.0; };
    std::printf("%s\t%.3f\t%.2f\t%.3f\t%.3f\t%.3f\t%.3f\n", pair.name.c_str(), free_m2 > 0 ? static_cast<double>(edge) * res / free_m2 : 0.0,
                share(occupied, wall_face), share(thin, free), share(unknown_box, box), share(off, mapped), share(plan_walls_on, plan_walls));
  }
  return 0;
} catch (const std::exception& e) {
  std::cerr << "slam_statistics: " << e.what() << "\n";
  return 2;
}
