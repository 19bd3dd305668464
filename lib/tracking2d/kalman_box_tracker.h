#pragma once
/// @file
/// SORT's constant-velocity Kalman filter for one bounding box (Bewley et al., "Simple Online
/// and Realtime Tracking", ICIP 2016, Sec. 3.2; reference implementation sort.py). Single-owner,
/// single-threaded value type.

#include <Eigen/Core>
#include <optional>

#include "core/detection.h"

namespace mvtrack::tracking2d {

/// Kalman filter on the SORT state x = [cx, cy, s, r, vx, vy, vs]^T (box centre in pixels,
/// area s = w*h in px^2, aspect ratio r = w/h, and the per-frame velocities of cx, cy and s; the
/// aspect ratio is modelled as constant). The measurement is z = [cx, cy, s, r]^T.
///
/// Noise settings are SORT's, per frame: R = diag(1, 1, 10, 10); initial P = diag(10, 10, 10,
/// 10, 1e4, 1e4, 1e4) (large velocity uncertainty because velocities are unobserved at birth);
/// Q = diag(1, 1, 1, 1, 0.01, 0.01, 1e-4). Updates use the Joseph form (as filterpy does).
///
/// The filter's box (Box()) is the current estimate: after Predict() the prior, after Update()
/// the posterior.
class KalmanBoxTracker {
 public:
  /// State dimension (7) and measurement dimension (4).
  static constexpr int kStateDim = 7;
  static constexpr int kMeasurementDim = 4;
  using State = Eigen::Matrix<double, kStateDim, 1>;
  using StateCovariance = Eigen::Matrix<double, kStateDim, kStateDim>;
  using Measurement = Eigen::Matrix<double, kMeasurementDim, 1>;

  /// Starts a filter at `box` with zero velocity. `box` must satisfy IsUsableBox (checked).
  explicit KalmanBoxTracker(const core::BoxPx& box);

  /// Advances the state by one frame with the constant-velocity model x <- F x,
  /// P <- F P F^T + noise_scale Q. As in SORT, a scale velocity that would make the area
  /// non-positive is zeroed first. `noise_scale` (finite, > 0; SortOptions::process_noise_scale)
  /// is 1 at the rate SORT's Q was set for; 1 gives SORT's filter exactly.
  void Predict(double noise_scale = 1.0);

  /// Corrects the state with an observed box (must satisfy IsUsableBox; checked).
  void Update(const core::BoxPx& box);

  /// The current state estimate as a box. Meaningful only when HasValidBox().
  core::BoxPx Box() const;

  /// True when the estimated area and aspect ratio are positive and the state is finite, i.e.
  /// Box() is a proper box.
  bool HasValidBox() const;
  /// Box() when HasValidBox(), else nullopt (the box is computed once for both).
  std::optional<core::BoxPx> ValidBox() const;

  /// Current state estimate.
  const State& state() const { return x_; }
  /// Current state covariance.
  const StateCovariance& covariance() const { return p_; }

  /// Box -> measurement [cx, cy, w*h, w/h] (SORT's convert_bbox_to_z).
  static Measurement BoxToMeasurement(const core::BoxPx& box);
  /// First four state entries -> box (SORT's convert_x_to_bbox): w = sqrt(s r), h = s / w.
  static core::BoxPx MeasurementToBox(const Measurement& z);

 private:
  // The dense-matrix form of Update (Eigen expressions); Update's fallback at a zero pivot.
  void UpdateDense(const Measurement& innovation);

  State x_;
  StateCovariance p_;
};

}  // namespace mvtrack::tracking2d
