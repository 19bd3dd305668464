#pragma once
/// @file
/// `mvtrack calib check`: sanity checks of a calibration and the camera overlap analysis (which
/// camera pairs can triangulate which floor area), as data; the CLI prints it and lib/viz draws
/// it. Stateless functions; pure computation (no I/O).
///
/// Coverage: the floor region is sampled on a grid of `cell_m` cells, each at height
/// `sample_height_m` (a standing person's torso, the part every layout triangulates). A camera
/// sees a sample when it is in front of the camera, its projection with lens distortion lies in
/// the image, and its pinhole projection lies in the image enlarged by 25 % on every side (so a
/// distortion polynomial folding far-away points back into the image does not count).
///
/// Short baseline (the paper's failure case 2, Sec. "limitations" / failure-case figure: "when
/// two cameras are very close to each other, the triangulation bias will be significantly
/// increased"): for a camera pair, the triangulation angle at a sample is the angle between the
/// two viewing lines, in [0°, 90°] (rays meeting at 170° are as ill-conditioned as at 10°:
/// cameras facing each other across the point); the pair is flagged when the median angle over
/// the samples both cameras see is below `min_triangulation_angle_deg` (default 10°). For a point
/// at distance d from two cameras a baseline b apart the angle is about b / d radians, so 10° is b
/// / d < 0.17; the depth error of a triangulated point grows like d² σ / (f b), i.e. like 1 /
/// angle. Failure case 1 (a place only one camera sees) is reported as the single-view area.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/types.h"
#include "geometry/camera_model.h"

