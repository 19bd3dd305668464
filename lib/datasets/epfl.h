#pragma once
/// @file
/// EPFL multi-camera pedestrians, sequence Terrace 1 (Fleuret et al., "Multi-Camera People
/// Tracking with a Probabilistic Occupancy Map", TPAMI 2008), with the per-view boxes and person
/// ids of the UCLA multi-view annotations as released by GNN-CCA: 4 cameras (360x288, 25 fps),
/// 9 people, one image -> floor homography per camera and no other calibration. The cameras are
/// recovered from the homographies (geometry/floor_homography.h) and the floor unit from a
/// person-height prior. No detector output exists: the annotated boxes are the detections, as
/// they are or through the seeded detector model of corruption.h. Files and formats:
/// `<data_root>/epfl/SOURCE.md`. Stateless.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/types.h"
#include "datasets/corruption.h"
#include "datasets/dataset.h"
#include "geometry/floor_homography.h"

namespace mvtrack::datasets {

/// The corruption defaults for Terrace's annotated boxes: the Campus defaults (same resolution;
/// box noise scales with the box, corruption.h), the blackout placed in the converted frames.
CorruptionOptions EpflCorruptionDefaults();

/// Options of LoadEpflTerrace.
struct EpflOptions {
  /// The detector model applied to the annotated boxes (CorruptionOptions::Clean(): the boxes as
  /// annotated). Default: EpflCorruptionDefaults().
  CorruptionOptions corruption = EpflCorruptionDefaults();
  /// The person-height prior the floor unit is estimated from, m.
  double person_height_m = 1.7;
  /// Metres per floor unit; nullopt: estimated from the person-height prior.
  std::optional<double> floor_unit_m;

  /// Valid corruption, person_height_m finite and in (0, 3], floor_unit_m (when given) finite
  /// and > 0. On failure writes the reason to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// How LoadEpflTerrace calibrated the cameras.
struct EpflCalibration {
  /// The image -> floor homographies of Homography.txt, camera order.
  std::vector<Mat3> homographies;
  /// The recovered cameras with their checks, at floor_unit_m, camera order.
  std::vector<geometry::FloorHomographyCamera> cameras;
  /// Person heights from the annotated boxes, in floor units (cameras at 1 unit = 1 m), with
  /// the prior's unit (ok false when no box could be used and the unit was given).
  geometry::PersonHeightEstimate person_height;
  /// Metres per floor unit: given, or person_height.unit_m.
  double floor_unit_m = 0.0;
  bool unit_estimated = false;
  /// Whether the floor's y axis is mirrored (world y = -floor y), as for every camera.
  bool mirrored_y = false;
};

/// Loads Terrace 1 from `data_root`/epfl/terrace1/terrace1-c{0..3}:
///  - cameras: ids 0..3 (c0..c3), 360x288, from Homography.txt by CameraFromFloorHomography
///    (square pixels, principal point at the image centre, focal length from the homography,
///    refined with R and t on the floor reprojection error),
///    floor unit from options (default: estimated by EstimateFloorUnitFromPersonHeight with
///    options.person_height_m over every annotated box); the world is the floor frame in metres
///    with y mirrored when the cameras need it (then for ground truth too), z up;
///  - frames: every frame from the first to the last with an annotated person (gt.txt rows with
///    lost = 0), consecutive, 25 fps;
///  - detections: every gt.txt row with lost = 0 as a box-only Detection2D (layout kNone, score
///    1), box [xmin, xmax] x [ymin, ymax] clipped to the image (boxes left narrower or lower than
///    2 px dropped), ordered by person id; then options.corruption (false-positive pool: the
///    camera's clean boxes; blackout inside the frames); source ids = person ids;
///  - ground truth: per frame, each person annotated in some camera at the mean floor point of
///    its box bottom centres (xmin + xmax) / 2, ymax mapped by those cameras' homographies,
///    leaving out boxes whose bottom is cut by the image border (ymax >= 287) unless all are;
///    metres, z = 0, id = the person id (0..8), no joints (gt_layout kNone);
///  - protocol: all the frames, all the people; notes with the unit, the person heights and the
///    per-camera checks.
/// `calibration`, when not null, receives how the cameras were made.
/// @throws DatasetError on a missing or malformed file, a camera that cannot be recovered, or
///   invalid options.
Dataset LoadEpflTerrace(const std::filesystem::path& data_root,
                        const EpflOptions& options = {},
                        EpflCalibration* calibration = nullptr);

}  // namespace mvtrack::datasets
