#pragma once
/// @file
/// The detector model of the synthetic scene: projects the ground truth into each camera and
/// produces the 2D detections a person detector / pose estimator would report (noise, misses,
/// false positives, occlusion). Stateless and deterministic: the randomness of a camera-frame
/// comes from streams seeded by (options.seed, frame, camera id), so frames and cameras can be
/// rendered in any order (or in parallel) with identical results.

#include <optional>
#include <vector>

#include "core/detection.h"
#include "geometry/camera_model.h"
#include "sim/crowd.h"
#include "sim/scene_options.h"

namespace mvtrack::sim {

/// Horizontal padding of a person box on each side, as a fraction of the box width.
inline constexpr double kBoxPadX = 0.05;
/// Vertical padding of a person box on each side, as a fraction of the box height.
inline constexpr double kBoxPadY = 0.03;
/// Box points closer to the camera plane than this (metres) make a person unrenderable.
inline constexpr double kNearPlaneM = 0.05;

/// The clean (noise-free) image of one person in one camera.
struct PersonProjection {
  /// Bounds of the projected BoxPoints(person), padded by kBoxPadX / kBoxPadY; not clipped.
  core::BoxPx padded_box;
  /// padded_box clipped to the image (may be empty when the person is outside the image).
  core::BoxPx clipped_box;
  /// The person counts as in view (can be detected): the centre of padded_box is in the image.
  bool in_view = false;
  /// The 17 projected joints (raw pixels) and whether each lies inside the image.
  std::vector<Vec2> keypoints_px;
  std::vector<bool> keypoint_in_image;
  /// Depth (camera z) of the body centre (midpoint of the hips and shoulders); orders occlusion.
  double depth_m = 0.0;
};

/// Projects `person` into `camera`; nullopt when any box point is behind or within kNearPlaneM
/// of the camera plane (such a person is never detected and never occludes).
std::optional<PersonProjection> ProjectPerson(const geometry::CameraModel& camera,
                                              const PersonTruth& person);

/// Area of the union of `rects` intersected with `target` (exact, by a sweep over x: O(n^2 log n)).
double CoveredArea(const core::BoxPx& target, const std::vector<core::BoxPx>& rects);

/// Detections of one camera at one frame. `person_ids`, if not null, receives for each detection
/// the id of the person it shows, or -1 for a false positive.
///
/// Model: every person in view is a candidate. With options.occlusion, a candidate whose clipped
/// box is covered to >= occlusion_threshold by the union of the clipped boxes of nearer people
/// (by depth_m; all people in front of the camera occlude, detected or not) is not detected;
/// otherwise it is missed with probability miss_rate. A detection's box is the padded box with
/// N(0, pixel_noise_px^2) added to each edge, clipped to the image (at least 1 px wide and high);
/// its score is 0.5 + 0.5 (1 - 0.6 u) (1 - covered fraction), u ~ U[0,1). With options.poses it
/// carries 17 COCO keypoints: projected joint + N(0, pixel_noise_px^2) per coordinate;
/// confidence 0 outside the image or with probability keypoint_dropout, in (0.05, 0.5] inside a
/// nearer person's box (occlusion on), else in (0.5, 1]. False positives: Poisson
/// (false_positives_per_frame) per camera-frame, boxes 15-60 % of the image height with aspect
/// w/h in [0.3, 0.5] centred uniformly in the image, score in [0.5, 0.8), and (with poses) a
/// random frontal walking skeleton fitted to the box with 2 % of the box height of noise.
/// The detections are returned in a random order so that order carries no identity. The number
/// of random draws per candidate (candidates taken in the order of truth.people) does not depend
/// on the rates, so changing e.g. miss_rate changes only which detections are dropped, not the
/// noise of the others. Pixels are raw: any CameraModel works, with lens distortion applied to
/// every projected point (frustum culling is then disabled). `options` should be valid; only
/// its detector fields and seed are used.
core::CameraFrame RenderCamera(const SceneOptions& options,
                               const geometry::CameraModel& camera,
                               const FrameTruth& truth,
                               std::vector<int>* person_ids = nullptr);

/// Detections of every camera at one frame (RenderCamera for each).
struct RenderedFrame {
  /// Parallel to the camera list.
  std::vector<core::CameraFrame> cameras;
  /// [camera][detection]: id of the person shown, -1 for a false positive.
  std::vector<std::vector<int>> person_ids;
};

/// Renders `truth` in every camera of `cameras`.
RenderedFrame RenderFrame(const SceneOptions& options,
                          const std::vector<geometry::CameraModel>& cameras,
                          const FrameTruth& truth);

}  // namespace mvtrack::sim
