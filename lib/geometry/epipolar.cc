#include "geometry/epipolar.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace mvtrack::geometry {
namespace {

Mat3 Skew(const Vec3& v) {
  Mat3 m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

}  // namespace

Mat3 FundamentalMatrix(const CameraModel& from, const CameraModel& to) {
  // to_from_from = to_from_world * world_from_from; E = [t]x R; F = K_to^-T E K_from^-1.
  const Rigid3 to_from_from = [&] {
    const Rigid3 world_from_from = from.cam_from_world.Inverse();
    return Rigid3{
        to.cam_from_world.rotation * world_from_from.rotation,
        to.cam_from_world.rotation * world_from_from.translation + to.cam_from_world.translation};
  }();
  // Without a baseline there is no epipolar geometry: return 0, whose lines are all "at
  // infinity", so every epipolar distance is +inf instead of round-off noise scaled to unit norm.
  const double scale = std::max({1.0, from.CenterInWorld().norm(), to.CenterInWorld().norm()});
  if (to_from_from.translation.norm() <= 1e-9 * scale) return Mat3::Zero();
  const Mat3 e = Skew(to_from_from.translation) * to_from_from.rotation;
  const Mat3 f = to.K.inverse().transpose() * e * from.K.inverse();
  const double norm = f.norm();
  return norm > 0.0 ? Mat3(f / norm) : f;
}

double PointLineDistance(const Vec2& x, const Vec3& line) {
  const double n = std::hypot(line.x(), line.y());
  if (!(n > 0.0)) return std::numeric_limits<double>::infinity();
  return std::abs(line.x() * x.x() + line.y() * x.y() + line.z()) / n;
}

double SymmetricEpipolarDistance(const Vec2& x_i, const Vec2& x_j, const Mat3& f_i_to_j) {
  const Vec3 line_in_j = f_i_to_j * x_i.homogeneous();
  const Vec3 line_in_i = f_i_to_j.transpose() * x_j.homogeneous();
  return PointLineDistance(x_i, line_in_i) + PointLineDistance(x_j, line_in_j);
}

double NormalizedEpipolarDistance(
    const Vec2& x_i, double scale_i_px, const Vec2& x_j, double scale_j_px, const Mat3& f_i_to_j) {
  const Vec3 line_in_j = f_i_to_j * x_i.homogeneous();
  const Vec3 line_in_i = f_i_to_j.transpose() * x_j.homogeneous();
  return PointLineDistance(x_i, line_in_i) / std::abs(scale_i_px) +
         PointLineDistance(x_j, line_in_j) / std::abs(scale_j_px);
}

}  // namespace mvtrack::geometry
