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
/// @throws DatasetError on a missing or malformed file.
Dataset LoadWildtrack(const std::filesystem::path& data_root);

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
