#pragma once
/// @file
/// Two 20-frame excerpts of CMU Panoptic Studio ("160906_band1" frames 168-187,
/// "160906_band2" frames 139-158; 3 seated musicians; Joo et al., ICCV 2015) with the full
/// calibration of the 31 HD cameras. There are no real detections: the 3D skeletons are
/// projected into the chosen cameras with the official distortion model and optionally
/// corrupted by the detector model of corruption.h. Files and formats:
/// `<data_root>/panoptic/SOURCE.md`. Stateless.

#include <filesystem>
#include <string>
#include <vector>

#include "datasets/corruption.h"
#include "datasets/dataset.h"

namespace mvtrack::datasets {

/// Rotation from Panoptic's world axes (y down) to ours (z up): (x, y, z) -> (x, z, -y), a
/// +90 degree rotation about x. Points: p_ours = 0.01 * kPanopticToWorld * p_panoptic_cm.
Mat3 PanopticToWorldRotation();

/// The default HD camera subset: the six HD cameras that see all valid joints of the three
/// people of 160906_band2 frame 139 with a pinhole projection (00_02, 00_06, 00_07, 00_12,
/// 00_13, 00_28; computed from the calibration, SOURCE.md does not list them).
std::vector<std::string> DefaultPanopticCameras();

/// Options of LoadPanoptic.
struct PanopticOptions {
  /// "160906_band1" or "160906_band2".
  std::string sequence = "160906_band2";
  /// HD cameras, each a name "00_xx" or a decimal index "0".."30"; empty = the default subset
  /// (DefaultPanopticCameras). Order is kept; duplicates are an error.
  std::vector<std::string> cameras;
  /// The detector model. The default noise is scaled to the HD images, where the seated
  /// people are 250-500 px tall (median about 330 px): sigma 6 px (about 2 % of the height,
  /// the same relative level as Campus's 2 px), other rates as CorruptionOptions.
  CorruptionOptions corruption = DefaultCorruption();

  /// CorruptionOptions{} with pixel_noise_px = 6.
  static CorruptionOptions DefaultCorruption();

  /// Known sequence, camera entries well-formed and unique, corruption valid. On failure
  /// writes the reason to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// Loads one Panoptic excerpt from `data_root`/panoptic/<sequence>:
///  - cameras: the chosen HD cameras of calibration_<sequence>.json (K, distCoef k1 k2 p1 p2
///    k3, R, t cm -> m), ids = HD index; the world is rotated by PanopticToWorldRotation
///    (cam_from_world.rotation = R * rotation^T) and scaled to metres;
///  - frames: the HD frame numbers of the body3DScene files, 29.97 fps;
///  - detections: every body with joints19 projected by CameraModel::Project (with lens
///    distortion); joints with confidence < 0, behind the camera or outside the image
///    [0, W] x [0, H] are not detected (confidence 0), the others get confidence 1; a body
///    with fewer than 2 detected joints in a camera is not detected there; no occlusion
///    between people is modelled; layout kPanoptic19; box = BoxFromKeypoints; then
///    CorruptCameraFrame; source ids are the body ids;
///  - ground truth: the 3D skeletons, kPanoptic19, joints with confidence < 0 missing.
/// @throws DatasetError on a missing or malformed file, or invalid options.
Dataset LoadPanoptic(const std::filesystem::path& data_root, const PanopticOptions& options = {});

}  // namespace mvtrack::datasets
