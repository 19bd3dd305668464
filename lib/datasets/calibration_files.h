#pragma once
/// @file
/// The calibration parsers of the dataset loaders, on their own: each reads one dataset's
/// calibration file into cameras in our world frame (metres, z up, cam_from_world), exactly as
/// the loaders do (LoadShelf, LoadCampus, LoadPanoptic, LoadWildtrack call the same code). Used by
/// `mvtrack calib import` (lib/config/calibration_import.h) so the parsing exists once. The
/// floor homography file (EPFL) is read by LoadEpflTerrace and `calib import homography`.
/// Formats: the `SOURCE.md` of each dataset folder. Stateless functions.

#include <filesystem>
#include <string>
#include <vector>

#include "core/types.h"
#include "datasets/dataset.h"
#include "geometry/camera_model.h"

namespace mvtrack::datasets {

/// 4D Association's calibration.json (the Shelf release): object of cameras keyed "0", "1", ...
/// with `K` (3x3 row-major), `RT` (3x4 row-major world->camera, metres) and `imgSize`
/// [width, height]; no distortion. Camera ids are the keys; cameras sorted by id.
/// @throws DatasetError on a missing or malformed file or an invalid camera.
std::vector<geometry::CameraModel> LoadShelfCalibrationFile(const std::filesystem::path& file);

/// Cross-View Tracking's Campus calibration.json (`cameras.Camera<i>`: `K` normalised by the
/// image size, `Tw` camera->world with the centre in cm); the image size is not in the file and
/// is given (360x288 for Campus). `dist_coeffs` are not applied (see LoadCampus). Ids are the
/// digits of the camera names; cameras sorted by id.
/// @throws DatasetError on a missing or malformed file or an invalid camera.
std::vector<geometry::CameraModel> LoadCampusCalibrationFile(const std::filesystem::path& file,
                                                             int width_px,
                                                             int height_px);

/// CMU Panoptic's calibration_<sequence>.json: the HD cameras named in `cameras` (each "00_xx" or
/// an index "0".."30", in the order given; empty = every HD camera of the file in index order),
/// K, distCoef (k1 k2 p1 p2 k3), R, t (cm); the world rotated to z up by
/// PanopticToWorldRotation and scaled to metres; ids = HD index.
/// @throws DatasetError on a missing or malformed file, an unknown or repeated camera, or an
///   invalid camera.
std::vector<geometry::CameraModel> LoadPanopticCalibrationFile(
    const std::filesystem::path& file, const std::vector<std::string>& cameras);

/// WILDTRACK's derived/calibration_wildtrack.json (K, dist, rvec, tvec_cm, R checked against
/// Rodrigues(rvec) to 1e-6; world in cm -> metres); ids 0..6 in index order.
/// @throws DatasetError on a missing or malformed file or an invalid camera.
std::vector<geometry::CameraModel> LoadWildtrackCalibrationFile(const std::filesystem::path& file);

/// An image -> floor homography as EPFL's Homography.txt holds it: 3 rows of 3 numbers
/// separated by blanks, tabs or commas (blank lines and lines starting with '#' ignored); H maps
/// an image pixel (u, v, 1) to a floor point (x, y, 1) (geometry/floor_homography.h).
/// @throws DatasetError on a missing file, a row that is not 3 finite numbers, or not 3 rows.
Mat3 LoadFloorHomographyFile(const std::filesystem::path& file);

}  // namespace mvtrack::datasets
