// Tests of geometry::CameraModel: projection and the OpenCV 5-parameter distortion model, checked
// against OpenCV itself (cv::projectPoints, cv::undistortPoints) as an independent reference.

#include "geometry/camera_model.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "support/eigen_matchers.h"
#include "support/synthetic_cameras.h"

namespace mvtrack::geometry {
namespace {

using testing::IsApproxVec;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// A 1920x1080 camera looking at the room centre with Panoptic-like intrinsics: slightly
/// different fx/fy, off-centre principal point, strong barrel distortion.
CameraModel PanopticLikeCamera() {
  CameraModel camera =
      testing::LookAtCamera(3, Vec3(4.0, 0.5, 3.0), Vec3(0.0, 0.0, 1.0), 1400.0, 1920, 1080);
  camera.K(1, 1) = 1395.0;
  camera.K(0, 2) = 955.3;
  camera.K(1, 2) = 541.7;
  camera.distortion = testing::PanopticLikeDistortion();
  return camera;
}

/// The same kind of camera with a non-zero skew term (which OpenCV's functions ignore), used only
/// for self-consistency round trips.
CameraModel SkewedCamera() {
  CameraModel camera = PanopticLikeCamera();
  camera.K(0, 1) = 2.5;
  camera.distortion.p1 = -2e-3;
  camera.distortion.p2 = 1.5e-3;
  return camera;
}

cv::Matx33d ToCv(const Mat3& m) {
  cv::Matx33d out;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out(r, c) = m(r, c);
  }
  return out;
}

std::vector<double> CvDistortion(const Distortion& d) { return {d.k1, d.k2, d.p1, d.p2, d.k3}; }

/// World points whose undistorted projection is uniform over the image and whose depth is
/// uniform in [1, 8] m.
std::vector<Vec3> RandomPointsInView(const CameraModel& camera, int count, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(0.0, static_cast<double>(camera.width_px));
  std::uniform_real_distribution<double> v(0.0, static_cast<double>(camera.height_px));
  std::uniform_real_distribution<double> depth(1.0, 8.0);
  std::vector<Vec3> points;
  for (int i = 0; i < count; ++i) {
    const Vec2 px(u(*rng), v(*rng));
    points.push_back(testing::BackProjectUndistorted(camera, px, depth(*rng)));
  }
  return points;
}

/// Raw pixels covering the whole image: a 40 px grid that includes all four corners and edges.
std::vector<Vec2> PixelGrid(const CameraModel& camera) {
  std::vector<Vec2> pixels;
  for (int y = 0; y <= camera.height_px; y += 40) {
    for (int x = 0; x <= camera.width_px; x += 40) {
      pixels.emplace_back(static_cast<double>(x), static_cast<double>(y));
    }
  }
  return pixels;
}

TEST_CASE("Project matches cv::projectPoints with Panoptic-like distortion", "[unit]") {
  const CameraModel camera = PanopticLikeCamera();
  std::mt19937 rng(101);
  const std::vector<Vec3> points = RandomPointsInView(camera, 500, &rng);

  std::vector<cv::Point3d> object_points;
  for (const Vec3& p : points) object_points.emplace_back(p.x(), p.y(), p.z());
  cv::Vec3d rvec;
  cv::Rodrigues(ToCv(camera.cam_from_world.rotation), rvec);
  const cv::Vec3d tvec(camera.cam_from_world.translation.x(),
                       camera.cam_from_world.translation.y(),
                       camera.cam_from_world.translation.z());
  std::vector<cv::Point2d> distorted, pinhole;
  cv::projectPoints(
      object_points, rvec, tvec, ToCv(camera.K), CvDistortion(camera.distortion), distorted);
  cv::projectPoints(object_points, rvec, tvec, ToCv(camera.K), std::vector<double>{}, pinhole);

  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::optional<Vec2> raw = camera.Project(points[i]);
    const std::optional<Vec2> undistorted = camera.ProjectUndistorted(points[i]);
    REQUIRE(raw.has_value());
    REQUIRE(undistorted.has_value());
    REQUIRE_THAT(*raw, IsApproxVec(Vec2(distorted[i].x, distorted[i].y), 1e-6));
    REQUIRE_THAT(*undistorted, IsApproxVec(Vec2(pinhole[i].x, pinhole[i].y), 1e-6));
  }
}

