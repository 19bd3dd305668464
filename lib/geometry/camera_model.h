#pragma once
/// @file
/// Pinhole camera with OpenCV's 5-parameter distortion (k1, k2, p1, p2, k3), projection and
/// undistortion. Immutable value type; all methods are const and thread-compatible.

#include <Eigen/Core>
#include <optional>
#include <string>

#include "core/types.h"

namespace mvtrack::geometry {

/// Rigid transform `target_from_source`: p_target = rotation * p_source + translation.
struct Rigid3 {
  Mat3 rotation = Mat3::Identity();
  Vec3 translation = Vec3::Zero();

  Vec3 operator*(const Vec3& p) const { return rotation * p + translation; }
  Rigid3 Inverse() const { return {rotation.transpose(), -(rotation.transpose() * translation)}; }
};

/// OpenCV distortion coefficients in OpenCV's order.
struct Distortion {
  double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0;
  bool IsZero() const { return k1 == 0.0 && k2 == 0.0 && p1 == 0.0 && p2 == 0.0 && k3 == 0.0; }
};

/// A calibrated camera. Pixel conventions follow OpenCV (x right, y down).
/// "Undistorted pixels" are the pinhole image K * [R|t] * X without lens distortion; every
/// algorithm module works in undistorted pixels.
struct CameraModel {
  CameraId id = 0;
  int width_px = 0;
  int height_px = 0;
  Mat3 K = Mat3::Identity();  ///< intrinsics (fx, fy, cx, cy, optional skew)
  Distortion distortion;
  Rigid3 cam_from_world;  ///< world -> camera (z forward)

  /// Checks finite values, positive focal lengths and image size, orthonormal rotation.
  bool Validate(std::string* why) const;

  /// 3x4 matrix mapping homogeneous world points to homogeneous undistorted pixels.
  Mat34 ProjectionMatrix() const;
  /// Camera centre in the world frame.
  Vec3 CenterInWorld() const;
  /// Point depth along the optical axis (z in the camera frame).
  double Depth(const Vec3& point_in_world) const;

  /// Projects to raw (distorted) pixels; nullopt if the point is not in front of the camera.
  std::optional<Vec2> Project(const Vec3& point_in_world) const;
  /// Projects to undistorted pixels; nullopt if the point is not in front of the camera.
  std::optional<Vec2> ProjectUndistorted(const Vec3& point_in_world) const;

  /// Raw pixel -> undistorted pixel (iterative inverse of the distortion model, as OpenCV's
  /// undistortPoints). Identity when there is no distortion.
  Vec2 UndistortPixel(const Vec2& raw_px) const;
  /// Undistorted pixel -> raw pixel (the forward distortion model).
  Vec2 DistortPixel(const Vec2& undistorted_px) const;

  /// Whether a raw pixel lies inside the image enlarged by `margin_px` on every side.
  bool InImage(const Vec2& raw_px, double margin_px = 0.0) const;

  /// The world point at height `z` (world frame, z up) on the viewing ray through an
  /// undistorted pixel: where a person's image point lies when its height is known. nullopt
  /// when the ray is (nearly) horizontal, or the point would be behind the camera.
  std::optional<Vec3> PointOnRayAtHeight(const Vec2& undistorted_px, double z) const;
};

/// Whether `camera` sees `point_in_world`: in front of it, and its distorted projection inside
/// the image, with a pinhole check (the undistorted projection within a quarter of the image
/// size of it) so that a distortion polynomial folding far points back into the image does
/// not count.
bool SeesPoint(const CameraModel& camera, const Vec3& point_in_world);

/// The rotation of a Rodrigues vector (OpenCV's rvec): |rvec| radians about rvec / |rvec|; the
/// identity for the zero vector.
Mat3 RotationFromRodrigues(const Vec3& rvec);

}  // namespace mvtrack::geometry