namespace mvtrack::config {

/// An axis-aligned rectangle of the floor (world x, y; metres).
struct FloorRegion {
  double x_min_m = 0.0;  ///< west edge
  double y_min_m = 0.0;  ///< south edge
  double x_max_m = 0.0;  ///< east edge
  double y_max_m = 0.0;  ///< north edge
  /// Extent along x, metres.
  double width_m() const { return x_max_m - x_min_m; }
  /// Extent along y, metres.
  double depth_m() const { return y_max_m - y_min_m; }
};

/// Options of CheckCalibration.
struct CalibrationCheckOptions {
  /// The floor region to sample; nullopt = DefaultFloorRegion(cameras, sample_height_m, margin).
  std::optional<FloorRegion> region;
  /// Margin added around the default region, metres.
  double margin_m = 1.0;
  /// Grid cell size, metres; enlarged automatically so the grid has at most kMaxCells cells.
  double cell_m = 0.1;
  /// Height of the sampled points above the floor (z = 0), metres.
  double sample_height_m = 1.0;
  /// A pair whose median triangulation angle is below this is a short-baseline pair, degrees.
  double min_triangulation_angle_deg = 10.0;
  /// Largest number of grid cells.
  static constexpr std::int64_t kMaxCells = 1'000'000;
  /// region (if set) non-empty and finite, margin_m >= 0, cell_m > 0, sample_height_m finite,
  /// min_triangulation_angle_deg in (0, 90). On failure writes the reason to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// Per-camera results.
struct CameraCheck {
  CameraId id = 0;                  ///< the camera
  Vec3 center_m = Vec3::Zero();     ///< camera centre in the world
  double horizontal_fov_deg = 0.0;  ///< 2 atan(width / 2 fx)
  double vertical_fov_deg = 0.0;    ///< 2 atan(height / 2 fy)
  /// Angle of the optical axis below the horizontal (90 = looking straight down), degrees.
  double pitch_down_deg = 0.0;
  /// Floor area (at sample height) the camera sees within the region, m².
  double seen_area_m2 = 0.0;
  /// Largest |DistortPixel(UndistortPixel(c)) - c| over the image corners and edge midpoints,
  /// pixels (0 without distortion): how well the distortion model inverts over the image.
  double distortion_roundtrip_px = 0.0;
  /// Problems found (human-readable, one per entry); empty when the camera looks sane.
  std::vector<std::string> warnings;
};

/// Per-pair results (every pair of cameras, a < b by position in the input).
struct PairCheck {
  CameraId a = 0;               ///< first camera of the pair
  CameraId b = 0;               ///< second camera of the pair
  double baseline_m = 0.0;      ///< distance between the camera centres
  double common_area_m2 = 0.0;  ///< floor area both cameras see
  /// Medians over the common samples (0 when there are none): mean distance of the sample to
  /// the two centres, and the triangulation angle.
  double median_distance_m = 0.0;
  double median_angle_deg = 0.0;  ///< see median_distance_m
  /// common_area_m2 > 0 and median_angle_deg < min_triangulation_angle_deg.
  bool short_baseline = false;
};

/// The sampled floor grid. Cell (col, row) covers x in [x_min + col cell, + cell), y in
/// [y_min + row cell, + cell); its sample is the cell centre at sample_height_m.
struct CoverageGrid {
  FloorRegion region;   ///< the sampled region
  double cell_m = 0.0;  ///< cell side, metres
  int cols = 0;         ///< cells along x
  int rows = 0;         ///< cells along y
  /// Per cell (index row * cols + col): how many cameras see it.
  std::vector<int> view_count;
  /// Per cell: the largest triangulation angle over the pairs of cameras that see it, degrees
  /// (0 when fewer than two cameras see it).
  std::vector<double> best_angle_deg;
  /// The world point sampled for a cell.
  Vec3 CellCenter(int col, int row, double sample_height_m) const;
};

/// The whole check.
struct CalibrationReport {
  CalibrationCheckOptions options;  ///< as used (region filled in)
  CoverageGrid grid;
  std::vector<CameraCheck> cameras;  ///< in input order
  std::vector<PairCheck> pairs;      ///< every pair, in input order (0-1, 0-2, ..., 1-2, ...)
  double area_unseen_m2 = 0.0;       ///< region area no camera sees
  double area_single_view_m2 = 0.0;  ///< seen by exactly one camera (no triangulation)
  /// Seen by two or more cameras but every pair there has a triangulation angle below the
  /// minimum.
  double area_weak_m2 = 0.0;
  double area_triangulable_m2 = 0.0;  ///< seen by a pair with a large enough angle
  /// Rig-level problems (units, duplicate centres, flagged pairs, single-view area, cameras
  /// sharing no floor with another).
  std::vector<std::string> warnings;
  /// The subset of `warnings` that means tracking cannot work as calibrated (units, duplicate
  /// centres, a world z pointing down, a camera sharing no floor): what replay and the daemon
  /// print at load. Short baselines and single-view areas are normal at a rig's edges.
  std::vector<std::string> load_warnings;
  /// Total number of warnings (rig + cameras).
  std::size_t WarningCount() const;
};

/// The default floor region: the bounding box of the camera centres and of the points where
/// each optical axis meets the plane z = sample_height_m (when it does, within max(10 m, the
/// diagonal of the centres' bounding box) of the camera), grown by `margin_m`. Cameras must be
/// valid and non-empty.
FloorRegion DefaultFloorRegion(const std::vector<geometry::CameraModel>& cameras,
                               double sample_height_m,
                               double margin_m);

/// Runs all checks. `cameras` must be valid (CameraModel::Validate) and non-empty, `options`
/// valid (both checked; aborts otherwise: call Validate on untrusted options).
CalibrationReport CheckCalibration(const std::vector<geometry::CameraModel>& cameras,
                                   const CalibrationCheckOptions& options = {});

/// The checks a program runs when it loads a calibration to track with (`mvtrack replay`,
/// `mvtrackd`): CheckCalibration on a 0.5 m grid (fast enough at start-up: about 0.1 s for 32
/// cameras), its load_warnings and each camera's warnings, prefixed "camera <id>: ". Empty when
/// the rig looks sane. `cameras` as for CheckCalibration.
std::vector<std::string> CalibrationLoadWarnings(const std::vector<geometry::CameraModel>& cameras);

}  // namespace mvtrack::config
