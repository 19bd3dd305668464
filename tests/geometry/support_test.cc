// Tests of the shared test helpers in tests/support/ (the Eigen matchers and the synthetic
// cameras). They live in the geometry suite because the helpers build on geometry types; other
// suites rely on them, so they must themselves be right.

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "geometry/camera_model.h"
#include "support/eigen_matchers.h"
#include "support/synthetic_cameras.h"

namespace mvtrack::testing {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST_CASE("IsApproxVec matches within the tolerance per entry", "[unit]") {
  const Vec3 expected(1.0, -2.0, 3.0);
  REQUIRE(IsApproxVec(expected, 1e-9).match(expected));
  REQUIRE(IsApproxVec(expected, 0.1).match(Vec3(1.05, -2.09, 2.95)));
  REQUIRE_FALSE(IsApproxVec(expected, 0.1).match(Vec3(1.0, -2.0, 3.11)));
  REQUIRE_FALSE(IsApproxVec(expected, 1e300).match(Vec3(1.0, kNaN, 3.0)));
  REQUIRE_FALSE(IsApproxVec(Vec3(kNaN, 0.0, 0.0), 1e300).match(Vec3(kNaN, 0.0, 0.0)));

  // Dynamic sizes: a shape mismatch never matches.
  Eigen::VectorXd dynamic(2);
  dynamic << 1.0, -2.0;
  REQUIRE_FALSE(IsApproxVec(dynamic, 1.0).match(Eigen::VectorXd(expected)));

