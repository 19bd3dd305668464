// Tests of the linear (DLT) triangulation of Eq. 5, two-view and N-view, on a synthetic ring of
// cameras around a room. Ground truth is the 3D point that generated the projections; the noise
// expectation is the first-order (Cramer-Rao) covariance sigma^2 (J^T J)^-1 of the point.

#include "geometry/triangulation.h"

#include <Eigen/Dense>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <span>
#include <vector>

#include "geometry/camera_model.h"
#include "support/eigen_matchers.h"
#include "support/synthetic_cameras.h"

namespace mvtrack::geometry {
namespace {

using testing::IsApproxVec;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Eight 1920x1080 cameras (fx 1400 px) on a 5 m circle, 3 m high, looking at (0, 0, 1).
std::vector<CameraModel> EightCameraRing() {
  return testing::RingOfCameras(8, 5.0, 3.0, Vec3(0.0, 0.0, 1.0), 1400.0, 1920, 1080);
}

std::vector<Mat34> Projections(const std::vector<CameraModel>& cameras) {
  std::vector<Mat34> out;
  for (const CameraModel& c : cameras) out.push_back(c.ProjectionMatrix());
  return out;
}

/// A point where a person's joints could be: inside 3 x 3 x 1.8 m around the room centre.
Vec3 RandomPointInRoom(std::mt19937* rng) {
  std::uniform_real_distribution<double> xy(-1.5, 1.5), z(0.1, 1.9);
  const double x = xy(*rng);
  const double y = xy(*rng);
  return {x, y, z(*rng)};
}

/// Undistorted pixel of `point` seen through projection `p` (explicit pinhole formula).
Vec2 ProjectWith(const Mat34& p, const Vec3& point) {
  const Vec3 h = p * point.homogeneous();
  return h.head<2>() / h.z();
}

/// First-order expected squared 3D error of the maximum-likelihood estimate from views `p`
/// with i.i.d. isotropic pixel noise of standard deviation `sigma_px`: trace(sigma^2 (J^T J)^-1)
/// where J stacks the 2x3 Jacobians d(pixel)/d(point) of all views.
double ExpectedSquaredError(const std::vector<Mat34>& p, const Vec3& point, double sigma_px) {
  Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
  for (const Mat34& pi : p) {
    const Vec3 h = pi * point.homogeneous();
    Eigen::Matrix<double, 2, 3> j;
    j.row(0) = (pi.block<1, 3>(0, 0) * h.z() - h.x() * pi.block<1, 3>(2, 0)) / (h.z() * h.z());
    j.row(1) = (pi.block<1, 3>(1, 0) * h.z() - h.y() * pi.block<1, 3>(2, 0)) / (h.z() * h.z());
    jtj += j.transpose() * j;
  }
  return sigma_px * sigma_px * jtj.inverse().trace();
}

TEST_CASE("TriangulateTwoView recovers points exactly from clean projections", "[unit]") {
  const std::vector<Mat34> p = Projections(EightCameraRing());
  std::mt19937 rng(301);
  for (std::size_t a = 0; a < p.size(); ++a) {
    for (std::size_t b = 0; b < p.size(); ++b) {
      if (a == b) continue;
      INFO("views " << a << ", " << b);
      for (int k = 0; k < 10; ++k) {
        const Vec3 point = RandomPointInRoom(&rng);
        const std::optional<Vec3> estimate =
            TriangulateTwoView(p[a], ProjectWith(p[a], point), p[b], ProjectWith(p[b], point));
        REQUIRE(estimate.has_value());
        REQUIRE_THAT(*estimate, IsApproxVec(point, 1e-8));
      }
    }
  }
}

TEST_CASE("TriangulateTwoView from precomputed rows equals the pixel form bit for bit", "[unit]") {
  const std::vector<Mat34> p = Projections(EightCameraRing());
  std::mt19937 rng(302);
  std::normal_distribution<double> noise(0.0, 2.0);
  int compared = 0;
  for (std::size_t a = 0; a < p.size(); ++a) {
    for (std::size_t b = 0; b < p.size(); ++b) {
      if (a == b) continue;
      for (int k = 0; k < 20; ++k) {
        const Vec3 point = RandomPointInRoom(&rng);
        const Vec2 xa = ProjectWith(p[a], point) + Vec2(noise(rng), noise(rng));
        const Vec2 xb = ProjectWith(p[b], point) + Vec2(noise(rng), noise(rng));
        const std::optional<Vec3> direct = TriangulateTwoView(p[a], xa, p[b], xb);
        const std::optional<Vec3> from_rows =
            TriangulateTwoView(MakeTwoViewRows(p[a], xa), MakeTwoViewRows(p[b], xb));
        REQUIRE(direct.has_value() == from_rows.has_value());
        if (direct) {
          REQUIRE(direct->x() == from_rows->x());
          REQUIRE(direct->y() == from_rows->y());
          REQUIRE(direct->z() == from_rows->z());
        }
        ++compared;
      }
    }
  }
  REQUIRE(compared == 8 * 7 * 20);
  // A non-finite pixel makes its rows unusable, as in the pixel form.
  const Vec2 bad(std::numeric_limits<double>::quiet_NaN(), 10.0);
  CHECK_FALSE(MakeTwoViewRows(p[0], bad).finite);
  CHECK_FALSE(TriangulateTwoView(MakeTwoViewRows(p[0], bad), MakeTwoViewRows(p[1], Vec2(1, 2))));
}

TEST_CASE("TriangulateDlt recovers points exactly from 2 to 8 clean views", "[unit]") {
  const std::vector<Mat34> all = Projections(EightCameraRing());
  std::mt19937 rng(302);
  std::uniform_real_distribution<double> weight(0.1, 3.0);
  for (std::size_t n = 2; n <= all.size(); ++n) {
    INFO(n << " views");
    for (int k = 0; k < 30; ++k) {
      // A random subset of n cameras, so that neighbours and opposite cameras both occur.
      std::vector<std::size_t> order(all.size());
      for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
      std::shuffle(order.begin(), order.end(), rng);
      std::vector<Mat34> p;
      for (std::size_t i = 0; i < n; ++i) p.push_back(all[order[i]]);

      const Vec3 point = RandomPointInRoom(&rng);
      std::vector<Vec2> x;
      std::vector<double> w;
      for (const Mat34& pi : p) {
        x.push_back(ProjectWith(pi, point));
        w.push_back(weight(rng));
      }
      const std::optional<Vec3> unweighted = TriangulateDlt(p, x);
      REQUIRE(unweighted.has_value());
      REQUIRE_THAT(*unweighted, IsApproxVec(point, 1e-8));
      // Positive weights do not move an exact solution.
      const std::optional<Vec3> weighted = TriangulateDlt(p, x, w);
      REQUIRE(weighted.has_value());
      REQUIRE_THAT(*weighted, IsApproxVec(point, 1e-8));
      if (n == 2) {
        REQUIRE_THAT(*unweighted, IsApproxVec(*TriangulateTwoView(p[0], x[0], p[1], x[1]), 1e-9));
      }
    }
  }
}

TEST_CASE("DLT error under pixel noise matches the first-order expectation", "[unit]") {
  const std::vector<Mat34> all = Projections(EightCameraRing());
  constexpr double kSigmaPx = 1.0;
  constexpr int kTrials = 300;
  std::normal_distribution<double> noise(0.0, kSigmaPx);
  std::vector<double> rms_by_views;
  for (const std::size_t n : {std::size_t{2}, std::size_t{4}, std::size_t{8}}) {
    INFO(n << " views");
    // Evenly spread views: 2 -> cameras 0 and 2 (90 degrees apart), 4 -> every other camera,
    // 8 -> all of them.
    std::vector<Mat34> p;
    const std::size_t step = n == 2 ? 2 : all.size() / n;
    for (std::size_t i = 0; i < n; ++i) p.push_back(all[i * step]);

    std::mt19937 rng(303);
    double sum_squared = 0.0, sum_expected = 0.0, sum_squared_two_view = 0.0;
    for (int k = 0; k < kTrials; ++k) {
      const Vec3 point = RandomPointInRoom(&rng);
      std::vector<Vec2> x;
      for (const Mat34& pi : p) x.push_back(ProjectWith(pi, point) + Vec2(noise(rng), noise(rng)));
      const std::optional<Vec3> estimate = TriangulateDlt(p, x);
      REQUIRE(estimate.has_value());
      sum_squared += (*estimate - point).squaredNorm();
      sum_expected += ExpectedSquaredError(p, point, kSigmaPx);
      if (n == 2) {
        sum_squared_two_view += (*TriangulateTwoView(p[0], x[0], p[1], x[1]) - point).squaredNorm();
      }
    }
    const double rms = std::sqrt(sum_squared / kTrials);
    const double expected_rms = std::sqrt(sum_expected / kTrials);
    INFO("rms " << rms << " m, expected " << expected_rms << " m");
    // The DLT is not exactly the ML estimate, but with rows normalised and similar depths in all
    // views it stays within ~10 % of it (measured ratios 1.00, 1.09, 1.07 for 2, 4, 8 views);
    // the sampling error of an RMS over 300 trials is 2.5-4 %.
    REQUIRE(rms > 0.85 * expected_rms);
    REQUIRE(rms < 1.2 * expected_rms);
    if (n == 2) {
      // TriangulateTwoView solves the inhomogeneous form of Eq. 5 (X = (x, y, z, 1)), a
      // different algebraic estimator from the homogeneous DLT; under noise the two agree to
      // well within the sampling error (measured 0.01 %).
      REQUIRE(std::sqrt(sum_squared_two_view / kTrials) == Approx(rms).epsilon(0.01));
    }
    rms_by_views.push_back(rms);
  }
  // More views, smaller error.
  REQUIRE(rms_by_views[1] < rms_by_views[0]);
  REQUIRE(rms_by_views[2] < rms_by_views[1]);
}

TEST_CASE("TriangulateDlt weights: zero ignores a view, invalid weights are rejected", "[unit]") {
  const std::vector<Mat34> p = Projections(EightCameraRing());
  const std::vector<Mat34> three = {p[0], p[2], p[5]};
  const Vec3 point(0.3, -0.4, 1.2);
  std::vector<Vec2> x;
  for (const Mat34& pi : three) x.push_back(ProjectWith(pi, point));
  x[2] += Vec2(40.0, -30.0);  // an outlier in the third view

  SECTION("an outlier with weight 1 biases the estimate") {
    const std::optional<Vec3> estimate = TriangulateDlt(three, x, std::vector<double>{1, 1, 1});
    REQUIRE(estimate.has_value());
    REQUIRE((*estimate - point).norm() > 0.01);
  }
  SECTION("an outlier with weight 0 is ignored") {
    const std::optional<Vec3> estimate = TriangulateDlt(three, x, std::vector<double>{1, 1, 0});
    REQUIRE(estimate.has_value());
    REQUIRE_THAT(*estimate, IsApproxVec(point, 1e-8));
  }
  SECTION("down-weighting the outlier reduces its influence") {
    const double full = (*TriangulateDlt(three, x) - point).norm();
    const double low = (*TriangulateDlt(three, x, std::vector<double>{1, 1, 0.1}) - point).norm();
    REQUIRE(low < 0.5 * full);
  }
  SECTION("a negative weight is rejected") {
    REQUIRE_FALSE(TriangulateDlt(three, x, std::vector<double>{1, 1, -0.5}).has_value());
  }
  SECTION("a NaN weight is rejected") {
    REQUIRE_FALSE(TriangulateDlt(three, x, std::vector<double>{1, kNaN, 1}).has_value());
  }
  SECTION("an infinite weight is rejected") {
    REQUIRE_FALSE(TriangulateDlt(three, x, std::vector<double>{kInf, 1, 1}).has_value());
  }
  SECTION("a weight count that differs from the view count is rejected") {
    REQUIRE_FALSE(TriangulateDlt(three, x, std::vector<double>{1, 1}).has_value());
    REQUIRE_FALSE(TriangulateDlt(three, x, std::vector<double>{1, 1, 1, 1}).has_value());
  }
  SECTION("all-zero weights leave the point undetermined") {
    REQUIRE_FALSE(TriangulateDlt(three, x, std::vector<double>{0, 0, 0}).has_value());
  }
  SECTION("a single view with non-zero weight leaves the point undetermined") {
    REQUIRE_FALSE(TriangulateDlt(three, x, std::vector<double>{0, 2, 0}).has_value());
  }
}

TEST_CASE("Degenerate triangulation inputs return nullopt", "[unit]") {
  const std::vector<Mat34> ring = Projections(EightCameraRing());
  const Vec3 point(0.3, -0.4, 1.2);

  SECTION("identical camera centres (pure rotation)") {
    const Vec3 centre(4.0, 1.0, 3.0);
    const Mat34 a = testing::LookAtCamera(0, centre, Vec3(0.0, 0.0, 1.0), 1400.0, 1920, 1080)
                        .ProjectionMatrix();
    const Mat34 b = testing::LookAtCamera(1, centre, Vec3(0.5, -0.8, 1.4), 1100.0, 1920, 1080)
                        .ProjectionMatrix();
    const Vec2 xa = ProjectWith(a, point), xb = ProjectWith(b, point);
    REQUIRE_FALSE(TriangulateTwoView(a, xa, b, xb).has_value());
    REQUIRE_FALSE(TriangulateDlt(std::vector<Mat34>{a, b}, std::vector<Vec2>{xa, xb}).has_value());
  }
  SECTION("the same view twice") {
    const Vec2 x = ProjectWith(ring[3], point);
    REQUIRE_FALSE(TriangulateTwoView(ring[3], x, ring[3], x).has_value());
  }
  SECTION("parallel rays (the point is at infinity)") {
    // Rectified stereo pair, both observing their principal point: the rays are parallel.
    const Mat34 a =
        testing::LookAtCamera(0, Vec3(0.0, 0.0, 1.5), Vec3(0.0, 5.0, 1.5), 1000.0, 1280, 720)
            .ProjectionMatrix();
    const Mat34 b =
        testing::LookAtCamera(1, Vec3(0.3, 0.0, 1.5), Vec3(0.3, 5.0, 1.5), 1000.0, 1280, 720)
            .ProjectionMatrix();
    const Vec2 principal_point(640.0, 360.0);
    REQUIRE_FALSE(TriangulateTwoView(a, principal_point, b, principal_point).has_value());
    REQUIRE_FALSE(TriangulateDlt(std::vector<Mat34>{a, b},
                                 std::vector<Vec2>{principal_point, principal_point})
                      .has_value());
    // Sanity check of the construction: with disparity the same pair triangulates.
    REQUIRE(
        TriangulateTwoView(a, principal_point, b, principal_point - Vec2(60.0, 0.0)).has_value());
  }
  SECTION("non-finite pixels") {
    const Vec2 good = ProjectWith(ring[1], point);
    for (const Vec2& bad : {Vec2(kNaN, 10.0), Vec2(10.0, kInf), Vec2(-kInf, kNaN)}) {
      REQUIRE_FALSE(TriangulateTwoView(ring[0], bad, ring[1], good).has_value());
      REQUIRE_FALSE(TriangulateTwoView(ring[1], good, ring[0], bad).has_value());
      REQUIRE_FALSE(TriangulateDlt(std::vector<Mat34>{ring[0], ring[1], ring[2]},
                                   std::vector<Vec2>{ProjectWith(ring[0], point), good, bad})
                        .has_value());
    }
  }
  SECTION("non-finite projection matrix") {
    Mat34 broken = ring[0];
    broken(1, 3) = kNaN;
    REQUIRE_FALSE(TriangulateTwoView(
                      broken, ProjectWith(ring[0], point), ring[1], ProjectWith(ring[1], point))
                      .has_value());
    REQUIRE_FALSE(TriangulateDlt(std::vector<Mat34>{ring[1], broken, ring[2]},
                                 std::vector<Vec2>{ProjectWith(ring[1], point),
                                                   ProjectWith(ring[0], point),
                                                   ProjectWith(ring[2], point)})
                      .has_value());
  }
  SECTION("mismatched span sizes and too few views") {
    const std::vector<Mat34> three = {ring[0], ring[1], ring[2]};
    std::vector<Vec2> x;
    for (const Mat34& pi : three) x.push_back(ProjectWith(pi, point));
    REQUIRE(TriangulateDlt(three, x).has_value());
    REQUIRE_FALSE(TriangulateDlt(three, std::span<const Vec2>(x).first(2)).has_value());
    REQUIRE_FALSE(TriangulateDlt(std::span<const Mat34>(three).first(2), std::span<const Vec2>(x))
                      .has_value());
    REQUIRE_FALSE(
        TriangulateDlt(std::span<const Mat34>(three).first(1), std::span<const Vec2>(x).first(1))
            .has_value());
    REQUIRE_FALSE(TriangulateDlt({}, {}).has_value());
  }
}

TEST_CASE("InFront tells which side of the camera a point is on", "[unit]") {
  const CameraModel camera = EightCameraRing()[2];
  const Mat34 p = camera.ProjectionMatrix();
  std::mt19937 rng(304);
  for (int k = 0; k < 100; ++k) {
    const Vec3 point = RandomPointInRoom(&rng);
    REQUIRE(camera.Depth(point) > 0.0);
    REQUIRE(InFront(p, point));
    // Mirror the point through the camera centre: now it is behind.
    const Vec3 mirrored = 2.0 * camera.CenterInWorld() - point;
    REQUIRE(camera.Depth(mirrored) < 0.0);
    REQUIRE_FALSE(InFront(p, mirrored));
  }
  // Close to the principal plane the sign of the depth decides.
  const Vec2 corner(100.0, 100.0);
  REQUIRE(InFront(p, testing::BackProjectUndistorted(camera, corner, 1e-6)));
  REQUIRE_FALSE(InFront(p, testing::BackProjectUndistorted(camera, corner, -1e-6)));
}

TEST_CASE("ReprojectionErrorPx is the pixel distance to the projection", "[unit]") {
  const std::vector<CameraModel> cameras = EightCameraRing();
  std::mt19937 rng(305);
  std::uniform_real_distribution<double> offset(-20.0, 20.0);
  for (const CameraModel& camera : cameras) {
    const Mat34 p = camera.ProjectionMatrix();
    for (int k = 0; k < 20; ++k) {
      const Vec3 point = RandomPointInRoom(&rng);
      const Vec2 exact = *camera.ProjectUndistorted(point);
      REQUIRE(ReprojectionErrorPx(p, point, exact) < 1e-9);
      // A 3-4-5 triangle.
      REQUIRE(ReprojectionErrorPx(p, point, exact + Vec2(3.0, -4.0)) == Approx(5.0).epsilon(1e-9));
      const Vec2 d(offset(rng), offset(rng));
      REQUIRE(ReprojectionErrorPx(p, point, exact + d) == Approx(d.norm()).epsilon(1e-9));
    }
  }
}

}  // namespace
}  // namespace mvtrack::geometry
