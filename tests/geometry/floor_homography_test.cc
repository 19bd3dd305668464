// Tests of geometry/floor_homography.h: a synthetic camera -> its image -> floor homography (in
// any floor unit, either sign, the floor's y mirrored or not) -> the recovered camera equals the
// original; the focal length estimated or given; degenerate and invalid homographies rejected
// with a reason; the floor unit recovered from boxes of people of a known height.

#include "geometry/floor_homography.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "support/eigen_matchers.h"
#include "support/synthetic_cameras.h"

namespace mvtrack::geometry {
namespace {

using testing::FloorHomographyOf;
using testing::IsApproxVec;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

void RequireSameCamera(const CameraModel& got, const CameraModel& want, double tol) {
  CHECK(got.id == want.id);
  CHECK(got.width_px == want.width_px);
  CHECK(got.height_px == want.height_px);
  CHECK((got.K - want.K).cwiseAbs().maxCoeff() < tol * want.K(0, 0));
  CHECK((got.cam_from_world.rotation - want.cam_from_world.rotation).cwiseAbs().maxCoeff() < tol);
  CHECK_THAT(got.CenterInWorld(), IsApproxVec(want.CenterInWorld(), tol * 10.0));
  CHECK(got.distortion.IsZero());
}

struct Case {
  const char* name;
  CameraModel camera;
};

std::vector<Case> Cameras() {
  return {
      {"Terrace-like: 360x288, f 430, 2 m up, looking down 30 deg",
       testing::LookAtCamera(0, Vec3(-3.0, -4.0, 2.0), Vec3(1.0, 1.0, 0.0), 430.0, 360, 288)},
      {"1920x1080, f 1400, 6 m up, steep",
       testing::LookAtCamera(3, Vec3(5.0, 2.0, 6.0), Vec3(0.5, -0.5, 0.0), 1400.0, 1920, 1080)},
      {"wide: f 300, 3 m up, horizon inside the image",
       testing::LookAtCamera(7, Vec3(0.0, -8.0, 3.0), Vec3(0.0, 0.0, 1.5), 300.0, 640, 480)},
  };
}

TEST_CASE("A camera's floor homography gives the camera back, for either sign of H", "[unit]") {
  for (const Case& c : Cameras()) {
    for (double scale : {1.0, 3.7, -0.25}) {
      INFO(c.name << ", H scaled by " << scale);
      const Mat3 H = FloorHomographyOf(c.camera, 1.0, false, scale);
      const FloorHomographyCamera r =
          CameraFromFloorHomography(H, c.camera.id, c.camera.width_px, c.camera.height_px);
      REQUIRE(r.ok);
      CHECK(r.reason.empty());
      RequireSameCamera(r.camera, c.camera, 1e-9);
      CHECK(r.focal_estimated);
      CHECK(r.focal_px == Approx(c.camera.K(0, 0)).epsilon(1e-9));
      CHECK_FALSE(r.mirrored_y);
      CHECK(r.orthogonality_residual < 1e-9);
      CHECK(r.height_m == Approx(c.camera.CenterInWorld().z()).epsilon(1e-9));
      const double f = c.camera.K(0, 0);
      CHECK(r.horizontal_fov_deg ==
            Approx(2.0 * std::atan(0.5 * c.camera.width_px / f) * kRadToDeg).epsilon(1e-9));
      CHECK(r.vertical_fov_deg ==
            Approx(2.0 * std::atan(0.5 * c.camera.height_px / f) * kRadToDeg).epsilon(1e-9));
      CHECK(r.floor_check_points > 0);
      CHECK(r.floor_check_points <= 121);
      CHECK(r.floor_reprojection_max_px < 1e-6);
      CHECK(r.camera.Validate(nullptr));
    }
  }
}

TEST_CASE("Pixels above the horizon are left out of the floor check", "[unit]") {
  // The wide camera looks at a point 1.5 m up: the horizon crosses the image.
  const CameraModel cam = Cameras()[2].camera;
  const FloorHomographyCamera r = CameraFromFloorHomography(
      FloorHomographyOf(cam, 1.0, false, 1.0), cam.id, cam.width_px, cam.height_px);
  REQUIRE(r.ok);
  CHECK(r.floor_check_points > 60);
  CHECK(r.floor_check_points < 121);
}

TEST_CASE("The floor unit scales the translation: a floor in centimetres", "[unit]") {
  const CameraModel cam = Cameras()[0].camera;
  const Mat3 H = FloorHomographyOf(cam, 0.01, false, 1.0);
  FloorHomographyOptions options;
  options.floor_unit_m = 0.01;
  const FloorHomographyCamera r =
      CameraFromFloorHomography(H, cam.id, cam.width_px, cam.height_px, options);
  REQUIRE(r.ok);
  RequireSameCamera(r.camera, cam, 1e-9);
  CHECK(r.height_m == Approx(2.0).epsilon(1e-9));
  // Read as metres, the same homography gives a camera 100 times farther from everything.
  const FloorHomographyCamera as_m =
      CameraFromFloorHomography(H, cam.id, cam.width_px, cam.height_px);
  REQUIRE(as_m.ok);
  CHECK(as_m.height_m == Approx(200.0).epsilon(1e-9));
  CHECK(as_m.focal_px == Approx(r.focal_px).epsilon(1e-12));
}

TEST_CASE("A left-handed floor frame is mirrored in y, the world is the original one", "[unit]") {
  for (const Case& c : Cameras()) {
    for (double scale : {1.0, -2.0}) {
      INFO(c.name << ", H scaled by " << scale);
      const Mat3 H = FloorHomographyOf(c.camera, 0.02, true, scale);
      FloorHomographyOptions options;
      options.floor_unit_m = 0.02;
      const FloorHomographyCamera r =
          CameraFromFloorHomography(H, c.camera.id, c.camera.width_px, c.camera.height_px, options);
      REQUIRE(r.ok);
      CHECK(r.mirrored_y);
      RequireSameCamera(r.camera, c.camera, 1e-9);
      CHECK(r.camera.cam_from_world.rotation.determinant() == Approx(1.0));
      CHECK(r.height_m > 0.0);
      CHECK(r.floor_reprojection_max_px < 1e-6);
      // A floor point maps to the world point of the original frame.
      const Vec3 world(1.0, 2.0, 0.0);
      const Vec2 floor(world.x() / 0.02, -world.y() / 0.02);
      CHECK_THAT(FloorToWorld(floor, 0.02, true), IsApproxVec(world, 1e-12));
      const std::optional<Vec2> px = c.camera.ProjectUndistorted(world);
      REQUIRE(px.has_value());
      const std::optional<Vec2> back = ImageToFloor(H, *px);
      REQUIRE(back.has_value());
      CHECK_THAT(*back, IsApproxVec(floor, 1e-6));
    }
  }
}

TEST_CASE("A given focal length is used as it is, the estimate needs none", "[unit]") {
  const CameraModel cam = Cameras()[0].camera;
  const Mat3 H = FloorHomographyOf(cam, 1.0, false, 1.0);
  FloorHomographyOptions options;
  options.focal_px = 430.0;
  FloorHomographyCamera r =
      CameraFromFloorHomography(H, cam.id, cam.width_px, cam.height_px, options);
  REQUIRE(r.ok);
  CHECK_FALSE(r.focal_estimated);
  CHECK(r.focal_px == 430.0);
  RequireSameCamera(r.camera, cam, 1e-9);
  // A wrong focal length still gives a camera, but the checks show it.
  options.focal_px = 600.0;
  r = CameraFromFloorHomography(H, cam.id, cam.width_px, cam.height_px, options);
  REQUIRE(r.ok);
  CHECK(r.camera.K(0, 0) == 600.0);
  CHECK(r.orthogonality_residual > 0.01);
  CHECK(r.floor_reprojection_max_px > 1.0);
}

TEST_CASE("A given principal point is used, the default is the image centre", "[unit]") {
  CameraModel cam = Cameras()[1].camera;
  cam.K(0, 2) = 900.0;
  cam.K(1, 2) = 560.0;
  const Mat3 H = FloorHomographyOf(cam, 1.0, false, 1.0);
  FloorHomographyOptions options;
  options.principal_point_px = Vec2(900.0, 560.0);
  const FloorHomographyCamera r =
      CameraFromFloorHomography(H, cam.id, cam.width_px, cam.height_px, options);
  REQUIRE(r.ok);
  RequireSameCamera(r.camera, cam, 1e-9);
  // Assuming the centre instead gives another camera whose checks show the mismatch.
  const FloorHomographyCamera centred =
      CameraFromFloorHomography(H, cam.id, cam.width_px, cam.height_px);
  REQUIRE(centred.ok);
  CHECK(centred.camera.K(0, 2) == 960.0);
  CHECK(centred.orthogonality_residual > 1e-4);
}

TEST_CASE("A homography of a camera outside the model: the refinement spreads the residual",
          "[unit]") {
  // The principal point 20 px right of and 12 px above the centre that is assumed: no camera of
  // the model makes this homography.
  CameraModel cam = Cameras()[0].camera;
  cam.K(0, 2) += 20.0;
  cam.K(1, 2) -= 12.0;
  const Mat3 H = FloorHomographyOf(cam, 1.0, false, 1.0);
  const FloorHomographyCamera r = CameraFromFloorHomography(H, cam.id, cam.width_px, cam.height_px);
  REQUIRE(r.ok);
  CHECK(r.orthogonality_residual > 1e-3);
  CHECK(r.focal_px != r.initial_focal_px);
  CHECK(r.focal_px == Approx(cam.K(0, 0)).epsilon(0.1));
  // With the focal length held at the closed-form value (only R, t refined) the floor reprojects
  // worse: f is refined too when it was estimated.
  FloorHomographyOptions fixed;
  fixed.focal_px = r.initial_focal_px;
  const FloorHomographyCamera same_f = CameraFromFloorHomography(H, cam.id, 360, 288, fixed);
  REQUIRE(same_f.ok);
  CHECK(r.floor_reprojection_median_px <= same_f.floor_reprojection_median_px + 1e-9);
  CHECK(r.floor_reprojection_max_px < 5.0);
  CHECK(r.height_m == Approx(2.0).epsilon(0.1));
}

TEST_CASE("A camera looking straight down needs its focal length", "[unit]") {
  const CameraModel cam =
      testing::LookAtCamera(1, Vec3(1.0, 2.0, 5.0), Vec3(1.0, 2.0, 0.0), 800.0, 640, 480);
  const Mat3 H = FloorHomographyOf(cam, 1.0, false, 1.0);
  const FloorHomographyCamera r = CameraFromFloorHomography(H, cam.id, cam.width_px, cam.height_px);
  CHECK_FALSE(r.ok);
  CHECK_THAT(r.reason, Catch::Contains("parallel to the floor") && Catch::Contains("focal length"));
  FloorHomographyOptions options;
  options.focal_px = 800.0;
  const FloorHomographyCamera given =
      CameraFromFloorHomography(H, cam.id, cam.width_px, cam.height_px, options);
  REQUIRE(given.ok);
  RequireSameCamera(given.camera, cam, 1e-9);
  CHECK(given.height_m == Approx(5.0));
}

TEST_CASE("A homography of no square-pixel camera has no positive focal length", "[unit]") {
  // Relative to the principal point, H⁻¹ = [a b c] with a = (2, 0, 1), b = (0, 1, 0): the
  // constraints give 1/f² = -1/3.
  Mat3 centred;
  centred << 2.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0;
  Mat3 unshift = Mat3::Identity();
  unshift(0, 2) = 180.0;
  unshift(1, 2) = 144.0;
  const Mat3 H = (unshift * centred).inverse();
  const FloorHomographyCamera r = CameraFromFloorHomography(H, 0, 360, 288);
  CHECK_FALSE(r.ok);
  CHECK_THAT(r.reason, Catch::Contains("no positive focal length"));
}

TEST_CASE("Non-finite or singular homographies and invalid options are rejected", "[unit]") {
  const CameraModel cam = Cameras()[0].camera;
  const Mat3 good = FloorHomographyOf(cam, 1.0, false, 1.0);
  const auto reason = [&](const Mat3& H, const FloorHomographyOptions& options = {}) {
    const FloorHomographyCamera r = CameraFromFloorHomography(H, 0, 360, 288, options);
    CHECK_FALSE(r.ok);
    return r.reason;
  };
  Mat3 bad = good;
  bad(1, 2) = kNaN;
  CHECK_THAT(reason(bad), Catch::Contains("non-finite"));
  bad(1, 2) = kInf;
  CHECK_THAT(reason(bad), Catch::Contains("non-finite"));
  CHECK_THAT(reason(Mat3::Zero()), Catch::Contains("singular"));
  bad = good;
  bad.row(2) = 2.0 * bad.row(0) - bad.row(1);  // rank 2
  CHECK_THAT(reason(bad), Catch::Contains("singular"));
  FloorHomographyOptions options;
  options.floor_unit_m = 0.0;
  CHECK_THAT(reason(good, options), Catch::Contains("floor_unit_m"));
  options.floor_unit_m = kNaN;
  CHECK_THAT(reason(good, options), Catch::Contains("floor_unit_m"));
  options = {};
  options.focal_px = -100.0;
  CHECK_THAT(reason(good, options), Catch::Contains("focal length"));
  options = {};
  options.principal_point_px = Vec2(kNaN, 1.0);
  CHECK_THAT(reason(good, options), Catch::Contains("principal point"));
  const FloorHomographyCamera no_size = CameraFromFloorHomography(good, 0, 0, 288);
  CHECK_FALSE(no_size.ok);
  CHECK_THAT(no_size.reason, Catch::Contains("image size"));
}

TEST_CASE("ImageToFloor: pixels on the horizon have no floor point", "[unit]") {
  Mat3 H = Mat3::Identity();
  H.row(2) << 0.0, 1.0, -100.0;  // the horizon is the row v = 100
  CHECK_FALSE(ImageToFloor(H, Vec2(20.0, 100.0)).has_value());
  const std::optional<Vec2> p = ImageToFloor(H, Vec2(20.0, 150.0));
  REQUIRE(p.has_value());
  CHECK_THAT(*p, IsApproxVec(Vec2(0.4, 3.0), 1e-12));
  CHECK_THAT(FloorToWorld(Vec2(10.0, 20.0), 0.5, false), IsApproxVec(Vec3(5.0, 10.0, 0.0), 0.0));
  CHECK_THAT(FloorToWorld(Vec2(10.0, 20.0), 0.5, true), IsApproxVec(Vec3(5.0, -10.0, 0.0), 0.0));
}

// The box of a standing person `height_m` tall whose feet are at `feet` (world, metres): bottom
// centre at the feet's pixel, top at the head's row, 40 px wide.
core::BoxPx PersonBox(const CameraModel& cam, const Vec3& feet, double height_m) {
  const Vec2 bottom = *cam.ProjectUndistorted(feet);
  const Vec2 top = *cam.ProjectUndistorted(feet + Vec3(0.0, 0.0, height_m));
  return core::BoxPx{bottom.x() - 20.0, top.y(), bottom.x() + 20.0, bottom.y()};
}

TEST_CASE("The floor unit from a person-height prior: homography -> cameras -> unit", "[unit]") {
  // Two cameras, a floor in units of 2 cm, people 1.7 m tall on a grid.
  const std::vector<CameraModel> metric = {
      testing::LookAtCamera(0, Vec3(-4.0, -4.0, 3.0), Vec3(1.0, 1.0, 0.0), 500.0, 360, 288),
      testing::LookAtCamera(1, Vec3(6.0, -3.0, 2.5), Vec3(1.0, 1.0, 0.0), 450.0, 360, 288)};
  constexpr double kUnitM = 0.02;
  std::vector<PersonBoxes> boxes;
  int cut = 0;
  for (const CameraModel& cam : metric) {
    PersonBoxes p;
    // The camera in floor units, as CameraFromFloorHomography gives it with floor_unit_m = 1.
    const FloorHomographyCamera r = CameraFromFloorHomography(
        FloorHomographyOf(cam, kUnitM, false, 1.0), cam.id, cam.width_px, cam.height_px);
    REQUIRE(r.ok);
    p.camera = r.camera;
    for (double x = -1.0; x <= 3.0; x += 0.5) {
      for (double y = -1.0; y <= 3.0; y += 0.5) {
        const core::BoxPx box = PersonBox(cam, Vec3(x, y, 0.0), 1.7);
        if (box.y_min < 1.0 || box.y_max > cam.height_px - 2.0) ++cut;
        p.boxes.push_back(box);
      }
    }
    // A box cut by the bottom border is never used.
    p.boxes.push_back(core::BoxPx{100.0, 100.0, 140.0, cam.height_px - 1.0});
    ++cut;
    boxes.push_back(std::move(p));
  }
  const PersonHeightEstimate e = EstimateFloorUnitFromPersonHeight(boxes, 1.7);
  REQUIRE(e.ok);
  CHECK(e.boxes_total == 2 * 81 + 2);
  CHECK(e.boxes_used == e.boxes_total - cut);
  CHECK(e.boxes_used > 40);
  // The box's top centre is above the feet's pixel, not the head's: a small bias.
  CHECK(e.unit_m == Approx(kUnitM).epsilon(0.01));
  CHECK(e.median_height == Approx(1.7 / kUnitM).epsilon(0.01));
  CHECK(e.p10_height <= e.median_height);
  CHECK(e.p90_height >= e.median_height);
  // Twice as tall a prior, twice the unit.
  CHECK(EstimateFloorUnitFromPersonHeight(boxes, 3.4).unit_m == Approx(2.0 * e.unit_m));

  const PersonHeightEstimate bad_prior = EstimateFloorUnitFromPersonHeight(boxes, 0.0);
  CHECK_FALSE(bad_prior.ok);
  CHECK_THAT(bad_prior.reason, Catch::Contains("person height"));
  std::vector<PersonBoxes> only_cut = {boxes.front()};
  only_cut.front().boxes = {core::BoxPx{10.0, 0.0, 50.0, 100.0}};
  const PersonHeightEstimate none = EstimateFloorUnitFromPersonHeight(only_cut, 1.7);
  CHECK_FALSE(none.ok);
  CHECK(none.boxes_used == 0);
  CHECK_THAT(none.reason, Catch::Contains("none of the 1 boxes"));
}

}  // namespace
}  // namespace mvtrack::geometry
