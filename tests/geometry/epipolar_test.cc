// Tests of the epipolar geometry functions and the paper's cross-view distances (Eq. 1 and 2).
// Expected values are computed independently: the fundamental matrix from Hartley & Zisserman's
// F = [e_b]x P_b P_a^+ (HZ Eq. 9.1) and from OpenCV's 8-point algorithm, point-line distances
// from their explicit formula.

#include "geometry/epipolar.h"

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "geometry/camera_model.h"
#include "support/eigen_matchers.h"
#include "support/synthetic_cameras.h"

namespace mvtrack::geometry {
namespace {

using testing::IsApproxUpToScale;
using testing::IsApproxVec;

/// Explicit distance from pixel `x` to the line l = (a, b, c): |a x + b y + c| / sqrt(a^2 + b^2).
double ExplicitLineDistance(const Vec2& x, const Vec3& l) {
  return std::abs(l(0) * x(0) + l(1) * x(1) + l(2)) / std::sqrt(l(0) * l(0) + l(1) * l(1));
}

Mat3 Skew(const Vec3& v) {
  Mat3 m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

/// Hartley & Zisserman Eq. 9.1: F = [e_b]x P_b P_a^+, with e_b = P_b C_a the epipole in b.
Mat3 ReferenceFundamental(const CameraModel& a, const CameraModel& b) {
  const Mat34 p_a = a.ProjectionMatrix();
  const Mat34 p_b = b.ProjectionMatrix();
  const Eigen::Matrix<double, 4, 3> p_a_pinv =
      p_a.transpose() * (p_a * p_a.transpose()).inverse();  // right pseudo-inverse (rank 3)
  const Vec3 e_b = p_b * a.CenterInWorld().homogeneous();
  return Skew(e_b) * p_b * p_a_pinv;
}

struct NamedPair {
  std::string name;
  CameraModel a;
  CameraModel b;
};

/// Camera pairs covering the typical and the special configurations: neighbours and opposite
/// cameras of a ring (epipoles inside the image), a rectified stereo pair (epipoles at
/// infinity), forward motion along the optical axis, and random poses with non-trivial
/// intrinsics (fx != fy, skew, off-centre principal point).
std::vector<NamedPair> CameraPairs() {
  std::vector<NamedPair> pairs;
  const std::vector<CameraModel> ring =
      testing::RingOfCameras(4, 4.0, 3.0, Vec3(0.0, 0.0, 1.0), 1400.0, 1920, 1080);
  pairs.push_back({"ring neighbours", ring[0], ring[1]});
  pairs.push_back({"ring opposite", ring[0], ring[2]});

  CameraModel left =
      testing::LookAtCamera(10, Vec3(0.0, 0.0, 1.5), Vec3(0.0, 5.0, 1.5), 1000.0, 1280, 720);
  CameraModel right =
      testing::LookAtCamera(11, Vec3(0.3, 0.0, 1.5), Vec3(0.3, 5.0, 1.5), 1000.0, 1280, 720);
  pairs.push_back({"rectified stereo", left, right});

  CameraModel back =
      testing::LookAtCamera(12, Vec3(0.0, -2.0, 1.5), Vec3(0.0, 5.0, 1.5), 900.0, 1280, 720);
  CameraModel front =
      testing::LookAtCamera(13, Vec3(0.0, -1.0, 1.5), Vec3(0.0, 5.0, 1.5), 1100.0, 1280, 720);
  pairs.push_back({"forward motion", back, front});

  std::mt19937 rng(201);
  std::uniform_real_distribution<double> pos(-4.0, 4.0), height(0.5, 3.5), target(-1.0, 1.0);
  std::uniform_real_distribution<double> focal(600.0, 2000.0), ratio(0.95, 1.05), skew(-3.0, 3.0);
  std::uniform_real_distribution<double> pp(-40.0, 40.0);
  for (int i = 0; i < 6; ++i) {
    std::vector<CameraModel> cams;
    for (int k = 0; k < 2; ++k) {
      CameraModel c = testing::LookAtCamera(20 + 2 * i + k,
                                            Vec3(pos(rng), pos(rng), height(rng)),
                                            Vec3(target(rng), target(rng), 1.0 + target(rng)),
                                            focal(rng),
                                            1920,
                                            1080);
      c.K(1, 1) = c.K(0, 0) * ratio(rng);
      c.K(0, 1) = skew(rng);
      c.K(0, 2) += pp(rng);
      c.K(1, 2) += pp(rng);
      cams.push_back(c);
    }
    pairs.push_back({"random pair " + std::to_string(i), cams[0], cams[1]});
  }
  return pairs;
}

/// Random points inside the box [-2, 2] x [-2, 2] x [0, 2] that are at least 0.5 m in front of
/// both cameras, with their exact undistorted projections.
struct Correspondences {
  std::vector<Vec3> points;
  std::vector<Vec2> in_a;
  std::vector<Vec2> in_b;
};

Correspondences RandomCorrespondences(const CameraModel& a,
                                      const CameraModel& b,
                                      int count,
                                      std::mt19937* rng) {
  std::uniform_real_distribution<double> xy(-2.0, 2.0), z(0.0, 2.0);
  Correspondences out;
  while (static_cast<int>(out.points.size()) < count) {
    const Vec3 p(xy(*rng), xy(*rng), z(*rng));
    if (a.Depth(p) < 0.5 || b.Depth(p) < 0.5) continue;
    out.points.push_back(p);
    out.in_a.push_back(*a.ProjectUndistorted(p));
    out.in_b.push_back(*b.ProjectUndistorted(p));
  }
  return out;
}

TEST_CASE("FundamentalMatrix satisfies the epipolar constraint for several camera pairs",
          "[unit]") {
  std::mt19937 rng(202);
  for (const NamedPair& pair : CameraPairs()) {
    INFO(pair.name);
    REQUIRE(pair.a.Validate(nullptr));
    REQUIRE(pair.b.Validate(nullptr));
    const Mat3 f = FundamentalMatrix(pair.a, pair.b);
    REQUIRE(f.allFinite());

    // Independent construction (HZ Eq. 9.1), equal up to scale.
    REQUIRE_THAT(f, IsApproxUpToScale(ReferenceFundamental(pair.a, pair.b), 1e-9));

    // Rank 2, with the epipoles as null vectors: F e_a = 0 and F^T e_b = 0.
    const Eigen::JacobiSVD<Mat3> svd(f);
    REQUIRE(svd.singularValues()(2) < 1e-10 * svd.singularValues()(0));
    const Vec3 e_a = pair.a.ProjectionMatrix() * pair.b.CenterInWorld().homogeneous();
    const Vec3 e_b = pair.b.ProjectionMatrix() * pair.a.CenterInWorld().homogeneous();
    REQUIRE((f * e_a).norm() < 1e-9 * f.norm() * e_a.norm());
    REQUIRE((f.transpose() * e_b).norm() < 1e-9 * f.norm() * e_b.norm());

    // x_b^T F x_a = 0 for projections of the same 3D point; both epipolar lines pass through
    // the corresponding point (measured in pixels).
    const Correspondences c = RandomCorrespondences(pair.a, pair.b, 200, &rng);
    for (std::size_t i = 0; i < c.points.size(); ++i) {
      const Vec3 xa = c.in_a[i].homogeneous(), xb = c.in_b[i].homogeneous();
      const Vec3 line_in_b = f * xa;
      const Vec3 line_in_a = f.transpose() * xb;
      REQUIRE(std::abs(xb.dot(line_in_b)) < 1e-9 * xb.norm() * line_in_b.norm());
      REQUIRE(ExplicitLineDistance(c.in_b[i], line_in_b) < 1e-6);
      REQUIRE(ExplicitLineDistance(c.in_a[i], line_in_a) < 1e-6);
    }

    // The transpose is the reverse-direction fundamental matrix.
    REQUIRE_THAT(FundamentalMatrix(pair.b, pair.a), IsApproxUpToScale(f.transpose(), 1e-9));
  }
}

TEST_CASE("FundamentalMatrix agrees with OpenCV's 8-point estimate from exact matches", "[unit]") {
  std::mt19937 rng(203);
  for (const NamedPair& pair : CameraPairs()) {
    INFO(pair.name);
    const Correspondences c = RandomCorrespondences(pair.a, pair.b, 60, &rng);
    std::vector<cv::Point2d> pts_a, pts_b;
    for (std::size_t i = 0; i < c.points.size(); ++i) {
      pts_a.emplace_back(c.in_a[i].x(), c.in_a[i].y());
      pts_b.emplace_back(c.in_b[i].x(), c.in_b[i].y());
    }
    // OpenCV's convention: pts_b^T F pts_a = 0, the same as FundamentalMatrix(a, b).
    const cv::Mat cv_f = cv::findFundamentalMat(pts_a, pts_b, cv::FM_8POINT);
    REQUIRE(cv_f.rows == 3);
    REQUIRE(cv_f.cols == 3);
    Mat3 reference;
    for (int r = 0; r < 3; ++r) {
      for (int col = 0; col < 3; ++col) reference(r, col) = cv_f.at<double>(r, col);
    }
    // The 8-point estimate is itself only accurate to ~1e-6 (relative) for the poorly
    // conditioned forward-motion pair; the exact check against HZ Eq. 9.1 is above.
    REQUIRE_THAT(FundamentalMatrix(pair.a, pair.b), IsApproxUpToScale(reference, 2e-5));
  }
}

TEST_CASE("FundamentalMatrix of cameras with identical centres is zero", "[unit]") {
  // No baseline: the essential matrix [t]x R vanishes and there is no epipolar geometry (a
  // duplicated extrinsic calibration, for example). Round-off in t = R_to C - R_to C must not be
  // normalised up into an arbitrary unit-norm "fundamental matrix".
  const Vec3 centre = GENERATE(Vec3(0.0, 0.0, 0.0), Vec3(1.0, 2.0, 3.0), Vec3(-4.1, 3.3, 2.9));
  INFO("centre " << centre.transpose());
  const CameraModel a = testing::LookAtCamera(0, centre, Vec3(0.3, 0.2, 1.0), 1000.0, 1280, 720);
  const CameraModel b = testing::LookAtCamera(1, centre, Vec3(2.0, -1.0, 0.0), 1000.0, 1280, 720);
  const Mat3 f = FundamentalMatrix(a, b);
  REQUIRE(f.allFinite());
  REQUIRE(f.norm() < 1e-12);
}

TEST_CASE("PointLineDistance matches a hand-computed case", "[unit]") {
  // Line 3x + 4y - 10 = 0 has unit normal (0.6, 0.8) and passes through (2, 1).
  const Vec3 line(3.0, 4.0, -10.0);
  // (4, 7): |3*4 + 4*7 - 10| / 5 = 30 / 5 = 6.
  REQUIRE(PointLineDistance(Vec2(4.0, 7.0), line) == Approx(6.0).epsilon(1e-15));
  REQUIRE(PointLineDistance(Vec2(2.0, 1.0), line) == Approx(0.0).margin(1e-15));
  // Moving 2.5 px against the normal from a point on the line gives 2.5 px.
  REQUIRE(PointLineDistance(Vec2(2.0 - 1.5, 1.0 - 2.0), line) == Approx(2.5).epsilon(1e-15));
  // Homogeneous lines: any non-zero scale, including negative, is the same line.
  REQUIRE(PointLineDistance(Vec2(4.0, 7.0), -2.5 * line) == Approx(6.0).epsilon(1e-15));
  // Vertical line x = 5.
  REQUIRE(PointLineDistance(Vec2(2.0, 100.0), Vec3(1.0, 0.0, -5.0)) == Approx(3.0));
  // The line at infinity (0, 0, 1) is infinitely far from every finite point.
  REQUIRE(std::isinf(PointLineDistance(Vec2(2.0, 1.0), Vec3(0.0, 0.0, 1.0))));
}

TEST_CASE("SymmetricEpipolarDistance is zero for exact correspondences and grows with error",
          "[unit]") {
  const std::vector<CameraModel> ring =
      testing::RingOfCameras(4, 4.0, 3.0, Vec3(0.0, 0.0, 1.0), 1400.0, 1920, 1080);
  std::mt19937 rng(204);
  for (const auto& [i, j] : {std::pair{0, 1}, std::pair{0, 2}, std::pair{1, 3}, std::pair{3, 2}}) {
    INFO("cameras " << i << " -> " << j);
    const CameraModel& ci = ring[static_cast<std::size_t>(i)];
    const CameraModel& cj = ring[static_cast<std::size_t>(j)];
    const Mat3 f = FundamentalMatrix(ci, cj);  // points of i -> lines in j
    const Correspondences c = RandomCorrespondences(ci, cj, 50, &rng);
    for (std::size_t k = 0; k < c.points.size(); ++k) {
      const Vec2& x_i = c.in_a[k];
      const Vec2& x_j = c.in_b[k];
      REQUIRE(SymmetricEpipolarDistance(x_i, x_j, f) < 1e-6);

      // Displace x_j across its epipolar line l_j = F x_i by delta pixels: the one-sided
      // distance in j is exactly delta, and the sum grows monotonically with delta.
      const Vec3 l_j = f * x_i.homogeneous();
      const Vec2 normal = Vec2(l_j(0), l_j(1)).normalized();
      double previous = 0.0;
      for (const double delta : {0.5, 2.0, 8.0, 32.0}) {
        const Vec2 wrong_j = x_j + delta * normal;
        const double d = SymmetricEpipolarDistance(x_i, wrong_j, f);
        const double expected = ExplicitLineDistance(x_i, f.transpose() * wrong_j.homogeneous()) +
                                ExplicitLineDistance(wrong_j, l_j);
        REQUIRE(d == Approx(expected).epsilon(1e-9));
        REQUIRE(ExplicitLineDistance(wrong_j, l_j) == Approx(delta).epsilon(1e-6));
        REQUIRE(d >= delta - 1e-6);
        REQUIRE(d > previous);
        previous = d;
        // Eq. 1 is symmetric: swapping the views (and transposing F) gives the same value.
        REQUIRE(SymmetricEpipolarDistance(wrong_j, x_i, f.transpose()) == Approx(d).epsilon(1e-9));
      }

      // Sliding x_j along its epipolar line cannot be detected: corresponding epipolar lines
      // map onto each other, so both one-sided distances stay zero.
      const Vec2 along = Vec2(-normal.y(), normal.x());
      REQUIRE(SymmetricEpipolarDistance(x_i, x_j + 25.0 * along, f) < 1e-6);
    }
  }
}

TEST_CASE("NormalizedEpipolarDistance divides each one-sided distance by its view's scale",
          "[unit]") {
  const std::vector<CameraModel> ring =
      testing::RingOfCameras(4, 4.0, 3.0, Vec3(0.0, 0.0, 1.0), 1400.0, 1920, 1080);
  const CameraModel& ci = ring[1];
  const CameraModel& cj = ring[2];
  const Mat3 f = FundamentalMatrix(ci, cj);
  std::mt19937 rng(205);
  std::normal_distribution<double> noise(0.0, 5.0);
  std::uniform_real_distribution<double> scale(20.0, 600.0);
  const Correspondences c = RandomCorrespondences(ci, cj, 100, &rng);
  for (std::size_t k = 0; k < c.points.size(); ++k) {
    const Vec2 x_i = c.in_a[k] + Vec2(noise(rng), noise(rng));
    const Vec2 x_j = c.in_b[k] + Vec2(noise(rng), noise(rng));
    const double s_i = scale(rng), s_j = scale(rng);

    // Eq. 2 written out: d(x_i, F^T x_j) / |w_i + h_i| + d(x_j, F x_i) / |w_j + h_j|.
    const Vec3 l_i = f.transpose() * Vec3(x_j.x(), x_j.y(), 1.0);
    const Vec3 l_j = f * Vec3(x_i.x(), x_i.y(), 1.0);
    const double d_i = std::abs(l_i(0) * x_i.x() + l_i(1) * x_i.y() + l_i(2)) /
                       std::sqrt(l_i(0) * l_i(0) + l_i(1) * l_i(1));
    const double d_j = std::abs(l_j(0) * x_j.x() + l_j(1) * x_j.y() + l_j(2)) /
                       std::sqrt(l_j(0) * l_j(0) + l_j(1) * l_j(1));
    const double expected = d_i / s_i + d_j / s_j;
    REQUIRE(expected > 0.0);
    REQUIRE(NormalizedEpipolarDistance(x_i, s_i, x_j, s_j, f) == Approx(expected).epsilon(1e-9));
    // Only |w + h| matters.
    REQUIRE(NormalizedEpipolarDistance(x_i, -s_i, x_j, -s_j, f) == Approx(expected).epsilon(1e-9));
    // With unit scales it reduces to Eq. 1.
    REQUIRE(NormalizedEpipolarDistance(x_i, 1.0, x_j, 1.0, f) ==
            Approx(SymmetricEpipolarDistance(x_i, x_j, f)).epsilon(1e-12));
    // Each term is divided by its own view's scale, not the other's.
    if (std::abs(d_i - d_j) > 1e-3 * (d_i + d_j) && std::abs(s_i - s_j) > 1.0) {
      REQUIRE(NormalizedEpipolarDistance(x_i, s_i, x_j, s_j, f) !=
              Approx(d_i / s_j + d_j / s_i).epsilon(1e-6));
    }
  }
}

TEST_CASE("NormalizedEpipolarDistance of a fixed 3D error does not depend on the distance",
          "[unit]") {
  // The motivation of Eq. 2: a person of height H at depth Z appears with scale ~ f H / Z, and
  // a 3D error of delta metres produces ~ f delta / Z pixels of epipolar distance, so their ratio
  // does not depend on Z. Place the same two-camera configuration at 3, 6 and 12 m from the
  // person, with the same 5 cm detection bias in one view.
  const double f_px = 1200.0;
  const double height_m = 1.7;
  const double error_m = 0.05;
  std::vector<double> raw, normalized;
  for (const double distance : {3.0, 6.0, 12.0}) {
    // Two cameras at +-30 degrees around the person, both at the same distance.
    const Vec3 person(0.0, 0.0, 1.0);
    const double angle = 0.5236;
    const CameraModel ci =
        testing::LookAtCamera(0,
                              person + distance * Vec3(std::cos(angle), std::sin(angle), 0.0),
                              person,
                              f_px,
                              1920,
                              1080);
    const CameraModel cj =
        testing::LookAtCamera(1,
                              person + distance * Vec3(std::cos(angle), -std::sin(angle), 0.0),
                              person,
                              f_px,
                              1920,
                              1080);
    const Mat3 f = FundamentalMatrix(ci, cj);
    // In view j the detection is off by error_m vertically (e.g. a biased box centre).
    const Vec2 x_i = *ci.ProjectUndistorted(person);
    const Vec2 x_j = *cj.ProjectUndistorted(person + Vec3(0.0, 0.0, error_m));
    const double s_i = 1.5 * f_px * height_m / ci.Depth(person);  // |w + h| with w = h / 2
    const double s_j = 1.5 * f_px * height_m / cj.Depth(person);
    raw.push_back(SymmetricEpipolarDistance(x_i, x_j, f));
    normalized.push_back(NormalizedEpipolarDistance(x_i, s_i, x_j, s_j, f));
  }
  // The raw distance halves each time the distance doubles; the normalized one stays constant.
  REQUIRE(raw[0] > 1.0);
  REQUIRE(raw[1] == Approx(raw[0] / 2.0).epsilon(0.01));
  REQUIRE(raw[2] == Approx(raw[0] / 4.0).epsilon(0.01));
  REQUIRE(normalized[1] == Approx(normalized[0]).epsilon(0.01));
  REQUIRE(normalized[2] == Approx(normalized[0]).epsilon(0.01));
}

}  // namespace
}  // namespace mvtrack::geometry
