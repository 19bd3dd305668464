#include "tracking2d/kalman_box_tracker.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <optional>
#include <random>

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

TEST_CASE("KalmanBoxTracker: the process noise scale grows the prediction's uncertainty",
          "[unit]") {
  const core::BoxPx box{100.0, 100.0, 140.0, 220.0};
  KalmanBoxTracker plain(box);
  KalmanBoxTracker same(box);
  KalmanBoxTracker slow(box);
  plain.Predict();
  same.Predict(1.0);
  slow.Predict(8.0);
  // Scale 1 is SORT's filter exactly; a larger scale adds that many times SORT's Q.
  CHECK(plain.covariance() == same.covariance());
  CHECK(plain.state() == slow.state());
  for (int i = 0; i < 7; ++i) {
    CHECK(slow.covariance()(i, i) > plain.covariance()(i, i));
  }
  // Q's first diagonal entry is 1 (SORT): 8 added instead of 1.
  CHECK(slow.covariance()(0, 0) - plain.covariance()(0, 0) == Approx(7.0));
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

TEST_CASE("KalmanBoxTracker::ValidBox is the predicted Box() of a valid state", "[unit]") {
  KalmanBoxTracker kf(core::BoxPx{10.0, 20.0, 50.0, 120.0});
  kf.Predict();
  kf.Update(core::BoxPx{14.0, 22.0, 56.0, 126.0});
  kf.Predict();
  REQUIRE(kf.HasValidBox());
  const std::optional<core::BoxPx> box = kf.ValidBox();
  REQUIRE(box.has_value());
  const core::BoxPx want = kf.Box();
  CHECK(box->x_min == want.x_min);
  CHECK(box->y_min == want.y_min);
  CHECK(box->x_max == want.x_max);
  CHECK(box->y_max == want.y_max);
}

// The textbook dense form of SORT's filter (filterpy): x = F x, P = F P F^T + Q; K = P H^T S^-1
// by Eigen's LDLT, x += K y, Joseph form P = (I - K H) P (I - K H)^T + K R K^T. KalmanBoxTracker
// writes these out on their non-zero blocks in Eigen's evaluation order; both must agree to the
// last bit (SORT's matching, hence every output, depends on them).
struct DenseFilter {
  KalmanBoxTracker::State x;
  KalmanBoxTracker::StateCovariance p;

  void Predict() {
    if (x(6) + x(2) <= 0.0) x(6) = 0.0;
    KalmanBoxTracker::StateCovariance f = KalmanBoxTracker::StateCovariance::Identity();
    f.topRightCorner<3, 3>().setIdentity();
    KalmanBoxTracker::State q;
    q << 1.0, 1.0, 1.0, 1.0, 0.01, 0.01, 0.0001;
    x = f * x;
    p = f * p * f.transpose();
    p.diagonal() += q;
  }
  void Update(const core::BoxPx& box) {
    Eigen::Matrix4d r = Eigen::Vector4d(1.0, 1.0, 10.0, 10.0).asDiagonal();
    const KalmanBoxTracker::Measurement innovation =
        KalmanBoxTracker::BoxToMeasurement(box) - x.head<4>();
    const Eigen::Matrix4d s = p.topLeftCorner<4, 4>() + r;
    const Eigen::Matrix<double, 7, 4> k = s.ldlt().solve(p.topRows<4>()).transpose();
    x += k * innovation;
    KalmanBoxTracker::StateCovariance i_kh = KalmanBoxTracker::StateCovariance::Identity();
    i_kh.leftCols<4>() -= k;
    p = i_kh * p * i_kh.transpose() + k * r * k.transpose();
  }
};

TEST_CASE("KalmanBoxTracker equals the dense Joseph-form filter bit for bit", "[unit]") {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  int updates = 0;
  int mismatches = 0;
  for (int track = 0; track < 300; ++track) {
    // Pedestrian-like boxes of any size and speed, with detector noise, misses and gaps.
    const double cx0 = 100.0 + 1000.0 * uniform(rng);
    const double cy0 = 100.0 + 500.0 * uniform(rng);
    const double h0 = 20.0 + 400.0 * uniform(rng);
    const double vx = 10.0 * noise(rng);
    const double vy = 3.0 * noise(rng);
    const double vh = 0.5 * noise(rng);
    const double noise_px = 0.2 + 5.0 * uniform(rng);
    auto box_at = [&](int t) {
      const double h = std::max(5.0, h0 + vh * t + noise_px * noise(rng));
      const double w = std::max(2.0, 0.4 * h + noise_px * noise(rng));
      const double cx = cx0 + vx * t + noise_px * noise(rng);
      const double cy = cy0 + vy * t + noise_px * noise(rng);
      return core::BoxPx{cx - 0.5 * w, cy - 0.5 * h, cx + 0.5 * w, cy + 0.5 * h};
    };
    const core::BoxPx first = box_at(0);
    KalmanBoxTracker kf(first);
    DenseFilter dense{kf.state(), kf.covariance()};
    for (int t = 1; t < 150; ++t) {
      kf.Predict();
      dense.Predict();
      if (uniform(rng) < 0.15) continue;  // missed detection: predict only
      const core::BoxPx box = box_at(t);
      kf.Update(box);
      dense.Update(box);
      ++updates;
      if (kf.state() != dense.x || kf.covariance() != dense.p) ++mismatches;
    }
  }
  REQUIRE(updates > 30000);
  REQUIRE(mismatches == 0);
}

}  // namespace
}  // namespace mvtrack::tracking2d
