#pragma once
/// @file
/// Linear (DLT) triangulation, two-view and N-view (Eq. 5). Stateless.

#include <optional>
#include <span>

#include "core/types.h"

namespace mvtrack::geometry {

/// Two-view DLT in undistorted pixels. nullopt if degenerate (rank deficiency, point at
/// infinity) or non-finite.
std::optional<Vec3> TriangulateTwoView(const Mat34& p_a,
                                       const Vec2& x_a,
                                       const Mat34& p_b,
                                       const Vec2& x_b);

/// The two rows one view contributes to the two-view DLT (Eq. 5), unit-normalised: everything
/// of TriangulateTwoView that depends on one view only, so a caller pairing one point with many
/// others computes it once.
struct TwoViewRows {
  Eigen::Matrix<double, 2, 4> rows = Eigen::Matrix<double, 2, 4>::Zero();  ///< x P3 - P1, y P3 - P2
  bool finite = false;  ///< the pixel was finite (otherwise the pair is degenerate)
};

/// The rows of pixel `x` in the view with projection `p`.
TwoViewRows MakeTwoViewRows(const Mat34& p, const Vec2& x);

/// TriangulateTwoView from precomputed rows: bit-identical to TriangulateTwoView(p_a, x_a, p_b,
/// x_b) when a = MakeTwoViewRows(p_a, x_a) and b = MakeTwoViewRows(p_b, x_b).
std::optional<Vec3> TriangulateTwoView(const TwoViewRows& a, const TwoViewRows& b);

/// N-view linear triangulation (N >= 2) in the inhomogeneous form of Eq. 5, X = (x, y, z, 1),
/// solved by 3x3 normal equations on unit-normalised rows: TriangulateTwoView for any number of
/// views (equal to the homogeneous DLT for exact data, within round-off for finite points, a
/// fraction of the cost of its 4x4 eigen-decomposition). `projections[i]` observes
/// `points_px[i]`. nullopt if degenerate or non-finite.
std::optional<Vec3> TriangulateLinear(std::span<const Mat34* const> projections,
                                      std::span<const Vec2> points_px);

/// N-view DLT (N >= 2) with optional per-view weights (empty = all 1). nullopt if degenerate.
std::optional<Vec3> TriangulateDlt(std::span<const Mat34> projections,
                                   std::span<const Vec2> points_px,
                                   std::span<const double> weights = {});

/// Whether `point` is in front of the camera with projection `p` (positive depth). Assumes
/// p = K [R | t] with det(K) > 0, as CameraModel::ProjectionMatrix returns.
bool InFront(const Mat34& p, const Vec3& point);

/// Reprojection error in pixels of `point` in the view (p, x).
double ReprojectionErrorPx(const Mat34& p, const Vec3& point, const Vec2& x);

}  // namespace mvtrack::geometry