TEST_CASE("UndistortPixel matches cv::undistortPoints with P = K over the whole image", "[unit]") {
  const CameraModel camera = PanopticLikeCamera();
  std::vector<Vec2> pixels = PixelGrid(camera);
  std::mt19937 rng(102);
  std::uniform_real_distribution<double> u(0.0, 1920.0), v(0.0, 1080.0);
  for (int i = 0; i < 300; ++i) pixels.emplace_back(u(rng), v(rng));

  std::vector<cv::Point2d> src, dst;
  for (const Vec2& p : pixels) src.emplace_back(p.x(), p.y());
  // OpenCV's default is 5 fixed-point iterations, far from converged at the corners of a
  // strongly distorted image; iterate to convergence so the reference is exact.
  cv::undistortPoints(
      src,
      dst,
      ToCv(camera.K),
      CvDistortion(camera.distortion),
      cv::noArray(),
      ToCv(camera.K),
      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 1000, 1e-12));
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    INFO("raw pixel " << pixels[i].transpose());
    REQUIRE_THAT(camera.UndistortPixel(pixels[i]), IsApproxVec(Vec2(dst[i].x, dst[i].y), 1e-6));
  }
}

TEST_CASE("Distortion round trips are exact over the whole image", "[unit]") {
  const CameraModel camera = GENERATE(PanopticLikeCamera(), SkewedCamera());
  INFO("skew " << camera.K(0, 1));

  SECTION("raw -> undistorted -> raw") {
    for (const Vec2& raw : PixelGrid(camera)) {
      INFO("raw pixel " << raw.transpose());
      const Vec2 undistorted = camera.UndistortPixel(raw);
      // Barrel distortion (k1 < 0) pushes undistorted points outwards, except at the centre.
      if ((raw - camera.K.block<2, 1>(0, 2)).norm() > 100.0) {
        REQUIRE((undistorted - camera.K.block<2, 1>(0, 2)).norm() >
                (raw - camera.K.block<2, 1>(0, 2)).norm());
      }
      REQUIRE_THAT(camera.DistortPixel(undistorted), IsApproxVec(raw, 1e-6));
    }
  }

  SECTION("undistorted -> raw -> undistorted") {
    std::mt19937 rng(103);
    std::uniform_real_distribution<double> u(-100.0, 2020.0), v(-100.0, 1180.0);
    for (int i = 0; i < 500; ++i) {
      const Vec2 undistorted(u(rng), v(rng));
      INFO("undistorted pixel " << undistorted.transpose());
      REQUIRE_THAT(camera.UndistortPixel(camera.DistortPixel(undistorted)),
                   IsApproxVec(undistorted, 1e-6));
    }
  }

  SECTION("Project == DistortPixel(ProjectUndistorted) and UndistortPixel(Project) is pinhole") {
    std::mt19937 rng(104);
    for (const Vec3& point : RandomPointsInView(camera, 300, &rng)) {
      const std::optional<Vec2> raw = camera.Project(point);
      const std::optional<Vec2> undistorted = camera.ProjectUndistorted(point);
      REQUIRE(raw.has_value());
      REQUIRE(undistorted.has_value());
      REQUIRE_THAT(*raw, IsApproxVec(camera.DistortPixel(*undistorted), 1e-9));
      REQUIRE_THAT(camera.UndistortPixel(*raw), IsApproxVec(*undistorted, 1e-6));
      // Independent pinhole model: K * (R X + t), dehomogenised.
      const Vec3 h =
          camera.K * (camera.cam_from_world.rotation * point + camera.cam_from_world.translation);
      REQUIRE_THAT(*undistorted, IsApproxVec(Vec2(h.x() / h.z(), h.y() / h.z()), 1e-9));
    }
  }
}

TEST_CASE("Without distortion, distort and undistort are the identity", "[unit]") {
  CameraModel camera = PanopticLikeCamera();
  camera.distortion = Distortion{};
  REQUIRE(camera.distortion.IsZero());
  std::mt19937 rng(105);
  for (const Vec3& point : RandomPointsInView(camera, 100, &rng)) {
    const Vec2 px = *camera.ProjectUndistorted(point);
    REQUIRE_THAT(*camera.Project(point), IsApproxVec(px, 1e-12));
    REQUIRE_THAT(camera.UndistortPixel(px), IsApproxVec(px, 1e-12));
    REQUIRE_THAT(camera.DistortPixel(px), IsApproxVec(px, 1e-12));
  }
  // A single non-zero coefficient is enough to make the model non-trivial.
  camera.distortion.p2 = 1e-3;
  REQUIRE_FALSE(camera.distortion.IsZero());
  REQUIRE((camera.DistortPixel(Vec2(100.0, 100.0)) - Vec2(100.0, 100.0)).norm() > 0.1);
}