  // Matrices work too, and expressions are accepted as the expected value.
  const Mat3 m = Mat3::Identity() * 2.0;
  REQUIRE(IsApproxVec(2.0 * Mat3::Identity(), 1e-12).match(m));
  REQUIRE_FALSE(IsApproxVec(Mat3::Identity(), 1e-12).match(m));
}

TEST_CASE("IsApproxVec describes the expected value, the actual value and the deviation",
          "[unit]") {
  const auto matcher = IsApproxVec(Vec2(1.0, 2.0), 0.5);
  REQUIRE_FALSE(matcher.match(Vec2(1.0, 4.0)));
  const std::string description = matcher.describe();
  CHECK_THAT(description, Catch::Contains("is within 0.5"));
  CHECK_THAT(description, Catch::Contains("[1, 2]"));
  CHECK_THAT(description, Catch::Contains("actual [1, 4]"));
  CHECK_THAT(description, Catch::Contains("max |diff| 2 at (1, 0)"));

  const auto matrix_matcher = IsApproxVec(Eigen::Matrix2d::Identity(), 0.0);
  REQUIRE(matrix_matcher.match(Eigen::Matrix2d::Identity()));
  CHECK_THAT(matrix_matcher.describe(), Catch::Contains("[1, 0; 0, 1]"));
}

TEST_CASE("IsApproxUpToScale ignores scale and sign but nothing else", "[unit]") {
  Mat3 f;
  f << 0.0, -1.0, 2.0, 1.0, 0.5, -3.0, -2.0, 4.0, 0.0;  // neither symmetric nor skew
  REQUIRE(IsApproxUpToScale(f, 1e-12).match(f));
  REQUIRE(IsApproxUpToScale(f, 1e-12).match(1e-6 * f));
  REQUIRE(IsApproxUpToScale(f, 1e-12).match(-250.0 * f));
  Mat3 g = f;
  g(0, 2) += 0.1;
  REQUIRE_FALSE(IsApproxUpToScale(f, 1e-3).match(g));
  REQUIRE_FALSE(IsApproxUpToScale(f, 1e-3).match(f.transpose()));
  REQUIRE_FALSE(IsApproxUpToScale(f, 1e-3).match(Mat3::Zero()));
  REQUIRE_FALSE(IsApproxUpToScale(Mat3(Mat3::Zero()), 1e-3).match(f));
  REQUIRE(IsApproxUpToScale(Mat3(Mat3::Zero()), 1e-3).match(Mat3::Zero()));
  Mat3 with_nan = f;
  with_nan(1, 1) = kNaN;
  REQUIRE_FALSE(IsApproxUpToScale(f, 1e300).match(with_nan));
  CHECK_THAT(IsApproxUpToScale(f, 1e-3).describe(), Catch::Contains("up to scale"));
}

TEST_CASE("LookAtCamera places a valid camera looking at the target, image y down", "[unit]") {
  const Vec3 position(3.0, -2.0, 3.0);
  const Vec3 target(0.0, 0.5, 1.0);
  const geometry::CameraModel camera = LookAtCamera(7, position, target, 1500.0, 1920, 1080);
  std::string why;
  REQUIRE(camera.Validate(&why));
  REQUIRE(camera.id == 7);
  REQUIRE(camera.width_px == 1920);
  REQUIRE(camera.height_px == 1080);
  REQUIRE(camera.distortion.IsZero());
  REQUIRE(camera.K(0, 0) == 1500.0);
  REQUIRE(camera.K(1, 1) == 1500.0);
  REQUIRE(camera.K(0, 1) == 0.0);
  REQUIRE_THAT(camera.CenterInWorld(), IsApproxVec(position, 1e-12));
  REQUIRE(camera.cam_from_world.rotation.determinant() == Approx(1.0));

  // The target is on the optical axis, at the principal point (the image centre).
  REQUIRE_THAT(*camera.ProjectUndistorted(target), IsApproxVec(Vec2(960.0, 540.0), 1e-9));
  REQUIRE(camera.Depth(target) == Approx((target - position).norm()));

  // World "up" is image "up" (smaller v) and the horizon is level: a point 0.5 m above the
  // target projects straight above the principal point.
  const Vec2 above = *camera.ProjectUndistorted(target + Vec3(0.0, 0.0, 0.5));
  REQUIRE(above.y() < 540.0 - 10.0);
  REQUIRE(above.x() == Approx(960.0).margin(1e-6));

  // Image x points to the camera's right: looking from `position` towards `target`, the right
  // is forward x up.
  const Vec3 right = (target - position).cross(Vec3::UnitZ()).normalized();
  const Vec2 to_the_right = *camera.ProjectUndistorted(target + 0.5 * right);
  REQUIRE(to_the_right.x() > 960.0 + 10.0);
  REQUIRE(to_the_right.y() == Approx(540.0).margin(1e-6));
}

TEST_CASE("LookAtCamera handles a camera looking straight down", "[unit]") {
  const geometry::CameraModel camera =
      LookAtCamera(1, Vec3(0.0, 0.0, 4.0), Vec3(0.0, 0.0, 0.0), 800.0, 640, 480);
  REQUIRE(camera.Validate(nullptr));
  REQUIRE_THAT(*camera.ProjectUndistorted(Vec3::Zero()), IsApproxVec(Vec2(320.0, 240.0), 1e-9));
  REQUIRE(camera.Depth(Vec3::Zero()) == Approx(4.0));
}

TEST_CASE("RingOfCameras spaces cameras evenly around the target", "[unit]") {
  const Vec3 target(1.0, -1.0, 1.0);
  const std::vector<geometry::CameraModel> ring =
      RingOfCameras(6, 4.0, 3.0, target, 1200.0, 1280, 720, 100);
  REQUIRE(ring.size() == 6);
  for (std::size_t i = 0; i < ring.size(); ++i) {
    INFO("camera " << i);
    const geometry::CameraModel& c = ring[i];
    REQUIRE(c.id == 100 + static_cast<CameraId>(i));
    REQUIRE(c.Validate(nullptr));
    const Vec3 centre = c.CenterInWorld();
    REQUIRE(centre.z() == Approx(3.0));
    REQUIRE((centre - target).head<2>().norm() == Approx(4.0));
    REQUIRE_THAT(*c.ProjectUndistorted(target), IsApproxVec(Vec2(640.0, 360.0), 1e-9));
    // Neighbours are 60 degrees apart: chord 2 r sin(30 deg) = r.
    const Vec3 next = ring[(i + 1) % ring.size()].CenterInWorld();
    REQUIRE((next - centre).norm() == Approx(4.0));
  }
  REQUIRE(ring[0].CenterInWorld().x() == Approx(5.0));  // the first camera is on the +x side
}

TEST_CASE("BackProjectUndistorted inverts ProjectUndistorted at the given depth", "[unit]") {
  geometry::CameraModel camera =
      LookAtCamera(2, Vec3(-2.0, 4.0, 2.5), Vec3(0.0, 0.0, 1.0), 1100.0, 1280, 720);
  camera.K(0, 1) = 1.2;
  camera.K(1, 1) = 1080.0;
  std::mt19937 rng(501);
  std::uniform_real_distribution<double> u(0.0, 1280.0), v(0.0, 720.0), depth(0.5, 9.0);
  for (int k = 0; k < 100; ++k) {
    const Vec2 px(u(rng), v(rng));
    const double d = depth(rng);
    const Vec3 point = BackProjectUndistorted(camera, px, d);
    REQUIRE(camera.Depth(point) == Approx(d).epsilon(1e-12));
    REQUIRE_THAT(*camera.ProjectUndistorted(point), IsApproxVec(px, 1e-9));
  }
}

TEST_CASE("PanopticLikeDistortion is strong and invertible over a 1920x1080 image", "[unit]") {
  const geometry::Distortion d = PanopticLikeDistortion();
  REQUIRE(d.k1 == -0.3);
  REQUIRE(d.k2 == 0.1);
  REQUIRE(d.p1 == 1e-3);
  REQUIRE(d.p2 == -1e-3);
  REQUIRE(d.k3 == -0.02);
  // The radial map r -> r (1 + k1 r^2 + k2 r^4 + k3 r^6) is strictly increasing up to beyond
  // the image corner (r = 0.79 for fx = 1400), so undistortion is well defined there.
  double previous = 0.0;
  for (double r = 0.01; r <= 1.2; r += 0.01) {
    const double r2 = r * r;
    const double distorted = r * (1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3)));
    REQUIRE(distorted > previous);
    previous = distorted;
  }
}

}  // namespace
}  // namespace mvtrack::testing
