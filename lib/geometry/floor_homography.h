#pragma once
/// @file
/// A full pinhole camera from an image -> floor homography, for datasets and installations
/// whose only calibration is one such homography per camera (EPFL's Homography.txt).
///
/// H maps an image pixel (u, v, 1) to a floor point (x, y, 1) in some floor unit (dehomogenise).
/// For a pinhole camera K [R | t] looking at the floor plane z = 0, H⁻¹ = s K [r1 r2 t] for some
/// scale s (Zhang, "A flexible new technique for camera calibration", TPAMI 2000, section 2.3).
/// Assumed: square pixels (fx = fy = f), zero skew, no lens distortion, the principal point at
/// the image centre (or given). The focal length is the least-squares solution in w = 1/f² of
/// the two constraints of the homography on the rotation, r1 . r2 = 0 and |r1|² = |r2|² (Zhang's
/// eqs. 3-4 with the image of the absolute conic diag(w, w, 1) after moving the principal point
/// to the origin), or given. Then r1, r2 are scaled by 2 / (|r1| + |r2|), r3 = r1 x r2, and R is
/// the nearest rotation (SVD) of [r1 r2 r3]. Last, R, t and (when it was estimated) f are refined
/// by Levenberg-Marquardt to minimise the floor reprojection error over a grid of 11 x 11 pixels
/// (Zhang's section 3.2): a homography is 8 numbers and this camera 7, so the closed form leaves
/// a residual, which the refinement spreads over the image instead of letting the
/// orthonormalisation put it anywhere (EPFL Terrace's camera 3: median floor reprojection error
/// 12.1 px closed-form, 1.7 px refined; tracking its annotated boxes, MOTA 88.7 -> 92.8 %,
/// IDF1 63.5 -> 70.8 % at 0.5 m).
///
/// Signs and handedness: H is defined up to a scale of either sign. The sign is chosen so that
/// most of the image (a grid of 11 x 11 pixels over it) sees floor points in front of the camera
/// (positive depth), i.e. the camera looks at the floor. The world's z axis points up, to the
/// camera's side of the floor. When (x, y) with z up is a left-handed frame, the floor's y axis is
/// mirrored (world y = -floor y), so that the world is right-handed with z up; the result says
/// so (`mirrored_y`), and a rig's cameras must agree on it (one floor frame).
///
/// Units: world metres = floor_unit_m x floor units. EstimateFloorUnitFromPersonHeight estimates
/// floor_unit_m from boxes of standing people and a person-height prior.
///
/// Pure functions (no I/O, no exceptions): failures are a `reason` in the result. Stateless;
/// thread-compatible.

#include <optional>
#include <string>
#include <vector>

#include "core/detection.h"
#include "core/types.h"
#include "geometry/camera_model.h"

namespace mvtrack::geometry {

/// Options of CameraFromFloorHomography.
struct FloorHomographyOptions {
  /// Metres per floor unit (> 0, finite).
  double floor_unit_m = 1.0;
  /// The focal length in pixels (> 0); nullopt: estimated from the homography.
  std::optional<double> focal_px;
  /// The principal point in pixels; nullopt: the image centre (width / 2, height / 2).
  std::optional<Vec2> principal_point_px;

