#pragma once
#include <Eigen/Geometry>
/// @file
/// Synthetic scene for the triangulation tests: four calibrated cameras in the corners of a
/// 6 m x 6 m room and walking 14-joint skeletons (Shelf/Campus joint order) whose 2D
/// observations are exact projections, optionally with Gaussian pixel noise. Header-only,
/// deterministic (noise from a caller-owned std::mt19937).

#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/check.h"
#include "core/observation.h"
#include "core/types.h"
#include "geometry/camera_model.h"
#include "geometry/camera_rig.h"
#include "support/synthetic_cameras.h"

namespace mvtrack::testing {

/// Joints of the synthetic skeleton (shelf14 order).
inline constexpr int kNumJoints = 14;
/// Index of the neck joint (moves linearly: no limb swing).
inline constexpr int kNeck = 12;
/// Frame rate of the synthetic sequences.
inline constexpr double kFps = 30.0;

/// A person walking in a straight line with swinging arms and legs (1 Hz gait).
struct Walker {
  Vec3 start = Vec3(-1.5, -1.0, 0.0);  ///< ground position at frame 0, metres
  Vec3 velocity_mps = Vec3(1.2, 0.6, 0.0);

  /// Ground-truth joints at frame t (world frame, metres, z up).
  std::vector<Vec3> Joints(FrameIndex t) const {
    const double time_s = static_cast<double>(t) / kFps;
    const Vec3 root = start + time_s * velocity_mps;
    const Vec3 forward = Vec3(velocity_mps.x(), velocity_mps.y(), 0.0).normalized();
    const Vec3 left = Vec3::UnitZ().cross(forward);
    const double s = std::sin(2.0 * std::numbers::pi * time_s);
    // {forward swing amplitude, lateral offset, height} per joint.
    static constexpr double kLocal[kNumJoints][3] = {{0.15, -0.10, 0.10},
                                                     {0.08, -0.10, 0.50},
                                                     {0.0, -0.10, 0.95},
                                                     {0.0, 0.10, 0.95},
                                                     {-0.08, 0.10, 0.50},
                                                     {-0.15, 0.10, 0.10},
                                                     {-0.20, -0.25, 0.85},
                                                     {-0.10, -0.22, 1.15},
                                                     {0.0, -0.20, 1.45},
                                                     {0.0, 0.20, 1.45},
                                                     {0.10, 0.22, 1.15},
                                                     {0.20, 0.25, 0.85},
                                                     {0.0, 0.0, 1.55},
                                                     {0.0, 0.0, 1.80}};
    std::vector<Vec3> joints;
    joints.reserve(kNumJoints);
    for (const auto& j : kLocal) {
      joints.push_back(root + j[0] * s * forward + j[1] * left + Vec3(0.0, 0.0, j[2]));
    }
    return joints;
  }

  /// Ground-truth box-mode point at frame t: the mid-hip (pelvis).
  Vec3 Pelvis(FrameIndex t) const {
    const auto j = Joints(t);
    return 0.5 * (j[2] + j[3]);
  }
};

/// Four cameras (ids 3, 5, 8, 13: deliberately not dense) 2.6 m high in the corners of a
/// 6 m x 6 m room centred on the origin, looking at (0, 0, 1); 1920x1080, f = 1000 px.
inline std::vector<geometry::CameraModel> RoomCameras() {
  const CameraId ids[4] = {3, 5, 8, 13};
  const Vec3 corners[4] = {
      Vec3(3.0, 3.0, 2.6), Vec3(-3.0, 3.0, 2.6), Vec3(-3.0, -3.0, 2.6), Vec3(3.0, -3.0, 2.6)};
  std::vector<geometry::CameraModel> cameras;
  for (int i = 0; i < 4; ++i) {
    cameras.push_back(LookAtCamera(ids[i], corners[i], Vec3(0.0, 0.0, 1.0), 1000.0, 1920, 1080));
  }
  return cameras;
}

/// A rig from `cameras`; aborts if the cameras are invalid.
inline geometry::CameraRig MakeRig(std::vector<geometry::CameraModel> cameras) {
  std::string why;
  geometry::CameraRig rig(std::move(cameras), &why);
  MVTRACK_CHECK_MSG(rig.ok(), why.c_str());
  return rig;
}

/// Observation of `points` (world) in `camera`: undistorted projections plus N(0, noise_px^2)
/// noise per coordinate, confidence `confidence`, and scale |w + h| of the box around
/// `body` (the full skeleton, also in box mode).
inline core::Observation2D Observe(const geometry::CameraModel& camera,
                                   const std::vector<Vec3>& points,
                                   const std::vector<Vec3>& body,
                                   double noise_px,
                                   std::mt19937* rng,
                                   double confidence = 1.0) {
  core::Observation2D obs;
  std::normal_distribution<double> noise(0.0, 1.0);
  for (const Vec3& p : points) {
    const auto x = camera.ProjectUndistorted(p);
    MVTRACK_CHECK(x.has_value());
    Vec2 px = *x;
    if (noise_px > 0.0) px += noise_px * Vec2(noise(*rng), noise(*rng));
    obs.points_px.push_back(px);
    obs.confidence.push_back(confidence);
  }
  Vec2 lo = Vec2::Constant(1e300), hi = Vec2::Constant(-1e300);
  for (const Vec3& p : body) {
    const Vec2 x = *camera.ProjectUndistorted(p);
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  obs.scale_px = (hi - lo).sum();
  return obs;
}

/// How a camera observes a walker: pose mode projects the 14 joints, box mode only the pelvis;
/// `noise_px` is the standard deviation of the pixel noise per coordinate.
struct ViewSpec {
  bool box_mode = false;
  double noise_px = 0.0;
};

/// A tracklet of `walker` in `camera` over `frames` (ascending). `edit(t, obs)` may modify each
/// observation after projection (corruption, low confidence).
inline core::Tracklet2D MakeTracklet(
    const geometry::CameraModel& camera,
    TrackId2D track_id,
    const Walker& walker,
    const std::vector<FrameIndex>& frames,
    const ViewSpec& spec,
    std::mt19937* rng,
    const std::function<void(FrameIndex, core::Observation2D*)>& edit = nullptr) {
  core::Tracklet2D tr;
  tr.camera_id = camera.id;
  tr.track_id = track_id;
  for (const FrameIndex t : frames) {
    const auto body = walker.Joints(t);
    const std::vector<Vec3> points = spec.box_mode ? std::vector<Vec3>{walker.Pelvis(t)} : body;
    core::Observation2D obs = Observe(camera, points, body, spec.noise_px, rng);
    if (edit) edit(t, &obs);
    tr.frames.push_back(t);
    tr.observations.push_back(std::move(obs));
  }
  return tr;
}

/// Frames [first, last] except those in `skip`.
inline std::vector<FrameIndex> FrameRange(FrameIndex first,
                                          FrameIndex last,
                                          const std::vector<FrameIndex>& skip = {}) {
  std::vector<FrameIndex> frames;
  for (FrameIndex t = first; t <= last; ++t) {
    bool skipped = false;
    for (const FrameIndex s : skip) skipped = skipped || s == t;
    if (!skipped) frames.push_back(t);
  }
  return frames;
}

}  // namespace mvtrack::testing
