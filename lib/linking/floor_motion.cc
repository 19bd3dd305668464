#include "linking/floor_motion.h"

#include <cmath>
#include <limits>

namespace mvtrack::linking {

// The model is isotropic (the same noise on x and y, no coupling between the axes), so when
// the filter starts with equal, uncoupled axes -- as Start does -- the covariance keeps the
// block form [a I, b I; b I, c I] forever: each axis is the same 2-state (position, velocity)
// filter. The three scalars (a, b, c) are stored instead of the 4x4 matrix; every operation
// below is the 4x4 Kalman filter's, written per axis.

bool MotionOptions::Validate(std::string* why) const {
  const auto fail = [why](const char* reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (!std::isfinite(measurement_sigma_m) || measurement_sigma_m <= 0.0) {
    return fail("measurement_sigma_m must be finite and > 0");
  }
  if (!std::isfinite(acceleration_sigma_mps2) || acceleration_sigma_mps2 <= 0.0) {
    return fail("acceleration_sigma_mps2 must be finite and > 0");
  }
  if (!std::isfinite(initial_speed_sigma_mps) || initial_speed_sigma_mps <= 0.0) {
    return fail("initial_speed_sigma_mps must be finite and > 0");
  }
  return true;
}

FloorMotion FloorMotion::Start(const Vec2& xy, const MotionOptions& options) {
  FloorMotion m;
  m.x_ << xy.x(), xy.y(), 0.0, 0.0;
  m.pp_ = options.measurement_sigma_m * options.measurement_sigma_m;
  m.pv_ = 0.0;
  m.vv_ = options.initial_speed_sigma_mps * options.initial_speed_sigma_mps;
  return m;
}

void FloorMotion::Predict(double dt, const MotionOptions& options) {
  if (dt == 0.0) return;
  // x' = F x, F = [1 dt; 0 1] per axis; P' = F P F^T + Q with the continuous white-noise
  // acceleration of spectral density q: Q = [q|dt|^3/3, q dt|dt|/2; q dt|dt|/2, q|dt|] (a
  // backward step flips the sign of the coupling term, so Q stays the covariance of the
  // accumulated noise).
  x_.head<2>() += dt * x_.tail<2>();
  const double q = options.acceleration_sigma_mps2 * options.acceleration_sigma_mps2;
  const double a = std::abs(dt);
  const double pp = pp_ + 2.0 * dt * pv_ + dt * dt * vv_ + q * a * a * a / 3.0;
  const double pv = pv_ + dt * vv_ + q * dt * a / 2.0;
  const double vv = vv_ + q * a;
  pp_ = pp;
  pv_ = pv;
  vv_ = vv;
}

void FloorMotion::Update(const Vec2& xy, const MotionOptions& options) {
  // Per axis: H = [1 0], S = pp + r, K = [pp; pv] / S; Joseph form
  // P' = (I - K H) P (I - K H)^T + K r K^T, which for this H is P - K S K^T, i.e.
  // pp' = pp r / S, pv' = pv r / S, vv' = vv - pv^2 / S.
  const double r = options.measurement_sigma_m * options.measurement_sigma_m;
  const double s = pp_ + r;
  const double kp = pp_ / s;
  const double kv = pv_ / s;
  for (int axis = 0; axis < 2; ++axis) {
    const double innovation = xy[axis] - x_[axis];
    x_[axis] += kp * innovation;
    x_[axis + 2] += kv * innovation;
  }
  const double pp = pp_ * r / s;
  const double pv = pv_ * r / s;
  const double vv = vv_ - pv_ * pv_ / s;
  pp_ = pp;
  pv_ = pv;
  vv_ = vv;
}

FloorMotion::Covariance FloorMotion::covariance() const {
  Covariance p = Covariance::Zero();
  p(0, 0) = p(1, 1) = pp_;
  p(2, 2) = p(3, 3) = vv_;
  p(0, 2) = p(2, 0) = p(1, 3) = p(3, 1) = pv_;
  return p;
}

double StateDistanceSquared(const FloorMotion& a, const FloorMotion& b) {
  // S = Pa + Pb keeps the per-axis form [pp pv; pv vv]; d^T S^-1 d summed over the axes.
  const double pp = a.pp_ + b.pp_;
  const double pv = a.pv_ + b.pv_;
  const double vv = a.vv_ + b.vv_;
  const double det = pp * vv - pv * pv;
  if (!(pp > 0.0) || !(det > 0.0)) return std::numeric_limits<double>::infinity();
  const FloorMotion::State d = a.state() - b.state();
  double sum = 0.0;
  for (int axis = 0; axis < 2; ++axis) {
    const double dp = d[axis];
    const double dv = d[axis + 2];
    sum += (vv * dp * dp - 2.0 * pv * dp * dv + pp * dv * dv) / det;
  }
  return sum;
}

}  // namespace mvtrack::linking
