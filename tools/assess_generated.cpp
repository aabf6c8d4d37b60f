// assess_generated [COUNT] [FIRST_SEED]: map assessment judged on generated distorted robot maps
// whose exact truth is known (docs/assessment.md). Each pair: a generated building, its robot map
// bent by a smooth drift (0.2–1.0 m) and broken into 0–3 pieces (2–10°); the map is assessed
// against the layout and compared with the truth:
//   warp error   the distance of the map's wall points from where they truly belong, under the
//                rigid answer and under the warp (median, 95th percentile)
//   pieces       the broken pieces found against the true count (pieces holding ≥ 15 m² of the
//                map's free space), each found piece's turn against its true piece's (the true
//                piece told by the found one's areas, and by its free cells; the true turn its
//                break's, and the least-squares rigid fit of where its walls truly go, bend and all)
//   coverage     the share of the layout's rooms and corridors explored, against the truth
// One tab-separated line per pair, then a summary.
#include <areamatch/areamatch.hpp>
#include <areamatch/synthetic.hpp>
#include <synthetic_cases.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <string>
#include <vector>

namespace {

using areamatch::pi;

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))];
}

/// The key with the most votes (the smallest such key).
int most_voted(const std::map<int, double>& votes) {
  int best = 0;
  double most = -1.0;
  for (const auto& [key, n] : votes) {
    if (n > most) best = key, most = n;
  }
  return best;
}

/// The rotation of the least-squares rigid fit taking `from` onto `to` (2D Procrustes).
double fitted_rotation(const std::vector<Eigen::Vector2d>& from, const std::vector<Eigen::Vector2d>& to) {
  Eigen::Vector2d mean_from = Eigen::Vector2d::Zero(), mean_to = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < from.size(); ++i) mean_from += from[i], mean_to += to[i];
  mean_from /= static_cast<double>(from.size());
  mean_to /= static_cast<double>(to.size());
  double cross = 0.0, dot = 0.0;
  for (std::size_t i = 0; i < from.size(); ++i) {
    const Eigen::Vector2d a = from[i] - mean_from, b = to[i] - mean_to;
    cross += a.x() * b.y() - a.y() * b.x();
    dot += a.dot(b);
  }
  return std::atan2(cross, dot);
}

struct PairTruth {
  int pieces = 1;
  double coverage = 0.0;
  std::vector<int> piece_of_area;  // per map area: the true piece holding most of its cells
  std::vector<int> piece_of_cell;  // per map cell: its true piece (-1: not a free cell of an area)
};

