#pragma once
/// \file merge/pose_graph.hpp
/// Every map's pose in one frame from pairwise matches: a weighted least-squares fit over all of
/// them at once, so that loops of matches agree.
///
/// A map's pose is `T_reference_map` (its world frame → the reference map's world frame). A match
/// of map s onto map d says where points of s lie in d: `T_dest_source`. For each match a few
/// anchor points p of s (where the match is grounded: its matched areas) must land in the same
/// place both ways round:
///
///     T_reference_s(p) = T_reference_d(T_dest_source(p))
///
/// Written with complex numbers, a pose without reflection is z ↦ a·z + t and with one
/// z ↦ a·conj(z) + t; with each map's reflection fixed beforehand (by a spanning tree of the
/// strongest matches) these equations are linear in every map's (a, t), and their residuals are
/// metres. The fit solves that linear system (a similarity per map), then makes each pose rigid
/// (a / |a|) and solves the translations again: the matches are rigid, so the scale is 1.

#include "../error.hpp"
#include "../transform.hpp"

#include <Eigen/Core>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <tuple>
#include <utility>
#include <vector>

namespace areamatch {

/// One match between two maps as the pose fit reads it.
struct PoseConstraint {
  std::size_t source = 0;
  std::size_t dest = 0;
  Similarity2 T_dest_source;
  /// Points of the source map's world frame where the match is grounded (at least two distinct).
  std::vector<Eigen::Vector2d> anchors;
  /// How much this match counts against the others (e.g. its p_correct), > 0.
  double weight = 1.0;
};

/// The fitted poses.
struct PoseFit {
  std::vector<bool> placed;                     ///< per map: connected to the reference
  std::vector<Similarity2> T_reference_map;     ///< per map (identity when not placed)
  /// Per constraint: RMS distance in metres between its anchors laid both ways round under the
  /// fitted poses; NaN for constraints not used (inactive, or not connected to the reference).
  std::vector<double> residual_m;
  /// Per constraint: its reflection disagrees with the spanning tree that fixed each map's (the
  /// constraint was not used).
  std::vector<bool> mirror_conflict;
};

namespace detail {

/// x ↦ conj(x) when `reflected` (the complex form of diag(1, −1)).
inline Eigen::Vector2d flip_if(const Eigen::Vector2d& p, bool reflected) {
  return reflected ? Eigen::Vector2d(p.x(), -p.y()) : p;
}

/// Rows of a·z (complex product) in the unknowns (a.re, a.im): [z.x, −z.y; z.y, z.x].
inline Eigen::Matrix2d complex_product_rows(const Eigen::Vector2d& z) {
  Eigen::Matrix2d m;
  m << z.x(), -z.y(), z.y(), z.x();
  return m;
}

inline void check_pose_inputs(std::size_t map_count, std::size_t reference, const std::vector<PoseConstraint>& constraints,
                              const std::vector<bool>& active) {
  if (reference >= map_count) throw parameter_error("fit_poses: the reference map index is out of range");
  if (active.size() != constraints.size()) throw parameter_error("fit_poses: one active flag per constraint");
  for (const auto& c : constraints) {
    if (c.source >= map_count || c.dest >= map_count || c.source == c.dest) {
      throw parameter_error("fit_poses: a constraint joins a map index out of range or a map to itself");
    }
    if (!(c.weight > 0.0) || c.anchors.size() < 2) throw parameter_error("fit_poses: a constraint needs weight > 0 and two anchors");
  }
}

/// Each map's reflection relative to the reference, along a maximum spanning tree of the active
/// constraints (the strongest matches decide; ties by index, so it is deterministic). Marks the
/// maps the tree reaches in `fit.placed`, and the active constraints among them whose reflection
/// disagrees in `fit.mirror_conflict`; returns the reflections and the constraints to use.
inline std::pair<std::vector<bool>, std::vector<std::size_t>> fix_reflections(std::size_t reference,
                                                                               const std::vector<PoseConstraint>& constraints,
                                                                               const std::vector<bool>& active, PoseFit& fit) {
  const std::size_t n_constraints = constraints.size();
  std::vector<bool> reflected(fit.placed.size(), false);
  fit.placed[reference] = true;
  for (;;) {
    std::size_t best = n_constraints;
    for (std::size_t e = 0; e < n_constraints; ++e) {
      const auto& c = constraints[e];
      if (!active[e] || fit.placed[c.source] == fit.placed[c.dest]) continue;
      if (best == n_constraints || c.weight > constraints[best].weight) best = e;
    }
    if (best == n_constraints) break;
    const auto& c = constraints[best];
    // T_reference_source = T_reference_dest ∘ T_dest_source: reflections add up (mod 2).
    if (fit.placed[c.dest]) reflected[c.source] = reflected[c.dest] != c.T_dest_source.reflected;
    else reflected[c.dest] = reflected[c.source] != c.T_dest_source.reflected;
    fit.placed[c.source] = fit.placed[c.dest] = true;
  }
  std::vector<std::size_t> used;
  for (std::size_t e = 0; e < n_constraints; ++e) {
    const auto& c = constraints[e];
    if (!active[e] || !fit.placed[c.source]) continue;
    if ((reflected[c.source] != reflected[c.dest]) != c.T_dest_source.reflected) {
      fit.mirror_conflict[e] = true;
      continue;
    }
    used.push_back(e);
  }
  return {std::move(reflected), std::move(used)};
}

/// The linear system of the `used` constraints, solved. Per anchor p of constraint s → d, with
/// q = T_dest_source(p): a_s·F_s(p) + t_s − a_d·F_d(q) − t_d = 0, each row weighted by
/// sqrt(weight / anchors). `column[m]`: map m's first unknown (a.re, a.im, t.x, t.y), −1 for the
/// reference (a = 1, t = 0, known). With `rotations` given (second pass), only the translations
/// are unknown (columns halved).
inline Eigen::VectorXd solve_poses(const std::vector<PoseConstraint>& constraints, const std::vector<std::size_t>& used,
                                   const std::vector<bool>& reflected, const std::vector<int>& column, int unknowns,
                                   const std::vector<Eigen::Vector2d>* rotations) {
  std::size_t rows = 0;
  for (std::size_t e : used) rows += 2 * constraints[e].anchors.size();
  const int cols = rotations ? unknowns / 2 : unknowns;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows), cols);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(rows));
  Eigen::Index row = 0;
  for (std::size_t e : used) {
    const auto& c = constraints[e];
    const double w = std::sqrt(c.weight / static_cast<double>(c.anchors.size()));
    for (const auto& p : c.anchors) {
      const Eigen::Vector2d q = c.T_dest_source * p;
      for (const auto& [map, point, sign] : {std::tuple{c.source, p, 1.0}, std::tuple{c.dest, q, -1.0}}) {
        const Eigen::Vector2d z = flip_if(point, reflected[map]);
        if (column[map] < 0) {
          b.segment<2>(row) -= w * sign * z;
          continue;
        }
        if (rotations) {
          const Eigen::Vector2d& a = (*rotations)[map];
          b.segment<2>(row) -= w * sign * complex_product_rows(z) * a;
          A.block<2, 2>(row, column[map] / 2) += w * sign * Eigen::Matrix2d::Identity();
        } else {
          A.block<2, 2>(row, column[map]) += w * sign * complex_product_rows(z);
          A.block<2, 2>(row, column[map] + 2) += w * sign * Eigen::Matrix2d::Identity();
        }
      }
      row += 2;
    }
  }
  return Eigen::VectorXd(A.colPivHouseholderQr().solve(b));
}

}  // namespace detail

