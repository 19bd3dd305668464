#include "tracking2d/kalman_box_tracker.h"

#include <Eigen/Cholesky>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <utility>

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

// The small fixed-trip loops of FactorLdlt and Update are fully unrolled ("#pragma GCC unroll"):
// that removes loop control and index arithmetic only; every floating-point operation and its
// order stay as written.

// Eigen's LDLT (ldlt_inplace<Lower>::unblocked) of a 4x4 matrix, operation for operation:
// diagonal pivoting (first largest |diagonal|), the same swaps of the lower triangle, the same
// left-to-right sums; only the lower triangle of `s` is read. Returns false at a zero pivot
// (the caller then uses Eigen itself, which has special handling for it).
bool FactorLdlt(const Eigen::Matrix4d& s, Eigen::Matrix4d* out, std::array<int, 4>* perm) {
  Eigen::Matrix4d& mat = *out;
  mat = s;
#pragma GCC unroll 8
  for (int k = 0; k < 4; ++k) {
    int big = k;
    double big_abs = std::abs(mat(k, k));
#pragma GCC unroll 8
    for (int i = k + 1; i < 4; ++i) {
      if (std::abs(mat(i, i)) > big_abs) {
        big_abs = std::abs(mat(i, i));
        big = i;
      }
    }
    (*perm)[static_cast<std::size_t>(k)] = big;
    if (big != k) {
#pragma GCC unroll 8
      for (int j = 0; j < k; ++j) std::swap(mat(k, j), mat(big, j));
#pragma GCC unroll 8
      for (int i = big + 1; i < 4; ++i) std::swap(mat(i, k), mat(i, big));
      std::swap(mat(k, k), mat(big, big));
#pragma GCC unroll 8
      for (int i = k + 1; i < big; ++i) {
        const double tmp = mat(i, k);
        mat(i, k) = mat(big, i);
        mat(big, i) = tmp;
      }
    }
    if (k > 0) {
      std::array<double, 4> temp{};
#pragma GCC unroll 8
      for (int j = 0; j < k; ++j) temp[static_cast<std::size_t>(j)] = mat(j, j) * mat(k, j);
      double dot = mat(k, 0) * temp[0];
#pragma GCC unroll 8
      for (int j = 1; j < k; ++j) dot = dot + mat(k, j) * temp[static_cast<std::size_t>(j)];
      mat(k, k) -= dot;
#pragma GCC unroll 8
      for (int row = k + 1; row < 4; ++row) {
        double acc = mat(row, 0) * temp[0];
#pragma GCC unroll 8
        for (int j = 1; j < k; ++j) acc = acc + mat(row, j) * temp[static_cast<std::size_t>(j)];
        mat(row, k) = mat(row, k) - acc;
      }
    }
    const double akk = mat(k, k);
    if (!(std::abs(akk) > 0.0)) return false;
#pragma GCC unroll 8
    for (int row = k + 1; row < 4; ++row) mat(row, k) /= akk;
  }
  return true;
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

void KalmanBoxTracker::Predict(double noise_scale) {
  if (x_(6) + x_(2) <= 0.0) x_(6) = 0.0;
  // x <- F x and P <- F P F^T + Q with F = [I3 0 I3; 0 1 0; 0 0 I3] (cx += vx, cy += vy,
  // s += vs) and diagonal Q, written out on the few non-zero entries instead of dense 7x7
  // products: every entry of the dense products is a sum of at most two non-zero terms plus
  // exact zeros, so this gives bit-identical results at a fraction of the cost.
  x_.head<3>() += x_.tail<3>();
  p_.topRows<3>() += p_.bottomRows<3>();                     // F P
  p_.leftCols<3>() += p_.rightCols<3>();                     // (F P) F^T
  p_.diagonal() += noise_scale * ProcessNoise().diagonal();  // + Q (scaled)
}

void KalmanBoxTracker::Update(const core::BoxPx& box) {
  MVTRACK_CHECK_MSG(IsUsableBox(box), "KalmanBoxTracker needs a finite box with positive size");
  // The Joseph-form update of the dense formulation (UpdateDense: K = P H^T S^-1 by Eigen's
  // LDLT, x += K y, P = (I - K H) P (I - K H)^T + K R K^T), written out on the non-zero blocks
  // of H = [I4 0] and I - K H. Every entry is summed in exactly the order Eigen evaluates the
  // dense expression (the LDLT and its solve, the products with their lazy and scalar paths,
  // see each step), and the skipped terms are exact zeros, so the result is bit-identical at a
  // fraction of the cost (tests/tracking2d/kalman_box_tracker_test.cc compares the two).
  const MeasurementCovariance r = MeasurementNoise();
  const Measurement innovation = BoxToMeasurement(box) - x_.head<kMeasurementDim>();
  const MeasurementCovariance s = p_.topLeftCorner<kMeasurementDim, kMeasurementDim>() + r;
  Eigen::Matrix4d l;
  std::array<int, kMeasurementDim> perm{};
  if (!FactorLdlt(s, &l, &perm)) {
    UpdateDense(innovation);  // a zero pivot: Eigen's own LDLT handles it
    return;
  }
  // K^T = S^-1 (H P) by LDLT::solve (P^T L D L^T P = S): row i of the right-hand side is
  // column i of k, so k ends as K. Columns carry an eighth, unused row so that every column
  // operation is whole aligned packets; the operations are element-wise, so the packets do not
  // change any value.
  using Column = Eigen::Matrix<double, 8, 1>;
  using Gain = Eigen::Matrix<double, 8, kMeasurementDim>;
  Gain k;
  k.topRows<kStateDim>() = p_.topRows<kMeasurementDim>().transpose();
  k.row(7).setZero();
#pragma GCC unroll 8
  for (int i = 0; i < kMeasurementDim; ++i) {
    const int pi = perm[static_cast<std::size_t>(i)];
    if (pi != i) k.col(i).swap(k.col(pi));
  }
// Unit lower solve, column-major kernel: each row subtracts the earlier rows in order.
#pragma GCC unroll 8
  for (int i = 0; i < kMeasurementDim; ++i) {
#pragma GCC unroll 8
    for (int q = i + 1; q < kMeasurementDim; ++q) k.col(q) -= k.col(i) * l(q, i);
  }
// D^+ (LDLT treats |d| <= the smallest normal double as zero).
#pragma GCC unroll 8
  for (int i = 0; i < kMeasurementDim; ++i) {
    const double d = l(i, i);
    if (std::abs(d) > std::numeric_limits<double>::min()) {
      k.col(i) /= d;
    } else {
      k.col(i).setZero();
    }
  }
// Unit upper solve with L^T (row-major kernel): a left-to-right dot of the later rows.
#pragma GCC unroll 8
  for (int i = kMeasurementDim - 2; i >= 0; --i) {
    Column dot = k.col(i + 1) * l(i + 1, i);
#pragma GCC unroll 8
    for (int q = i + 2; q < kMeasurementDim; ++q) dot = dot + k.col(q) * l(q, i);
    k.col(i) -= dot;
  }
#pragma GCC unroll 8
  for (int i = kMeasurementDim - 1; i >= 0; --i) {
    const int pi = perm[static_cast<std::size_t>(i)];
    if (pi != i) k.col(i).swap(k.col(pi));
  }
  // x += K y: Eigen's lazy product sums rows 0-5 (packets) left to right and row 6 (scalar
  // reduction) pairwise.
  const Column dx =
      ((k.col(0) * innovation(0) + k.col(1) * innovation(1)) + k.col(2) * innovation(2)) +
      k.col(3) * innovation(3);
  x_.head<6>() += dx.head<6>();
  x_(6) += (k(6, 0) * innovation(0) + k(6, 1) * innovation(1)) +
           (k(6, 2) * innovation(2) + k(6, 3) * innovation(3));
  // a = the first four columns of I - K H (the others are those of I).
  Gain a = -k;
#pragma GCC unroll 8
  for (int c = 0; c < kMeasurementDim; ++c) a(c, c) = 1.0 - k(c, c);
  // t1 = (I - K H) P: rows 0-5 left to right, row 6 pairwise.
  Eigen::Matrix<double, 8, kStateDim> t1;
#pragma GCC unroll 8
  for (int j = 0; j < kStateDim; ++j) {
    t1.col(j) =
        ((a.col(0) * p_(0, j) + a.col(1) * p_(1, j)) + a.col(2) * p_(2, j)) + a.col(3) * p_(3, j);
    t1(4, j) += p_(4, j);
    t1(5, j) += p_(5, j);
    t1(6, j) = (a(6, 0) * p_(0, j) + (a(6, 1) * p_(1, j) + a(6, 2) * p_(2, j))) +
               (a(6, 3) * p_(3, j) + p_(6, j));
  }
  // P = t1 (I - K H)^T + (K R) K^T: P aliases the right-hand side, so Eigen evaluates both
  // products by scalar (pairwise) reductions for every entry.
  Gain kr;
#pragma GCC unroll 8
  for (int c = 0; c < kMeasurementDim; ++c) kr.col(c) = k.col(c) * r(c, c);
#pragma GCC unroll 8
  for (int j = 0; j < kStateDim; ++j) {
    const Column head = t1.col(0) * a(j, 0) + (t1.col(1) * a(j, 1) + t1.col(2) * a(j, 2));
    const Column tail =
        j < kMeasurementDim ? Column(t1.col(3) * a(j, 3)) : Column(t1.col(3) * a(j, 3) + t1.col(j));
    const Column krk =
        (kr.col(0) * k(j, 0) + kr.col(1) * k(j, 1)) + (kr.col(2) * k(j, 2) + kr.col(3) * k(j, 3));
    p_.col(j) = ((head + tail) + krk).head<kStateDim>();
  }
}

void KalmanBoxTracker::UpdateDense(const Measurement& innovation) {
  const MeasurementCovariance r = MeasurementNoise();
  const MeasurementCovariance s = p_.topLeftCorner<kMeasurementDim, kMeasurementDim>() + r;
  // K = P H^T S^-1, computed as (S^-1 H P)^T since P and S are symmetric.
  const Eigen::Matrix<double, kStateDim, kMeasurementDim> k =
      s.ldlt().solve(p_.topRows<kMeasurementDim>()).transpose();
  x_ += k * innovation;
  StateCovariance i_kh = StateCovariance::Identity();
  i_kh.leftCols<kMeasurementDim>() -= k;
  p_ = i_kh * p_ * i_kh.transpose() + k * r * k.transpose();
}

core::BoxPx KalmanBoxTracker::Box() const { return MeasurementToBox(x_.head<kMeasurementDim>()); }

bool KalmanBoxTracker::HasValidBox() const { return ValidBox().has_value(); }

std::optional<core::BoxPx> KalmanBoxTracker::ValidBox() const {
  if (!(x_.allFinite() && x_(2) > 0.0 && x_(3) > 0.0)) return std::nullopt;
  const core::BoxPx box = Box();
  if (!IsUsableBox(box)) return std::nullopt;
  return box;
}

}  // namespace mvtrack::tracking2d
