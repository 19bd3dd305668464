#pragma once
/// @file
/// Synthetic calibrated cameras for tests: a look-at constructor, a ring rig of cameras around a
/// room, back-projection of pixels to 3D, a Panoptic-like lens distortion, and a camera's
/// image -> floor homography. Header-only, stateless, deterministic.
///
/// World convention used here: metres, z up (the floor is z = 0). Cameras follow OpenCV's
/// convention (x right, y down, z forward), which is what geometry::CameraModel expects.

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/check.h"
#include "core/types.h"
#include "geometry/camera_model.h"

namespace mvtrack::testing {

/// Lens distortion of the magnitude seen in the CMU Panoptic HD cameras (k1 = -0.3, k2 = 0.1,
/// p1 = 1e-3, p2 = -1e-3, k3 = -0.02): strong barrel distortion, still monotonic (invertible)
/// well beyond the corners of a 1920x1080 image with fx around 1400 px.
inline geometry::Distortion PanopticLikeDistortion() {
  geometry::Distortion d;
  d.k1 = -0.3;
  d.k2 = 0.1;
  d.p1 = 1e-3;
  d.p2 = -1e-3;
  d.k3 = -0.02;
  return d;
}

/// Rotation `cam_from_world` of a camera whose optical axis (+z) points along `forward` and whose
/// image y axis points "down", i.e. against world +z. When `forward` is (nearly) vertical the
/// image y axis is taken against world +y instead. `forward` must be non-zero.
inline Mat3 LookAtRotation(const Vec3& forward) {
  MVTRACK_CHECK_MSG(forward.norm() > 0.0, "LookAtRotation: forward direction must be non-zero");
  const Vec3 z = forward.normalized();
  Vec3 up = Vec3::UnitZ();
  if (std::abs(z.dot(up)) > 0.999) up = Vec3::UnitY();
  const Vec3 x = z.cross(up).normalized();  // image right
  const Vec3 y = z.cross(x);                // image down; x, y, z right-handed
  Mat3 cam_from_world;
  cam_from_world.row(0) = x.transpose();
  cam_from_world.row(1) = y.transpose();
  cam_from_world.row(2) = z.transpose();
  return cam_from_world;
}

/// A distortion-free camera `id` centred at `position_in_world` whose optical axis passes through
/// `target_in_world`, with square pixels of focal length `fx_px`, zero skew, principal point at
/// the image centre (width/2, height/2) and a `width_px` x `height_px` image. Set `distortion` on
/// the result to add a lens model. The two positions must differ.
inline geometry::CameraModel LookAtCamera(CameraId id,
                                          const Vec3& position_in_world,
                                          const Vec3& target_in_world,
                                          double fx_px,
                                          int width_px,
                                          int height_px) {
  geometry::CameraModel camera;
  camera.id = id;
  camera.width_px = width_px;
  camera.height_px = height_px;
  camera.K << fx_px, 0.0, 0.5 * width_px, 0.0, fx_px, 0.5 * height_px, 0.0, 0.0, 1.0;
  camera.cam_from_world.rotation = LookAtRotation(target_in_world - position_in_world);
  camera.cam_from_world.translation = -(camera.cam_from_world.rotation * position_in_world);
  return camera;
}

/// `count` LookAtCameras with ids first_id, first_id + 1, ..., evenly spaced on a horizontal
/// circle of radius `radius_m` around `target_in_world` (the first one on the +x side), all at
/// height `height_m` and all looking at `target_in_world`.
inline std::vector<geometry::CameraModel> RingOfCameras(int count,
                                                        double radius_m,
                                                        double height_m,
                                                        const Vec3& target_in_world,
                                                        double fx_px,
                                                        int width_px,
                                                        int height_px,
                                                        CameraId first_id = 0) {
  std::vector<geometry::CameraModel> cameras;
  cameras.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const double angle =
        2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(count);
    const Vec3 position(target_in_world.x() + radius_m * std::cos(angle),
                        target_in_world.y() + radius_m * std::sin(angle),
                        height_m);
    cameras.push_back(
        LookAtCamera(first_id + i, position, target_in_world, fx_px, width_px, height_px));
  }
  return cameras;
}

/// World point seen at undistorted pixel `undistorted_px` at depth `depth_m` (camera z) in
/// `camera`: the inverse of CameraModel::ProjectUndistorted for a known depth.
inline Vec3 BackProjectUndistorted(const geometry::CameraModel& camera,
                                   const Vec2& undistorted_px,
                                   double depth_m) {
  const Vec3 ray_in_cam = camera.K.inverse() * undistorted_px.homogeneous();  // z == 1
  return camera.cam_from_world.Inverse() * (depth_m * ray_in_cam);
}

/// The image -> floor homography H of a distortion-free `camera` (world metres, z up, floor
/// z = 0) when the floor's coordinates are in units of `unit_m` metres, with the floor's y
/// negated when `mirror_y`, times `scale`: H (u, v, 1) ~ (x, y, 1) with the world point
/// unit_m (x, ±y, 0) seen at pixel (u, v).
inline Mat3 FloorHomographyOf(const geometry::CameraModel& camera,
                              double unit_m,
                              bool mirror_y,
                              double scale) {
  const Mat3& R = camera.cam_from_world.rotation;
  Mat3 floor_to_image;
  floor_to_image.col(0) = unit_m * R.col(0);
  floor_to_image.col(1) = (mirror_y ? -unit_m : unit_m) * R.col(1);
  floor_to_image.col(2) = camera.cam_from_world.translation;
  floor_to_image = camera.K * floor_to_image;
  return scale * floor_to_image.inverse();
}

}  // namespace mvtrack::testing
