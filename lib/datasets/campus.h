#pragma once
/// @file
/// The Campus dataset (Belagiannis et al., CVPR 2014, "CampusSeq1") as released by Cross-View
/// Tracking (Chen et al., CVPR 2020): 3 cameras (360x288, 25 fps), 2000 frames, 2D and 3D
/// ground truth of 3 actors, and Cross-View Tracking's own output. No real detections exist
/// for Campus: the 2D ground truth is the input, optionally corrupted by the seeded detector
/// model of corruption.h. Files and formats: `<data_root>/campus/SOURCE.md`. Stateless.

#include <filesystem>
#include <string>

#include "datasets/corruption.h"
#include "datasets/dataset.h"

namespace mvtrack::datasets {

/// Options of LoadCampus.
struct CampusOptions {
  /// The detector model applied to the 2D ground truth (CorruptionOptions::Clean() for the
  /// clean variant). Defaults: see CorruptionOptions.
  CorruptionOptions corruption;

  /// corruption.Validate. On failure writes the reason to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// Loads Campus from `data_root`/campus/crossview_longcw:
///  - cameras: calibration.json, Camera0..2 -> ids 0..2; K de-normalised by the image size
///    (fx = K00 * 360, cx = K02 * 360, fy = K11 * 288, cy = K12 * 288), cam_from_world the
///    inverse of Tw (camera -> world, centre in cm -> m); dist_coeffs are NOT applied (the 2D
///    ground truth is the undistorted projection of the 3D ground truth, SOURCE.md);
///  - frames: 0..1999 at 25 fps, frame = round(timestamp / 0.04);
///  - detections: annotation_2d.json, one Detection2D per annotated person in layout kShelf14
///    (keypoints with their score, 1), box = BoxFromKeypoints, score = MeanKeypointScore,
///    then CorruptCameraFrame with the options (false-positive pool: every clean pose of the
///    same camera); source ids are the annotation ids;
///  - ground truth: annotation_3d.json (cm -> m), kShelf14, actor ids 0..2; protocol frames
///    350-470 and 650-750 (VoxelPose's test frames).
/// @throws DatasetError on a missing or malformed file, or invalid options.
Dataset LoadCampus(const std::filesystem::path& data_root, const CampusOptions& options = {});

/// Cross-View Tracking's own output on Campus (crossview_longcw/result_3d.json: COCO-17
/// joints, cm -> m, 64-bit track ids remapped to 1, 2, ... in order of first appearance,
/// frame = round(timestamp / 0.04)). A joint with score 0 is missing. `shelf14` is derived
/// with core::MakeKeypointMapping(kCoco17, kShelf14) (head_bottom and head_top by VoxelPose's
/// coco2campus rule, docs/DECISIONS.md).
/// @throws DatasetError on a missing or malformed file.
PeerOutput LoadCampusPeerCrossView(const std::filesystem::path& data_root);

}  // namespace mvtrack::datasets
