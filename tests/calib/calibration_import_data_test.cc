// The importers on the real calibration files of ../shared/data (label "data"): two independent
// releases of the same cameras must import to the same cameras, and the dataset loaders must
// see the same cameras as `mvtrack calib import`.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "calib/calib_test_util.h"
#include "config/calibration_import.h"
#include "datasets/data_test_util.h"
#include "datasets/epfl.h"
#include "datasets/panoptic.h"
#include "datasets/wildtrack.h"

namespace mvtrack::config {
namespace {

using datasets::testing::FindDataset;

double MaxDiff(const Mat3& a, const Mat3& b) { return (a - b).cwiseAbs().maxCoeff(); }
double MaxDiff(const Vec3& a, const Vec3& b) { return (a - b).cwiseAbs().maxCoeff(); }

void RequireSameCameras(const std::vector<geometry::CameraModel>& a,
                        const std::vector<geometry::CameraModel>& b,
                        double centre_tol_m,
                        double k_tol_px,
                        double r_tol) {
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    INFO("camera " << a[i].id);
    CHECK(a[i].id == b[i].id);
    CHECK(a[i].width_px == b[i].width_px);
    CHECK(a[i].height_px == b[i].height_px);
    CHECK(MaxDiff(a[i].CenterInWorld(), b[i].CenterInWorld()) < centre_tol_m);
    CHECK(MaxDiff(a[i].K, b[i].K) < k_tol_px);
    CHECK(MaxDiff(a[i].cam_from_world.rotation, b[i].cam_from_world.rotation) < r_tol);
  }
}

TEST_CASE("Shelf: 4D Association and VoxelPose calibrations import to the same cameras", "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "shelf");
  const ImportedCalibration fda =
      ImportFourDAssociation((root / "shelf/4d_association/calibration.json").string());
  const ImportedCalibration vp = ImportVoxelPose(
      (root / "shelf/voxelpose/calibration_shelf.json").string(), ImageSize{1032, 776});
  REQUIRE(fda.document.cameras.size() == 5);
  // SOURCE.md: centres agree to 5e-6 m, intrinsics to 5e-5 px; the VoxelPose file prints its
  // rotations with 6 decimals (re-orthonormalised by the importer).
  RequireSameCameras(fda.document.cameras, vp.document.cameras, 1e-5, 1e-4, 1e-5);
  bool noted = false;
  for (const std::string& n : vp.notes) noted |= n.find("nearest rotation") != std::string::npos;
  CHECK(noted);
  // And the same cameras as the Shelf loader (`mvtrack convert shelf`).
  const datasets::Dataset& shelf = datasets::testing::ShelfData();
  RequireSameCameras(fda.document.cameras, shelf.cameras, 1e-12, 1e-12, 1e-15);
}

TEST_CASE("Campus: Cross-View Tracking and VoxelPose calibrations agree", "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "campus");
  const ImportedCalibration cv =
      ImportCampus((root / "campus/crossview_longcw/calibration.json").string());
  const ImportedCalibration vp = ImportVoxelPose(
      (root / "campus/voxelpose/calibration_campus.json").string(), ImageSize{360, 288});
  REQUIRE(cv.document.cameras.size() == 3);
  RequireSameCameras(cv.document.cameras, vp.document.cameras, 1e-6, 1e-6, 1e-9);
}

TEST_CASE("Panoptic: all 31 HD cameras, and the loader's subset is the same cameras", "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "panoptic");
  const std::string file = (root / "panoptic/160906_band2/calibration_160906_band2.json").string();
  const ImportedCalibration all = ImportPanoptic(file, {});
  REQUIRE(all.document.cameras.size() == 31);
  for (std::size_t i = 0; i < 31; ++i)
    CHECK(all.document.cameras[i].id == static_cast<CameraId>(i));
  CHECK(all.document.names.at(28) == "00_28");
  const ImportedCalibration subset = ImportPanoptic(file, datasets::DefaultPanopticCameras());
  const datasets::Dataset& pan = datasets::testing::CachedDataset(
      "panoptic/band2", [] { return datasets::LoadPanoptic(datasets::DefaultDataRoot()); });
  RequireSameCameras(subset.document.cameras, pan.cameras, 1e-15, 1e-15, 1e-15);
  // The dome is z up after the import: every HD camera is above the floor.
  for (const geometry::CameraModel& c : all.document.cameras) CHECK(c.CenterInWorld().z() > 0.0);
}

TEST_CASE("WILDTRACK: the derived JSON agrees with ReST's homographies, the XML route with it",
          "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "wildtrack");
  const ImportedCalibration json =
      ImportWildtrack((root / "wildtrack/derived/calibration_wildtrack.json").string());
  REQUIRE(json.document.cameras.size() == 7);
  CHECK(json.document.names.at(0) == "CVLab1");
  CHECK(json.document.names.at(6) == "IDIAP3");
  // Independent source: image_from_ground homographies in cm. Ground points project alike.
  const std::vector<Mat3> homographies = datasets::WildtrackHomographies(root);
  REQUIRE(homographies.size() == 7);
  for (std::size_t c = 0; c < 7; ++c) {
    for (const Vec2& ground_cm : {Vec2(0, 0), Vec2(300, 500), Vec2(-200, 1200)}) {
      const Vec2 from_h = (homographies[c] * Vec3(ground_cm.x(), ground_cm.y(), 1.0)).hnormalized();
      const std::optional<Vec2> ours = json.document.cameras[c].ProjectUndistorted(
          Vec3(ground_cm.x() / 100, ground_cm.y() / 100, 0));
      if (!ours) continue;  // behind this camera
      INFO("camera " << c << " ground " << ground_cm.transpose());
      CHECK((*ours - from_h).norm() < 0.05);
    }
  }
  // The official XML files written from these numbers import to the same cameras.
  testing::TempDir dir;
  for (std::size_t c = 0; c < 7; ++c) {
    const geometry::CameraModel& cam = json.document.cameras[c];
    const std::string name = json.document.names.at(cam.id);
    const Eigen::AngleAxisd aa(cam.cam_from_world.rotation);
    const Vec3 rvec = aa.angle() * aa.axis();
    const Vec3 tvec_cm = 100.0 * cam.cam_from_world.translation;
    std::filesystem::create_directories(dir.path() / "intrinsic_zero");
    {
      cv::FileStorage out((dir.path() / "intrinsic_zero" / ("intr_" + name + ".xml")).string(),
                          cv::FileStorage::WRITE);
      cv::Mat k(3, 3, CV_64F);
      for (int r = 0; r < 3; ++r) {
        for (int col = 0; col < 3; ++col) k.at<double>(r, col) = cam.K(r, col);
      }
      out << "camera_matrix" << k;
      out << "distortion_coefficients" << cv::Mat::zeros(1, 5, CV_64F);
    }
    char extr[512];
    std::snprintf(extr,
                  sizeof extr,
                  "<?xml version=\"1.0\"?>\n<opencv_storage>\n<rvec>%.17g %.17g %.17g</rvec>\n"
                  "<tvec>%.17g %.17g %.17g</tvec>\n</opencv_storage>\n",
                  rvec.x(),
                  rvec.y(),
                  rvec.z(),
                  tvec_cm.x(),
                  tvec_cm.y(),
                  tvec_cm.z());
    testing::WriteText((dir.path() / "extrinsic" / ("extr_" + name + ".xml")).string(), extr);
  }
  const ImportedCalibration xml = ImportWildtrack(dir.path().string());
  RequireSameCameras(json.document.cameras, xml.document.cameras, 1e-9, 1e-9, 1e-12);
  for (std::size_t c = 0; c < 7; ++c) {
    CHECK(xml.document.names.at(static_cast<CameraId>(c)) ==
          json.document.names.at(static_cast<CameraId>(c)));
  }
}

TEST_CASE("EPFL Terrace: the homography import gives the loader's cameras", "[data]") {
  MVTRACK_REQUIRE_DATASET(root, "epfl");
  datasets::EpflOptions options;
  options.corruption = datasets::CorruptionOptions::Clean();
  datasets::EpflCalibration cal;
  const datasets::Dataset ds = datasets::LoadEpflTerrace(root, options, &cal);
  std::vector<std::string> paths;
  for (int c = 0; c < 4; ++c) {
    paths.push_back(
        (root / "epfl/terrace1" / ("terrace1-c" + std::to_string(c)) / "Homography.txt").string());
  }
  HomographyImportOptions import_options;
  import_options.image_size = ImageSize{360, 288};
  import_options.floor_unit_m = cal.floor_unit_m;
  const ImportedHomographies imported = ImportFloorHomographies(paths, import_options);
  RequireSameCameras(imported.calibration.document.cameras, ds.cameras, 1e-12, 1e-12, 1e-15);
  // SOURCE.md: focal lengths 420-447 px, horizontal field of view about 45 deg.
  for (const geometry::FloorHomographyCamera& c : imported.checks) {
    INFO("camera " << c.camera.id);
    CHECK(c.focal_px > 415.0);
    CHECK(c.focal_px < 450.0);
    CHECK(c.horizontal_fov_deg == Approx(45.0).margin(3.0));
    CHECK(c.floor_reprojection_median_px < 2.0);
    CHECK(c.mirrored_y == cal.mirrored_y);
  }
  CHECK(cal.mirrored_y);
}

}  // namespace
}  // namespace mvtrack::config
