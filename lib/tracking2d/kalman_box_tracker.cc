#include "tracking2d/kalman_box_tracker.h"

#include <Eigen/Cholesky>
#include <cmath>

#include "core/check.h"
#include "tracking2d/box_iou.h"

namespace mvtrack::tracking2d {
namespace {

using State = KalmanBoxTracker::State;
using StateCovariance = KalmanBoxTracker::StateCovariance;
using Measurement = KalmanBoxTracker::Measurement;
using MeasurementCovariance =
    Eigen::Matrix<double, KalmanBoxTracker::kMeasurementDim, KalmanBoxTracker::kMeasurementDim>;

// SORT: R[2:, 2:] *= 10 on an identity.
MeasurementCovariance MeasurementNoise() {
  Measurement d;
  d << 1.0, 1.0, 10.0, 10.0;
  return d.asDiagonal();
}

// SORT: Q[-1, -1] *= 0.01; Q[4:, 4:] *= 0.01 on an identity.
StateCovariance ProcessNoise() {
  State d;
  d << 1.0, 1.0, 1.0, 1.0, 0.01, 0.01, 0.0001;
  return d.asDiagonal();
}

// SORT: P[4:, 4:] *= 1000; P *= 10 on an identity.
StateCovariance InitialCovariance() {
  State d;
  d << 10.0, 10.0, 10.0, 10.0, 1e4, 1e4, 1e4;
  return d.asDiagonal();
}

}  // namespace

KalmanBoxTracker::Measurement KalmanBoxTracker::BoxToMeasurement(const core::BoxPx& box) {
  const double w = box.width();
  const double h = box.height();
  Measurement z;
  z << box.x_min + 0.5 * w, box.y_min + 0.5 * h, w * h, w / h;
  return z;
}

core::BoxPx KalmanBoxTracker::MeasurementToBox(const Measurement& z) {
  const double w = std::sqrt(z(2) * z(3));
  const double h = z(2) / w;
  core::BoxPx box;
  box.x_min = z(0) - 0.5 * w;
  box.y_min = z(1) - 0.5 * h;
  box.x_max = z(0) + 0.5 * w;
  box.y_max = z(1) + 0.5 * h;
  return box;
}

KalmanBoxTracker::KalmanBoxTracker(const core::BoxPx& box)
    : x_(State::Zero()), p_(InitialCovariance()) {
  MVTRACK_CHECK_MSG(IsUsableBox(box), "KalmanBoxTracker needs a finite box with positive size");
  x_.head<kMeasurementDim>() = BoxToMeasurement(box);
}

void KalmanBoxTracker::Predict() {
  if (x_(6) + x_(2) <= 0.0) x_(6) = 0.0;
  // x <- F x and P <- F P F^T + Q with F = [I3 0 I3; 0 1 0; 0 0 I3] (cx += vx, cy += vy,
  // s += vs) and diagonal Q, written out on the few non-zero entries instead of dense 7x7
  // products: every entry of the dense products is a sum of at most two non-zero terms plus
  // exact zeros, so this gives bit-identical results at a fraction of the cost.
  x_.head<3>() += x_.tail<3>();
  p_.topRows<3>() += p_.bottomRows<3>();       // F P
  p_.leftCols<3>() += p_.rightCols<3>();       // (F P) F^T
  p_.diagonal() += ProcessNoise().diagonal();  // + Q
}

void KalmanBoxTracker::Update(const core::BoxPx& box) {
  MVTRACK_CHECK_MSG(IsUsableBox(box), "KalmanBoxTracker needs a finite box with positive size");
  // H = [I4 0] selects the first four state entries, so H x, H P, H P H^T and K H are blocks
  // (exactly what the dense products give).
  const MeasurementCovariance r = MeasurementNoise();
  const Measurement innovation = BoxToMeasurement(box) - x_.head<kMeasurementDim>();
  const MeasurementCovariance s = p_.topLeftCorner<kMeasurementDim, kMeasurementDim>() + r;
  // K = P H^T S^-1, computed as (S^-1 H P)^T since P and S are symmetric.
  const Eigen::Matrix<double, kStateDim, kMeasurementDim> k =
      s.ldlt().solve(p_.topRows<kMeasurementDim>()).transpose();
  x_ += k * innovation;
  StateCovariance i_kh = StateCovariance::Identity();
  i_kh.leftCols<kMeasurementDim>() -= k;
  p_ = i_kh * p_ * i_kh.transpose() + k * r * k.transpose();
}

core::BoxPx KalmanBoxTracker::Box() const {
  return MeasurementToBox(x_.head<kMeasurementDim>());
}

bool KalmanBoxTracker::HasValidBox() const {
  return x_.allFinite() && x_(2) > 0.0 && x_(3) > 0.0 && IsUsableBox(Box());
}

}  // namespace mvtrack::tracking2d
