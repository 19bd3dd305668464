// ImportFloorHomographies (lib/config/calibration_import.h): homography text files written from
// synthetic cameras import to those cameras (unit, mirroring, focal length given or estimated),
// the notes state the assumptions, and bad files are ConfigErrors naming the file and camera.
#include <catch2/catch.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "calib/calib_test_util.h"
#include "config/calibration.h"
#include "config/calibration_import.h"
#include "support/synthetic_cameras.h"

namespace mvtrack::config {
namespace {

using testing::TempDir;
using testing::WriteText;

// H as EPFL writes it: 3 tab-separated rows, 11 decimals.
std::string HomographyText(const Mat3& h) {
  std::string text;
  for (int r = 0; r < 3; ++r) {
    char line[200];
    std::snprintf(line, sizeof line, "%.17g\t%.17g\t%.17g\n", h(r, 0), h(r, 1), h(r, 2));
    text += line;
  }
  return text;
}

std::vector<geometry::CameraModel> Rig() {
  return {::mvtrack::testing::LookAtCamera(
              0, Vec3(-3.0, -4.0, 2.0), Vec3(1.0, 1.0, 0.0), 430.0, 360, 288),
          ::mvtrack::testing::LookAtCamera(
              1, Vec3(8.0, -2.0, 2.5), Vec3(2.0, 2.0, 0.0), 420.0, 360, 288),
          ::mvtrack::testing::LookAtCamera(
              2, Vec3(2.0, 9.0, 3.0), Vec3(1.0, 1.0, 0.0), 445.0, 360, 288)};
}

// Writes one file per camera of the rig (floor in `unit_m`, y mirrored when `mirror`), returns
// the paths.
std::vector<std::string> WriteRig(const TempDir& dir, double unit_m, bool mirror) {
  std::vector<std::string> paths;
  double scale = 1.0;
  for (const geometry::CameraModel& cam : Rig()) {
    paths.push_back(dir.File("c" + std::to_string(cam.id) + "/Homography.txt"));
    WriteText(paths.back(),
              HomographyText(::mvtrack::testing::FloorHomographyOf(cam, unit_m, mirror, scale)));
    scale *= -2.5;  // either sign
  }
  return paths;
}

bool HasNote(const ImportedCalibration& c, const std::string& text) {
  for (const std::string& note : c.notes) {
    if (note.find(text) != std::string::npos) return true;
  }
  return false;
}

TEST_CASE("Homography files import to the cameras that made them", "[unit]") {
  const TempDir dir;
  const std::vector<geometry::CameraModel> rig = Rig();
  for (bool mirror : {false, true}) {
    INFO("mirrored floor: " << mirror);
    const std::vector<std::string> paths = WriteRig(dir, 0.02, mirror);
    HomographyImportOptions options;
    options.image_size = ImageSize{360, 288};
    options.floor_unit_m = 0.02;
    const ImportedHomographies imported = ImportFloorHomographies(paths, options);
    const std::vector<geometry::CameraModel>& cams = imported.calibration.document.cameras;
    REQUIRE(cams.size() == 3);
    REQUIRE(imported.checks.size() == 3);
    CHECK(imported.calibration.document.names.empty());
    for (std::size_t i = 0; i < 3; ++i) {
      INFO("camera " << i);
      CHECK(cams[i].id == static_cast<CameraId>(i));
      CHECK(cams[i].width_px == 360);
      CHECK((cams[i].K - rig[i].K).cwiseAbs().maxCoeff() < 1e-6);
      CHECK(
          (cams[i].cam_from_world.rotation - rig[i].cam_from_world.rotation).cwiseAbs().maxCoeff() <
          1e-9);
      CHECK((cams[i].CenterInWorld() - rig[i].CenterInWorld()).norm() < 1e-8);
      CHECK(imported.checks[i].mirrored_y == mirror);
      CHECK(imported.checks[i].focal_estimated);
      CHECK(imported.checks[i].floor_reprojection_max_px < 1e-6);
    }
    CHECK(HasNote(imported.calibration, "square pixels"));
    CHECK(HasNote(imported.calibration, "floor unit 0.02 m as given"));
    CHECK(HasNote(imported.calibration, "at the image centre"));
    CHECK(HasNote(imported.calibration, mirror ? "y mirrored" : "right-handed"));
    CHECK(HasNote(imported.calibration,
                  "0: 430.0 px (closed form 430.0), 1: 420.0 px (closed form 420.0), 2: 445.0 px "
                  "(closed form 445.0)"));
    CHECK(HasNote(imported.calibration, "refined to minimise the floor reprojection error"));
    // The cameras are a valid calibration file.
    SaveCalibration(dir.File("cal.yaml"), cams, imported.calibration.document.names);
    CHECK(LoadCalibration(dir.File("cal.yaml")).size() == 3);
  }
}

TEST_CASE("Homography import: unit, focal length and principal point options", "[unit]") {
  const TempDir dir;
  const std::vector<std::string> paths = WriteRig(dir, 0.02, false);
  HomographyImportOptions options;
  options.image_size = ImageSize{360, 288};
  SECTION("no unit: 1 m per unit, said in a note") {
    const ImportedHomographies imported = ImportFloorHomographies(paths, options);
    CHECK(HasNote(imported.calibration, "floor unit taken as 1 m"));
    CHECK(imported.checks[0].height_m == Approx(2.0 / 0.02));
  }
  SECTION("a given focal length") {
    options.focal_px = 500.0;
    const ImportedHomographies imported = ImportFloorHomographies(paths, options);
    for (const geometry::FloorHomographyCamera& c : imported.checks) {
      CHECK_FALSE(c.focal_estimated);
      CHECK(c.camera.K(0, 0) == 500.0);
      CHECK(c.orthogonality_residual > 1e-3);
    }
    CHECK(HasNote(imported.calibration, "focal length as given: 0: 500.0 px, 1: 500.0 px"));
  }
  SECTION("a given principal point") {
    options.principal_point_px = Vec2(170.0, 150.0);
    const ImportedHomographies imported = ImportFloorHomographies(paths, options);
    CHECK(imported.checks[1].camera.K(0, 2) == 170.0);
    CHECK(imported.checks[1].camera.K(1, 2) == 150.0);
    CHECK(HasNote(imported.calibration, "point as given"));
  }
}

TEST_CASE("Homography files: commas, blank lines and comments are accepted", "[unit]") {
  const TempDir dir;
  const Mat3 h = ::mvtrack::testing::FloorHomographyOf(Rig()[0], 1.0, false, 1.0);
  char text[400];
  std::snprintf(text,
                sizeof text,
                "# camera 0\n\n%.17g, %.17g, %.17g\r\n  %.17g %.17g %.17g\n%.17g,%.17g,%.17g\n\n",
                h(0, 0),
                h(0, 1),
                h(0, 2),
                h(1, 0),
                h(1, 1),
                h(1, 2),
                h(2, 0),
                h(2, 1),
                h(2, 2));
  WriteText(dir.File("h.txt"), text);
  HomographyImportOptions options;
  options.image_size = ImageSize{360, 288};
  const ImportedHomographies imported = ImportFloorHomographies({dir.File("h.txt")}, options);
  CHECK(imported.checks[0].focal_px == Approx(430.0));
}

TEST_CASE("Homography import errors name the file and the camera", "[unit]") {
  const TempDir dir;
  const std::vector<std::string> paths = WriteRig(dir, 1.0, false);
  HomographyImportOptions options;
  options.image_size = ImageSize{360, 288};
  const auto import_with = [&](const std::string& second_file_text) {
    WriteText(dir.File("bad.txt"), second_file_text);
    return ImportFloorHomographies({paths[0], dir.File("bad.txt")}, options);
  };
  CHECK_THROWS_WITH(import_with("1 0 0\n0 1 0\n"),
                    Catch::Contains("bad.txt") && Catch::Contains("3 rows"));
  CHECK_THROWS_WITH(
      import_with("1 0 0\n0 1\n0 0 1\n"),
      Catch::Contains("bad.txt") && Catch::Contains("line 2") && Catch::Contains("3 numbers"));
  CHECK_THROWS_WITH(import_with("1 0 0\n0 1 x\n0 0 1\n"),
                    Catch::Contains("bad.txt") && Catch::Contains("'x' is not a finite number"));
  CHECK_THROWS_WITH(import_with("1 0 0\n0 1 nan\n0 0 1\n"),
                    Catch::Contains("bad.txt") && Catch::Contains("'nan'"));
  CHECK_THROWS_WITH(import_with("1 0 0\n0 1 0\n0 0 1\n1 1 1\n"),
                    Catch::Contains("bad.txt") && Catch::Contains("more than 3 rows"));
  CHECK_THROWS_WITH(
      import_with("1 2 3\n2 4 6\n0 0 1\n"),
      Catch::Contains("bad.txt") && Catch::Contains("camera 1") && Catch::Contains("singular"));
  CHECK_THROWS_WITH(ImportFloorHomographies({paths[0], dir.File("nope.txt")}, options),
                    Catch::Contains("nope.txt") && Catch::Contains("not found"));
  CHECK_THROWS_WITH(ImportFloorHomographies({}, options), Catch::Contains("no homography files"));
  // One camera's floor mirrored, the other's not: not one floor frame.
  const TempDir mirrored_dir;
  const std::vector<std::string> mirrored = WriteRig(mirrored_dir, 1.0, true);
  CHECK_THROWS_WITH(ImportFloorHomographies({paths[0], mirrored[1]}, options),
                    Catch::Contains(mirrored[1]) && Catch::Contains("camera 1") &&
                        Catch::Contains("one floor frame"));
  HomographyImportOptions no_size;
  CHECK_THROWS_WITH(ImportFloorHomographies(paths, no_size),
                    Catch::Contains(paths[0]) && Catch::Contains("--image-size"));
  HomographyImportOptions bad_unit = options;
  bad_unit.floor_unit_m = -1.0;
  CHECK_THROWS_WITH(ImportFloorHomographies(paths, bad_unit), Catch::Contains("floor_unit_m"));
  try {
    import_with("1 2 3\n2 4 6\n0 0 1\n");
    FAIL("no ConfigError");
  } catch (const ConfigError& e) {
    CHECK(e.file() == dir.File("bad.txt"));
    CHECK(e.key_path() == "camera 1");
  }
}

}  // namespace
}  // namespace mvtrack::config
