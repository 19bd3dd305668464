#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "tracking2d/kalman_box_tracker.h"

namespace mvtrack::tracking2d {
namespace {

// A box of constant aspect ratio whose centre moves and whose area grows linearly with time,
// exactly the SORT motion model: cx = cx0 + vx t, cy = cy0 + vy t, s = s0 + vs t, r const.
core::BoxPx TrueBox(double t) {
  const double cx = 100.0 + 6.0 * t;
  const double cy = 200.0 - 3.0 * t;
  const double area = 4000.0 + 50.0 * t;
  const double aspect = 0.4;
  KalmanBoxTracker::Measurement z;
  z << cx, cy, area, aspect;
  return KalmanBoxTracker::MeasurementToBox(z);
}

void RequireBoxNear(const core::BoxPx& got, const core::BoxPx& want, double tol_px) {
  INFO("got [" << got.x_min << ", " << got.y_min << ", " << got.x_max << ", " << got.y_max
               << "] want [" << want.x_min << ", " << want.y_min << ", " << want.x_max << ", "
               << want.y_max << "]");
  REQUIRE(std::abs(got.x_min - want.x_min) < tol_px);
  REQUIRE(std::abs(got.y_min - want.y_min) < tol_px);
  REQUIRE(std::abs(got.x_max - want.x_max) < tol_px);
  REQUIRE(std::abs(got.y_max - want.y_max) < tol_px);
}

TEST_CASE("Box and measurement conversions are inverse", "[unit]") {
  const core::BoxPx box{10.0, 20.0, 50.0, 120.0};
  const KalmanBoxTracker::Measurement z = KalmanBoxTracker::BoxToMeasurement(box);
  REQUIRE(z(0) == Approx(30.0));
  REQUIRE(z(1) == Approx(70.0));
  REQUIRE(z(2) == Approx(40.0 * 100.0));
  REQUIRE(z(3) == Approx(0.4));
  RequireBoxNear(KalmanBoxTracker::MeasurementToBox(z), box, 1e-9);
}

TEST_CASE("KalmanBoxTracker starts at the box with zero velocity", "[unit]") {
  const core::BoxPx box{10.0, 20.0, 50.0, 120.0};
  KalmanBoxTracker kf(box);
  RequireBoxNear(kf.Box(), box, 1e-9);
  REQUIRE(kf.state().tail<3>().isZero());
  kf.Predict();
  RequireBoxNear(kf.Box(), box, 1e-9);  // no velocity yet
  // Prediction without measurement grows the uncertainty.
  REQUIRE(kf.covariance()(0, 0) > 10.0);
}

TEST_CASE("KalmanBoxTracker learns and extrapolates constant velocity motion", "[unit]") {
  KalmanBoxTracker kf(TrueBox(0.0));
  for (int t = 1; t <= 30; ++t) {
    kf.Predict();
    kf.Update(TrueBox(t));
  }
  // Velocities converge to the true per-frame rates.
  REQUIRE(kf.state()(4) == Approx(6.0).margin(0.05));
  REQUIRE(kf.state()(5) == Approx(-3.0).margin(0.05));
  REQUIRE(kf.state()(6) == Approx(50.0).margin(1.0));
  // Predicting through a 5-frame occlusion follows the true trajectory.
  for (int t = 31; t <= 35; ++t) {
    kf.Predict();
    RequireBoxNear(kf.Box(), TrueBox(t), 0.5);
  }
  REQUIRE(kf.HasValidBox());
}

TEST_CASE("KalmanBoxTracker tracks noisy constant velocity motion", "[unit]") {
  std::mt19937 rng(42);
  std::normal_distribution<double> noise(0.0, 1.0);
  KalmanBoxTracker kf(TrueBox(0.0));
  double sum_sq_filtered = 0.0;
  double sum_sq_measured = 0.0;
  int counted = 0;
  for (int t = 1; t <= 60; ++t) {
    core::BoxPx measured = TrueBox(t);
    const double dx = noise(rng);
    const double dy = noise(rng);
    measured.x_min += dx;
    measured.x_max += dx;
    measured.y_min += dy;
    measured.y_max += dy;
    kf.Predict();
    kf.Update(measured);
    if (t > 20) {
      const Vec2 truth = TrueBox(t).center();
      sum_sq_filtered += (kf.Box().center() - truth).squaredNorm();
      sum_sq_measured += (measured.center() - truth).squaredNorm();
      ++counted;
    }
  }
  REQUIRE(counted == 40);
  // Once converged, filtering beats the raw measurements.
  REQUIRE(sum_sq_filtered < sum_sq_measured);
  REQUIRE(kf.state()(4) == Approx(6.0).margin(0.5));
}

TEST_CASE("KalmanBoxTracker never predicts a non-positive area from a shrinking box", "[unit]") {
  // The area shrinks fast; SORT zeroes the scale velocity when it would drive the area <= 0.
  KalmanBoxTracker kf(core::BoxPx{0.0, 0.0, 40.0, 100.0});
  kf.Predict();
  kf.Update(core::BoxPx{18.0, 45.0, 22.0, 55.0});
  for (int i = 0; i < 20; ++i) {
    kf.Predict();
    REQUIRE(kf.state()(2) > 0.0);
  }
  REQUIRE(kf.HasValidBox());
}

}  // namespace
}  // namespace mvtrack::tracking2d
