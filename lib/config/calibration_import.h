#pragma once
/// @file
/// Importers of the calibration formats integrators already have, into our calibration
/// (`mvtrack.calibration/1`, calibration.h): world frame in metres, cam_from_world extrinsics,
/// OpenCV pixels and distortion. Each format, its units and how it is mapped is specified in
/// docs/FORMATS.md ("Calibration importers"):
///
///  - OpenCV FileStorage YAML/XML, EasyMocap's `intri.yml` + `extri.yml` pair (`names`, `K_<c>`,
///    `dist_<c>`, `R_<c>` Rodrigues and/or `Rot_<c>` 3x3, `T_<c>` metres; optional `H_<c>`,
///    `W_<c>`), read with cv::FileStorage;
///  - 4D Association's calibration.json and CMU Panoptic's calibration_<seq>.json, and WILDTRACK's
///    derived JSON, parsed by lib/datasets (datasets/calibration_files.h: one parser per format);
///  - VoxelPose's calibration_<dataset>.json (`R`, `T` = camera centre in mm, `fx fy cx cy`, `k`,
///    `p`);
///  - WILDTRACK's calibration XML files (`intrinsic_zero/intr_<name>.xml` with `camera_matrix`
///    and `distortion_coefficients`, `extrinsic/extr_<name>.xml` with `rvec`, `tvec` in cm);
///  - image -> floor homographies, one 3x3 text file per camera (EPFL's Homography.txt), made
///    into full cameras under stated assumptions (geometry/floor_homography.h).
///
/// Every importer validates every camera (geometry::CameraModel::Validate) and throws ConfigError
/// naming the file, the entry and the reason. Stateless functions; thread-compatible.

#include <optional>
#include <string>
#include <vector>

#include "config/calibration.h"
#include "config/config_error.h"
#include "core/types.h"
#include "geometry/floor_homography.h"

