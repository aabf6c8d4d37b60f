#pragma once
/// \file simulate/drift.hpp
/// SLAM's errors in a simulated map (simulate.hpp): odometry drift with an imperfect loop
/// closure, each scan's registration error, a broken piece; and the ground truth they leave.

#include "../detail/random.hpp"
#include "../transform.hpp"
#include "params.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace areamatch::detail {

/// Per scan, where SLAM believes it was: the position and heading errors of a random-walk
/// odometry whose end error is taken out linearly along the path (the loop closure), scaled so
/// that the largest position error is `bend_m` (the ground truth's rigid fit leaves at most about
/// that), plus the broken piece.
struct Drift {
  std::vector<Eigen::Vector2d> position;
  std::vector<double> heading;
  bool broken = false;
};

inline Drift odometry_drift(const std::vector<Eigen::Vector3d>& poses, const LidarSlamParams& p, Random& random) {
  const std::size_t n = poses.size();
  Drift drift;
  drift.position.assign(n, Eigen::Vector2d::Zero());
  drift.heading.assign(n, 0.0);
  std::vector<double> along(n, 0.0);
  for (std::size_t k = 1; k < n; ++k) {
    const Eigen::Vector2d step = poses[k].head<2>() - poses[k - 1].head<2>();
    const double ds = step.norm();
    along[k] = along[k - 1] + ds;
    drift.heading[k] = drift.heading[k - 1] + 0.01 * std::sqrt(ds) * random.normal();
    const Eigen::Vector2d turned = Eigen::Rotation2Dd(drift.heading[k]) * step;
    drift.position[k] = drift.position[k - 1] + (turned - step) + 0.01 * std::sqrt(ds) * Eigen::Vector2d(random.normal(), random.normal());
  }
  const double total = n > 1 ? along.back() : 0.0;
  if (total > 0.0) {
    const Eigen::Vector2d end = drift.position.back();
    const double end_heading = drift.heading.back();
    for (std::size_t k = 0; k < n; ++k) {
      drift.position[k] -= (along[k] / total) * end;
      drift.heading[k] -= (along[k] / total) * end_heading;
    }
  }
  double largest = 0.0;
  for (const auto& e : drift.position) largest = std::max(largest, e.norm());
  const double gain = largest > 1e-9 ? p.bend_m / largest : 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    drift.position[k] *= gain;
    drift.heading[k] *= gain;
  }
  if (n > 8 && random.chance(p.break_probability)) {
    drift.broken = true;
    const std::size_t from = n / 4 + static_cast<std::size_t>(random.integer(0, static_cast<int>(n / 2)));
    const double turn = (random.chance(0.5) ? 1.0 : -1.0) * p.break_rotation_rad;
    const double direction = random.uniform(0.0, 2.0 * pi);
    const Eigen::Vector2d shift = p.break_shift_m * Eigen::Vector2d(std::cos(direction), std::sin(direction));
    const Eigen::Vector2d pivot = poses[from].head<2>() + drift.position[from];
    const Eigen::Rotation2Dd R(turn);
    for (std::size_t k = from; k < n; ++k) {
      const Eigen::Vector2d believed = poses[k].head<2>() + drift.position[k];
      drift.position[k] = pivot + R * (believed - pivot) + shift - poses[k].head<2>();
      drift.heading[k] += turn;
    }
  }
  return drift;
}


/// Per scan, the rigid motion from the true world into the map's frame: the believed pose
/// (drift and the scan's own registration error), the whole turned and mirrored as asked.
inline std::vector<Similarity2> scan_frames(const std::vector<Eigen::Vector3d>& poses, const Drift& drift,
                                            const LidarSlamParams& params, Random& random) {
  Similarity2 frame;
  frame.rotation = params.rotation_rad;
  frame.reflected = params.mirror;
  std::vector<Similarity2> to_map(poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    // About the true position: turned by the heading error, moved by the position error, and the
    // scan's own registration error on top (not in the ground truth: it averages out).
    const double turn = drift.heading[k] + params.scan_jitter_rad * random.normal();
    const Eigen::Vector2d jitter = params.scan_jitter_m * Eigen::Vector2d(random.normal(), random.normal());
    Similarity2 local;
    local.rotation = turn;
    local.translation = poses[k].head<2>() + drift.position[k] + jitter - Eigen::Rotation2Dd(turn) * poses[k].head<2>();
    to_map[k] = frame * local;
  }
  return to_map;
}

/// The ground truth, map world → plan world: the rigid motion that best lays the believed scan
/// positions on the true ones (least squares, closed form in 2D), the mirror put back after.
inline Similarity2 rigid_ground_truth(const std::vector<Eigen::Vector3d>& poses, const std::vector<Similarity2>& to_map, bool mirror) {
  std::vector<Eigen::Vector2d> believed(poses.size());
  Eigen::Vector2d believed_mean = Eigen::Vector2d::Zero(), true_mean = Eigen::Vector2d::Zero();
  for (std::size_t k = 0; k < poses.size(); ++k) {
    believed[k] = to_map[k] * poses[k].head<2>();
    if (mirror) believed[k].y() = -believed[k].y();
    believed_mean += believed[k];
    true_mean += poses[k].head<2>();
  }
  believed_mean /= static_cast<double>(poses.size());
  true_mean /= static_cast<double>(poses.size());
  double dot = 0.0, cross = 0.0;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const Eigen::Vector2d a = believed[k] - believed_mean, b = poses[k].head<2>() - true_mean;
    dot += a.dot(b);
    cross += a.x() * b.y() - a.y() * b.x();
  }
  Similarity2 fit;
  fit.rotation = std::atan2(cross, dot);
  fit.translation = true_mean - Eigen::Rotation2Dd(fit.rotation) * believed_mean;
  Similarity2 unmirror;
  unmirror.reflected = mirror;
  return fit * unmirror;
}

}  // namespace areamatch::detail
