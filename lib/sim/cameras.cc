#include "sim/cameras.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/check.h"

namespace mvtrack::sim {
namespace {

std::vector<geometry::CameraModel> RingCameras(const SceneOptions& o) {
  std::vector<geometry::CameraModel> cameras;
  const double cx = 0.5 * o.room_width_m, cy = 0.5 * o.room_depth_m;
  // The ellipse through the four corners with the room's aspect: semi-axes W/sqrt(2), D/sqrt(2).
  const double ax = o.room_width_m / std::numbers::sqrt2;
  const double ay = o.room_depth_m / std::numbers::sqrt2;
  const Vec3 target(cx, cy, o.look_at_height_m);
  for (int i = 0; i < o.num_cameras; ++i) {
    // Start at the corner (0, 0), i.e. angle -135 deg, and go counter-clockwise.
    const double angle = -0.75 * std::numbers::pi + 2.0 * std::numbers::pi * i / o.num_cameras;
    const Vec3 center(cx + ax * std::cos(angle), cy + ay * std::sin(angle), o.camera_height_m);
    cameras.push_back(MakeCamera(
        i, o.image_width_px, o.image_height_px, o.horizontal_fov_deg, center, target - center));
  }
  return cameras;
}

std::vector<geometry::CameraModel> GridCameras(const SceneOptions& o) {
  std::vector<geometry::CameraModel> cameras;
  const int n = o.num_cameras;
  // Rows over the depth so that cells are roughly square; cameras spread as evenly as possible.
  const int rows = std::clamp(
      static_cast<int>(std::lround(std::sqrt(n * o.room_depth_m / o.room_width_m))), 1, n);
  const double pitch = o.grid_pitch_deg * kDeg;
  int id = 0;
  for (int r = 0; r < rows; ++r) {
    const int in_row = n / rows + (r < n % rows ? 1 : 0);
    const double y = o.room_depth_m * (r + 0.5) / rows;
    for (int c = 0; c < in_row; ++c) {
      const double x = o.room_width_m * (c + 0.5) / in_row;
      // Checkerboard of diagonal yaws; border cameras look into the room.
      double dx = (c % 2 == 0) ? 1.0 : -1.0;
      double dy = (r % 2 == 0) ? 1.0 : -1.0;
      if (in_row > 1 && c == 0) dx = 1.0;
      if (in_row > 1 && c == in_row - 1) dx = -1.0;
      if (rows > 1 && r == 0) dy = 1.0;
      if (rows > 1 && r == rows - 1) dy = -1.0;
      const double yaw = std::atan2(dy, dx);
      const Vec3 forward(
          std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), -std::sin(pitch));
      cameras.push_back(MakeCamera(id++,
                                   o.image_width_px,
                                   o.image_height_px,
                                   o.horizontal_fov_deg,
                                   Vec3(x, y, o.camera_height_m),
                                   forward));
    }
  }
  return cameras;
}

std::vector<geometry::CameraModel> CorridorCameras(const SceneOptions& o) {
  std::vector<geometry::CameraModel> cameras;
  const double w = o.room_width_m, d = o.room_depth_m;
  for (int i = 0; i < o.num_cameras; ++i) {
    const double x = w * (i + 0.5) / o.num_cameras;
    const bool far_wall = i % 2 == 1;
    // Pairs of cameras (one per wall) look ahead, the next pair back.
    const double along = ((i / 2) % 2 == 0 ? 0.5 : -0.5) * d;
    const Vec3 center(x, far_wall ? d : 0.0, o.camera_height_m);
    const double yaw = std::atan2((far_wall ? 0.25 * d : 0.75 * d) - center.y(),
                                  std::clamp(x + along, 0.0, w) - x);
    const double pitch = o.grid_pitch_deg * kDeg;
    const Vec3 forward(
        std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), -std::sin(pitch));
    cameras.push_back(
        MakeCamera(i, o.image_width_px, o.image_height_px, o.horizontal_fov_deg, center, forward));
  }
  return cameras;
}

}  // namespace

geometry::CameraModel MakeCamera(CameraId id,
                                 int width_px,
                                 int height_px,
                                 double horizontal_fov_deg,
                                 const Vec3& center_in_world,
                                 const Vec3& forward_in_world) {
  MVTRACK_CHECK(forward_in_world.norm() > 0.0);
  const Vec3 forward = forward_in_world.normalized();
  // Image x ("right") is horizontal: forward x up, or world +x for a camera looking straight
  // down or up. Image y ("down") completes the right-handed camera frame (z = forward).
  Vec3 right = forward.cross(Vec3::UnitZ());
  if (right.norm() < 1e-9) {
    right = Vec3::UnitX();
  } else {
    right.normalize();
  }
  const Vec3 down = forward.cross(right);
  geometry::CameraModel camera;
  camera.id = id;
  camera.width_px = width_px;
  camera.height_px = height_px;
  const double f = 0.5 * width_px / std::tan(0.5 * horizontal_fov_deg * kDeg);
  camera.K << f, 0.0, 0.5 * width_px, 0.0, f, 0.5 * height_px, 0.0, 0.0, 1.0;
  Mat3 r;
  r.row(0) = right.transpose();
  r.row(1) = down.transpose();
  r.row(2) = forward.transpose();
  camera.cam_from_world.rotation = r;
  camera.cam_from_world.translation = -(r * center_in_world);
  return camera;
}

std::vector<geometry::CameraModel> MakeCameras(const SceneOptions& options) {
  std::string why;
  MVTRACK_CHECK_MSG(options.Validate(&why), why.c_str());
  switch (options.camera_layout) {
    case CameraLayout::kRing:
      return RingCameras(options);
    case CameraLayout::kCeilingGrid:
      return GridCameras(options);
    case CameraLayout::kCorridor:
      return CorridorCameras(options);
  }
  return {};
}

}  // namespace mvtrack::sim
