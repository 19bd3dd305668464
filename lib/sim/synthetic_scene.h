#pragma once
/// @file
/// Deterministic, seeded synthetic multi-camera scenes: cameras around or above a room, people
/// walking in it (ground truth 3D footprints and COCO-17 skeletons) and the 2D detections
/// (boxes and poses with noise, misses, false positives and occlusion) every camera reports.
/// Used by the tracker's tests, `mvtrack demo` and `mvtrack sim`. Pure: no I/O, threads or
/// clock; the same options always give the identical scene.
///
/// For long or large runs, avoid materialising the whole Scene: step a CrowdSimulator
/// (crowd.h) and call RenderFrame (render.h) per frame; GenerateScene is exactly that loop.

#include <vector>

#include "core/detection.h"
#include "geometry/camera_model.h"
#include "sim/cameras.h"
#include "sim/crowd.h"
#include "sim/render.h"
#include "sim/scene_options.h"

namespace mvtrack::sim {

/// A generated scene.
struct Scene {
  SceneOptions options;
  /// Ids 0..N-1, undistorted pinhole cameras (see MakeCameras).
  std::vector<geometry::CameraModel> cameras;
  /// One per frame, frames 0..num_frames-1.
  std::vector<FrameTruth> truth;
  /// [frame][camera]: detections in a random (seeded) order, so order carries no identity.
  std::vector<std::vector<core::CameraFrame>> detections;
  /// [frame][camera][detection]: id of the person a detection shows, -1 for a false positive
  /// (ground-truth labels for evaluation; never feed them to the tracker).
  std::vector<std::vector<std::vector<int>>> detection_person_ids;
};

/// Generates the scene of `options`, which must be valid (checked; call Validate() first on
/// untrusted options). Cost O(frames x cameras x people) plus O(people^2) per camera-frame in
/// the worst case for occlusion.
Scene GenerateScene(const SceneOptions& options);

}  // namespace mvtrack::sim