namespace mvtrack::config {

/// An imported calibration: the cameras (ids and optional names) and notes for people on the
/// conventions that were applied (units, axes, what was assumed).
struct ImportedCalibration {
  CalibrationDocument document;    ///< the cameras and their names
  std::vector<std::string> notes;  ///< one sentence per convention applied
};

/// An image size given on the command line when the source format does not carry one.
struct ImageSize {
  int width_px = 0;   ///< 0 = not given
  int height_px = 0;  ///< 0 = not given
  /// True when both sides are given (> 0).
  bool given() const { return width_px > 0 && height_px > 0; }
};

/// Parses "WIDTHxHEIGHT" (e.g. "1920x1080"; both 1..1048576).
/// @throws ConfigError with `source_name` as the file when the text is not such a size.
ImageSize ParseImageSize(const std::string& text, const std::string& source_name);

/// EasyMocap's intri.yml / extri.yml (OpenCV FileStorage; YAML `%YAML:1.0` with
/// `!!opencv-matrix`, or the same keys in FileStorage XML). Cameras are the `names` of
/// intri.yml, in that order; a camera id is the name's decimal value when every name is a
/// decimal integer (e.g. "01" -> 1), else the position in `names` (0, 1, ...); the name is kept
/// either way. K 3x3; dist 4, 5 or 8 values (k1 k2 p1 p2 [k3 [k4 k5 k6]]; k4..k6 must be 0, the
/// rational model is not supported); `Rot_<c>` (3x3) or, when absent, `R_<c>` (Rodrigues 3x1);
/// when both are present they must agree to 1e-6; `T_<c>` 3x1 in metres; image size from `W_<c>`
/// and `H_<c>` when present, else `image_size` (required then).
/// @throws ConfigError on unreadable files, FileStorage syntax errors, missing or malformed
///   entries, names missing from extri.yml, or an invalid camera.
ImportedCalibration ImportEasyMocap(const std::string& intri_path,
                                    const std::string& extri_path,
                                    const ImageSize& image_size = {});

/// 4D Association's calibration.json (`K`, `RT` world->camera in metres, `imgSize`).
/// @throws ConfigError (wrapping the dataset parser's error) on any problem.
ImportedCalibration ImportFourDAssociation(const std::string& path);

/// VoxelPose's calibration JSON: an object of cameras keyed by decimal ids with `R` (3x3,
/// world->camera rotation), `T` (3x1, the camera centre in millimetres: x_cam = R (X - T)),
/// `fx`, `fy`, `cx`, `cy`, `k` (3 radial: k1 k2 k3) and `p` (2 tangential: p1 p2). The files
/// carry no image size, so `image_size` is required (Shelf 1032x776, Campus 360x288). A
/// rotation printed with few decimals (max|RᵀR - I| <= 1e-4, det > 0) is replaced by the
/// nearest rotation (SVD), with a note; a farther one is an error.
/// @throws ConfigError on a syntax error, unknown or missing keys, or an invalid camera.
ImportedCalibration ImportVoxelPose(const std::string& path, const ImageSize& image_size);

/// CMU Panoptic's calibration_<sequence>.json: the HD cameras in `cameras` ("00_xx" or "0".."30";
/// empty = all HD cameras), world rotated to z up and scaled cm -> m as `mvtrack convert
/// panoptic` does; names "00_xx".
/// @throws ConfigError on any problem.
ImportedCalibration ImportPanoptic(const std::string& path,
                                   const std::vector<std::string>& cameras);

/// WILDTRACK: `path` is either the derived JSON (a file; see datasets/calibration_files.h) or a
/// directory holding the official XML files, either `calibrations/` itself or its parent: the
/// cameras are the `intrinsic_zero/intr_<name>.xml` files with a matching
/// `extrinsic/extr_<name>.xml`, in the dataset's order C1..C7 (CVLab1..4, IDIAP1..3) when the
/// names are those, else sorted by name; ids 0, 1, ...; tvec in cm -> m. The XML files carry no
/// image size: `image_size` when given, else WILDTRACK's 1920x1080.
/// @throws ConfigError on missing files, malformed XML or an invalid camera.
ImportedCalibration ImportWildtrack(const std::string& path, const ImageSize& image_size = {});

/// Cross-View Tracking's Campus calibration.json (see datasets/calibration_files.h); the file
/// has no image size: `image_size` when given, else Campus's 360x288.
/// @throws ConfigError on any problem.
ImportedCalibration ImportCampus(const std::string& path, const ImageSize& image_size = {});

/// Options of ImportFloorHomographies.
struct HomographyImportOptions {
  /// The image size of every camera (required: the files carry none).
  ImageSize image_size;
  /// Metres per floor unit; nullopt: 1 (the floor unit taken as the metre, said in a note).
  std::optional<double> floor_unit_m;
  /// The focal length of every camera, pixels; nullopt: estimated per camera from its
  /// homography.
  std::optional<double> focal_px;
  /// The principal point of every camera, pixels; nullopt: the image centre.
  std::optional<Vec2> principal_point_px;
};

/// The result of ImportFloorHomographies: the calibration, and per camera (the order of the
/// files) the recovered camera with the checks to show a user.
struct ImportedHomographies {
  ImportedCalibration calibration;
  std::vector<geometry::FloorHomographyCamera> checks;
};

/// Image -> floor homographies, one file per camera (3 rows of 3 numbers, H (u, v, 1) = (x, y,
/// 1) up to scale: datasets::LoadFloorHomographyFile), made into cameras by
/// geometry::CameraFromFloorHomography (square pixels, zero skew, no distortion, principal point
/// at the image centre unless given, focal length from each homography unless given; the sign
/// that puts the floor in front of the camera, world z up, the floor's y mirrored when (x, y)
/// with z up is left-handed). Camera ids 0..n-1 in the order of `paths`, no names. Notes state
/// the assumptions, the unit, the mirroring and each camera's focal length.
/// @throws ConfigError naming the file and the camera on a missing or malformed file, no image
///   size, invalid options, a homography that gives no camera (non-finite, singular, no
///   positive focal length, ...), or cameras that disagree on the mirroring (then the files do
///   not share one floor frame).
ImportedHomographies ImportFloorHomographies(const std::vector<std::string>& paths,
                                             const HomographyImportOptions& options);

}  // namespace mvtrack::config