/// Fits every map's pose to the `active` constraints; map `reference` fixes the frame. Maps not
/// joined to the reference by active constraints are not placed.
inline PoseFit fit_poses(std::size_t map_count, std::size_t reference, const std::vector<PoseConstraint>& constraints,
                         const std::vector<bool>& active) {
  detail::check_pose_inputs(map_count, reference, constraints, active);
  PoseFit fit;
  fit.placed.assign(map_count, false);
  fit.T_reference_map.assign(map_count, Similarity2{});
  fit.residual_m.assign(constraints.size(), std::numeric_limits<double>::quiet_NaN());
  fit.mirror_conflict.assign(constraints.size(), false);
  const auto [reflected, used] = detail::fix_reflections(reference, constraints, active, fit);

  // Unknowns: (a.re, a.im, t.x, t.y) of every placed map but the reference (a = 1, t = 0).
  std::vector<int> column(map_count, -1);
  int unknowns = 0;
  for (std::size_t m = 0; m < map_count; ++m) {
    if (fit.placed[m] && m != reference) {
      column[m] = unknowns;
      unknowns += 4;
    }
  }
  for (std::size_t m = 0; m < map_count; ++m) {
    if (fit.placed[m]) fit.T_reference_map[m].reflected = reflected[m];
  }
  if (unknowns == 0) {
    for (std::size_t e : used) fit.residual_m[e] = 0.0;
    return fit;
  }
  // A similarity per map first, then each made rigid (a / |a|) and the translations solved again.
  const Eigen::VectorXd similarity = detail::solve_poses(constraints, used, reflected, column, unknowns, nullptr);
  std::vector<Eigen::Vector2d> rotations(map_count, Eigen::Vector2d(1.0, 0.0));
  for (std::size_t m = 0; m < map_count; ++m) {
    if (column[m] < 0) continue;
    const Eigen::Vector2d a = similarity.segment<2>(column[m]);
    const double norm = a.norm();
    rotations[m] = norm > 0.0 ? Eigen::Vector2d(a / norm) : Eigen::Vector2d(1.0, 0.0);
  }
  const Eigen::VectorXd translations = detail::solve_poses(constraints, used, reflected, column, unknowns, &rotations);
  for (std::size_t m = 0; m < map_count; ++m) {
    if (column[m] < 0) continue;
    Similarity2& T = fit.T_reference_map[m];
    T.rotation = std::atan2(rotations[m].y(), rotations[m].x());
    T.translation = translations.segment<2>(column[m] / 2);
  }
  for (std::size_t e : used) {
    const auto& c = constraints[e];
    double sum = 0.0;
    for (const auto& p : c.anchors) {
      sum += (fit.T_reference_map[c.source] * p - fit.T_reference_map[c.dest] * (c.T_dest_source * p)).squaredNorm();
    }
    fit.residual_m[e] = std::sqrt(sum / static_cast<double>(c.anchors.size()));
  }
  return fit;
}

}  // namespace areamatch
