#pragma once
/// @file
/// The calibration file format `mvtrack.calibration/1` (YAML; JSON files work too, JSON being
/// valid YAML): camera intrinsics, OpenCV distortion and cam_from_world extrinsics in metres.
/// The format is specified key by key in docs/FORMATS.md ("Calibration file"); an example rig
/// is docs/examples/calibration.example.yaml.
///
/// Loading is strict: unknown, missing or duplicate keys, wrong types, non-finite numbers,
/// duplicate camera ids and cameras that fail geometry::CameraModel::Validate are ConfigErrors
/// naming the file, the line and the key path. Stateless functions; thread-compatible.

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "config/config_error.h"
#include "core/types.h"
#include "geometry/camera_model.h"

namespace mvtrack::config {

/// The value of the mandatory top-level `format` key.
inline constexpr std::string_view kCalibrationFormat = "mvtrack.calibration/1";

/// A parsed calibration file: the cameras in file order and their optional names.
struct CalibrationDocument {
  /// Cameras in the order of the file (geometry::CameraRig sorts them by id).
  std::vector<geometry::CameraModel> cameras;
  /// The optional `name` of each camera that has one, by camera id.
  std::map<CameraId, std::string> names;
};

/// Parses calibration text; `source_name` (usually the path) is used in error messages.
/// @throws ConfigError on any syntax or content error.
CalibrationDocument ParseCalibrationDocument(std::string_view text, const std::string& source_name);
/// Reads and parses the calibration file at `path`.
/// @throws ConfigError when the file is missing or unreadable, or on any content error.
CalibrationDocument LoadCalibrationDocument(const std::string& path);

/// The cameras of ParseCalibrationDocument (names dropped).
/// @throws ConfigError as ParseCalibrationDocument.
std::vector<geometry::CameraModel> ParseCalibration(std::string_view text,
                                                    const std::string& source_name);
/// The cameras of LoadCalibrationDocument (names dropped).
/// @throws ConfigError as LoadCalibrationDocument.
std::vector<geometry::CameraModel> LoadCalibration(const std::string& path);

/// Canonical `mvtrack.calibration/1` text: cameras in ascending id order, each with `id`,
/// `name` (when `names` has one), `image_size`, `K` (3x3), `distortion` (5 values, always
/// written), `R` (3x3) and `t`; every real in the shortest decimal form that reads back to the
/// same double, so ParseCalibration(CalibrationToYaml(c)) reproduces `c` bit for bit (sorted by
/// id). The same cameras always give the same text (usable as a hash input). The cameras are
/// written as they are; SaveCalibration validates first.
std::string CalibrationToYaml(const std::vector<geometry::CameraModel>& cameras,
                              const std::map<CameraId, std::string>& names = {});

/// Writes CalibrationToYaml(cameras, names) to `path` (atomically: temporary file + rename).
/// @throws ConfigError naming `path` when a camera fails CameraModel::Validate, two cameras
/// share an id, there are no cameras, or the file cannot be written.
void SaveCalibration(const std::string& path,
                     const std::vector<geometry::CameraModel>& cameras,
                     const std::map<CameraId, std::string>& names = {});

}  // namespace mvtrack::config
