#include "geometry/camera_model.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace mvtrack::geometry {
namespace {

bool AllFinite(const Mat3& m) { return m.allFinite(); }

}  // namespace

bool CameraModel::Validate(std::string* why) const {
  auto fail = [&](const std::string& reason) {
    if (why != nullptr) *why = "camera " + std::to_string(id) + ": " + reason;
    return false;
  };
  if (width_px <= 0 || height_px <= 0) return fail("image size must be positive");
  if (!AllFinite(K)) return fail("intrinsic matrix K has non-finite entries");
  if (!(K(0, 0) > 0.0) || !(K(1, 1) > 0.0)) return fail("focal lengths fx, fy must be positive");
  if (K(1, 0) != 0.0 || K(2, 0) != 0.0 || K(2, 1) != 0.0 || K(2, 2) != 1.0) {
    return fail("K must be upper triangular with K(2,2) = 1");
  }
  const Distortion& d = distortion;
  if (!std::isfinite(d.k1) || !std::isfinite(d.k2) || !std::isfinite(d.p1) ||
      !std::isfinite(d.p2) || !std::isfinite(d.k3)) {
    return fail("distortion coefficients must be finite");
  }
  if (!AllFinite(cam_from_world.rotation) || !cam_from_world.translation.allFinite()) {
    return fail("extrinsics have non-finite entries");
  }
  const Mat3 rtr = cam_from_world.rotation.transpose() * cam_from_world.rotation;
  if (!rtr.isApprox(Mat3::Identity(), 1e-6) || cam_from_world.rotation.determinant() < 0.0) {
    return fail("rotation is not a proper orthonormal matrix (R^T R != I or det(R) < 0)");
  }
  return true;
}

Mat34 CameraModel::ProjectionMatrix() const {
  Mat34 rt;
  rt.leftCols<3>() = cam_from_world.rotation;
  rt.col(3) = cam_from_world.translation;
  return K * rt;
}

Vec3 CameraModel::CenterInWorld() const { return cam_from_world.Inverse().translation; }

double CameraModel::Depth(const Vec3& point_in_world) const {
  return (cam_from_world * point_in_world).z();
}

std::optional<Vec2> CameraModel::ProjectUndistorted(const Vec3& point_in_world) const {
  const Vec3 p = cam_from_world * point_in_world;
  if (!(p.z() > 1e-9)) return std::nullopt;
  const Vec3 x = K * (p / p.z());
  return Vec2(x.x(), x.y());
}

std::optional<Vec2> CameraModel::Project(const Vec3& point_in_world) const {
  auto undistorted = ProjectUndistorted(point_in_world);
  if (!undistorted) return std::nullopt;
  return DistortPixel(*undistorted);
}

Vec2 CameraModel::DistortPixel(const Vec2& undistorted_px) const {
  if (distortion.IsZero()) return undistorted_px;
  // Normalized coordinates (inverting the upper-triangular K).
  const double fx = K(0, 0), fy = K(1, 1), cx = K(0, 2), cy = K(1, 2), s = K(0, 1);
  const double y = (undistorted_px.y() - cy) / fy;
  const double x = (undistorted_px.x() - cx - s * y) / fx;
  const Distortion& d = distortion;
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  const double xd = x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x);
  const double yd = y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y;
  return {fx * xd + s * yd + cx, fy * yd + cy};
}

Vec2 CameraModel::UndistortPixel(const Vec2& raw_px) const {
  if (distortion.IsZero()) return raw_px;
  const double fx = K(0, 0), fy = K(1, 1), cx = K(0, 2), cy = K(1, 2), s = K(0, 1);
  const double yd = (raw_px.y() - cy) / fy;
  const double xd = (raw_px.x() - cx - s * yd) / fx;
  const Distortion& d = distortion;
  // Fixed-point iteration as in OpenCV's cvUndistortPointsInternal, followed by Gauss-Newton
  // refinement so strongly distorted points converge too.
  double x = xd, y = yd;
  for (int it = 0; it < 20; ++it) {
    const double r2 = x * x + y * y;
    const double icdist = 1.0 / (1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3)));
    const double dx = 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x);
    const double dy = d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y;
    x = (xd - dx) * icdist;
    y = (yd - dy) * icdist;
  }
  for (int it = 0; it < 5; ++it) {
    const double r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
    const double dradial =
        2.0 * (d.k1 + r2 * (2.0 * d.k2 + 3.0 * r2 * d.k3));  // d radial / d r2 * 2
    const double fxv = x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x) - xd;
    const double fyv = y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y - yd;
    Eigen::Matrix2d j;
    j(0, 0) = radial + x * dradial * x + 2.0 * d.p1 * y + 6.0 * d.p2 * x;
    j(0, 1) = x * dradial * y + 2.0 * d.p1 * x + 2.0 * d.p2 * y;
    j(1, 0) = y * dradial * x + 2.0 * d.p1 * x + 2.0 * d.p2 * y;
    j(1, 1) = radial + y * dradial * y + 6.0 * d.p1 * y + 2.0 * d.p2 * x;
    if (std::abs(j.determinant()) < 1e-12) break;
    const Vec2 step = j.inverse() * Vec2(fxv, fyv);
    if (!step.allFinite()) break;
    x -= step.x();
    y -= step.y();
    if (step.squaredNorm() < 1e-24) break;
  }
  return {fx * x + s * y + cx, fy * y + cy};
}

bool CameraModel::InImage(const Vec2& raw_px, double margin_px) const {
  return raw_px.x() >= -margin_px && raw_px.y() >= -margin_px &&
         raw_px.x() <= width_px + margin_px && raw_px.y() <= height_px + margin_px;
}

std::optional<Vec3> CameraModel::PointOnRayAtHeight(const Vec2& undistorted_px, double z) const {
  const Vec3 direction = cam_from_world.rotation.transpose() *
                         (K.inverse() * Vec3(undistorted_px.x(), undistorted_px.y(), 1.0));
  const Vec3 center = CenterInWorld();
  // A ray within about 0.06 degrees of the horizontal meets the plane too far away to matter.
  if (!(std::abs(direction.z()) > 1e-3 * direction.norm())) return std::nullopt;
  const double s = (z - center.z()) / direction.z();
  if (!(s > 0.0)) return std::nullopt;
  return center + s * direction;
}

Mat3 RotationFromRodrigues(const Vec3& rvec) {
  const double angle = rvec.norm();
  if (angle == 0.0) return Mat3::Identity();
  return Eigen::AngleAxisd(angle, rvec / angle).toRotationMatrix();
}

bool SeesPoint(const CameraModel& camera, const Vec3& point_in_world) {
  const std::optional<Vec2> pinhole = camera.ProjectUndistorted(point_in_world);
  if (!pinhole) return false;
  const double margin = 0.25 * std::max(camera.width_px, camera.height_px);
  if (!camera.InImage(*pinhole, margin)) return false;
  const std::optional<Vec2> raw = camera.Project(point_in_world);
  return raw.has_value() && std::isfinite(raw->x()) && std::isfinite(raw->y()) &&
         camera.InImage(*raw);
}

}  // namespace mvtrack::geometry
