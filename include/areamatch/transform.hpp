#pragma once
/// \file transform.hpp
/// `Similarity2`: the transform between two maps' world frames, and its pixel-space form.
///
/// A `Similarity2` named `T_dest_source` maps a point in the source map's world frame to the
/// destination map's world frame:
///
///     p_dest = scale · Rot(rotation) · F · p_source + translation,   F = diag(1, −1) if reflected
///
/// Maps of one building are related by a rigid transform (scale 1) once each map's resolution is
/// right; `scale` is there for maps whose resolution is unknown. `reflected` is real life: an image
/// saved by ROS and the same map drawn as a picture are mirror images.

#include "grid.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>

namespace areamatch {

inline constexpr double pi = 3.14159265358979323846;

/// The 2×3 matrix [[a, b, tx], [c, d, ty]] mapping a source image pixel (col, row) to a
/// destination image pixel (col, row), pixel centres at integer coordinates (the convention of
/// `pairs.json`).
using PixelTransform = Eigen::Matrix<double, 2, 3>;

/// A 2D similarity transform, possibly with a reflection (see the file comment).
struct Similarity2 {
  double rotation = 0.0;                                    ///< radians, counter-clockwise
  Eigen::Vector2d translation = Eigen::Vector2d::Zero();    ///< metres, in the destination frame
  double scale = 1.0;                                       ///< destination metres per source metre
  bool reflected = false;                                   ///< y is flipped before rotating

  /// scale · Rot(rotation) · F
  Eigen::Matrix2d linear() const {
    Eigen::Matrix2d m = scale * Eigen::Rotation2Dd(rotation).toRotationMatrix();
    if (reflected) m.col(1) = -m.col(1);
    return m;
  }
  Eigen::Affine2d affine() const {
    Eigen::Affine2d a = Eigen::Affine2d::Identity();
    a.linear() = linear();
    a.translation() = translation;
    return a;
  }
  /// Homogeneous 3×3 matrix.
  Eigen::Matrix3d matrix() const { return affine().matrix(); }

  Eigen::Vector2d operator*(const Eigen::Vector2d& p) const { return linear() * p + translation; }

  /// Decomposes an affine map that is a similarity (up to rounding) into its parts.
  static Similarity2 from_affine(const Eigen::Affine2d& a) {
    Similarity2 s;
    Eigen::Matrix2d m = a.linear();
    const double det = m.determinant();
    s.reflected = det < 0.0;
    s.scale = std::sqrt(std::abs(det));
    if (s.reflected) m.col(1) = -m.col(1);  // m = scale·R·F  →  m·F = scale·R
    s.rotation = std::atan2(m(1, 0), m(0, 0));
    s.translation = a.translation();
    return s;
  }

  Similarity2 inverse() const { return from_affine(affine().inverse()); }

  /// (a * b)(p) = a(b(p)).
  friend Similarity2 operator*(const Similarity2& a, const Similarity2& b) {
    return from_affine(a.affine() * b.affine());
  }
};

/// Rotation angle wrapped to (−π, π].
inline double wrap_angle(double angle) {
  const double two_pi = 2.0 * pi;
  angle = std::fmod(angle, two_pi);
  if (angle <= -pi) angle += two_pi;
  if (angle > pi) angle -= two_pi;
  return angle;
}

/// The pixel transform (source image pixel → destination image pixel) equivalent to a world
/// transform between the two grids' frames.
inline PixelTransform to_pixel_transform(const Similarity2& T_dest_source,
                                         const OccupancyGrid& source, const OccupancyGrid& dest) {
  const Eigen::Affine2d a = dest.pixel_from_world() * T_dest_source.affine() * source.world_from_pixel();
  return a.matrix().topRows<2>();
}

/// The world transform (source world → destination world) equivalent to a pixel transform.
inline Similarity2 from_pixel_transform(const PixelTransform& pixel_transform,
                                        const OccupancyGrid& source, const OccupancyGrid& dest) {
  Eigen::Affine2d pixel = Eigen::Affine2d::Identity();
  pixel.matrix().topRows<2>() = pixel_transform;
  return Similarity2::from_affine(dest.world_from_pixel() * pixel * source.pixel_from_world());
}

}  // namespace areamatch
