#pragma once
/// @file
/// WILDTRACK (Chavdarova et al., CVPR 2018): 7 cameras (1920x1080), the official calibration,
/// MVDeTr's detections of the 40 test frames 360..399 drawn as boxes into every view, and the
/// ground-truth floor positions of the 400 annotated frames (MVDet's gt.txt: positions without
/// person ids). Files and formats: `<data_root>/wildtrack/SOURCE.md`. Stateless.

#include <filesystem>
#include <string>
#include <vector>

#include "core/types.h"
#include "datasets/corruption.h"
#include "datasets/dataset.h"

namespace mvtrack::datasets {

/// Loads WILDTRACK from `data_root`/wildtrack:
///  - cameras: derived/calibration_wildtrack.json (K = intrinsic_zero, R = Rodrigues(rvec),
///    t = tvec cm -> m, ground plane z = 0, 1920x1080, no distortion), ids 0..6 (C1..C7);
///  - frames: the annotated-frame indices 360..399 of rest/MVDeTr_test.json (image files
///    5 * index), 2 fps;
///  - detections: every [left, top, width, height, -1, cam] entry as a box-only Detection2D
///    (layout kNone), box [left, left + width] x [top, top + height], score 1; source ids are
///    kUnknownSourceId;
///  - ground truth: WildtrackGroundTruth of the detection frames (no joints, gt_layout kNone;
///    ids are per-frame position indices, not person ids), when mvdet/gt.txt exists; else empty.
///  - then `corruption` (clean by default: the boxes as they are; corruption.h, the blackout
///    placed inside the frames), e.g. misses to see what missing boxes cost.
/// @throws DatasetError on a missing or malformed file; std::invalid_argument on invalid
/// corruption options.
Dataset LoadWildtrack(const std::filesystem::path& data_root,
                      const CorruptionOptions& corruption = CorruptionOptions::Clean());

/// Where the detections of LoadWildtrackAnnotated come from.
struct WildtrackAnnotatedOptions {
  /// Annotated frames first..last (annotated-frame indices 0..399, image file = 5 x index).
  FrameIndex first = 360;
  FrameIndex last = 399;
  /// The detector model applied to the annotated boxes (box-only detections: box noise, misses,
  /// false positives; corruption.h). Disabled: the boxes as annotated.
  CorruptionOptions corruption = CorruptionOptions::Clean();

  /// 0 <= first <= last <= 399 and valid corruption. On failure writes the reason to `why`.
  bool Validate(std::string* why) const;
};

/// The corruption defaults for WILDTRACK's annotated boxes: the Campus defaults (box noise
/// scales with the box, corruption.h), the blackout placed in the converted frames.
CorruptionOptions WildtrackCorruptionDefaults();

/// Loads WILDTRACK with the annotated per-view boxes of `<data_root>`/wildtrack/opentraj (the
/// original annotations with person ids) as the detections:
///  - cameras as LoadWildtrack;
///  - frames: annotated frames options.first..last (2 fps);
///  - detections: each person's box in each view where it is annotated (not -1), clipped to the
///    image (boxes left narrower or lower than 2 px dropped), box-only, score 1, in file order,
///    then options.corruption (blackout placed inside the frames); source ids = person ids;
///  - ground truth: WildtrackGroundTruthWithIds of the same frames.
/// @throws DatasetError on a missing or malformed file; std::invalid_argument on invalid options.
Dataset LoadWildtrackAnnotated(const std::filesystem::path& data_root,
                               const WildtrackAnnotatedOptions& options);

/// Ground truth with person ids of annotated frames `first`..`last` from
/// `<data_root>`/wildtrack/opentraj/annotations_positions (one JSON file per annotated frame,
/// image index 5 k): one EvalFrame per frame (also frames without people), object id =
/// personID, position from positionID on the 480 x 1440 grid (x = -3 + 0.025 (id mod 480),
/// y = -9 + 0.025 (id div 480), z = 0), objects in file order.
/// @throws DatasetError on a missing or malformed file (a position outside the grid, a person
/// twice in a frame) or a range outside 0..399.
eval::EvalSequence WildtrackGroundTruthWithIds(const std::filesystem::path& data_root,
                                               FrameIndex first,
                                               FrameIndex last);

/// Whether `<data_root>`/wildtrack/opentraj/annotations_positions exists.
bool HasWildtrackAnnotations(const std::filesystem::path& data_root);

/// The floor area WILDTRACK annotates (its 480 x 1440 grid of 2.5 cm cells from (-3, -9) m):
/// x in [-3, 9) m, y in [-9, 27) m. Positions outside are never annotated.
struct WildtrackArea {
  static constexpr double kMinX = -3.0;
  static constexpr double kMaxX = 9.0;
  static constexpr double kMinY = -9.0;
  static constexpr double kMaxY = 27.0;
};

/// Ground-truth floor positions of the annotated frames `first`..`last` (annotated-frame
/// indices 0..399, image file = 5 x index) from `<data_root>`/wildtrack/mvdet/gt.txt: rows
/// `image_frame grid_x grid_y` (integers), position x = -3 + 0.025 grid_x m, y = -9 + 0.025
/// grid_y m, z = 0 (SOURCE.md). One EvalFrame per annotated frame in the range (also frames
/// without people), objects in file order with id = their index within the frame (gt.txt has no
/// person ids: detection metrics only). The range must lie within the file's frames.
/// @throws DatasetError on a missing or malformed file (a non-integer field, an image frame
/// that is not a multiple of 5, a cell outside the grid) or a range outside the file.
eval::EvalSequence WildtrackGroundTruth(const std::filesystem::path& data_root,
                                        FrameIndex first,
                                        FrameIndex last);

/// Whether `<data_root>`/wildtrack/mvdet/gt.txt exists.
bool HasWildtrackGroundTruth(const std::filesystem::path& data_root);

/// Options of WildtrackGroundPoints.
struct WildtrackGroundOptions {
  /// Clusters of ground points are merged while their means are at most this far apart, m.
  double cluster_radius_m = 0.3;

