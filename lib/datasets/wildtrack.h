#pragma once
/// @file
/// WILDTRACK (Chavdarova et al., CVPR 2018): 7 cameras (1920x1080), the official calibration,
/// and MVDeTr's detections of the 40 test frames 360..399 drawn as boxes into every view. No
/// ground truth is available. Files and formats: `<data_root>/wildtrack/SOURCE.md`. Stateless.

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
///  - no ground truth (gt_layout kNone, empty ground_truth).
/// @throws DatasetError on a missing or malformed file.
Dataset LoadWildtrack(const std::filesystem::path& data_root);

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