TEST_CASE("ProjectionMatrix, CenterInWorld and Depth agree with the pose", "[unit]") {
  const Vec3 position(-3.0, 2.0, 3.0);
  const Vec3 target(0.5, -0.5, 1.0);
  CameraModel camera = testing::LookAtCamera(1, position, target, 1200.0, 1280, 720);
  camera.K(0, 1) = 1.5;  // skew must be honoured by the projection matrix too
  REQUIRE_THAT(camera.CenterInWorld(), IsApproxVec(position, 1e-12));

  const Mat34 p = camera.ProjectionMatrix();
  REQUIRE_THAT(p * position.homogeneous(), IsApproxVec(Vec3::Zero(), 1e-9));
  // The look-at target lies on the optical axis: it projects to the principal point.
  REQUIRE_THAT(*camera.ProjectUndistorted(target), IsApproxVec(Vec2(640.0, 360.0), 1e-9));
  REQUIRE(camera.Depth(target) == Approx((target - position).norm()).epsilon(1e-12));

  const Vec3 axis = (target - position).normalized();
  std::mt19937 rng(106);
  for (const Vec3& point : RandomPointsInView(camera, 100, &rng)) {
    const Vec3 h = p * point.homogeneous();
    REQUIRE_THAT(*camera.ProjectUndistorted(point), IsApproxVec(Vec2(h.x(), h.y()) / h.z(), 1e-9));
    REQUIRE(camera.Depth(point) == Approx(axis.dot(point - position)).epsilon(1e-12));
    // P = K [R | t] with K(2,2) = 1 and an orthonormal R: the third row gives the depth.
    REQUIRE(h.z() == Approx(camera.Depth(point)).epsilon(1e-12));
  }
}

TEST_CASE("PointOnRayAtHeight inverts the projection at a known height", "[unit]") {
  const CameraModel camera =
      testing::LookAtCamera(1, Vec3(-3.0, 2.0, 3.0), Vec3(0.5, -0.5, 1.0), 1200.0, 1280, 720);
  std::mt19937 rng(107);
  for (const Vec3& point : RandomPointsInView(camera, 50, &rng)) {
    const std::optional<Vec2> px = camera.ProjectUndistorted(point);
    REQUIRE(px.has_value());
    const std::optional<Vec3> back = camera.PointOnRayAtHeight(*px, point.z());
    REQUIRE(back.has_value());
    REQUIRE_THAT(*back, IsApproxVec(point, 1e-6));
  }
  // Above the camera along a ray that looks down: behind it. A horizontal ray: never.
  REQUIRE_FALSE(camera.PointOnRayAtHeight(Vec2(640.0, 360.0), 4.0).has_value());
  const CameraModel level =
      testing::LookAtCamera(2, Vec3(0.0, 0.0, 1.0), Vec3(5.0, 0.0, 1.0), 1000.0, 1280, 720);
  REQUIRE_FALSE(level.PointOnRayAtHeight(Vec2(640.0, 360.0), 0.0).has_value());
}

TEST_CASE("Projection returns nullopt for points not in front of the camera", "[unit]") {
  const CameraModel camera = PanopticLikeCamera();
  const Vec2 centre(960.0, 540.0);
  const Vec3 in_front = testing::BackProjectUndistorted(camera, centre, 2.0);
  const Vec3 behind = testing::BackProjectUndistorted(camera, centre, -2.0);
  const Vec3 on_camera_plane = testing::BackProjectUndistorted(camera, centre, 0.0);
  const Vec3 just_in_front = testing::BackProjectUndistorted(camera, centre, 1e-3);

  REQUIRE(camera.ProjectUndistorted(in_front).has_value());
  REQUIRE(camera.Project(in_front).has_value());
  REQUIRE(camera.ProjectUndistorted(just_in_front).has_value());
  REQUIRE_THAT(*camera.ProjectUndistorted(just_in_front), IsApproxVec(centre, 1e-6));

  REQUIRE(camera.Depth(behind) < 0.0);
  REQUIRE_FALSE(camera.ProjectUndistorted(behind).has_value());
  REQUIRE_FALSE(camera.Project(behind).has_value());
  REQUIRE_FALSE(camera.ProjectUndistorted(on_camera_plane).has_value());
  REQUIRE_FALSE(camera.Project(on_camera_plane).has_value());
  REQUIRE_FALSE(camera.ProjectUndistorted(camera.CenterInWorld()).has_value());
  REQUIRE_FALSE(camera.ProjectUndistorted(Vec3(kNaN, 0.0, 0.0)).has_value());
}

TEST_CASE("Validate accepts a calibrated camera", "[unit]") {
  std::string why = "untouched";
  REQUIRE(PanopticLikeCamera().Validate(&why));
  REQUIRE(SkewedCamera().Validate(nullptr));
}