  /// cluster_radius_m finite and >= 0. On failure writes the reason to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// One ground point: MVDeTr's estimate of one person's position.
struct WildtrackGroundPoint {
  Vec3 position_m = Vec3::Zero();  ///< on the ground, z = 0
  int num_views = 0;               ///< boxes merged into it (one per camera at most)
};

/// The de-duplicated ground points of one frame.
struct WildtrackGroundFrame {
  FrameIndex frame = 0;
  std::vector<WildtrackGroundPoint> points;
};

/// MVDeTr's ground points per frame, for the footprint comparison: the bottom centre
/// (left + width / 2, top + height) of every box is mapped to the ground by the inverse of the
/// camera's homography in rest/metainfo.json (ground cm -> pixels), cm -> m; then, per frame,
/// the points are clustered agglomeratively: starting from single points, the two clusters
/// with the closest means are merged while that distance is <= cluster_radius_m and the two
/// clusters share no camera (each view draws a person once); ties go to the lowest indices in
/// file order. Each cluster's mean is one ground point. Points are sorted by x, then y.
/// @throws DatasetError on a missing or malformed file, or invalid options.
std::vector<WildtrackGroundFrame> WildtrackGroundPoints(const std::filesystem::path& data_root,
                                                        const WildtrackGroundOptions& options = {});

/// WildtrackGroundPoints of the boxes in `detections` ([frame][camera index], as
/// Dataset::detections; e.g. MVDeTr's boxes after a corruption model) instead of the file's.
/// @throws DatasetError on a missing or malformed homography file, or invalid options.
std::vector<WildtrackGroundFrame> WildtrackGroundPoints(
    const std::filesystem::path& data_root,
    const std::vector<std::vector<core::CameraFrame>>& detections,
    const WildtrackGroundOptions& options = {});

/// The clustering step of WildtrackGroundPoints on one frame: `points_m[i]` seen by camera
/// `cameras[i]` (0..63). Starting from single points, the two clusters with the closest means
/// are merged while that distance is <= radius_m and they share no camera; ties go to the
/// cluster pair with the lowest indices (clusters ordered by their first point). Returns the
/// cluster means (z = 0) with their sizes, sorted by x, then y. O(n^2) memory, about O(n^2)
/// time.
std::vector<WildtrackGroundPoint> MergeGroundPoints(const std::vector<Vec2>& points_m,
                                                    const std::vector<int>& cameras,
                                                    double radius_m);

/// The image-from-ground homographies of rest/metainfo.json (7 matrices, ground (x, y, 1) in
/// cm -> homogeneous pixels), in camera order.
/// @throws DatasetError on a missing or malformed file.
std::vector<Mat3> WildtrackHomographies(const std::filesystem::path& data_root);

}  // namespace mvtrack::datasets
