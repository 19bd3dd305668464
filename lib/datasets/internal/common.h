#pragma once
/// @file
/// Internal to lib/datasets: helpers the loaders share. Stateless.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/detection.h"
#include "core/keypoint_layout.h"
#include "core/types.h"
#include "datasets/corruption.h"
#include "datasets/dataset.h"
#include "eval/sequence.h"
#include "geometry/camera_model.h"

namespace mvtrack::datasets::internal {

/// Centimetres to metres (Campus, Panoptic and WILDTRACK give centimetres).
inline constexpr double kCmToM = 0.01;

/// Builds a camera and checks it with CameraModel::Validate.
/// @throws DatasetError naming `file` and `what` (e.g. "camera \"3\"") when it is invalid.
geometry::CameraModel MakeCamera(const std::string& file,
                                 const std::string& what,
                                 CameraId id,
                                 int width_px,
                                 int height_px,
                                 const Mat3& K,
                                 const Mat3& cam_from_world_rotation,
                                 const Vec3& cam_from_world_translation_m,
                                 const geometry::Distortion& distortion = {});

/// Row-major 3x3 matrix from 9 numbers.
Mat3 Mat3FromRowMajor(const std::vector<double>& v, std::size_t offset = 0);

/// The midpoint of joints `l_hip` and `r_hip` when both are present, else the centroid of the
/// present joints; z set to 0. std::nullopt when no joint is present.
std::optional<Vec3> FootprintFromHips(const std::vector<std::optional<Vec3>>& joints,
                                      int l_hip,
                                      int r_hip);

/// A ground-truth or predicted object: `joints` in `layout`, footprint by FootprintFromJoints.
/// std::nullopt when no joint is present.
std::optional<eval::EvalObject> MakeEvalObject(std::int64_t id,
                                               std::vector<std::optional<Vec3>> joints,
                                               core::KeypointLayoutId layout);

/// A pose detection in `layout` from its keypoints: box = BoxFromKeypoints, score =
/// MeanKeypointScore. std::nullopt with fewer than 2 detected keypoints.
std::optional<core::Detection2D> MakePoseDetection(std::vector<core::Keypoint2D> keypoints,
                                                   core::KeypointLayoutId layout);

/// Empty camera-frames for `frames` x `cameras` (frame numbers, utime and camera ids filled in)
/// and the parallel, empty source-id lists.
void InitDetectionGrid(const std::vector<FrameIndex>& frames,
                       const std::vector<geometry::CameraModel>& cameras,
                       double fps,
                       std::vector<std::vector<core::CameraFrame>>* detections,
                       std::vector<std::vector<std::vector<std::int64_t>>>* source_ids);

/// Applies the detector model `corruption` (blackout already placed) to every camera-frame of
/// `detections` / `source_ids` (as InitDetectionGrid lays them out); the false-positive pool of
/// a camera is all its clean poses. Nothing when corruption is disabled.
void CorruptDetectionGrid(const CorruptionOptions& corruption,
                          const std::vector<geometry::CameraModel>& cameras,
                          std::vector<std::vector<core::CameraFrame>>* detections,
                          std::vector<std::vector<std::vector<std::int64_t>>>* source_ids);

/// The detector model on a loaded dataset: places `corruption`'s blackout (PlaceBlackout) among
/// ds's cameras inside `ranges` (inclusive frame ranges) at ds->fps, then applies it
/// (CorruptDetectionGrid). Returns the options with the blackout placed (for protocol notes).
CorruptionOptions CorruptDataset(const CorruptionOptions& corruption,
                                 const std::vector<std::pair<FrameIndex, FrameIndex>>& ranges,
                                 Dataset* ds);

/// Maps a sequence with `mapping` (joint by joint, a target joint present only when all its
/// sources are); footprints are recomputed in the target layout; objects left without joints
/// are dropped.
eval::EvalSequence MapSequence(const eval::EvalSequence& sequence,
                               const core::KeypointMapping& mapping);

}  // namespace mvtrack::datasets::internal
