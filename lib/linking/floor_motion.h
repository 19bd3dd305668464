#pragma once
/// @file
/// A person's motion on the floor: a constant-velocity Kalman filter on the footprint (x, y)
/// with white-noise acceleration, so the uncertainty of a prediction grows with the time it
/// spans (position variance ~ sigma_a^2 t^3 / 3, velocity variance ~ sigma_a^2 t). The window
/// linker uses it to decide whether a short-term 3D tracklet that appears after a gap can be
/// the continuation of a lost track (docs/DECISIONS.md "Window linking"). Pure value type: no
/// I/O, deterministic, single-threaded.

#include <Eigen/Core>
#include <string>

#include "core/types.h"

namespace mvtrack::linking {

/// Noise model of FloorMotion.
struct MotionOptions {
  /// Standard deviation of one footprint measurement, metres (triangulation and the
  /// disagreement between windows). Finite, > 0.
  double measurement_sigma_m = 0.1;
  /// Spectral density of the white-noise acceleration, as a standard deviation in m/s^2 over
  /// one second: how fast a walking person can change velocity (starting, stopping, turning).
  /// Finite, > 0.
  double acceleration_sigma_mps2 = 1.0;
  /// Standard deviation of the velocity of a track before any motion is observed, m/s.
  /// Finite, > 0.
  double initial_speed_sigma_mps = 1.5;

  /// Checks the ranges above; on failure writes a reason to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// State [x, y, vx, vy] (metres, m/s) with its covariance; the caller keeps the time it
/// refers to.
class FloorMotion {
 public:
  using State = Eigen::Matrix<double, 4, 1>;
  using Covariance = Eigen::Matrix<double, 4, 4>;

  FloorMotion() = default;

  /// A filter that has seen one measurement `xy` (velocity unknown: 0 with
  /// initial_speed_sigma_mps). `options` must be valid.
  static FloorMotion Start(const Vec2& xy, const MotionOptions& options);

  /// Moves the state by `dt_s` seconds (a negative step predicts backwards with the same
  /// model; the process noise uses |dt|).
  void Predict(double dt_s, const MotionOptions& options);
  /// Fuses a footprint measured at the state's time.
  void Update(const Vec2& xy, const MotionOptions& options);

  const State& state() const { return x_; }
  /// The 4x4 covariance (built from the per-axis form the filter keeps; see the .cc).
  Covariance covariance() const;
  Vec2 position() const { return x_.head<2>(); }
  Vec2 velocity() const { return x_.tail<2>(); }

 private:
  friend double StateDistanceSquared(const FloorMotion& a, const FloorMotion& b);
  State x_ = State::Zero();
  // Per-axis covariance [pp pv; pv vv], the same for x and y, no coupling between the axes.
  double pp_ = 1.0;
  double pv_ = 0.0;
  double vv_ = 1.0;
};

/// Squared Mahalanobis distance between two independent estimates of the same state at the
/// same time (the caller's responsibility): (xa - xb)^T (Pa + Pb)^-1 (xa - xb),
/// chi-square with 4 degrees of freedom when both describe one person. +infinity when the
/// summed covariance is not positive definite.
double StateDistanceSquared(const FloorMotion& a, const FloorMotion& b);

}  // namespace mvtrack::linking
