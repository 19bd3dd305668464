#include "linking/floor_motion.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <string>

namespace mvtrack::linking {
namespace {

TEST_CASE("FloorMotion: prediction covariance grows with white-noise acceleration", "[unit]") {
  MotionOptions o;
  o.measurement_sigma_m = 0.1;
  o.acceleration_sigma_mps2 = 2.0;
  o.initial_speed_sigma_mps = 1.5;
  FloorMotion m = FloorMotion::Start(Vec2(1.0, 2.0), o);
  CHECK(m.position() == Vec2(1.0, 2.0));
  CHECK(m.velocity() == Vec2::Zero());
  CHECK(m.covariance()(0, 0) == Approx(0.01));
  CHECK(m.covariance()(2, 2) == Approx(2.25));

  // Hand-computed: P' = F P F^T + Q with P = diag(r, r, V, V), q = 4:
  //   P'_xx = r + V dt^2 + q dt^3 / 3, P'_xv = V dt + q dt^2 / 2, P'_vv = V + q dt.
  const double dt = 0.5;
  m.Predict(dt, o);
  const double r = 0.01, v = 2.25, q = 4.0;
  CHECK(m.covariance()(0, 0) == Approx(r + v * dt * dt + q * dt * dt * dt / 3.0));
  CHECK(m.covariance()(1, 1) == Approx(m.covariance()(0, 0)));
  CHECK(m.covariance()(0, 2) == Approx(v * dt + q * dt * dt / 2.0));
  CHECK(m.covariance()(2, 2) == Approx(v + q * dt));
  CHECK(m.covariance()(0, 1) == Approx(0.0).margin(1e-15));

  // Backwards, the position-velocity coupling changes sign; the variances grow the same way.
  FloorMotion b = FloorMotion::Start(Vec2(1.0, 2.0), o);
  b.Predict(-dt, o);
  CHECK(b.covariance()(0, 0) == Approx(m.covariance()(0, 0)));
  CHECK(b.covariance()(0, 2) == Approx(-(v * dt + q * dt * dt / 2.0)));
  CHECK(b.covariance()(2, 2) == Approx(m.covariance()(2, 2)));
}

TEST_CASE("FloorMotion: an update fuses a measurement with its variance", "[unit]") {
  MotionOptions o;
  o.measurement_sigma_m = 0.2;
  FloorMotion m = FloorMotion::Start(Vec2(0.0, 0.0), o);
  m.Predict(1.0, o);
  const double prior = m.covariance()(0, 0);
  m.Update(Vec2(1.0, 0.0), o);
  const double r = 0.04;
  // Scalar Kalman gain on x: k = P / (P + r).
  CHECK(m.position().x() == Approx(prior / (prior + r)));
  CHECK(m.covariance()(0, 0) == Approx(prior * r / (prior + r)));
  CHECK(m.position().y() == Approx(0.0).margin(1e-15));
}

TEST_CASE("FloorMotion: a constant-velocity walk is tracked, state distances", "[unit]") {
  MotionOptions o;
  FloorMotion m = FloorMotion::Start(Vec2(0.0, 0.0), o);
  for (int i = 1; i <= 60; ++i) {
    m.Predict(1.0 / 30.0, o);
    m.Update(Vec2(1.2 * i / 30.0, 0.0), o);
  }
  CHECK(m.velocity().x() == Approx(1.2).margin(0.05));
  CHECK(m.position().x() == Approx(2.4).margin(0.02));
  CHECK(StateDistanceSquared(m, m) == Approx(0.0).margin(1e-12));

  // Two independent estimates with diagonal covariances: the sum of squared z-scores.
  FloorMotion a = FloorMotion::Start(Vec2(0.0, 0.0), o);
  FloorMotion c = FloorMotion::Start(Vec2(0.3, 0.4), o);
  // Both P = diag(0.01, 0.01, 2.25, 2.25): S = diag(0.02, 0.02, 4.5, 4.5).
  CHECK(StateDistanceSquared(a, c) == Approx((0.09 + 0.16) / 0.02));
}

TEST_CASE("MotionOptions::Validate", "[unit]") {
  std::string why;
  CHECK(MotionOptions{}.Validate(&why));
  MotionOptions o;
  o.measurement_sigma_m = 0.0;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("measurement_sigma_m") != std::string::npos);
  o = {};
  o.acceleration_sigma_mps2 = NAN;
  CHECK_FALSE(o.Validate(&why));
  o = {};
  o.initial_speed_sigma_mps = -1.0;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("initial_speed_sigma_mps") != std::string::npos);
}

}  // namespace
}  // namespace mvtrack::linking