PairTruth truth_of(const areamatch::RobotMap& robot, const areamatch::AreaGraph& map_graph,
                   const areamatch::AreaRaster& reference_raster, double min_piece_m2) {
  PairTruth t;
  const auto& grid = robot.grid;
  std::map<int, double> piece_m2;
  std::vector<std::map<int, double>> votes(map_graph.areas.size());
  std::vector<char> seen(reference_raster.labelled_count(), 0);
  const double cell_m2 = grid.resolution() * grid.resolution();
  t.piece_of_cell.assign(grid.cells().size(), -1);
  for (int row = 0; row < grid.height(); ++row) {
    for (int col = 0; col < grid.width(); ++col) {
      if (grid.at(col, row) != areamatch::CellState::free) continue;
      const Eigen::Vector2d s = grid.cell_center(col, row);
      const Eigen::Vector2d bent = robot.smooth(robot.T_dest_source * s);
      const int piece = robot.piece_at(bent);
      const int label = map_graph.labels[grid.index(col, row)];
      if (label >= 0) {
        t.piece_of_cell[grid.index(col, row)] = piece;
        piece_m2[piece] += cell_m2;
        votes[static_cast<std::size_t>(label)][piece] += 1.0;
      }
    }
  }
  // Coverage: the robot cell that truly shows each raster centre, found by inverting the truth
  // (each piece's motion, then the bend and drift by fixed point, then the rigid transform).
  const areamatch::Similarity2 back = robot.T_dest_source.inverse();
  for (std::size_t k = 0; k < reference_raster.labelled_count(); ++k) {
    const Eigen::Vector2d c = reference_raster.centre(k);
    for (int piece = 0; piece <= static_cast<int>(robot.breaks.size()); ++piece) {
      const Eigen::Vector2d bent = robot.piece_motion(piece).inverse() * c;
      if (robot.piece_at(bent) != piece) continue;
      const Eigen::Vector2d p = robot.smooth_inverse(bent);
      const Eigen::Vector2i cell = grid.world_to_cell(back * p);
      if (grid.contains(cell.x(), cell.y()) && grid.at(cell.x(), cell.y()) == areamatch::CellState::free) seen[k] = 1;
      break;
    }
  }
  t.pieces = 0;
  for (const auto& [piece, m2] : piece_m2) t.pieces += m2 >= min_piece_m2;
  t.pieces = std::max(1, t.pieces);
  std::size_t explored = 0;
  for (const char v : seen) explored += v != 0;
  t.coverage = static_cast<double>(explored) / static_cast<double>(std::max<std::size_t>(1, reference_raster.labelled_count()));
  for (const auto& v : votes) t.piece_of_area.push_back(most_voted(v));
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  const int count = argc > 1 ? std::atoi(argv[1]) : 60;
  const std::uint64_t first_seed = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 4300;
  areamatch::Matcher<> matcher;
  areamatch::AssessParams params;
  params.assume_same_building = true;  // the generated map is of the layout's building
  std::printf("seed\tbend_m\tbreaks\tok\trigid_med\trigid_p95\twarp_med\twarp_p95\ttrue_pieces\tfound_pieces\tmax_turn_err_deg\tmax_turn_err_cells_deg\tmax_turn_err_fitted_deg\t"
              "true_cov\tcov\tassess_s\tmatch_s\n");
  int placed = 0, strong = 0, strong_ok = 0, pieces_exact = 0, turns_ok = 0, turns_by_cells_ok = 0, turns_fitted_ok = 0, coverage_ok = 0;
  std::vector<double> strong_med, strong_p95, warp_times, match_times;
  for (int i = 0; i < count; ++i) {
    const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(i);
    const areamatch_test::DistortedCase pair = areamatch_test::distorted_case(first_seed, i);
    const auto& building = pair.building;
    const auto& rp = pair.robot_params;
    const auto& robot = pair.robot;
    const auto map_graph = matcher.segmenter.segment(robot.grid);
    const auto reference_graph = matcher.segmenter.segment(building.layout);
    const auto result = matcher.match(robot.grid, map_graph, building.layout, reference_graph);
    const auto a = areamatch::assess_match(robot.grid, map_graph, building.layout, reference_graph, result, params);
    const auto reference_raster = areamatch::make_area_raster(reference_graph, params.sample_cell_m);
    const PairTruth truth = truth_of(robot, map_graph, reference_raster, 15.0);
    double rigid_med = std::nan(""), rigid_p95 = std::nan(""), warp_med = std::nan(""), warp_p95 = std::nan(""), max_turn = std::nan(""),
           max_turn_cells = std::nan(""), max_turn_fitted = std::nan("");
    const std::size_t found = a.ok ? a.brokenness.pieces.size() : 0;
    const std::vector<Eigen::Vector2d> wall_points = areamatch::detail::wall_points(robot.grid, 0.1);
    std::map<int, double> true_turn;  // per true piece: its rigid turn, with the bend
    if (a.ok) {
      ++placed;
      std::vector<double> rigid, warped;
      // Per true piece, its wall points and where they truly belong: its own rigid turn is their
      // least-squares fit (its break's motion and the bend across it, which turns a bent piece too).
      std::map<int, std::pair<std::vector<Eigen::Vector2d>, std::vector<Eigen::Vector2d>>> piece_walls;
      for (const auto& p : wall_points) {
        const Eigen::Vector2d truth_point = robot.true_dest(p);
        rigid.push_back((result.T_dest_source * p - truth_point).norm());
        warped.push_back((a.warp.field.apply(p) - truth_point).norm());
        auto& [from, to] = piece_walls[robot.piece_at(robot.smooth(robot.T_dest_source * p))];
        from.push_back(p);
        to.push_back(truth_point);
      }
      rigid_med = percentile(rigid, 0.5), rigid_p95 = percentile(rigid, 0.95);
      for (int k = 0; k <= static_cast<int>(robot.breaks.size()); ++k) true_turn[k] = robot.piece_motion(k).rotation;  // a piece without walls
      for (const auto& [piece, walls] : piece_walls) true_turn[piece] = fitted_rotation(walls.first, walls.second);
      warp_med = percentile(warped, 0.5), warp_p95 = percentile(warped, 0.95);
      if (rigid_med >= 0.3) {
        ++strong;
        strong_med.push_back(warp_med);
        strong_p95.push_back(warp_p95);
        strong_ok += warp_med <= 0.05 && warp_p95 <= 0.15;
      }
      // Each found piece's turn against the main one, next to its true piece's against the main's
      // true piece. Which true piece a found one is: the one holding most of its areas' m² (an area
      // across a cut counts whole), and the one holding most of its free cells (finer).
      const auto& pieces = a.brokenness.pieces;
      auto true_by_areas = [&](std::size_t k) {
        std::map<int, double> m2;
        for (int area : pieces[k].areas) {
          m2[truth.piece_of_area[static_cast<std::size_t>(area)]] += map_graph.areas[static_cast<std::size_t>(area)].size_m2;
        }
        return most_voted(m2);
      };
      std::vector<std::map<int, double>> cell_votes(pieces.size());
      for (int row = 0; row < robot.grid.height(); ++row) {
        for (int col = 0; col < robot.grid.width(); ++col) {
          const int true_piece = truth.piece_of_cell[robot.grid.index(col, row)];
          if (true_piece < 0) continue;
          const int found_piece = a.brokenness.piece_at(robot.grid.cell_center(col, row));
          cell_votes[static_cast<std::size_t>(found_piece)][true_piece] += 1.0;
        }
      }
      auto true_by_cells = [&](std::size_t k) { return most_voted(cell_votes[k]); };
      auto break_turn = [&](int true_piece) { return robot.piece_motion(true_piece).rotation; };
      auto rigid_turn = [&](int true_piece) { return true_turn.at(true_piece); };
      // The largest error of a found piece's turn against the main one, the true pieces told by
      // `true_piece` and their turns by `turn_of`.
      auto max_turn_error = [&](const auto& true_piece, const auto& turn_of) {
        double worst = 0.0;
        for (std::size_t k = 1; k < pieces.size(); ++k) {
          const double truth_turn = areamatch::wrap_angle(turn_of(true_piece(k)) - turn_of(true_piece(0)));
          worst = std::max(worst, std::abs(areamatch::wrap_angle(pieces[k].rotation_rad - truth_turn)) * 180.0 / pi);
        }
        return worst;
      };
      max_turn = max_turn_error(true_by_areas, break_turn);
      max_turn_cells = max_turn_error(true_by_cells, break_turn);
      max_turn_fitted = max_turn_error(true_by_cells, rigid_turn);
      turns_by_cells_ok += static_cast<int>(found) == truth.pieces && max_turn_cells <= 0.5;
      turns_fitted_ok += static_cast<int>(found) == truth.pieces && max_turn_fitted <= 0.5;
      pieces_exact += static_cast<int>(found) == truth.pieces;
      turns_ok += static_cast<int>(found) == truth.pieces && max_turn <= 0.5;
      coverage_ok += std::abs(a.coverage.explored_share - truth.coverage) <= 0.02;
      warp_times.push_back(a.timings.warp_s + a.timings.assess_s);
      match_times.push_back(result.timings.total_s);
    }
    std::printf("%llu\t%.1f\t%d\t%d\t%.3f\t%.3f\t%.3f\t%.3f\t%d\t%zu\t%.2f\t%.2f\t%.2f\t%.3f\t%.3f\t%.3f\t%.3f\n",
                static_cast<unsigned long long>(seed), rp.wall_bend_m, rp.break_count, a.ok ? 1 : 0, rigid_med, rigid_p95,
                warp_med, warp_p95, truth.pieces, found, max_turn, max_turn_cells, max_turn_fitted, truth.coverage, a.ok ? a.coverage.explored_share : std::nan(""),
                a.timings.warp_s + a.timings.assess_s, result.timings.total_s);
    std::fflush(stdout);
  }
  std::printf("\n%d pairs, %d placed\n", count, placed);
  std::printf("warp error where the rigid median >= 0.3 m: %d pairs; median of medians %.3f m, median of 95th percentiles %.3f m; "
              "%d pairs with median <= 0.05 and 95th <= 0.15\n",
              strong, percentile(strong_med, 0.5), percentile(strong_p95, 0.5), strong_ok);
  std::printf("broken pieces counted exactly: %d of %d placed; and every piece's turn within 0.5 deg: %d (pieces told by their areas), "
              "%d (by their cells), %d (by their cells, against each true piece's rigid fit with the bend)\n",
              pieces_exact, placed, turns_ok, turns_by_cells_ok, turns_fitted_ok);
  std::printf("coverage within 2 points of the truth: %d of %d placed\n", coverage_ok, placed);
  std::printf("median time: match %.3f s, warp + assessment %.3f s\n", percentile(match_times, 0.5), percentile(warp_times, 0.5));
  return 0;
}
