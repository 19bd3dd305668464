#include "config/calibration_check.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/synthetic_cameras.h"

namespace mvtrack::config {
namespace {

using mvtrack::testing::LookAtCamera;
using mvtrack::testing::RingOfCameras;

constexpr double kDeg = 180.0 / std::numbers::pi;

bool AnyContains(const std::vector<std::string>& lines,
                 const std::string& a,
                 const std::string& b = "") {
  for (const std::string& l : lines) {
    if (l.find(a) != std::string::npos && l.find(b) != std::string::npos) return true;
  }
  return false;
}

std::size_t CellAt(const CoverageGrid& g, double x, double y) {
  const int col = static_cast<int>(std::floor((x - g.region.x_min_m) / g.cell_m));
  const int row = static_cast<int>(std::floor((y - g.region.y_min_m) / g.cell_m));
  if (col < 0 || row < 0 || col >= g.cols || row >= g.rows) {
    throw std::out_of_range("CellAt: (" + std::to_string(x) + ", " + std::to_string(y) +
                            ") is outside the coverage grid");
  }
  return static_cast<std::size_t>(row) * static_cast<std::size_t>(g.cols) +
         static_cast<std::size_t>(col);
}

TEST_CASE("Two downward cameras: the common area and angles known by construction", "[unit]") {
  // 3 m high, fx 500 px, 1000 x 1000 images: at the sample height 1 m each sees a square of
  // half-width (3 - 1) * 500 / 500 = 2 m: [-2, 2]^2 and [0, 4] x [-2, 2]; common 2 m x 4 m.
  const std::vector<geometry::CameraModel> cams = {
      LookAtCamera(0, Vec3(0, 0, 3), Vec3(0, 0, 0), 500.0, 1000, 1000),
      LookAtCamera(1, Vec3(2, 0, 3), Vec3(2, 0, 0), 500.0, 1000, 1000)};
  CalibrationCheckOptions options;
  options.region = FloorRegion{-3.0, -3.0, 5.0, 3.0};
  options.cell_m = 0.05;
  const CalibrationReport r = CheckCalibration(cams, options);
  const double tol = 12.0 * 0.05;  // the squares' perimeter times the cell size
  CHECK(r.cameras[0].seen_area_m2 == Approx(16.0).margin(tol));
  CHECK(r.cameras[1].seen_area_m2 == Approx(16.0).margin(tol));
  REQUIRE(r.pairs.size() == 1);
  CHECK(r.pairs[0].a == 0);
  CHECK(r.pairs[0].b == 1);
  CHECK(r.pairs[0].baseline_m == Approx(2.0));
  CHECK(r.pairs[0].common_area_m2 == Approx(8.0).margin(tol));
  CHECK(r.area_single_view_m2 == Approx(16.0).margin(2 * tol));
  CHECK(r.area_unseen_m2 == Approx(48.0 - 24.0).margin(2 * tol));
  CHECK(r.area_triangulable_m2 + r.area_weak_m2 == Approx(8.0).margin(tol));
  CHECK(r.grid.view_count[CellAt(r.grid, 1.0, 0.5)] == 2);
  CHECK(r.grid.view_count[CellAt(r.grid, -1.0, 0.5)] == 1);
  CHECK(r.grid.view_count[CellAt(r.grid, 4.5, 0.5)] == 0);
  // At (1, 0, 1) the rays from (0, 0, 3) and (2, 0, 3) meet at 2 atan(1 / 2) = 53.13 degrees.
  CHECK(r.grid.best_angle_deg[CellAt(r.grid, 1.0, 0.0)] ==
        Approx(2.0 * std::atan(0.5) * kDeg).margin(1.0));
  CHECK_FALSE(r.pairs[0].short_baseline);
  // The single-view area is reported (the paper's failure case 1).
  CHECK(AnyContains(r.warnings, "one camera only"));
}

TEST_CASE("Cameras close together are a short-baseline pair, spread apart they are not", "[unit]") {
  for (double half_baseline : {0.05, 0.25, 3.0}) {
    INFO("baseline " << 2 * half_baseline << " m");
    const std::vector<geometry::CameraModel> cams = {
        LookAtCamera(4, Vec3(-half_baseline, -6.0, 2.5), Vec3(0, 0, 1), 800.0, 1280, 720),
        LookAtCamera(9, Vec3(half_baseline, -6.0, 2.5), Vec3(0, 0, 1), 800.0, 1280, 720)};
    const CalibrationReport r = CheckCalibration(cams);
    REQUIRE(r.pairs.size() == 1);
    const PairCheck& p = r.pairs[0];
    CHECK(p.baseline_m == Approx(2 * half_baseline));
    CHECK(p.common_area_m2 > 1.0);
    // Small angles: angle ~ baseline / distance (radians).
    if (half_baseline < 1.0) {
      CHECK(p.median_angle_deg == Approx(p.baseline_m / p.median_distance_m * kDeg).epsilon(0.05));
    }
    const bool expect_short = 2 * half_baseline / p.median_distance_m < 10.0 / kDeg;
    CHECK(p.short_baseline == expect_short);
    CHECK(AnyContains(r.warnings, "camera 4 and camera 9", "short baseline") == expect_short);
  }
  // The 0.5 m pair at about 6 m is below 10 degrees: flagged; with a 3 degree limit it is not.
  const std::vector<geometry::CameraModel> cams = {
      LookAtCamera(0, Vec3(-0.25, -6.0, 2.5), Vec3(0, 0, 1), 800.0, 1280, 720),
      LookAtCamera(1, Vec3(0.25, -6.0, 2.5), Vec3(0, 0, 1), 800.0, 1280, 720)};
  CHECK(CheckCalibration(cams).pairs[0].short_baseline);
  CalibrationCheckOptions lenient;
  lenient.min_triangulation_angle_deg = 3.0;
  CHECK_FALSE(CheckCalibration(cams, lenient).pairs[0].short_baseline);
}

TEST_CASE("Cameras facing each other across the floor are not a short baseline", "[unit]") {
  // Opposite cameras: viewing rays meet at nearly 180 degrees in the middle; the angle between
  // the lines is what conditions triangulation.
  const std::vector<geometry::CameraModel> cams = {
      LookAtCamera(0, Vec3(-5, 0, 1.2), Vec3(0, 0, 1), 700.0, 1280, 720),
      LookAtCamera(1, Vec3(5, 0, 1.2), Vec3(0, 0, 1), 700.0, 1280, 720)};
  const CalibrationReport r = CheckCalibration(cams);
  REQUIRE(r.pairs.size() == 1);
  CHECK(r.pairs[0].median_angle_deg <= 90.0);
  // Between the cameras the rays meet at 180 - 2 atan(0.2 / 5) degrees: the lines are 4.6
  // degrees apart ...
  CHECK(r.grid.best_angle_deg[CellAt(r.grid, 0.0, 0.0)] ==
        Approx(2.0 * std::atan(0.2 / 5.0) * kDeg).margin(0.5));
  // ... and off it larger (at (0, 1, 1): 180 - acos(-23.96 / 26.04) = 23 degrees).
  CHECK(r.grid.best_angle_deg[CellAt(r.grid, 0.0, 1.0)] >
        r.grid.best_angle_deg[CellAt(r.grid, 0.0, 0.0)]);
}

TEST_CASE("A ring of cameras covers the room centre with every camera", "[unit]") {
  const std::vector<geometry::CameraModel> cams =
      RingOfCameras(4, 5.0, 3.0, Vec3(0, 0, 1), 600.0, 1280, 720);
  const CalibrationReport r = CheckCalibration(cams);
  CHECK(r.grid.view_count[CellAt(r.grid, 0.0, 0.0)] == 4);
  CHECK(r.pairs.size() == 6);
  for (const PairCheck& p : r.pairs) CHECK_FALSE(p.short_baseline);
  for (const CameraCheck& c : r.cameras) {
    INFO("camera " << c.id);
    CHECK(c.warnings.empty());
    CHECK(c.pitch_down_deg == Approx(std::atan2(2.0, 5.0) * kDeg).margin(1e-9));
    CHECK(c.horizontal_fov_deg == Approx(2.0 * std::atan(640.0 / 600.0) * kDeg));
  }
  CHECK(r.area_triangulable_m2 > 20.0);
  // The default region contains the centres with the margin.
  CHECK(r.grid.region.x_min_m <= -5.0 - 1.0 + 1e-9);
  CHECK(r.grid.region.x_max_m >= 5.0 + 1.0 - 1e-9);
}

TEST_CASE("Per-camera sanity warnings", "[unit]") {
  std::vector<geometry::CameraModel> cams =
      RingOfCameras(3, 4.0, 3.0, Vec3(0, 0, 1), 600.0, 1280, 720);
  SECTION("principal point outside the image") {
    cams[1].K(0, 2) = 2000.0;
    const CalibrationReport r = CheckCalibration(cams);
    CHECK(AnyContains(r.cameras[1].warnings, "principal point"));
    CHECK(r.cameras[0].warnings.empty());
  }
  SECTION("implausible focal length") {
    cams[2].K(0, 0) = 1.2;  // K normalised by the image size
    cams[2].K(1, 1) = 1.5;
    const CalibrationReport r = CheckCalibration(cams);
    CHECK(AnyContains(r.cameras[2].warnings, "field of view"));
  }
  SECTION("a camera below the floor") {
    cams[0] = LookAtCamera(0, Vec3(4, 0, -0.5), Vec3(0, 0, 1), 600.0, 1280, 720);
    const CalibrationReport r = CheckCalibration(cams);
    CHECK(AnyContains(r.cameras[0].warnings, "below the floor"));
    CHECK_FALSE(AnyContains(r.warnings, "look upwards"));  // one camera looking up is fine
  }
  SECTION("a world with z down: the rig mirrored, every camera looks up") {
    for (geometry::CameraModel& c : cams) {
      const Vec3 centre = c.CenterInWorld();
      c = LookAtCamera(c.id, Vec3(centre.x(), centre.y(), -3.0), Vec3(0, 0, -1), 600.0, 1280, 720);
    }
    const CalibrationReport r = CheckCalibration(cams);
    CHECK(AnyContains(r.warnings, "3 of 3 cameras look upwards"));
  }
  SECTION("millimetres instead of metres") {
    for (geometry::CameraModel& c : cams) c.cam_from_world.translation *= 1000.0;
    const CalibrationReport r = CheckCalibration(cams);
    CHECK(AnyContains(r.warnings, "millimetres"));
  }
  SECTION("distortion that does not invert over the image") {
    // r_d = r (1 - 0.6 r^2) never exceeds 0.5, but the image corner is at r_d = 1.22.
    cams[1].distortion.k1 = -0.6;
    const CalibrationReport r = CheckCalibration(cams);
    CHECK(r.cameras[1].distortion_roundtrip_px > 0.5);
    CHECK(AnyContains(r.cameras[1].warnings, "does not invert"));
    CHECK(r.cameras[0].distortion_roundtrip_px == 0.0);
  }
  SECTION("a camera seeing none of the region") {
    CalibrationCheckOptions options;
    options.region = FloorRegion{100.0, 100.0, 102.0, 102.0};
    const CalibrationReport r = CheckCalibration(cams, options);
    // Camera 0 (at x = 4 looking towards -x) has that region behind it.
    CHECK(r.cameras[0].seen_area_m2 == 0.0);
    CHECK(AnyContains(r.cameras[0].warnings, "sees none"));
    // The four area classes partition the region.
    CHECK(r.area_unseen_m2 + r.area_single_view_m2 + r.area_weak_m2 + r.area_triangulable_m2 ==
          Approx(4.0));
  }
}

TEST_CASE("A camera sharing no floor with the others is a load warning, normal rigs have none",
          "[unit]") {
  // Two cameras over one spot, a third far away over another.
  const std::vector<mvtrack::geometry::CameraModel> cams = {
      LookAtCamera(0, Vec3(0, 0, 3), Vec3(0, 0, 0), 500.0, 1000, 1000),
      LookAtCamera(1, Vec3(1, 0, 3), Vec3(1, 0, 0), 500.0, 1000, 1000),
      LookAtCamera(7, Vec3(40, 0, 3), Vec3(40, 0, 0), 500.0, 1000, 1000)};
  const CalibrationReport report = CheckCalibration(cams);
  REQUIRE(report.load_warnings.size() == 1);
  CHECK_THAT(report.load_warnings[0], Catch::StartsWith("camera 7 shares no floor"));
  const std::vector<std::string> at_load = CalibrationLoadWarnings(cams);
  REQUIRE(at_load.size() == 1);
  CHECK(at_load[0] == report.load_warnings[0]);
  // The first two alone: a single-view border (a region wider than the floor both see) is a
  // warning of calib check, not at load. (Their default region, the rig plus 1 m, is seen by
  // both everywhere: no warning at all there.)
  const std::vector<mvtrack::geometry::CameraModel> pair(cams.begin(), cams.begin() + 2);
  CHECK(CheckCalibration(pair).warnings.empty());
  CalibrationCheckOptions wide;
  wide.region = FloorRegion{-5.0, -5.0, 6.0, 5.0};
  const CalibrationReport wide_report = CheckCalibration(pair, wide);
  CHECK(wide_report.area_single_view_m2 > 0.0);
  CHECK_FALSE(wide_report.warnings.empty());
  CHECK(CalibrationLoadWarnings(pair).empty());
}

TEST_CASE("SeesPoint and option validation", "[unit]") {
  const geometry::CameraModel cam =
      LookAtCamera(0, Vec3(0, -5, 2), Vec3(0, 0, 1), 800.0, 1280, 720);
  CHECK(geometry::SeesPoint(cam, Vec3(0, 0, 1)));
  CHECK_FALSE(geometry::SeesPoint(cam, Vec3(0, -8, 1)));  // behind
  CHECK_FALSE(geometry::SeesPoint(cam, Vec3(20, 0, 1)));  // far to the side
  CalibrationCheckOptions o;
  std::string why;
  CHECK(o.Validate(&why));
  o.cell_m = 0.0;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("cell_m") != std::string::npos);
  o = CalibrationCheckOptions{};
  o.min_triangulation_angle_deg = 95.0;
  CHECK_FALSE(o.Validate(&why));
  o = CalibrationCheckOptions{};
  o.region = FloorRegion{1.0, 0.0, 1.0, 2.0};
  CHECK_FALSE(o.Validate(&why));
}

TEST_CASE("A huge region is sampled with larger cells", "[unit]") {
  const std::vector<geometry::CameraModel> cams =
      RingOfCameras(2, 5.0, 3.0, Vec3(0, 0, 1), 600.0, 640, 480);
  CalibrationCheckOptions options;
  options.region = FloorRegion{-500.0, -500.0, 500.0, 500.0};
  options.cell_m = 0.01;
  const CalibrationReport r = CheckCalibration(cams, options);
  CHECK(static_cast<std::int64_t>(r.grid.cols) * r.grid.rows <=
        CalibrationCheckOptions::kMaxCells + 2001);
  CHECK(r.grid.cell_m == Approx(1.0));
}

}  // namespace
}  // namespace mvtrack::config