TEST_CASE("Validate rejects invalid cameras with a reason", "[unit]") {
  CameraModel camera = PanopticLikeCamera();
  std::string expected_words;

  SECTION("zero width") {
    camera.width_px = 0;
    expected_words = "image size";
  }
  SECTION("zero height") {
    camera.height_px = 0;
    expected_words = "image size";
  }
  SECTION("negative width") {
    camera.width_px = -1920;
    expected_words = "image size";
  }
  SECTION("zero fx") {
    camera.K(0, 0) = 0.0;
    expected_words = "focal";
  }
  SECTION("negative fy") {
    camera.K(1, 1) = -1395.0;
    expected_words = "focal";
  }
  SECTION("NaN focal length") {
    camera.K(0, 0) = kNaN;
    expected_words = "non-finite";
  }
  SECTION("infinite principal point") {
    camera.K(1, 2) = kInf;
    expected_words = "non-finite";
  }
  SECTION("K not normalised") {
    camera.K(2, 2) = 2.0;
    expected_words = "K(2,2)";
  }
  SECTION("K not upper triangular") {
    camera.K(2, 0) = 1e-3;
    expected_words = "upper triangular";
  }
  SECTION("NaN k1") {
    camera.distortion.k1 = kNaN;
    expected_words = "distortion";
  }
  SECTION("infinite k2") {
    camera.distortion.k2 = kInf;
    expected_words = "distortion";
  }
  SECTION("NaN p1") {
    camera.distortion.p1 = kNaN;
    expected_words = "distortion";
  }
  SECTION("infinite p2") {
    camera.distortion.p2 = -kInf;
    expected_words = "distortion";
  }
  SECTION("NaN k3") {
    camera.distortion.k3 = kNaN;
    expected_words = "distortion";
  }
  SECTION("NaN rotation entry") {
    camera.cam_from_world.rotation(1, 2) = kNaN;
    expected_words = "non-finite";
  }
  SECTION("infinite translation") {
    camera.cam_from_world.translation.y() = kInf;
    expected_words = "non-finite";
  }
  SECTION("scaled rotation") {
    camera.cam_from_world.rotation *= 1.01;
    expected_words = "rotation";
  }
  SECTION("reflection (det = -1)") {
    camera.cam_from_world.rotation.row(2) *= -1.0;
    REQUIRE(camera.cam_from_world.rotation.determinant() == Approx(-1.0));
    expected_words = "rotation";
  }
  SECTION("sheared rotation") {
    camera.cam_from_world.rotation(0, 1) += 0.05;
    expected_words = "rotation";
  }

  std::string why;
  REQUIRE_FALSE(camera.Validate(&why));
  CHECK_THAT(why, Catch::Contains(expected_words));
  CHECK_THAT(why, Catch::StartsWith("camera 3"));
  REQUIRE_FALSE(camera.Validate(nullptr));
}

TEST_CASE("InImage honours the image bounds and the margin", "[unit]") {
  const CameraModel camera = PanopticLikeCamera();
  REQUIRE(camera.InImage(Vec2(0.0, 0.0)));
  REQUIRE(camera.InImage(Vec2(1920.0, 1080.0)));
  REQUIRE(camera.InImage(Vec2(960.0, 540.0)));
  REQUIRE_FALSE(camera.InImage(Vec2(-0.5, 540.0)));
  REQUIRE_FALSE(camera.InImage(Vec2(960.0, 1080.5)));
  REQUIRE_FALSE(camera.InImage(Vec2(1921.0, 540.0)));
  REQUIRE(camera.InImage(Vec2(-9.0, 1089.0), 10.0));
  REQUIRE_FALSE(camera.InImage(Vec2(-11.0, 540.0), 10.0));
  // A negative margin shrinks the accepted area.
  REQUIRE_FALSE(camera.InImage(Vec2(5.0, 540.0), -10.0));
  REQUIRE_FALSE(camera.InImage(Vec2(kNaN, 540.0)));
}

TEST_CASE("RotationFromRodrigues matches cv::Rodrigues", "[unit]") {
  CHECK(RotationFromRodrigues(Vec3::Zero()).isApprox(Mat3::Identity()));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int i = 0; i < 200; ++i) {
    const Vec3 r(u(rng), u(rng), u(rng));
    cv::Mat rotation;
    cv::Rodrigues(cv::Vec3d(r.x(), r.y(), r.z()), rotation);
    const Mat3 ours = RotationFromRodrigues(r);
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) CHECK(std::abs(ours(a, b) - rotation.at<double>(a, b)) < 1e-12);
    }
  }
}

}  // namespace
}  // namespace mvtrack::geometry
