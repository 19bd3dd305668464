#pragma once
/// @file
/// Test helpers of the association tests: people modelled as boxes of fixed metric size seen by
/// distortion-free calibrated cameras, and 2D tracklets built from them. Header-only,
/// deterministic (noise only through a caller-seeded std::mt19937).

#include <cstddef>
#include <optional>
#include <random>
#include <set>
#include <vector>

#include "core/observation.h"
#include "core/types.h"
#include "geometry/camera_model.h"

namespace mvtrack::testing {

/// A standing person as an axis-aligned 3D box on the floor (z = 0), world z up.
struct BoxPerson {
  double width_m = 0.5;   ///< along world x
  double depth_m = 0.3;   ///< along world y
  double height_m = 1.8;  ///< along world z
};

/// What a box detector reports for `person` standing at floor point `foot_in_world` in
/// `camera`: scale_px = w + h of the bounding box of the 8 projected box corners (undistorted
/// pixels) and one point, the projection of the box centre displaced by
/// `point_offset_in_world` (a detection bias), plus optional isotropic pixel noise. nullopt if
/// any corner is behind the camera.
inline std::optional<core::Observation2D> ObserveBoxPerson(const geometry::CameraModel& camera,
                                                           const BoxPerson& person,
                                                           const Vec3& foot_in_world,
                                                           const Vec3& point_offset_in_world,
                                                           double noise_px = 0.0,
                                                           std::mt19937* rng = nullptr) {
  double x_min = 0.0, x_max = 0.0, y_min = 0.0, y_max = 0.0;
  bool first = true;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p = foot_in_world + Vec3(((corner & 1) ? 0.5 : -0.5) * person.width_m,
                                        ((corner & 2) ? 0.5 : -0.5) * person.depth_m,
                                        (corner & 4) ? person.height_m : 0.0);
    const std::optional<Vec2> x = camera.ProjectUndistorted(p);
    if (!x) return std::nullopt;
    if (first || x->x() < x_min) x_min = x->x();
    if (first || x->x() > x_max) x_max = x->x();
    if (first || x->y() < y_min) y_min = x->y();
    if (first || x->y() > y_max) y_max = x->y();
    first = false;
  }
  const Vec3 centre = foot_in_world + Vec3(0.0, 0.0, 0.5 * person.height_m);
  const std::optional<Vec2> point = camera.ProjectUndistorted(centre + point_offset_in_world);
  if (!point) return std::nullopt;
  core::Observation2D o;
  o.points_px = {*point};
  if (noise_px > 0.0 && rng != nullptr) {
    std::normal_distribution<double> noise(0.0, noise_px);
    o.points_px[0] += Vec2(noise(*rng), noise(*rng));
  }
  o.confidence = {1.0};
  o.scale_px = (x_max - x_min) + (y_max - y_min);
  return o;
}

/// Builds the 2D tracklet of `person` in `camera` over frames [first_frame, last_frame], with
/// foot positions `foot_at(frame)` and a constant 3D detection bias `point_offset_in_world`.
template <typename FootAt>
core::Tracklet2D MakeBoxTracklet(const geometry::CameraModel& camera,
                                 TrackId2D track_id,
                                 const BoxPerson& person,
                                 FrameIndex first_frame,
                                 FrameIndex last_frame,
                                 FootAt foot_at,
                                 const Vec3& point_offset_in_world,
                                 double noise_px = 0.0,
                                 std::mt19937* rng = nullptr) {
  core::Tracklet2D t;
  t.camera_id = camera.id;
  t.track_id = track_id;
  for (FrameIndex f = first_frame; f <= last_frame; ++f) {
    std::optional<core::Observation2D> o =
        ObserveBoxPerson(camera, person, foot_at(f), point_offset_in_world, noise_px, rng);
    if (!o) continue;
    t.frames.push_back(f);
    t.observations.push_back(*o);
  }
  return t;
}

/// A partition as a set of sets, for comparisons that ignore cluster order.
inline std::set<std::set<int>> AsPartition(const std::vector<std::vector<int>>& clusters) {
  std::set<std::set<int>> partition;
  for (const std::vector<int>& c : clusters) partition.insert(std::set<int>(c.begin(), c.end()));
  return partition;
}

/// Whether `a` and `b` are in the same cluster.
inline bool SameCluster(const std::vector<std::vector<int>>& clusters, int a, int b) {
  for (const std::vector<int>& c : clusters) {
    bool has_a = false, has_b = false;
    for (int i : c) {
      has_a = has_a || i == a;
      has_b = has_b || i == b;
    }
    if (has_a || has_b) return has_a && has_b;
  }
  return false;
}

}  // namespace mvtrack::testing
