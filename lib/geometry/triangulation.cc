#include "geometry/triangulation.h"

#include <Eigen/Dense>
#include <cmath>

namespace mvtrack::geometry {
namespace {

/// Solves A X = 0 for homogeneous X (Eq. 5) given A^T A, and dehomogenises; nullopt when
/// degenerate. The null vector of A is the eigenvector of A^T A with the smallest eigenvalue;
/// the 4x4 self-adjoint solver is much cheaper than an SVD of A and equally accurate here
/// because the rows are normalised to unit length before.
std::optional<Vec3> SolveNormalMatrix(const Eigen::Matrix4d& ata) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> solver(ata);
  if (solver.info() != Eigen::Success) return std::nullopt;
  const Eigen::Vector4d x = solver.eigenvectors().col(0);
  // Rank check: the two smallest eigenvalues must be separated, otherwise the rays are
  // (nearly) parallel and the point is undetermined.
  const Eigen::Vector4d& ev = solver.eigenvalues();
  if (!(ev(1) > 1e-14 * std::max(1.0, ev(3)))) return std::nullopt;
  if (!(std::abs(x(3)) > 1e-12)) return std::nullopt;
  const Vec3 point = x.head<3>() / x(3);
  if (!point.allFinite()) return std::nullopt;
  return point;
}

void FillRows(const Mat34& p,
              const Vec2& x,
              double w,
              Eigen::Ref<Eigen::Matrix<double, 2, 4>> rows) {
  Eigen::RowVector4d r0 = x.x() * p.row(2) - p.row(0);
  Eigen::RowVector4d r1 = x.y() * p.row(2) - p.row(1);
  const double n0 = r0.norm(), n1 = r1.norm();
  rows.row(0) = n0 > 0.0 ? Eigen::RowVector4d(w * r0 / n0) : r0;
  rows.row(1) = n1 > 0.0 ? Eigen::RowVector4d(w * r1 / n1) : r1;
}

// Solves the 3x3 normal equations m X = rhs of the inhomogeneous triangulation; nullopt where
// degenerate geometry (parallel rays, the same ray twice, no baseline) makes m singular.
std::optional<Vec3> SolveNormalEquations(const Mat3& m, const Vec3& rhs) {
  const double trace = m.trace();
  const double det = m.determinant();
  if (!(trace > 0.0) || !(det > 1e-14 * trace * trace * trace)) return std::nullopt;
  const Vec3 point = m.inverse() * rhs;
  if (!point.allFinite()) return std::nullopt;
  return point;
}

}  // namespace

std::optional<Vec3> TriangulateTwoView(const Mat34& p_a,
                                       const Vec2& x_a,
                                       const Mat34& p_b,
                                       const Vec2& x_b) {
  return TriangulateTwoView(MakeTwoViewRows(p_a, x_a), MakeTwoViewRows(p_b, x_b));
}

TwoViewRows MakeTwoViewRows(const Mat34& p, const Vec2& x) {
  TwoViewRows out;
  out.finite = x.allFinite();
  if (out.finite) FillRows(p, x, 1.0, out.rows);
  return out;
}

std::optional<Vec3> TriangulateTwoView(const TwoViewRows& rows_a, const TwoViewRows& rows_b) {
  if (!rows_a.finite || !rows_b.finite) return std::nullopt;
  // Hot path of CMMT (every camera pair, every point, every frame): the inhomogeneous form of
  // Eq. 5, X = (x, y, z, 1), solved by 3x3 normal equations on unit-normalised rows. It equals
  // the homogeneous solution for exact data and is within round-off of it for finite points,
  // at a fraction of the cost of a 4x4 eigen-decomposition.
  Eigen::Matrix4d a;
  a.topRows<2>() = rows_a.rows;
  a.bottomRows<2>() = rows_b.rows;
  const Eigen::Matrix<double, 4, 3> a3 = a.leftCols<3>();
  return SolveNormalEquations(a3.transpose() * a3, -(a3.transpose() * a.col(3)));
}

std::optional<Vec3> TriangulateLinear(std::span<const Mat34* const> projections,
                                      std::span<const Vec2> points_px) {
  const std::size_t n = projections.size();
  if (n < 2 || points_px.size() != n) return std::nullopt;
  Mat3 m = Mat3::Zero();
  Vec3 rhs = Vec3::Zero();
  Eigen::Matrix<double, 2, 4> rows;
  for (std::size_t i = 0; i < n; ++i) {
    if (!points_px[i].allFinite()) return std::nullopt;
    FillRows(*projections[i], points_px[i], 1.0, rows);
    const Eigen::Matrix<double, 2, 3> a3 = rows.leftCols<3>();
    m.noalias() += a3.transpose() * a3;
    rhs.noalias() -= a3.transpose() * rows.col(3);
  }
  return SolveNormalEquations(m, rhs);
}

std::optional<Vec3> TriangulateDlt(std::span<const Mat34> projections,
                                   std::span<const Vec2> points_px,
                                   std::span<const double> weights) {
  const std::size_t n = projections.size();
  if (n < 2 || points_px.size() != n || (!weights.empty() && weights.size() != n)) {
    return std::nullopt;
  }
  // Accumulates A^T A (4x4) row pair by row pair: no allocation for any number of views.
  Eigen::Matrix4d ata = Eigen::Matrix4d::Zero();
  Eigen::Matrix<double, 2, 4> rows;
  for (std::size_t i = 0; i < n; ++i) {
    if (!points_px[i].allFinite()) return std::nullopt;
    const double w = weights.empty() ? 1.0 : weights[i];
    if (!std::isfinite(w) || w < 0.0) return std::nullopt;
    FillRows(projections[i], points_px[i], w, rows);
    ata.noalias() += rows.transpose() * rows;
  }
  return SolveNormalMatrix(ata);
}

bool InFront(const Mat34& p, const Vec3& point) {
  // For P = K [R | t] with det(K) > 0 the third homogeneous coordinate is the depth.
  return p.row(2).dot(point.homogeneous()) > 0.0;
}

double ReprojectionErrorPx(const Mat34& p, const Vec3& point, const Vec2& x) {
  const Vec3 h = p * point.homogeneous();
  return (h.head<2>() / h.z() - x).norm();
}

}  // namespace mvtrack::geometry