  /// floor_unit_m finite and > 0, focal_px (when given) finite and > 0, principal_point_px
  /// (when given) finite. On failure writes the reason to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// The camera recovered from one homography, with the checks a user can read.
struct FloorHomographyCamera {
  /// False when no camera could be recovered; `reason` then says why.
  bool ok = false;
  std::string reason;
  /// The camera: K = [f 0 cx; 0 f cy; 0 0 1], no distortion, cam_from_world in metres, world z
  /// up with the floor at z = 0 (valid by CameraModel::Validate when ok).
  CameraModel camera;
  /// Whether f was estimated from the homography (false: given).
  bool focal_estimated = false;
  /// The focal length, pixels: given, or estimated and refined.
  double focal_px = 0.0;
  /// The closed-form focal length before the refinement (the given one when given), pixels.
  double initial_focal_px = 0.0;
  /// Whether the floor's y axis was mirrored (world y = -floor y) to make the world frame
  /// right-handed with z up.
  bool mirrored_y = false;
  /// How far the homography is from a rotation's first two columns at the initial focal length,
  /// before orthonormalisation: max(|r1 . r2|, ||r1| - |r2||) with r1, r2 scaled to a mean norm
  /// of 1 (0 for a homography made by a camera of this model).
  double orthogonality_residual = 0.0;
  /// Height of the camera centre above the floor, m.
  double height_m = 0.0;
  /// Horizontal and vertical fields of view, degrees (from the principal point to each edge).
  double horizontal_fov_deg = 0.0;
  double vertical_fov_deg = 0.0;
  /// Floor reprojection error (what the refinement minimised): the grid pixels that see the
  /// floor in front of the camera are mapped to the floor by H and projected back by the camera;
  /// median and maximum distance to the pixel they came from, pixels; `floor_check_points` of the
  /// 121 grid pixels were used.
  double floor_reprojection_median_px = 0.0;
  double floor_reprojection_max_px = 0.0;
  int floor_check_points = 0;
};

/// Recovers camera `id` (image `width_px` x `height_px`) from `image_to_floor` under the
/// assumptions of this file. Fails (ok false, with the reason) on non-finite or singular H
/// (smallest singular value below 1e-12 of the largest), an invalid image size or options, a
/// homography whose constraints give no positive 1/f² (give the focal length), or one that
/// does not determine f (image plane parallel to the floor: give the focal length), a camera in
/// the floor plane, no grid pixel seeing the floor in front of the camera, and a camera that
/// fails CameraModel::Validate.
FloorHomographyCamera CameraFromFloorHomography(const Mat3& image_to_floor,
                                                CameraId id,
                                                int width_px,
                                                int height_px,
                                                const FloorHomographyOptions& options = {});

/// The floor point (floor units) of an image pixel: H (u, v, 1) dehomogenised. nullopt when the
/// third coordinate is (nearly) 0 (the pixel is on the horizon) or the result is not finite.
/// The point may be behind the camera (pixels above the horizon).
std::optional<Vec2> ImageToFloor(const Mat3& image_to_floor, const Vec2& pixel);

/// The world point (metres, z = 0) of a floor point in floor units: floor_unit_m (x, ±y, 0),
/// with y negated when `mirrored_y`.
Vec3 FloorToWorld(const Vec2& floor_point, double floor_unit_m, bool mirrored_y);

/// Boxes of one camera for EstimateFloorUnitFromPersonHeight.
struct PersonBoxes {
  /// The camera (its world unit is what the estimate measures heights in).
  CameraModel camera;
  /// Boxes of standing people seen by this camera, raw pixels (undistorted with the camera's
  /// model).
  std::vector<core::BoxPx> boxes;
};

/// The result of EstimateFloorUnitFromPersonHeight.
struct PersonHeightEstimate {
  /// False when no box could be used; `reason` then says why.
  bool ok = false;
  std::string reason;
  /// Person heights in the cameras' world unit: median, 10th and 90th percentiles (linear
  /// interpolation between order statistics).
  double median_height = 0.0;
  double p10_height = 0.0;
  double p90_height = 0.0;
  /// Boxes used (top and bottom inside the image, a valid height) and boxes given.
  int boxes_used = 0;
  int boxes_total = 0;
  /// person_height_m / median_height: metres per world unit of the cameras.
  double unit_m = 0.0;
};

/// Estimates the metres per world unit of `cameras` (floor at z = 0, z up, e.g. from
/// CameraFromFloorHomography with floor_unit_m = 1) from boxes of standing people and the prior
/// that a person is `person_height_m` tall (e.g. 1.7). For every box whose top and bottom are
/// inside the image (y_min >= 1 and y_max <= height - 2: not cut by the image border), the
/// bottom centre is back-projected to the floor (the feet), and the person's height is where
/// the ray through the top centre passes over the feet (the point of that ray horizontally
/// closest to the vertical through the feet). Heights that are not positive and finite are not
/// used. unit_m = person_height_m / the median height. Fails (ok false) when person_height_m is
/// not finite and positive or no box can be used.
PersonHeightEstimate EstimateFloorUnitFromPersonHeight(const std::vector<PersonBoxes>& cameras,
                                                       double person_height_m);

}  // namespace mvtrack::geometry
